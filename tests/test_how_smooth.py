"""Notebooks 11 and 12 as a student reads them (issue 36): pictures that show what the text says, readable printouts.

lab.interrogation.knot_lines: the close-up of a knot line in notebook 12 shows what its text says.

The sheet of notebook 12 with the knot v = 2 of multiplicity 1, 2, 3 and the column next to it lifted by 0.05
(G2, G1, G0 by lab.continuity).  Reflection lines (light lines along (1, 1, 0), eye (0.2, -0.3, 1)) on the two
one-sided pieces: across G2 they turn by less than KINK_G2 degrees where they meet the knot line (the limit is
0: the normal is C1 across), across G1 by more than KINK_G1 degrees, and across G0 no light line continues:
its nearest end on the other side lies more than GAP_G0 away (the sheet is 3 wide)."""

import os
from pathlib import Path

import numpy as np
import pytest

import lab
from lab import render, surfaces
from lab.i18n import set_language
from lab.interrogation.knot_lines import knot_line_mesh, line_crossings

KINK_G2, KINK_G1, GAP_G0 = 1.0, 45.0, 0.5
EYE = (0.2, -0.3, 1.0)


def sheet(r, lift=0.05):
    x = np.arange(7.0)
    X, Y = np.meshgrid(x, x, indexing="ij")
    s = lab.BSplineSurface(np.stack([X, Y, 0.3 * np.sin(X / 2) + 0.2 * np.cos(Y / 3)], axis=-1),
                           [0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4], [0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4], 3, 3)
    t = s.insert_knot(2.0, "v", r - 1) if r > 1 else s
    greville = np.array([t.knots_v[j + 1 : j + 4].mean() for j in range(t.control_points.shape[1])])
    P = t.control_points.copy()
    P[:, int(np.argmin(np.abs(greville - 2.0))), 2] += lift
    return lab.BSplineSurface(P, t.knots_u, t.knots_v, 3, 3)


@pytest.fixture(scope="module")
def measured():
    out = {}
    for r in (1, 2, 3):
        s = sheet(r)
        m = knot_line_mesh(s, "v", 2.0, 0.5, along=(0.5, 3.5))
        lines = lab.reflection_lines(m, direction=(1, 1, 0), count=15, view=EYE)
        out[r] = s, m, line_crossings(lines, m)
    return out


def test_the_three_sheets_are_g2_g1_g0(measured):
    assert [lab.continuity(measured[r][0]).achieved for r in (1, 2, 3)] == ["G2", "G1", "G0"]


def test_each_side_keeps_its_one_sided_normal(measured):
    """The two rows on the knot line: same points, normals apart by continuity's g1 (17.0° at G0, 0 else)."""
    for r in (1, 2, 3):
        s, m, _ = measured[r]
        uv, face = np.asarray(m.point_data["uv"]), np.asarray(m.point_data["face"])
        rows = [np.flatnonzero((np.abs(uv[:, 1] - 2.0) < 1e-6) & (face == k)) for k in (0, 1)]
        a, b = (rows[k][np.argsort(uv[rows[k], 0])] for k in (0, 1))
        np.testing.assert_allclose(m.points[a], m.points[b], atol=1e-7)
        N = np.asarray(m.point_data["N"])
        angle = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", N[a], N[b]), -1, 1)))
        g1 = next(e.g1 for e in lab.continuity(s).edges if e.direction == "v" and e.value == 2.0)
        assert abs(angle.max() - g1) < 0.05, (r, angle.max(), g1)  # the grid samples the edge; g1 its maximum


def test_reflection_lines_run_on_across_g2(measured):
    gap, angle, _ = measured[1][2]
    assert len(gap) >= 4
    assert np.all(gap < 1e-6) and np.all(angle < KINK_G2), (gap, angle)


def test_reflection_lines_kink_across_g1(measured):
    gap, angle, _ = measured[2][2]
    assert len(gap) >= 4
    assert np.all(gap < 1e-6) and np.all(angle > KINK_G1), (gap, angle)


def test_reflection_lines_break_across_g0(measured):
    gap, _, _ = measured[3][2]
    assert np.all(gap > GAP_G0), gap


def test_bad_input_is_named():
    s = sheet(1)
    with pytest.raises(ValueError, match="direction"):
        knot_line_mesh(s, "w", 2.0, 0.5)
    with pytest.raises(ValueError, match="value must lie inside"):
        knot_line_mesh(s, "v", 4.0, 0.5)
    with pytest.raises(ValueError, match="knot_line_mesh"):
        line_crossings(lab.reflection_lines(lab.mesh.surface_mesh(s, 20, 20)), lab.mesh.surface_mesh(s, 20, 20))


# -- umbilics marked where lines of curvature end; printouts for people -------------------------------------------


def test_marks_are_drawn_where_the_points_are():
    """A white dot in a black ring at each mark: the picture with marks differs from the one without only near
    the projected mark (the plane z = 0 seen from above, a mark at its centre)."""
    X, Y = np.meshgrid(np.linspace(-1, 1, 4), np.linspace(-1, 1, 4), indexing="ij")
    plane = lab.BSplineSurface(np.stack([X, Y, np.zeros((4, 4))], axis=-1), [0] * 4 + [1] * 4, [0] * 4 + [1] * 4, 3, 3)
    options = {"window_size": (200, 200), "legend": False, "direction": (0, 0, 1)}
    bare = render.picture(plane, **options).astype(int)
    marked = render.picture(plane, marks=[[0.0, 0.0, 0.0]], **options).astype(int)
    changed = np.argwhere(np.any(np.abs(marked - bare) > 40, axis=-1))
    assert len(changed) > 20
    centre = changed.mean(axis=0)
    assert np.all(np.abs(changed - centre).max(axis=0) < 12), "the mark is one dot of at most 15 pixels"
    assert np.all(marked[tuple(np.round(centre).astype(int))] > 230), "white in the middle"
    assert marked[changed[:, 0], changed[:, 1]].min() < 40, "a black ring"
    with pytest.raises(ValueError, match="marks must be finite points"):
        render.picture(plane, marks=[[0.0, 0.0]], **options)


@pytest.fixture
def german():
    set_language("de")
    yield
    set_language("en")


def test_an_umbilic_prints_as_a_line_for_people(german):
    """The ellipsoid (3, 2, 1): lemons at (±2.371708, 0, ±0.612372) (closed form), no -0 or e-16 in y."""
    found = lab.umbilics(surfaces.ellipsoid(3, 2, 1))
    text = str(found[0])
    assert text.startswith("Nabelpunkt (Zitrone, Index +0,5) bei (2,37171; 0; 0,612372)"), text
    assert "e-" not in text and "-0;" not in text and "Umbilic(" not in text
    set_language("en")
    assert str(found[0]).startswith("umbilic (lemon, index +0.5) at (2.37171, 0, 0.612372)")


def test_principal_directions_print_in_two_lines(german):
    c = surfaces.ellipsoid(3, 2, 1).curvature(0.3, 0.3, directions=True)
    first, second = str(c).split("\n")
    assert first.startswith(f"K = {float(c.K):.6g}".replace(".", ",")) and "κ1 = " in first
    assert second.startswith("d1 = (") and ";" in second and "." not in second
    assert "CurvatureDirections(" in repr(c)  # the repr stays the record


def test_continuity_writes_open_edges_in_german(german):
    """Issue 36: "none: 0" in the German table; the level "none" is written "offen"."""
    report = lab.continuity(sheet(1))
    assert "offen: 0" in report.table() and "none" not in report.table()
    assert report.summary() in report.table()


def test_a_model_prints_its_file_name_not_the_machines_path():
    model = lab.models.teapot()
    assert os.path.basename(model.path) in repr(model)
    assert os.path.dirname(model.path) not in repr(model)
    assert str(model) == "teapot.bbp: 32 faces (Bézier surface × 32); 0 shared edges"
    set_language("de")
    try:
        assert str(model) == "teapot.bbp: 32 Flächenstücke (Bézier-Fläche × 32); 0 gemeinsame Kanten"
    finally:
        set_language("en")


def test_the_face_menu_speaks_german(german):
    from lab.view.explorers.models import face_label

    labels = [face_label(f) for f in lab.models.linkrods().faces]
    assert "1: Zylinder" in labels
    assert any(label.endswith(("Ebene, umgekehrt orientiert", "Zylinder, umgekehrt orientiert")) for label in labels)
    assert not any(kind in label for label in labels for kind in ("Cylinder", "Plane", "BSplineSurface"))  # "Torus" is German too


def test_hint_boxes_wrap_at_word_boundaries():
    """JupyterLab sets ``word-break: break-all`` on an output's <pre> ("tw|isted"): the report's box overrides it."""
    from lab import check

    def principal_directions(bu, bv, buu, buv, bvv):
        return np.zeros((2, 3))

    box = check.principal_directions(principal_directions)._repr_html_()
    assert "word-break:normal" in box and "overflow-wrap:break-word" in box and "white-space:pre-wrap" in box


# -- the explorers on a model: controls where they apply, a legend for the stripes ----------------------------------


def test_reflection_explorer_shows_only_the_controls_its_kind_uses(german):
    from lab.view.explorers.interrogation import ReflectionExplorer

    r = ReflectionExplorer(surfaces.hood(), resolution=16, live=False)
    shown = {"stripes": {"orientation", "stripe_legend"}, "lines": {"spacing", "azimuth", "elevation"},
             "isophotes": {"azimuth", "elevation"}}
    for kind, expected in shown.items():
        r.kind.value = kind
        visible = {n for n in ("orientation", "stripe_legend", "spacing", "azimuth", "elevation")
                   if getattr(r, n).layout.display != "none"}
        assert visible == expected, kind
    legend = r.stripe_legend.value
    for wall in ("Wand −x", "Wand +y", "Boden (−z)", "Decke (+z)"):  # one swatch per colour the box draws
        assert wall in legend
    assert legend.count("background:#") == 6


def test_pull_and_r_appear_only_with_their_map():
    from lab.view.explorers import CurvatureExplorer

    ex = CurvatureExplorer(surfaces.hood(), live=False, depth=1)
    t = ex.tools
    for value, pull, radius in (("curvature", "none", "none"), ("draft", None, "none"), ("radius", "none", None)):
        t.map.value = value
        assert (t.pull.layout.display, t.radius.layout.display) == (pull, radius), value


def test_combs_on_a_face_are_scaled_to_it_and_the_probe_is_marked():
    """Linkrods' fillet 13: 16 teeth per border, the longest a quarter of the face's size (was a black tangle at
    the default 0.05 per unit of curvature); with the probe on, a red dot of 16 pixels at the point."""
    from lab.interrogation import combs
    from lab.view.explorers import CurvatureExplorer

    ex = CurvatureExplorer(lab.models.linkrods(), live=False)
    t = ex.tools
    t.face.value = 13
    t.choose_face()
    assert t.comb_density.value == 16
    found = combs.border_combs(t.surface, density=16, scale=t.comb_scale.value)
    points = np.concatenate([c.points for c in found])
    teeth = np.concatenate([np.linalg.norm(c.tips - c.points, axis=1) for c in found])
    size = np.linalg.norm(np.ptp(points, axis=0))
    assert np.nanmax(teeth) == pytest.approx(0.25 * size, rel=1e-9)
    t.probe.value = True
    t.update_lines()
    assert t.mark_actor is not None and t.mark_actor.GetProperty().GetPointSize() == 16
    np.testing.assert_allclose(t.mark_actor.mapper.dataset.points[0], t.last_probe.point)
    t.probe.value = False
    t.update_lines()
    assert t.mark_actor is None
    ex.close()


def test_generated_and_marking_notebooks_carry_the_kernels_metadata(tmp_path):
    """What JupyterLab writes on opening (ipykernel's spec and language_info): the notebooks open unmodified
    (tests/test_browser.py opens one)."""
    import json
    import sys

    from lab.teaching.course.exercises import KERNELSPEC
    from lab.teaching.course.mark import _notebook

    version = sys.version.split()[0]
    marking = _notebook(tmp_path, "04_color_maps", "en")
    assert marking.metadata["kernelspec"] == KERNELSPEC and marking.metadata["language_info"]["version"] == version
    generated = json.loads((Path(__file__).parent.parent / "solutions" / "de" / "12_how_smooth.ipynb").read_text())
    assert generated["metadata"]["kernelspec"] == KERNELSPEC
    assert generated["metadata"]["language_info"]["file_extension"] == ".py"  # the kernel's whole record
