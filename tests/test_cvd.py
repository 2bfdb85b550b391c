"""Colour-vision deficiency (lab.vision): the simulation against published values, the ΔE goals of every colour map,
the measured table in the docs, pictures and the command line as a colour-blind student sees them."""

import importlib.util
import re
from pathlib import Path

import numpy as np
import pytest

from lab import colormaps as cm
from lab import vision

ROOT = Path(__file__).resolve().parent.parent

#: Machado, Oliveira & Fernandes (2009), the matrices for severity 1.0 (their supplementary table), on linear RGB.
MACHADO = {
    "protanopia": [[0.152286, 1.052583, -0.204868], [0.114503, 0.786281, 0.099216], [-0.003882, -0.048116, 1.051998]],
    "deuteranopia": [[0.367322, 0.860646, -0.227968], [0.280085, 0.672501, 0.047413], [-0.011820, 0.042940, 0.968881]],
    "tritanopia": [[1.255528, -0.076749, -0.178779], [-0.078411, 0.930809, 0.147602], [0.004733, 0.691367, 0.303900]],
}


def _linear(srgb):
    """sRGB (IEC 61966-2-1) to linear RGB."""
    c = np.asarray(srgb, dtype=float)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


@pytest.mark.parametrize("deficiency", list(MACHADO))
def test_simulation_is_machados_matrix_on_linear_rgb(deficiency):
    """Colours whose image stays inside the gamut: the simulation is the published matrix applied to linear RGB."""
    rgb = np.array([[0.5, 0.5, 0.5], [0.4, 0.6, 0.5], [0.7, 0.45, 0.3], [0.35, 0.4, 0.6]])
    want = _linear(rgb) @ np.array(MACHADO[deficiency]).T
    assert np.all((want > 0) & (want < 1))
    np.testing.assert_allclose(_linear(vision.simulate(rgb, deficiency)), want, atol=1e-6)


def test_simulation_and_delta_e_against_colorspacious_reference_values():
    """colorspacious's own test vectors (gold_values.py): deuteranomaly 50 and protanomaly 95, and a ΔE."""
    np.testing.assert_allclose(vision.simulate([0.9, 0.5, 0.3], "deuteranopia", severity=50),
                               [0.76726301, 0.59528358, 0.29263454], atol=1e-7)
    np.testing.assert_allclose(vision.simulate([[0.1, 0.2, 0.3]], "protanopia", severity=95),
                               [[0.15588987, 0.2038791, 0.30416046]], atol=1e-7)
    assert vision.delta_e(np.array([173, 52, 52]) / 255, np.array([69, 120, 51]) / 255) == pytest.approx(44.698469808, abs=1e-6)
    np.testing.assert_array_equal(vision.simulate(np.eye(3), None), np.eye(3))  # normal vision: unchanged


def test_f3_red_and_green_merge_under_deuteranopia_the_new_classes_do_not():
    red, green, _blue = cm.colors_for([1.0, 0.0, -1.0], "classification")
    seen = vision.simulate(np.array([red, green]), "deuteranopia")
    assert vision.delta_e(red, green) > 70  # 76 apart for normal vision
    assert vision.delta_e(seen[0], seen[1]) < 30  # 25: both read as yellow
    new = cm.colors_for([1.0, 0.0, -1.0], "classification-vik")
    for deficiency in vision.VISIONS:
        assert vision.smallest_difference(vision.simulate(new, deficiency))[0] >= 40, deficiency


def test_every_map_measured_and_the_goals_met():
    found = {name: vision.measure(name) for name in cm.COLOR_MAPS}
    assert found["classification-vik"].worst == pytest.approx(48.3, abs=0.1)  # navy, near-white, burnt orange
    assert found["classification"].smallest["deuteranopia"] == pytest.approx(24.9, abs=0.1)
    assert found["linear"].smallest["protanopia"] == pytest.approx(4.1, abs=0.1)  # h: green and yellow
    for name in ("linear-batlow", "symmetric-vik", "signed-log-vik", "dill-batlow"):
        assert found[name].worst >= 10 and found[name].ordered, name
    assert found["symmetric-vik"].kind == "diverging" and found["symmetric-vik"].worst >= 34
    for name in ("linear", "cut", "dill", "symmetric", "percentile", "signed-log"):  # the rainbow fails
        assert found[name].worst < 10 and not found[name].ordered, name


def _benchmark():
    spec = importlib.util.spec_from_file_location("colors_benchmark", ROOT / "benchmarks" / "colors.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_docs_show_the_measured_table():
    table = _benchmark().table()
    page = (ROOT / "docs" / "students" / "colour.md").read_text()
    assert table in page, "docs/students/colour.md does not hold the output of benchmarks/colors.py"
    assert re.search(r"\| `classification-vik` \| classes \| 57\.0 \| 48\.3 \| 52\.5 \| 55\.4 \| yes \| yes \|", table)


def test_bad_input_is_refused_with_what_was_expected():
    with pytest.raises(ValueError, match="deficiency must be one of protanopia, deuteranopia, tritanopia"):
        vision.simulate([0.5, 0.5, 0.5], "colourblind")
    with pytest.raises(TypeError, match=r"rgb must be an array of sRGB colours \(\.\.\., 3\) in \[0, 1\]; got str"):
        vision.simulate("red", "protanopia")
    with pytest.raises(ValueError, match=r"divide 8-bit colours by 255\); got values in \[0, 255\]"):
        vision.simulate([255, 0, 0], "protanopia")
    with pytest.raises(ValueError, match="3 channels"):
        vision.delta_e([0.5, 0.5], [0.5, 0.5])
    with pytest.raises(ValueError, match="severity must be a number from 0 to 100; got 120"):
        vision.simulate([0.5, 0.5, 0.5], "tritanopia", severity=120)
    with pytest.raises(ValueError, match="unknown colour map 'jet'"):
        vision.measure("jet")
    with pytest.raises(TypeError, match="8-bit RGB or RGBA picture"):
        vision.simulate_image(np.zeros((4, 4, 3)), "protanopia")


def test_an_image_is_simulated_pixel_by_pixel_and_keeps_its_alpha():
    image = np.zeros((2, 3, 4), dtype=np.uint8)
    image[..., 0], image[..., 3] = 200, 77
    seen = vision.simulate_image(image, "deuteranopia")
    want = np.rint(vision.simulate(np.array([200, 0, 0]) / 255, "deuteranopia") * 255)
    assert seen.dtype == np.uint8 and np.all(seen[..., 3] == 77)
    np.testing.assert_array_equal(seen[..., :3], np.broadcast_to(want, (2, 3, 3)))


def test_the_visions_are_named_in_the_labs_language():
    import lab.i18n

    assert [vision.name(v) for v in vision.VISIONS] == ["normal", "protanopia", "deuteranopia", "tritanopia"]
    with lab.i18n.using("de"):  # notebook 04's table of smallest steps
        assert [vision.name(v) for v in vision.VISIONS] == ["normal", "Protanopie", "Deuteranopie", "Tritanopie"]
    with pytest.raises(ValueError, match="vision must be None or one of protanopia, deuteranopia, tritanopia; got 'x'"):
        vision.name("x")


def test_a_picture_as_a_deuteranope_sees_it(tmp_path):
    """render.picture(simulate=…) is the normal picture simulated, with a note in its legend saying so; the
    command line's --simulate writes it."""
    import imageio.v3 as iio

    from lab import cli, render, surfaces

    patches = surfaces.practical().to_bezier_patches().refine(1)
    normal = render.picture(patches, "gaussian", "classification", window_size=(480, 320))
    seen = render.picture(patches, "gaussian", "classification", window_size=(480, 320), simulate="deuteranopia")
    legend = (slice(None), slice(280, None))  # the legend's note differs: compare the 3D view
    np.testing.assert_array_equal(seen[:, :280], vision.simulate_image(normal, "deuteranopia")[:, :280])
    assert not np.array_equal(seen[legend], vision.simulate_image(normal, "deuteranopia")[legend])
    out = tmp_path / "deut.png"
    assert cli.main(["render", "--surface", "practical", "--color-map", "classification", "--depth", "1",
                     "--simulate", "deuteranopia", "--window-size", "480x320", "--quiet", "-o", str(out)]) == 0
    image = iio.imread(out)
    red = np.all(image == [255, 0, 0], axis=-1).sum() + np.all(np.abs(image.astype(int) - [220, 30, 30]) < 40,
                                                                 axis=-1).sum()
    assert red == 0  # nothing red is left: a deuteranope sees no red


def test_crameris_tables_are_cmcrameris_and_the_maps_use_them():
    """The tables read from cmcrameri's data files are its colour maps (as matplotlib sees them)."""
    from cmcrameri import cm as crameri

    from lab.geometry import palettes

    for name in ("batlow", "vik"):
        np.testing.assert_allclose(palettes.table(name), getattr(crameri, name)(np.arange(256))[:, :3], atol=1e-6)
    np.testing.assert_allclose(cm.colors_for([-2.0, 0.0, 3.0], "classification-vik"), palettes.classes()[[0, 1, 2]])
    np.testing.assert_allclose(cm.apply("dill-batlow", [-0.06, 0.0, 0.02]), palettes.bands()[[0, 3, 4]])
    assert cm.normalisation("signed-log-vik") == "signed-log" and cm.normalisation(cm.ColorMap.CUT) == "cut"
    with pytest.raises(ValueError, match="unknown palette 'jet'; expected one of batlow, vik"):
        palettes.table("jet")


def test_band_lines_are_the_parabolic_lines_at_zero_and_dills_edges():
    from lab import parabolic_lines, surfaces
    from lab.interrogation.bands import band_lines

    torus = surfaces.torus()
    zero = band_lines(torus, "gaussian", [0.0], tol=1e-9 / 36)
    np.testing.assert_allclose(zero.points, parabolic_lines(torus).points)  # the same marching triangles
    edges = band_lines(torus, "K", [-0.6, -0.2])
    assert sorted(set(edges.cell_data["level"])) == [0, 1] and set(edges.cell_data["value"]) == {-0.6, -0.2}
    with pytest.raises(ValueError, match="values must name point data of the mesh or a measure"):
        band_lines(torus, "nonsense", [0.0])


def test_an_explorer_shows_its_scene_and_legend_as_a_deuteranope_sees_them():
    from lab.widgets import CurvatureExplorer

    from lab import surfaces
    from lab.view.explorers.vision import simulate_css

    e = CurvatureExplorer(surfaces.practical(), live=False, depth=1)
    e.color_map.value = "classification"
    table = np.asarray(e.lut.values)[:, :3].copy()
    legend = e.legend_view.value
    e.vision.value = "deuteranopia"
    want = np.rint(vision.simulate(table / 255, "deuteranopia") * 255)
    np.testing.assert_array_equal(np.asarray(e.lut.values)[:, :3], want)  # the live view's colours
    assert e.legend_view.value == simulate_css(legend, "deuteranopia") != legend
    e.show_bands.value = True  # the parabolic lines, drawn on the surface
    assert e.bands_actor.GetVisibility() and e.bands_mesh.n_points > 0
    e.color_map.value = "linear"  # a new table is simulated too
    assert e.vision.value == "deuteranopia" and not np.array_equal(np.asarray(e.lut.values)[0, :3], [0, 0, 255])
    e.vision.value = "normal"
    np.testing.assert_array_equal(np.asarray(e.lut.values)[0, :3], [0, 0, 255])  # h(0) again
    assert "simulated" not in simulate_css("<b style='color:#ff0000'>x</b>", None)
    e.close()
