"""Every explorer's "save picture": a PNG of the current view at the requested size, with its colour bar or legend and
a caption naming surface, measure, map and range in the lab's language (lab.view.explorers.saving).

One explorer of each kind for the module; the curvature explorer's picture against a stored reference
(tests/picture_support.py's tolerance)."""

from pathlib import Path

import numpy as np
import pytest
from lab.widgets import CurvatureExplorer, FocalExplorer, GeodesicExplorer, ReflectionExplorer

from lab import surfaces
from lab.i18n import using
from lab.view.explorers.saving import caption
from tests.picture_support import assert_like_reference

REFERENCE = Path(__file__).parent / "data" / "explorer_saved_hood_de.png"


@pytest.fixture(scope="module")
def explorers():
    made = {"curvature": CurvatureExplorer(surfaces.hood(), live=False, depth=2),
            "focal": FocalExplorer(surfaces.sphere(2.0), scale=0.5, live=False),
            "geodesic": GeodesicExplorer(surfaces.plane(4.0), start=(0.5, 0.5), n_angles=6, step=0.5, n_curves=2,
                                         live=False),
            "reflection": ReflectionExplorer(surfaces.hood(), resolution=32, live=False)}
    yield made
    for e in made.values():
        e.close()


def read(path):
    import imageio.v3 as iio
    return iio.imread(path)[..., :3]


@pytest.mark.parametrize("kind", ["curvature", "focal", "geodesic", "reflection"])
def test_every_explorer_saves_a_picture_of_the_requested_width(explorers, kind, tmp_path):
    e = explorers[kind]
    path, size = e.save_picture(tmp_path / f"{kind}.png", width=640)
    w, h = e.window_size
    image = read(path)
    assert size == (640, round(640 * h / w)) == (image.shape[1], image.shape[0])
    assert np.any(image[: size[1] // 12] < 128)  # the caption: dark text in the top band
    box = e.widget.children[1].children[-1]  # the control row: width, file name, button
    width, name, button = box.children
    assert width.value == 2400 and button.description == "save picture"
    width.value, name.value = 500, str(tmp_path / "clicked.png")
    button.click()
    assert read(tmp_path / "clicked.png").shape[1] == 500 and "500" in e.status.value


def test_the_saved_picture_has_its_colour_bar_and_a_german_caption(explorers, tmp_path):
    e = explorers["curvature"]
    e.show_edges.value = True
    e.toggle_overlays()
    with using("de"):
        text = caption(e)
        path, size = e.save_picture(tmp_path / "hood.png", width=960)
    assert text.startswith("Motorhaube: K, ") and "Bereich -2,511 … 1,844" in text, text
    assert text.endswith("Kanten nach Stetigkeit: G3: 0, G2: 35, G1: 5, G0: 0, offen: 0"), text  # the overlay's legend
    assert size == (960, 600)
    image = read(path)
    bar = image[:, int(0.78 * 960):, :].astype(int)  # the colour bar beside the view: saturated colours
    assert np.count_nonzero(bar.max(axis=-1) - bar.min(axis=-1) > 150) > 500
    assert_like_reference(image, REFERENCE, tmp_path)


def test_bad_requests_are_refused(explorers, tmp_path):
    e = explorers["focal"]
    with pytest.raises(ValueError, match="width"):
        e.save_picture(tmp_path / "x.png", width=50)
    with pytest.raises(ValueError, match=".png"):
        e.save_picture(tmp_path / "x.jpg")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        e.save_picture(tmp_path / "no" / "x.png")
    with pytest.raises(TypeError, match="file name"):
        e.save_picture(None)


def test_captions_name_what_each_explorer_shows(explorers):
    """The caption names the surface and the explorer's settings; a colour bar's range is added, a swatch legend is
    drawn beside the picture instead (geodesics, stripes), light lines need none."""
    assert caption(explorers["geodesic"]) == "plane: geodesic explorer"
    assert caption(explorers["reflection"]) == "car hood: stripe box mapping, 8, light 0° / 60°"
    assert "; range " in caption(explorers["focal"])


def test_pictures_without_a_colour_bar_draw_their_swatches(explorers, tmp_path):
    """The geodesics' two kinds of line and the stripe box's six walls as swatches in the saved picture's legend
    column (right of the view), in the very colours the view draws them with; in German too."""
    from lab.interrogation.reflection import DEFAULT_COLORS
    from lab.view.figures import CLOSED_COLOR, PATH_COLOR

    def legend_colours(image, colours):
        column = image[:, int(0.71 * image.shape[1]):].reshape(-1, 3).astype(int)  # right of the view
        return [int(np.count_nonzero(np.all(np.abs(column - c) <= 1, axis=1))) for c in colours]

    hexes = [[int(c[k:k + 2], 16) for k in (1, 3, 5)] for c in (PATH_COLOR, CLOSED_COLOR)]
    walls = [[round(255 * x) for x in rgb] for rgb in DEFAULT_COLORS]
    for lang in ("en", "de"):
        with using(lang):
            geodesic = read(explorers["geodesic"].save_picture(tmp_path / f"fan_{lang}.png", width=960)[0])
            stripes = read(explorers["reflection"].save_picture(tmp_path / f"box_{lang}.png", width=960)[0])
        assert min(legend_colours(geodesic, hexes)) >= 100, legend_colours(geodesic, hexes)  # a 12 x 12 px swatch each
        assert min(legend_colours(stripes, walls)) >= 100, legend_colours(stripes, walls)
    legend = explorers["geodesic"].picture_legend()
    assert [label for label, _c in legend.classes] == ["6 geodesics", "polar isodistance curves"]
    assert legend.note == "at $s_L$, $2 s_L$, … ($s_L$ = 0.5)"
    with using("de"):
        assert explorers["geodesic"].picture_legend().note == "bei $s_L$, $2 s_L$, … ($s_L$ = 0,5)"
    explorers["reflection"].kind.value = "lines"
    try:
        assert explorers["reflection"].picture_legend() is None  # light lines: no colours to explain
    finally:
        explorers["reflection"].kind.value = "stripes"
