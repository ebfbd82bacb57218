"""Texture crumbs of a billboard cloud: opaque bits cut off their billboard's piece (beyond the paper).

A billboard's texture is one superpixel (or strip) of the tree cut out with
the drawing's alpha. Where the soft rim of an outline (alpha just below
0.5) runs between them, a few texels with alpha >= 0.5 end up apart from
the texture's main piece. In the front view they sit beside a neighbouring
billboard's texels and nothing shows; from the side every billboard moves
with its own depth, and the crumb floats as a loose dot or stroke fragment
beside the crown (issue 24: 1-8 floating ink fragments per side view on 4
of 25 trees at 96 px). :func:`adopt_crumbs` gives each crumb to the
billboard beside it in the front view (the one that shows under it, else
its most frequent opaque neighbour), so it moves with what it touches, and
drops crumbs the front view does not show. The front view stays exactly as
drawn (checked; the cloud is returned unchanged otherwise).

Examples
--------
>>> import numpy as np
>>> from branchnb.trees.billboard import BillboardCloud
>>> a = np.zeros((4, 6, 4), np.float32); a[:, :4] = (0, 0.5, 0, 1); a[0, 5] = (0, 0, 0, 1)   # crumb at column 5
>>> b = np.zeros((4, 2, 4), np.float32); b[:, :] = (0, 0.3, 0, 1); b[0, 1, 3] = 0
>>> cloud = BillboardCloud(np.array([[3.0, 2, 0], [5.0, 2, 1]]), np.array([[6.0, 4], [2.0, 4]]),
...                        np.array([0, 1]), np.ones(2), np.zeros(2, int), np.arange(2), [a, b])
>>> out = adopt_crumbs(cloud)
>>> float(out.textures[0][0, 5, 3]), out.n_billboards
(0.0, 2)
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__ = ["adopt_crumbs"]

_EIGHT = np.ones((3, 3), bool)
_NEIGHBOURS = [(dy, dx) for dy in (-1, 0, 1) for dx in (-1, 0, 1) if dy or dx]


def _origins(centers, textures, texture) -> np.ndarray:
    """Front-view (row, column) of each billboard's texel (0, 0)."""
    h = np.array([textures[t].shape[0] for t in texture], float)
    w = np.array([textures[t].shape[1] for t in texture], float)
    return np.stack([np.round(centers[:, 1] - 0.5 * h), np.round(centers[:, 0] - 0.5 * w)], 1).astype(int)


def _front(centers, textures, texture, shape):
    """Front view in image pixels: ``(ids, rgba)`` of the nearest opaque texel (alpha >= 0.5)."""
    H, W = shape
    ids = np.full((H, W), -1, np.int64)
    rgba = np.zeros((H, W, 4), np.float32)
    org = _origins(centers, textures, texture)
    for i in np.argsort(centers[:, 2], kind="stable"):
        tex = textures[texture[i]]
        vv, uu = np.nonzero(tex[:, :, 3] >= 0.5)
        py, px = vv + org[i, 0], uu + org[i, 1]
        ok = (py >= 0) & (py < H) & (px >= 0) & (px < W)
        ids[py[ok], px[ok]] = i
        rgba[py[ok], px[ok]] = tex[vv[ok], uu[ok]]
    return ids, rgba


def adopt_crumbs(cloud, *, max_texels: int = 16):
    """Give a billboard's detached texels to the billboard they touch in the front view.

    Parameters
    ----------
    cloud : BillboardCloud
        Not modified.
    max_texels : int
        Largest crumb moved (8-connected opaque texels apart from the
        texture's largest piece, and at most a quarter of its size).

    Returns
    -------
    BillboardCloud
        A copy with the crumbs moved (textures grown where needed, each
        texture then used by one billboard), or ``cloud`` itself when there
        is nothing to move or the front view would change.

    Examples
    --------
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> from branchnb.trees.drawn import drawn_tree
    >>> cloud = billboard_cloud(drawn_tree("fruit", rng=0, size=96), params=BillboardParams(max_size=96), rng=0)
    >>> adopt_crumbs(cloud).n_billboards == cloud.n_billboards
    True
    """
    from .billboard import BillboardCloud

    if not isinstance(cloud, BillboardCloud):
        raise TypeError(f"cloud must be a BillboardCloud, got {type(cloud).__name__}")
    K = cloud.n_billboards
    if K < 2:
        return cloud
    textures = list(cloud.textures)
    texture = np.asarray(cloud.texture).copy()
    centers = np.asarray(cloud.centers, float).copy()
    sizes = np.asarray(cloud.sizes, float).copy()
    masks = list(cloud.line_masks) if len(cloud.line_masks) == len(textures) else [None] * len(textures)
    shape = cloud.image.shape[:2] if cloud.image is not None else None
    if shape is None:
        org = _origins(centers, textures, texture)
        ext = org + np.array([[t.shape[0], t.shape[1]] for t in (textures[k] for k in texture)])
        shape = (int(max(ext[:, 0].max(), 1)), int(max(ext[:, 1].max(), 1)))
    ids0, rgba0 = _front(centers, textures, texture, shape)
    uses = np.bincount(texture, minlength=len(textures)).tolist()

    def own(i):
        """Billboard ``i``'s texture, copied first when others share it."""
        t = int(texture[i])
        if uses[t] > 1:
            textures.append(textures[t].copy())
            masks.append(None if masks[t] is None else masks[t].copy())
            uses[t] -= 1
            texture[i] = len(textures) - 1
            uses.append(1)
        else:
            textures[t] = textures[t].copy()
            if masks[t] is not None:
                masks[t] = masks[t].copy()
        return int(texture[i])

    crumbs = []                                     # (i, image rows, cols, rgba, line bits)
    org = _origins(centers, textures, texture)
    for i in range(K):
        tex = textures[texture[i]]
        op = tex[:, :, 3] >= 0.5
        lab, n = ndi.label(op, structure=_EIGHT)
        if n < 2:
            continue
        size = np.bincount(lab.ravel(), minlength=n + 1)
        size[0] = 0
        big = int(np.argmax(size))
        small = [k for k in range(1, n + 1) if k != big and size[k] <= min(max_texels, 0.25 * size[big])]
        if not small:
            continue
        t = own(i)
        tex = textures[t]
        m = masks[t]
        for k in small:
            vv, uu = np.nonzero(lab == k)
            crumbs.append((i, vv + org[i, 0], uu + org[i, 1], tex[vv, uu].copy(),
                           None if m is None else m[vv, uu].copy()))
            tex[vv, uu, 3] = 0.0
            if m is not None:
                m[vv, uu] = False
    if not crumbs:
        return cloud
    ids1, _ = _front(centers, textures, texture, shape)
    H, W = shape
    for i, rows, cols, rgba, bits in crumbs:
        ok = (rows >= 0) & (rows < H) & (cols >= 0) & (cols < W)
        seen = np.zeros(len(rows), bool)
        seen[ok] = ids0[rows[ok], cols[ok]] == i
        if not seen.any():
            continue                                # hidden in the front view: dropped
        rows, cols, rgba = rows[seen], cols[seen], rgba[seen]
        bits = None if bits is None else bits[seen]
        under = ids1[rows, cols]
        if (under >= 0).all() and len(np.unique(under)) == 1:
            j = int(under[0])
        else:
            near = []
            for dy, dx in _NEIGHBOURS:
                r, c = rows + dy, cols + dx
                ok = (r >= 0) & (r < H) & (c >= 0) & (c < W)
                near.append(ids1[r[ok], c[ok]])
            near = np.concatenate(near)
            near = near[(near >= 0) & (near != i)]
            if not near.size:
                j = i                               # nothing beside it: it stays
            else:
                j = int(np.bincount(near).argmax())
        t = own(j)
        tex = textures[t]
        y0, x0 = (np.round(centers[j, 1] - 0.5 * tex.shape[0]), np.round(centers[j, 0] - 0.5 * tex.shape[1]))
        y0, x0 = int(y0), int(x0)
        top, left = max(0, y0 - rows.min()), max(0, x0 - cols.min())
        bottom = max(0, rows.max() + 1 - (y0 + tex.shape[0]))
        right = max(0, cols.max() + 1 - (x0 + tex.shape[1]))
        if top or left or bottom or right:
            tex = np.pad(tex, ((top, bottom), (left, right), (0, 0)))
            if masks[t] is not None:
                masks[t] = np.pad(masks[t], ((top, bottom), (left, right)))
            y0, x0 = y0 - top, x0 - left
            textures[t] = tex
            centers[j, 0] = x0 + 0.5 * tex.shape[1]
            centers[j, 1] = y0 + 0.5 * tex.shape[0]
            sizes[j] = sizes[j] * np.array([tex.shape[1], tex.shape[0]]) / np.maximum(
                np.array([tex.shape[1] - left - right, tex.shape[0] - top - bottom]), 1)
        tex[rows - y0, cols - x0] = rgba
        if bits is not None and bits.any():
            if masks[t] is None:
                masks[t] = np.zeros(tex.shape[:2], bool)
            masks[t][rows - y0, cols - x0] |= bits
    ids2, rgba2 = _front(centers, textures, texture, shape)
    if not np.array_equal(rgba2, rgba0) or not np.array_equal(ids2 >= 0, ids0 >= 0):
        return cloud
    return BillboardCloud(centers, sizes, texture, cloud.tint.copy(), cloud.layer.copy(), cloud.source.copy(),
                          textures, cloud.axis, cloud.image, cloud.superpixels, cloud.depth, cloud.replaced,
                          cloud.scale, cloud.lines, masks if len(cloud.line_masks) == len(cloud.textures) else [])
