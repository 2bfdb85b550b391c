"""Pictures of what a student coloured have their legend; rows of pictures share one camera (issue 20, item 3)."""

import numpy as np
import pytest

import lab
from lab import render, surfaces
from lab.view import legend as L


@pytest.fixture(scope="module")
def patches():
    return surfaces.practical().to_bezier_patches().refine(1)


@pytest.mark.parametrize("mode, name, field", [("gaussian", "linear", "K"), ("mean", "cut", "H"),
                                               ("gaussian", "classification", "K"), ("k2", "symmetric", "k2")])
def test_stored_colours_get_the_legend_of_their_measure_and_map(patches, mode, name, field):
    p = patches.copy()
    p.visualize_curvature(mode, name)
    got = render.stored_legend(p)
    values = getattr(p.corner_curvature(), field)
    want = L.legend("classification" if name == "classification" else mode, name, values.ravel(),
                    tol=lab.curvature.zero_tolerance(mode, p.size))
    assert got == want


def test_a_students_own_colours_get_the_ramp_over_the_stored_range_with_a_note(patches):
    p = patches.copy()
    K = p.corner_curvature().K
    p.curvature[...] = K
    p.colors[...] = lab.colormaps.h(np.clip(0.5 + K / (4 * np.abs(K).max()), 0, 1))  # no map of the lab's
    got = render.stored_legend(p)
    assert got.title == L.measure_title("gaussian") and got.clim == (K.min(), K.max())
    assert "your own colours" in got.note


def test_values_of_no_known_measure_are_named_as_stored(patches):
    p = patches.copy()
    p.curvature[...] = np.arange(p.curvature.size, dtype=float).reshape(p.curvature.shape)
    p.colors[...] = lab.colormaps.colors_for(p.curvature, "linear")
    assert render.stored_legend(p).title == "values stored with set_curvature"
    assert render.stored_legend(patches.copy()) is None  # no colours: no legend


def test_a_picture_of_stored_colours_has_its_colour_bar(patches):
    p = patches.copy()
    p.visualize_curvature("gaussian", "linear")
    with_bar = render.picture(p, window_size=(480, 320))
    without = render.picture(p, window_size=(480, 320), legend=False)
    right = slice(int(0.75 * 480), None)
    # the bar: the ramp's red and blue appear in the right quarter only with the legend
    assert np.any(np.all(with_bar[:, right] == [255, 0, 0], axis=-1)) or (
        np.abs(with_bar[:, right].astype(int) - without[:, right]).max() > 100)


def test_show_row_puts_the_pictures_side_by_side_with_one_camera(patches):
    p = patches.copy()
    p.visualize_curvature("gaussian", "classification")
    image = render.show_row([p, p], titles=["a", "b"], window_size=(600, 300))
    import io

    from PIL import Image

    array = np.asarray(Image.open(io.BytesIO(image.data)).convert("RGB"))
    assert array.shape == (300, 600, 3)
    left, right = array[40:, :300].astype(int), array[40:, 300:].astype(int)  # below the titles: the same view
    assert np.abs(left - right).mean() < 1.0
    with pytest.raises(ValueError, match=r"titles must give one title per object \(2\); got 1"):
        render.show_row([p, p], titles=["a"])
