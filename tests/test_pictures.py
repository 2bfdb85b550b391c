"""The lab's picture style (render.picture / show / save, the CLI, the gallery) and its legends in curvature units."""

from pathlib import Path

import numpy as np
import pytest

from lab import colormaps, surfaces
from lab.view import legend as L
from lab.view import render, style
from tests.picture_support import assert_like_reference

DATA = Path(__file__).parent / "data"


# ----------------------------------------------------------------------------- legends


def test_labels_keep_neighbours_apart_without_minus_zero():
    assert L.format_values([-0.07, -0.05, -0.03, -0.01, 0.01, 0.03]) == ["−0.07", "−0.05", "−0.03", "−0.01", "0.01",
                                                                       "0.03"]
    assert L.format_values([0.0, 10.0, 20.0, 30.0]) == ["0", "10", "20", "30"]
    assert L.format_values([-1e-17, 0.5]) == ["0", "0.5"]  # rounding noise is 0, never "-0.00"
    assert L.format_values([2.5e-5, 5e-5]) == ["2.5e−5", "5e−5"]
    ticks = L.nice_ticks(-1.199, 36.68)
    np.testing.assert_allclose(ticks, [0, 10, 20, 30])


@pytest.mark.parametrize("name", ["linear", "dill", "symmetric", "percentile", "signed-log", "cut", "viridis"])
def test_every_bar_is_labelled_in_curvature_units(name):
    rng = np.random.default_rng(7)
    K = np.concatenate([rng.normal(0, 0.3, 500), [36.7, -1.2]])
    legend = L.legend("gaussian", name, K)
    assert legend.title == "Gaussian curvature K  [1/length²]"
    positions = [p for p, _ in legend.ticks]
    assert positions == sorted(positions) and 0 <= positions[0] and positions[-1] <= 1 and len(positions) >= 2
    labels = [label for _, label in legend.ticks]
    assert len(set(labels)) == len(labels) and not any(label.startswith("−0.0") and set(label) <= set("−0.") for label in labels)
    lo, hi = legend.clim
    values = [float(label.replace("−", "-")) for label in labels]
    assert lo - 1e-9 <= min(values) and max(values) <= hi + 1e-9  # the labels are values of the range shown
    if name == "signed-log":  # nonlinear: 0 in the middle, ±max at the ends, labels where the map puts them
        assert dict(legend.ticks)[0.5] == "0" and labels[0] == "−36.7" and labels[-1] == "36.7"
        scale, top = np.median(np.abs(K)), np.abs(K).max()
        for p, v in zip(positions, values):
            assert colormaps.signed_log(np.array([v, top]), scale=scale)[0] == pytest.approx(p, abs=0.01)
    if name == "dill":
        assert labels == ["−0.07", "−0.05", "−0.03", "−0.01", "0.01", "0.03"]  # Dill's bands, not "0.00 / −0.0"
        assert len(legend.stops) == 10  # five flat bands


def test_classification_legend_and_html():
    legend = L.legend("gaussian", "classification", [1.0, -1.0], tol=1e-9)
    assert [label for label, _ in legend.classes] == ["K > 0 elliptic", "K ≈ 0 parabolic, flat", "K < 0 hyperbolic"]
    assert "1e−9" in legend.note
    html = legend.html()
    assert "elliptic" in html and "lab-legend" in html
    bar = L.legend("mean", "linear", [-2.0, 3.0]).html()
    assert bar.count("lab-colorbar-label") == 6 and "mean curvature H  [1/length]" in bar


# ----------------------------------------------------------------------------- pictures


def _parts(obj, curvature, color_map, size, title="a surface and its curvature", **options):
    image = render.picture(obj, curvature, color_map, window_size=size, title=title, **options)
    _, legend = render._as_mesh(obj, curvature, color_map, 1, 64, options.get("map_options"))
    return image, style.layout(size, title, legend), legend


def _surface_mask(image, frame):
    x, y, w, h = frame.view
    return np.any(np.abs(image[y:y + h, x:x + w].astype(int) - 255) > 12, axis=-1)


@pytest.fixture(scope="module")
def practical():
    return surfaces.practical().to_bezier_patches().refine(3)


def test_picture_has_its_colour_bar_title_and_a_fitted_surface(practical):
    size = (800, 600)
    image, frame, legend = _parts(practical, "gaussian", "linear", size)
    assert image.shape == (600, 800, 3)
    bx, by, bw, bh = (round(v) for v in style.bar_box(frame))
    column = image[by + 2:by + bh - 2, bx + bw // 2].astype(int)  # top to bottom
    expected = (255 * legend.colors(len(column))[::-1]).astype(int)
    assert np.mean(np.abs(column - expected)) < 12, "the colour bar is missing or shows other colours"
    assert np.all(image[by + bh - 4, bx + bw // 2] < [60, 60, 256]) and image[by + 4, bx + bw // 2][0] > 200  # blue … red
    tx, ty, tw, th = frame.title
    assert np.count_nonzero(np.any(image[ty:ty + th, tx:tx + tw] < 100, axis=-1)) > 100, "no title"
    surface = _surface_mask(image, frame)
    # the practical's surface seen from above at a slant fills this much of the 3D view (its outline is a
    # curved quadrilateral, so its bounding box is not full); before this style it was about 22% of the picture
    assert surface.mean() >= 0.35
    assert surface.sum() / (size[0] * size[1]) >= 0.23
    _x, _y, w, h = frame.view
    rows, cols = np.nonzero(surface)
    assert rows.min() < 0.1 * h and rows.max() > 0.9 * h  # fitted: the surface spans the view
    assert 0.3 * w < (cols.min() + cols.max()) / 2 < 0.7 * w  # centred


def test_closed_surface_fills_the_picture():
    image, frame, _ = _parts(surfaces.torus().to_bezier_patches().refine(3), "gaussian", "classification", (800, 600))
    assert _surface_mask(image, frame).sum() / (800 * 600) >= 0.33


def test_light_keeps_colours_true():
    """A surface of one colour (the cylinder is parabolic everywhere: green) keeps its colour on every flank."""
    image, frame, _ = _parts(surfaces.cylinder(), "gaussian", "classification", (640, 480))
    x, y, w, h = frame.view
    pixels = image[y:y + h, x:x + w][_surface_mask(image, frame)].astype(int)
    green = pixels[:, 1]
    assert np.percentile(green, 1) >= 0.6 * 255  # no dark flanks
    assert np.percentile(pixels[:, 0], 99) < 40 and np.percentile(pixels[:, 2], 99) < 40  # and no washed-out white


def test_camera_is_oblique_and_never_edge_on(practical):
    mesh, _ = render._as_mesh(practical, "gaussian", "linear", 1, 64)
    d = style.view_direction(mesh)
    elevation = np.degrees(np.arcsin(d[2]))
    assert 20 <= elevation <= 65
    # the surface faces the camera (a landscape), not its side (edge-on): the mean |N . d| comes close to the
    # best any view direction reaches, and above the old fixed view's
    N = np.asarray(mesh.point_data["N"])
    best = max(np.mean(np.abs(N @ style._direction(az, el))) for az in range(-180, 180, 10) for el in range(0, 91, 5))
    old = np.asarray(render.VIEW_DIRECTION, float) / np.linalg.norm(render.VIEW_DIRECTION)
    assert np.mean(np.abs(N @ d)) > max(0.9 * best, np.mean(np.abs(N @ old)) + 0.05)
    np.testing.assert_allclose(style.view_direction(mesh, -60, 35), style._direction(-60, 35))


def test_picture_matches_stored_reference(practical, tmp_path):
    """The practical's surface, K with the signed-log map, depth 3, in the lab's style, against a stored picture."""

    image = render.picture(practical, "gaussian", "signed-log", window_size=(640, 480), title="practical, K")
    assert_like_reference(image, DATA / "style_practical_gaussian_signed_log.png", tmp_path)


def test_show_returns_a_png_in_the_style(practical):
    shown = render.show(practical, "mean", "symmetric", window_size=(400, 300), edges=True)
    assert shown.data[:4] == b"\x89PNG"
    plain = render.picture(practical, window_size=(400, 300), legend=True)  # colours of unknown meaning: no bar
    assert plain.shape == (300, 400, 3)


def test_lines_are_drawn_over_the_surface_not_hidden_in_it():
    """Reflection lines lie on the surface; drawn with a depth offset they show whole (without it: ~700 of 4300 px)."""
    import lab

    hood = surfaces.hood()
    lines = lab.reflection_lines(hood, direction=(1, 0, 0), count=12, resolution=96)
    mesh, _ = render._as_mesh(hood, None, None, 1, 64)
    dark = lambda im: int(np.sum(np.all(im < 80, axis=-1)))
    assert dark(render.render_view(mesh, (400, 300), direction=render.VIEW_DIRECTION)) < 20
    assert dark(render.render_view(mesh, (400, 300), lines=lines, direction=render.VIEW_DIRECTION)) > 3000
    # beside a control net the lines are still drawn (the net's own lines must not take their place)
    net = render._net_lines(hood)
    net_only = dark(render.render_view(mesh, (400, 300), net=net, direction=render.VIEW_DIRECTION))
    both = dark(render.render_view(mesh, (400, 300), net=net, lines=lines, direction=render.VIEW_DIRECTION))
    assert both > net_only + 2000
    with pytest.raises(TypeError, match="lines must be a pyvista.PolyData of polylines.*got list"):
        render.picture(hood, lines=[lines])
