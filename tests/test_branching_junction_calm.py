"""Corner-keeping smoothing leaves junctions alone (issue 23, branching107): within a parent radius of a
junction the skeleton bends from one line's centre to another's, no corner of the line; kept, those bends
were copied into new heads (a delta's trunk started with a kink and all its channels left on one side)."""
import numpy as np
from skimage.draw import line as draw_line

from branchnb.branching import extract_structure, path_smoothing
from branchnb.branching._delta_examples import FAN_KINDS, delta_fan_mask
from branchnb.branching.furcation import vertex_angles
from branchnb.branching.path_smoothing import keep_corners_smooth
from branchnb.core import resample_uniform, turning_angles


def _pixel_path(corners):
    out = []
    for (x0, y0), (x1, y1) in zip(corners[:-1], corners[1:]):
        rr, cc = draw_line(int(round(y0)), int(round(x0)), int(round(y1)), int(round(x1)))
        seg = np.c_[cc, rr].astype(float)
        out.append(seg if not out else seg[1:])
    return np.concatenate(out)


def _max_turn(p, lo, hi):
    """Largest |turn| (degrees per 4 px) of ``p`` between arc lengths ``lo`` and ``hi``."""
    r = resample_uniform(np.asarray(p, float), 4.0)
    a = np.abs(np.degrees(turning_angles(r)))
    s = 4.0 * np.arange(1, len(r) - 1)
    return float(a[(s >= lo) & (s <= hi)].max())


def test_calm_samples_are_smoothed_wide_and_corners_elsewhere_kept():
    # two 45 deg corners 60 px apart: the first in a calm stretch, the second not
    path = _pixel_path(np.array([(0.0, 0.0), (60.0, 0.0), (102.0, 42.0), (102.0, 102.0)]))
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(path, axis=0).T))]
    calm = np.abs(s - 60.0) < 5.0
    kept = keep_corners_smooth(path, 4.0)
    calmed = keep_corners_smooth(path, 4.0, calm=calm)
    wide = keep_corners_smooth(path, 4.0, noise=1e9)   # the one wide Gaussian
    # the calm corner is the wide Gaussian's (within 0.05 px), as round as without corner keeping
    near = np.abs(s - 60.0) < 12.0
    assert np.abs(calmed[near] - wide[near]).max() < 0.05
    assert _max_turn(calmed, 40, 80) < 0.8 * _max_turn(kept, 40, 80)
    # the other corner is kept as sharp as without ``calm``
    far = np.abs(s - (60.0 + 42.0 * np.sqrt(2.0))) < 12.0
    assert np.abs(calmed[far] - kept[far]).max() < 1e-9
    assert np.allclose(calmed[[0, -1]], path[[0, -1]])


def test_delta_channels_start_without_junction_kinks(monkeypatch):
    # a 300 px delta's Y (fan0): its traced channels bent 28-32 deg at their second sample with corners
    # kept and the trunk 40 deg at one sample where they part (with the one wide Gaussian: 10-20 deg)
    t, c, f, n = FAN_KINDS["fan0"]
    img = np.dstack([delta_fan_mask((300, 300), 303, t, c, f, n)[0]] * 3)
    monkeypatch.setattr(path_smoothing, "KEEP_CORNERS", True)
    s = extract_structure(img)
    kids = [b for b in s.branches if b.parent is not None]
    assert kids
    for b in kids:
        a = np.abs(np.degrees(vertex_angles(np.asarray(b.points))))
        assert a[:6].max() < 22.0, a[:6]
    root = max((b for b in s.branches if b.parent is None), key=lambda b: b.length)
    a = np.abs(np.degrees(vertex_angles(np.asarray(root.points))))
    assert a.max() < 25.0, a.max()
