import numpy as np
import pytest

from branchnb.core.render import coverage_polylines, draw_polylines
from branchnb.core.svg import polylines_to_svg


def test_coverage_area_matches_capsule():
    # A horizontal line of width 6 and length 40: area ~ 6 * 40 + pi * 3^2.
    cov, owner = coverage_polylines((40, 60), [[(10, 20), (50, 20)]], widths=6.0)
    assert cov.sum() == pytest.approx(6 * 40 + np.pi * 9, rel=0.03)
    assert owner[20, 30] == 0 and owner[0, 0] == -1


def test_per_vertex_width_tapers():
    cov, _ = coverage_polylines((40, 60), [[(5, 20), (55, 20)]], widths=[[12.0, 2.0]])
    thick = cov[:, 10].sum()
    thin = cov[:, 50].sum()
    assert thick > 3 * thin


def test_draw_polylines_colours_and_antialiasing():
    img = draw_polylines(np.ones((30, 30, 3)), [[(5, 15), (25, 15)], [(15, 2), (15, 28)]], widths=4.0,
                         colors=[(1, 0, 0), (0, 0, 1)])
    assert np.allclose(img[15, 8], (1, 0, 0), atol=1e-6)
    assert np.allclose(img[5, 15], (0, 0, 1), atol=1e-6)
    edge = img[13:18, 8, 1]
    assert ((edge > 0.01) & (edge < 0.99)).any()  # partial coverage at the border


def test_draw_polylines_rgba_canvas_gains_alpha():
    img = draw_polylines(np.zeros((10, 10, 4)), [[(1, 5), (8, 5)]], widths=3.0, colors=(0, 1, 0))
    assert img[5, 5, 3] == pytest.approx(1.0) and img[0, 0, 3] == 0


@pytest.mark.parametrize("lines,widths,match", [
    ([[(0, 0, 0)]], None, r"polylines\[0\]"),
    ([[(np.nan, 0), (1, 1)]], None, "NaN"),
    ([[(0, 0), (1, 1)]], [[1.0]], r"widths\[0\]"),
    ([[(0, 0), (1, 1)]], -1.0, ">= 0"),
])
def test_draw_polylines_bad_input(lines, widths, match):
    with pytest.raises(ValueError, match=match):
        draw_polylines(np.ones((5, 5, 3)), lines, widths=widths)


def test_svg_export_structure():
    svg = polylines_to_svg([[(0, 0), (10, 0)], [(0, 5), (5, 5), (9, 9)]], widths=[2.0, [1.0, 2.0, 3.0]],
                           size=(20, 10))
    assert svg.count("<polyline") == 1 and svg.count("<line") == 2
    import xml.etree.ElementTree as ET

    ET.fromstring(svg)  # well-formed
