"""The shared notebook plotting helper: panels, scalar maps that stay visible, labelled histograms."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from branchnb import plot  # noqa: E402


def test_scalar_map_uses_its_own_range_not_unit_clipping():
    fig, axes = plot.panels(1)
    values = np.linspace(-5.0, 200.0, 64, dtype=np.float32).reshape(8, 8)
    artist = plot.image_panel(axes[0], values, "log cost", colorbar="cost")
    assert artist.get_clim() == pytest.approx((-5.0, 200.0))
    assert len(fig.axes) == 2  # the colour bar
    plot.close(fig)


def test_rgba_is_composited_and_panels_hide_spares():
    fig, axes = plot.panels(3, cols=2)
    assert len(axes) == 3 and len(fig.axes) == 4 and not fig.axes[3].get_visible()
    rgba = np.zeros((10, 10, 4), np.float32)
    artist = plot.image_panel(axes[0], rgba, "transparent", background=(1, 0, 0))
    shown = artist.get_array()
    assert np.allclose(shown[..., 0], 1.0) and np.allclose(shown[..., 1:], 0.0)
    plot.close(fig)


def test_hist_panel_labels_and_normalises():
    fig, axes = plot.panels(1)
    plot.hist_panel(axes[0], {"a": np.arange(10), "b": np.arange(100)}, bins=5, xlabel="angle (deg)")
    ax = axes[0]
    assert ax.get_xlabel() == "angle (deg)" and ax.get_ylabel() == "share"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["a (n=10)", "b (n=100)"]
    for patch in ax.patches:
        assert patch.get_data().values.sum() == pytest.approx(1.0)
    plot.close(fig)


@pytest.mark.parametrize("bad", [0, -1, 2.5, True, "3"])
def test_panels_rejects_bad_counts(bad):
    with pytest.raises(ValueError, match="n must be"):
        plot.panels(bad)


def test_panel_size_is_400_px_by_default():
    plot.use_style()
    fig, _ = plot.panels(2)
    w, h = fig.get_size_inches() * fig.dpi
    assert (w, h) == (800, 400)
    plot.close(fig)


def test_legend_patches_label_category_colours():
    fig, axes = plot.panels(1)
    leg = plot.legend_patches(axes[0], {"root": (0.1, 0.6, 0.2), "child": "tab:blue"}, title="generation")
    assert [t.get_text() for t in leg.get_texts()] == ["root", "child"]
    assert leg.get_title().get_text() == "generation"
    face = leg.legend_handles[0].get_facecolor()
    assert face[:3] == pytest.approx((0.1, 0.6, 0.2))
    plot.close(fig)


@pytest.mark.parametrize("bad", [{}, None, {"a": "not-a-colour"}, {"a": (1, 2)}])
def test_legend_patches_rejects_bad_colours(bad):
    fig, axes = plot.panels(1)
    with pytest.raises((TypeError, ValueError), match="colo"):
        plot.legend_patches(axes[0], bad)
    plot.close(fig)
