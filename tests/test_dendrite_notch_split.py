"""A 2 x 2 cluster of discs and a bold word whose letters touch side by side are cut apart at
their outline's notches (issue 25, dendrite43: :func:`split_at_notches`); single letters,
discs, capsules, bananas and worms are not."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy import ndimage
from test_dendrite_touching_shapes import _singles

from branchnb.dendrite import stylize
from branchnb.dendrite.strike_notch import split_at_notches
from branchnb.dendrite.strike_outline import outline_parts


def _word(text: str, n: int, overlap: float = 0.15) -> np.ndarray:
    """Label image (n/2 x n) of a bold word, its letters (1..) overlapping ``overlap`` of
    their width."""
    font = cv2.FONT_HERSHEY_DUPLEX
    h, w = n // 2, n
    widths = [cv2.getTextSize(ch, font, 1.0, 1)[0][0] for ch in text]
    cap = cv2.getTextSize("H", font, 1.0, 1)[0][1]
    scale = min(0.8 * w / (sum(widths) * (1 - overlap)), 0.6 * h / cap)
    thick = max(2, int(round(0.22 * cap * scale)))
    lab = np.zeros((h, w), int)
    x = (w - sum(widths) * scale * (1 - overlap)) / 2
    for i, (ch, tw) in enumerate(zip(text, widths), 1):
        m = np.zeros((h, w), np.uint8)
        cv2.putText(m, ch, (int(x), int(h / 2 + cap * scale / 2)), font, scale, 1, thick, cv2.LINE_8)
        lab[(m > 0) & (lab == 0)] = i
        x += tw * scale * (1 - overlap)
    return lab


def _cluster(n: int, gap: float) -> np.ndarray:
    """Label image of 4 bumpy discs of radius 0.2 n in a 2 x 2 grid, centres ``gap`` radii apart."""
    yy, xx = np.mgrid[0:n, 0:n]
    r = 0.2 * n
    lab = np.zeros((n, n), int)
    for i, (sx, sy) in enumerate(((-1, -1), (1, -1), (-1, 1), (1, 1)), 1):
        cx, cy = n / 2 + sx * gap * r / 2, n / 2 + sy * gap * r / 2
        ang = np.arctan2(yy - cy, xx - cx)
        bump = 1 + sum(0.03 * np.sin(k * ang + 2 * i + k) for k in range(2, 6))
        lab[(np.hypot(xx - cx, yy - cy) < r * bump) & (lab == 0)] = i
    return lab


def _apart(parts: np.ndarray, lab: np.ndarray) -> bool:
    """Every object mostly in a part of its own."""
    got = [int(np.argmax(np.bincount(parts[lab == k], minlength=2)[1:])) + 1
           for k in range(1, lab.max() + 1)]
    return len(set(got)) == len(got)


@pytest.mark.parametrize("n", [128, 400, 768])
@pytest.mark.parametrize("gap", [1.3, 1.4, 1.6])
def test_a_two_by_two_cluster_of_discs_comes_apart(n, gap):
    lab = _cluster(n, gap)
    parts = outline_parts(lab > 0)
    assert parts.max() == 4 and _apart(parts, lab)
    # (the ground truth gives every overlap to one disc, the cuts halve it)
    ious = [max(((parts == j) & (lab == k)).sum() / ((parts == j) | (lab == k)).sum()
                for j in range(1, 5)) for k in range(1, 5)]
    assert min(ious) >= 0.6


@pytest.mark.parametrize("n", [256, 768])
def test_a_bold_word_comes_apart_between_its_letters(n):
    lab = _word("HAM", n)
    assert lab.max() == 3 and ndimage.label(lab > 0, np.ones((3, 3)))[1] == 1  # one piece
    parts = outline_parts(lab > 0)
    assert parts.max() == 3
    ious = [max(((parts == j) & (lab == k)).sum() / ((parts == j) | (lab == k)).sum()
                for j in range(1, 4)) for k in range(1, 4)]
    assert min(ious) >= 0.9
    lab = _word("MOON", n)
    parts = outline_parts(lab > 0)
    assert parts.max() >= 4 and _apart(parts, lab)


@pytest.mark.parametrize("n", [256, 768])
def test_a_single_bold_letter_stays_whole(n):
    for ch in "MWNHAO":
        m = _word(ch, n) > 0
        assert outline_parts(m).max() == 1, ch
        assert split_at_notches(m, 0.02 * m.size) is None, ch


@pytest.mark.parametrize("n", [128, 1000])
def test_convex_and_elongated_objects_have_no_notch_cut(n):
    for seed in (0, 1):
        for name, m in _singles(n, seed).items():
            assert split_at_notches(m, 0.02 * m.size) is None, (name, seed)


def test_split_at_notches_checks_its_piece():
    with pytest.raises(ValueError, match="piece"):
        split_at_notches(np.ones((4, 4, 2), bool), 1.0)


def test_lightning_traces_every_letter_of_a_touching_word():
    lab = _word("HAM", 768)
    img = np.ones((*lab.shape, 3), np.float32)
    img[lab > 0] = (0.15, 0.15, 0.2)
    pic = np.asarray(stylize(img, metaphor="lightning", rng=0).rendering.image)[..., :3]
    near = ndimage.distance_transform_edt(~(pic.mean(-1) > 0.5)) <= 4
    covers = [near[(lab == k) & ~ndimage.binary_erosion(lab == k)].mean() for k in (1, 2, 3)]
    assert min(covers) >= 0.6  # before: 0.07 (the word one piece, the paper's bolt through it)
