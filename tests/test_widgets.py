"""The explorers without a browser: in-place updates, readouts, no work without an action, latest-wins
requests, main-thread renders, lifecycle, messages, static fallback."""

import asyncio
import re
import threading

import ipywidgets as W
import numpy as np
import pytest
from lab.widgets import CurvatureExplorer, FocalExplorer, GeodesicExplorer, ReflectionExplorer

import lab
from lab import surfaces
from lab.view.explorers import base
from tests.picture_support import assert_like_reference


def sig4(x):
    """A number as the readouts show it (4 significant digits)."""
    return float(f"{x:.4g}")


@pytest.fixture(scope="module")
def explorer():
    return CurvatureExplorer(surfaces.practical(), live=False, depth=2)


def test_recolour_changes_colours_only(explorer):
    e = explorer
    actor, mesh, lut = e.actor, e.mesh, e.lut
    e.color_map.value = "linear"
    K = np.asarray(mesh.point_data["K"])
    np.testing.assert_allclose(e.lut.scalar_range, (K.min(), K.max()))
    np.testing.assert_allclose(mesh.point_data["display"], K, rtol=1e-6)  # single precision for the browser
    e.color_map.value = "symmetric"
    m = np.abs(K).max()
    np.testing.assert_allclose(e.lut.scalar_range, (-m, m))
    e.measure.value = "mean"
    np.testing.assert_allclose(mesh.point_data["display"], mesh.point_data["H"], rtol=1e-6)
    e.color_map.value = "classification"
    assert set(np.unique(mesh.point_data["display"])) <= {0.0, 0.5, 1.0}
    assert e.actor is actor and e.mesh is mesh and e.lut is lut  # nothing rebuilt
    assert e.status.value == ""
    e.measure.value = "gaussian"
    e.color_map.value = "linear"


def test_readouts_show_the_range_used_and_manual_starts_there(explorer):
    e = explorer
    e.color_map.value = "linear"
    K = np.asarray(e.mesh.point_data["K"])
    for mode, expected in (("auto", (K.min(), K.max())), ("symmetric", (-np.abs(K).max(), np.abs(K).max()))):
        e.range_mode.value = mode
        np.testing.assert_allclose(e.actor.mapper.scalar_range, expected)
        assert (float(e.range_min.value), float(e.range_max.value)) == tuple(sig4(x) for x in expected)
        assert e.range_min.disabled and e.range_max.disabled
    e.range_mode.value = "manual"  # starts at the range used just before (± max), not min = max
    np.testing.assert_allclose(e.actor.mapper.scalar_range, (-np.abs(K).max(), np.abs(K).max()))
    assert not e.range_min.disabled
    e.range_max.value = "10"
    np.testing.assert_allclose(e.actor.mapper.scalar_range, (-np.abs(K).max(), 10.0))
    assert e.range_max.value == "10" and float(e.range_min.value) == sig4(-np.abs(K).max())
    e.range_min.value = "-0.5"
    np.testing.assert_allclose(e.lut.scalar_range, (-0.5, 10.0))
    e.range_min.value = "abc"
    assert "min and max must be numbers" in e.status.value
    np.testing.assert_allclose(e.lut.scalar_range, (-0.5, 10.0))
    assert e.range_min.value == "-0.5"  # the readout shows the range used again
    e.range_min.value = "20"
    assert "max must be larger than min" in e.status.value
    e.range_mode.value = "auto"
    assert e.range_min.disabled
    np.testing.assert_allclose(e.lut.scalar_range, (K.min(), K.max()))


@pytest.mark.parametrize("name", ["cut", "percentile", "signed-log", "symmetric", "classification"])
def test_maps_with_their_own_range_disable_the_range_control(explorer, name):
    e = explorer
    e.color_map.value = name
    assert e.range_mode.disabled and e.range_min.disabled
    legend = e.legend()
    if name == "classification":
        assert e.range_min.value == "" and [c[0].split()[0] for c in legend.classes] == ["K", "K", "K"]
    else:
        assert (float(e.range_min.value), float(e.range_max.value)) == tuple(sig4(x) for x in legend.clim)
    e.color_map.value = "linear"
    assert not e.range_mode.disabled


def test_no_work_without_an_action(explorer):
    """Values the explorer writes into its own controls (readouts, buttons) never call back: no feedback loop."""
    e = explorer
    e.color_map.value = "linear"
    before = dict(e.counts)
    e._show_readouts()
    e._show_readouts()
    e.refresh()
    assert dict(e.counts) == before
    # a readout that changes while the range is automatic (as a browser echo would) is ignored
    e.range_min.value = "-123"
    assert e.counts["recolor"] == before.get("recolor", 0)


def test_depth_updates_the_mesh_in_place():
    e = CurvatureExplorer(surfaces.practical(), live=False, depth=1)
    mesh = e.mesh
    assert mesh.n_points == 15**2
    e.depth.value = 3
    assert e.mesh is mesh and mesh.n_points == 57**2
    assert mesh.points.dtype == np.float32 and mesh.point_data["Normals"].dtype == np.float32
    K = surfaces.practical().curvature(np.linspace(0, 7, 57)[:, None], np.linspace(0, 7, 57)[None, :]).K
    np.testing.assert_allclose(np.sort(mesh.point_data["K"]), np.sort(K.ravel()), rtol=1e-9, atol=1e-12)
    assert e.progress.layout.visibility == "hidden"  # shown only while a computation runs


def test_a_newer_request_cancels_an_older_one():
    """On the kernel's event loop, depth changes that arrive together run once, with the last value."""
    e = CurvatureExplorer(surfaces.practical(), live=False, depth=1)
    seen = []

    async def scenario():
        e._loop = asyncio.get_running_loop()
        for depth in (2, 3, 4):  # three changes before the loop runs anything: only the last survives
            e.depth.value = depth
        while not all(t.done() for t in e._tasks.values()):
            seen.append(e.progress.layout.visibility)
            await asyncio.sleep(0)

    asyncio.run(scenario())
    assert e.counts["set_depth"] == 1 and e.mesh.n_points == (7 * 16 + 1) ** 2
    assert "visible" in seen and e.progress.layout.visibility == "hidden"

    async def interrupted():  # a change arriving while a computation runs cancels it at its next step
        e._loop = asyncio.get_running_loop()
        e.depth.value = 5
        for _ in range(3):
            await asyncio.sleep(0)
        e.depth.value = 2
        while not all(t.done() for t in e._tasks.values()):
            await asyncio.sleep(0)

    asyncio.run(interrupted())
    assert e.mesh.n_points == (7 * 4 + 1) ** 2 and 5 not in e._meshes
    assert e.status.value == ""


def test_callbacks_from_other_threads_render_on_the_main_thread():
    e = CurvatureExplorer(surfaces.saddle(), live=False, depth=1)
    ran_on = []
    scheduled = []

    class Loop:
        def call_soon_threadsafe(self, func, *args):
            scheduled.append((func, args))

    e._loop = Loop()

    def action():
        ran_on.append(threading.current_thread().name)

    observer = e._callback(action)
    t = threading.Thread(target=observer, name="comm-subshell")
    t.start()
    t.join()
    assert ran_on == [] and len(scheduled) == 1  # nothing ran on the subshell thread
    func, args = scheduled[0]
    func(*args)  # what the kernel's event loop does on the main thread
    assert ran_on == ["MainThread"]
    assert e.callback_threads == ["comm-subshell"]


def test_close_releases_everything():
    e = CurvatureExplorer(surfaces.saddle(), live=False, depth=1)
    widget = e.widget
    controls = [e.measure, e.color_map, e.depth, e.range_min, widget]
    assert all(w.comm is not None for w in controls)
    e.close()
    assert all(w.comm is None for w in controls)  # closed in the frontend too
    assert e.measure.layout.comm is None and e.depth.style.comm is None  # with their layout and style widgets
    assert e.closed and e not in base._INSTANCES and e.mesh is None and e.plotter is None
    e.close()  # twice is fine


def test_rerunning_a_cell_closes_the_explorer_it_made(monkeypatch):
    where = {"cell": ("cell-a", 1)}
    monkeypatch.setattr(base, "_current_cell", lambda: where["cell"])
    monkeypatch.setattr(base, "_BY_CELL", {})
    first = CurvatureExplorer(surfaces.saddle(), live=False, depth=0)
    second = CurvatureExplorer(surfaces.saddle(), live=False, depth=0)  # same run of the cell: both stay
    assert not first.closed and not second.closed
    where["cell"] = ("cell-b", 2)
    other = CurvatureExplorer(surfaces.saddle(), live=False, depth=0)  # another cell
    where["cell"] = ("cell-a", 3)  # the first cell again
    again = CurvatureExplorer(surfaces.saddle(), live=False, depth=0)
    assert first.closed and second.closed and not other.closed and not again.closed


def test_static_bundle_without_a_jupyter_session(monkeypatch):
    e = CurvatureExplorer(surfaces.saddle(), live=False, depth=1)
    monkeypatch.delenv("JPY_SESSION_NAME", raising=False)
    bundle = e._repr_mimebundle_()
    assert set(bundle) == {"image/png", "text/plain"}
    import base64
    import io

    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(base64.b64decode(bundle["image/png"]))).convert("RGB"))
    assert img.shape == (500, 800, 3) and np.mean(np.any(img < 240, axis=-1)) > 0.2
    monkeypatch.setenv("LAB_INTERACTIVE", "1")
    live = e._repr_mimebundle_()
    assert "application/vnd.jupyter.widget-view+json" in live and "image/png" not in live  # no render in the kernel



def test_without_jupyter_server_proxy_a_hub_student_gets_pictures_and_the_reason(monkeypatch):
    """Under JupyterHub the live view needs jupyter-server-proxy; without it: static pictures, and the status says
    why and what to install."""
    import sys

    from lab import i18n

    for name in ("LAB_STATIC", "LAB_GRADING", "PYVISTA_TRAME_SERVER_PROXY_PREFIX"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("LAB_INTERACTIVE", "1")  # a Jupyter session
    monkeypatch.setenv("JUPYTERHUB_SERVICE_PREFIX", "/user/ada/")
    assert base.live_view_choice() == (True, None)  # the proxy is installed here
    monkeypatch.setitem(sys.modules, "jupyter_server_proxy", None)  # now it cannot be imported
    with i18n.using("en"):
        e = CurvatureExplorer(surfaces.saddle(), depth=1)  # live=None: the explorer decides
        assert e.live is False
        view = e.widget.children[2]
        assert isinstance(view, W.Image) and "lab-static-view" in view._dom_classes
        says_why = ("live 3D view unavailable: behind JupyterHub or a proxy the view needs jupyter-server-proxy "
                    "(pip install jupyter-server-proxy, then restart the server); showing pictures")
        assert says_why in e.status.value
        e.color_map.value = "symmetric"  # an action that ends without a note of its own: the reason stays
        assert says_why in e.status.value
    with i18n.using("de"):
        live, why = base.live_view_choice()
    assert not live and "nicht verfügbar" in why and "pip install jupyter-server-proxy" in why
    monkeypatch.delenv("JUPYTERHUB_SERVICE_PREFIX")
    assert base.live_view_choice() == (True, None)  # a local JupyterLab needs no proxy
    monkeypatch.setenv("PYVISTA_TRAME_SERVER_PROXY_PREFIX", "/proxy/")  # a remote Jupyter does
    assert base.live_view_choice()[0] is False
    e.close()

def test_widget_layout_fills_the_output():
    e = CurvatureExplorer(surfaces.saddle(), live=False, depth=1)
    w = e.widget
    assert w.layout.width == "100%" and "lab-explorer" in w._dom_classes
    assert e._view.layout.width == "100%"
    grid = next(c for c in w.children if isinstance(c, W.GridBox))
    assert "auto-fill" in grid.layout.grid_template_columns  # controls wrap into as many columns as fit
    assert "lab-colorbar" in e.legend_view.value and "Gaussian curvature K" in e.legend_view.value
    # every text meant to span the grid's full row is a cell of the grid itself (inside a box in one
    # column, the probe's readout wrapped word by word in a 250 px column)
    rows = [c for c in grid.children if c.layout.grid_column == "1 / -1"]
    assert e.tools.readout in rows and e.info in rows and e.edge_legend in rows
    # ipywidgets drops grid_column when it first draws (its issue #2334): a class and a rule in the title do it
    assert all("lab-full-row" in c._dom_classes or "lab-wide" in c._dom_classes for c in rows)
    assert ".lab-controls > .lab-full-row {grid-column: 1 / -1}" in w.children[0].children[0].value

    def nested(box):
        for child in getattr(box, "children", ()):
            yield child
            yield from nested(child)

    inside = [c for c in grid.children for d in nested(c) if d.layout.grid_column == "1 / -1"]
    assert inside == []
    e.close()


def test_students_class_errors_become_messages():
    class Stub(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            raise NotImplementedError("write visualize_curvature")

    e = CurvatureExplorer(surfaces.practical(), Stub, live=False, depth=1)
    assert "not implemented yet: write visualize_curvature" in e.status.value

    class Broken(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            for patch in self:
                patch.set_curvature(0, 0, 0, 0)

    e = CurvatureExplorer(surfaces.practical(), Broken, live=False, depth=1)
    assert "did not store colours for every patch" in e.status.value

    class Reference(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            lab.BezierPatches.visualize_curvature(self, curvature_mode, color_map)

    e = CurvatureExplorer(surfaces.practical(), Reference, live=False, depth=1)
    assert "lab-colorbar-label" in e.legend_html()  # the student's explorer has the same colour bar
    lo, hi = e.legend().clim
    stored = np.asarray(e.mesh.point_data["values"])
    assert (lo, hi) == (stored.min(), stored.max())
    e.color_map.value = "classification"
    assert e.status.value == ""
    assert "RGB" in e.mesh.point_data and "K &gt; 0 elliptic" in e.legend_html()
    with pytest.raises(TypeError, match="patches_class must be a subclass of lab.BezierPatches"):
        CurvatureExplorer(surfaces.practical(), object, live=False)
    with pytest.raises(TypeError, match="not made of Bézier patches"):
        CurvatureExplorer(surfaces.catenoid(), Reference, live=False)


def test_focal_explorer_moves_points_by_a_f_n():
    f = FocalExplorer(surfaces.sphere(2.0), scale=0.5, live=False)
    X = np.asarray(f.surface_mesh.points)
    N = np.asarray(f.surface_mesh.point_data["N"])
    f.scale.value = -1.0  # H = -1/2 on this sphere: F = X + 0.5 N
    np.testing.assert_allclose(np.asarray(f.focal_mesh.points), X + 0.5 * N, atol=1e-6)
    assert "mean curvature H" in f.legend_html()


def test_geodesic_explorer_messages_and_fans():
    g = GeodesicExplorer(surfaces.plane(4.0), start=(0.5, 0.5), n_angles=12, step=0.5, n_curves=3, live=False)
    assert g.status.value == "" and len(g.fan) == 12
    assert [len(pieces) for pieces in g.isodistance] == [1, 1, 1]  # three isodistance curves, twelve paths
    g.count.value = 12  # 6 units: beyond the 4 x 4 plane
    assert "paths reach the boundary" in g.status.value and "no path reaches" in g.status.value
    g.angle_range.value = (90.0, 90.0)
    assert "the angle range is empty" in g.status.value
    g.angle_range.value = (0.0, 90.0)
    assert not g.fan.full_circle and len(g.fan) == 12
    assert g.domain_view.value.startswith("<svg") and g.domain_view.value.count("<polyline") > 12


def test_geodesic_explorer_recomputes_only_what_changed():
    g = GeodesicExplorer(surfaces.practical(), start=(4.9, 2.1), n_angles=16, step=0.5, n_curves=6, live=False)
    fan = g.fan
    g.count.value = 4  # shorter: the paths are reused, only the curves are new
    assert g.fan is fan and len(g.isodistance) == 4
    g.step.value = 0.25
    g.count.value = 12  # 3.0: still within the 3.0 integrated
    assert g.fan is fan and len(g.isodistance) == 12
    g.count.value = 16  # 4.0, longer than integrated: a new fan
    assert g.fan is not fan and g.fan.length == pytest.approx(4.0)
    fan = g.fan
    g.u0.value = 4.5  # a new start: a new fan
    assert g.fan is not fan and g.fan.origin[0] == pytest.approx(4.5)


def test_geodesic_explorer_old_count_keyword_still_works():
    with pytest.warns(DeprecationWarning, match=r"count=…\) is deprecated: the number of isodistance curves is now n_curves"):
        g = GeodesicExplorer(surfaces.plane(4.0), start=(0.5, 0.5), n_angles=6, step=0.5, count=2, live=False)
    assert len(g.isodistance) == 2 and len(g.fan) == 6


def test_reflection_explorer_kinds():
    r = ReflectionExplorer(surfaces.hood(), resolution=32, live=False)
    assert "RGB" in r.overlay.cell_data
    r.kind.value = "isophotes"
    assert r.overlay.n_lines > 0 and r.status.value == ""
    r.elevation.value = 90.0
    r.kind.value = "lines"
    assert "horizontal part" in r.status.value


def test_edge_overlay_colours_each_edge_by_what_it_achieves(tmp_path):
    """The hood's borders: the crease over the double knot v = 3 in G1's colour, the others G2's; the checkbox
    shows and hides it; an offscreen picture against a stored one (tolerance as test_mesh's)."""
    from pathlib import Path

    from lab.view.explorers.edges import EDGE_COLORS, edge_lines

    ex = CurvatureExplorer(surfaces.hood(), live=False, depth=2)
    assert ex.edges.actor is None  # nothing computed before the checkbox is ticked
    ex.show_edges.value = True
    ex.toggle_overlays()
    rep = ex.edges.report
    assert rep.counts() == {"G3": 0, "G2": 35, "G1": 5, "G0": 0, "none": 0}
    assert "G1: 5" in ex.edge_legend.value and ex.edges.actor.GetVisibility()
    lines = edge_lines(rep)
    crease = [e for e in rep.edges if e.achieved == "G1"]
    rgb = np.asarray(lines.cell_data["RGB"])
    g1 = np.array([int(EDGE_COLORS["G1"][k:k + 2], 16) for k in (1, 3, 5)])
    assert np.count_nonzero(np.all(rgb == g1, axis=1)) == sum(len(e.points) - 1 for e in crease)
    image = ex.plotter.screenshot(str(tmp_path / "edges.png"), window_size=(480, 320))[..., :3]
    assert_like_reference(image, Path(__file__).parent / "data" / "explorer_edges_hood.png", tmp_path)
    assert np.count_nonzero(np.all(np.abs(image.astype(int) - g1) < 30, axis=-1)) > 200  # the crease is drawn
    ex.show_edges.value = False
    ex.toggle_overlays()
    assert not ex.edges.actor.GetVisibility() and ex.edge_legend.value == ""
    refl = ReflectionExplorer(surfaces.hood(), live=False)
    refl.show_edges.value = True
    refl.toggle_edges()
    assert refl.edges.report.counts()["G1"] == 1 and "G1: 1" in refl.edge_legend.value  # the knot line v = 3
    ex.close()
    refl.close()


# ----------------------------------------------------------------------------- the explorers on a model (lab.read)


@pytest.fixture(scope="module")
def teapot():
    """Newell's teapot, shipped with the lab: 32 untrimmed Bézier faces, no shared edges in its file."""
    return lab.models.teapot()


def test_curvature_explorer_on_a_model(teapot):
    """Every face with its exact curvature, one colour range over all faces, lines per face instead of the depth,
    face borders, the CAD tools on a chosen face."""
    import warnings

    from lab.view.explorers.edges import edge_lines

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", lab.DegeneratePointWarning)  # the lid's top and the bottom's centre
        e = CurvatureExplorer(teapot, live=False)
        ref = teapot.to_mesh(16, 16)
    mesh = e.mesh
    assert e.depth.description == "lines per face" and e.depth.value == 16
    np.testing.assert_allclose(mesh.point_data["K"], ref.point_data["K"])
    np.testing.assert_array_equal(mesh.point_data["face"], ref.point_data["face"])
    K = np.asarray(ref.point_data["K"])
    e.color_map.value = "linear"
    np.testing.assert_allclose(e.lut.scalar_range, (K.min(), K.max()))  # one range over all 32 faces
    face = np.asarray(ref.point_data["face"])
    own = [np.ptp(K[face == i]) for i in np.unique(face)]  # ... not each face's own range (K's extremes are at the
    assert sum(r < 0.5 * np.ptp(K) for r in own) >= 30  # spout's mouth: per face, most faces would span the map)
    e.measure.value = "mean"
    np.testing.assert_allclose(mesh.point_data["display"], ref.point_data["H"], rtol=1e-6)
    assert "32 faces" in e.info.value and e.picture_title() == "H, h∘f2 linear (min/max), 16 lines per face"
    e.depth.value = 8  # the resolution: each face on 8 lines, in place
    assert e.mesh is mesh and mesh.n_points == teapot.to_mesh(8, 8).n_points and e.status.value.find("Error") < 0
    e.depth.value = 16
    assert e._model_meshes.cached(8) is not None and mesh.n_points == ref.n_points
    e.show_borders.value = True  # each face's own border: its (u, v) on the domain's border (untrimmed faces)
    borders = e.borders_actor.mapper.dataset
    uv = np.asarray(borders.point_data["uv"])
    assert borders.n_lines > 0 and np.all(np.min(np.abs(np.stack([uv, uv - 1.0])), axis=0).min(axis=1) < 1e-12)
    e.show_edges.value = True  # the file gives no shared edges: said so
    assert "not sewn" in e.edge_legend.value and edge_lines(e.edges.report).n_points == 0
    t = e.tools
    assert [v for _label, v in t.face.options] == [f.index for f in teapot.faces]
    t.face.value = 5
    t.probe.value = True
    p = lab.probe(teapot.face(5), t.u.value, t.v.value)
    assert t.last_probe.K == pytest.approx(p.K) and t.last_probe.H == pytest.approx(p.H)
    u0, u1 = teapot.face(5).domain[0]
    assert (t.u.min, t.u.max) == (u0, u1)
    t.combs.value = True
    assert t.lines_actor is not None and "Error" not in e.status.value
    t.map.value = "draft"  # the CAD maps colour every face
    assert "RGB" in mesh.point_data and e.picture_title() == "draft angle, pull +z, 16 lines per face"
    assert np.asarray(mesh.point_data["cad"]).shape == (mesh.n_points,)
    e.close()
    assert e._model_meshes is None  # the model's meshes go with the explorer


def test_edges_by_continuity_on_a_real_part():
    """The hammer's 104 shared face edges, one polyline each, in the colour of what lab.continuity says it achieves."""
    from pathlib import Path

    from lab.interrogation.continuity import LEVELS, level_name
    from lab.view.explorers.edges import EDGE_COLORS, edge_lines

    if not Path("/usr/share/opencascade/data/occ/hammer.brep").exists() and not __import__("os").environ.get(
            "LAB_OCC_DATA"):
        pytest.skip("OpenCASCADE's sample parts (Debian occt-misc) are not installed")
    model = lab.models.hammer()
    e = CurvatureExplorer(model, live=False, lines=8)
    e.show_edges.value = True
    rep = e.edges.report
    expected = lab.continuity(model)
    assert len(rep.edges) == len(model.edges) == 104 and rep.counts() == expected.counts()
    lines = edge_lines(rep)
    edge = np.asarray(lines.cell_data["edge"])
    assert sorted(set(edge)) == list(range(len(model.edges)))  # one polyline per shared edge
    rgb = np.asarray(lines.cell_data["RGB"])
    for i, found in enumerate(expected.edges):
        want = [int(EDGE_COLORS[found.achieved][k:k + 2], 16) for k in (1, 3, 5)]
        assert np.all(rgb[edge == i] == want) and tuple(rep.edges[i].faces) == tuple(model.edges[i].faces)
        assert np.all(np.asarray(lines.cell_data["level"])[edge == i] == LEVELS.index(found.achieved))
    counts = expected.counts()
    assert all(f"{level_name(level)}: {counts[level]}" in e.edge_legend.value for level in counts)
    assert counts["G3"] == 23 and counts["G2"] == 2  # a model's face edges too: its faces' third derivatives
    assert e.edges.actor.GetVisibility()
    e.close()


def test_reflection_explorer_on_a_model_joins_lines_across_faces(teapot):
    """Stripes on every face; light lines and isophotes joined across the teapot's tangent-continuous patch borders."""
    import warnings

    from lab.interrogation import meshes as M

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", lab.DegeneratePointWarning)
        r = ReflectionExplorer(teapot, live=False)
    assert "RGB" in r.overlay.cell_data and len(np.unique(r.surface_mesh.point_data["face"])) == 32
    assert r.status.value == ""
    r.kind.value = "lines"
    joined = len(M.polylines(r.overlay))
    apart = r.surface_mesh.copy()
    del apart.point_data["face"]  # the same mesh, each face alone
    alone = len(M.polylines(lab.reflection_lines(apart, direction=(1.0, 0.0, 0.0), count=r.count.value,
                                                 spacing=3.0 * float(np.linalg.norm(np.ptp(apart.points, axis=0)))
                                                 / r.count.value)))
    assert 0 < joined < 0.75 * alone, (joined, alone)
    r.kind.value = "isophotes"
    assert r.overlay.n_lines > 0 and r.status.value == ""
    r.show_edges.value = True
    assert "not sewn" in r.edge_legend.value
    r.close()


def test_focal_explorer_on_a_model(teapot):
    """Each face's focal surface F = X + a H N with the face's normal, from a mesh built once."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", lab.DegeneratePointWarning)
        f = FocalExplorer(teapot, scale=0.01, live=False)
    base = f._mesh
    X = np.asarray(f.surface_mesh.points)
    N = np.asarray(f.surface_mesh.point_data["N"], dtype=float)
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    H = np.asarray(f.surface_mesh.point_data["H"])
    f.scale.value = 0.02
    np.testing.assert_allclose(np.asarray(f.focal_mesh.points), X + 0.02 * H[:, None] * N, atol=1e-9)
    assert f._mesh is base and len(np.unique(f.focal_mesh.point_data["face"])) == 32
    assert "mean curvature H" in f.legend_html()
    f.close()


def _descendants(widget):
    yield widget
    for child in getattr(widget, "children", ()) or ():
        yield from _descendants(child)


def _four_explorers():
    return [CurvatureExplorer(surfaces.practical(), live=False, depth=1),
            ReflectionExplorer(surfaces.hood(), resolution=16, live=False),
            FocalExplorer(surfaces.torus(2.0, 1.0), resolution=12, live=False),
            GeodesicExplorer(surfaces.torus(2.0, 1.0), live=False)]


FLOAT_SLIDERS = (W.FloatSlider, W.FloatLogSlider, W.FloatRangeSlider)


def test_german_float_sliders_show_decimal_commas():
    """ipywidgets' readout (d3-format) always writes a decimal point: in German each float slider has none of its
    own but the lab's text beside it, in one grid cell, shown and hidden with the slider; English keeps the native
    readout."""
    with lab.i18n.using("de"):
        explorers = _four_explorers()
    try:
        sliders = 0
        for e in explorers:
            grid = next(c for c in e.widget.children if isinstance(c, W.GridBox))
            for cell in grid.children:
                for slider in (w for w in _descendants(cell) if isinstance(w, FLOAT_SLIDERS)):
                    sliders += 1
                    assert not slider.readout, f"{slider.description}: ipywidgets' readout writes a decimal point"
                    readout = next(w for w in cell.children if isinstance(w, W.Label))
                    assert readout.value and not re.search(r"\d\.\d", readout.value), readout.value
                    slider.value = slider.max if not isinstance(slider, W.FloatRangeSlider) else (slider.min, 0.5 *
                                                                                                   slider.max)
                    assert not re.search(r"\d\.\d", readout.value), readout.value
        assert sliders == 10, f"{sliders} float sliders (comb scale, u, v, spacing, azimuth, elevation, a, u0, v0, α)"
        r = explorers[1]
        cells = {id(c.children[0]): c for c in next(c for c in r.widget.children if isinstance(c, W.GridBox)).children
                 if isinstance(c, W.HBox) and c.children and isinstance(c.children[0], FLOAT_SLIDERS)}
        for kind in ("stripes", "lines"):
            r.kind.value = kind
            for name in ("spacing", "azimuth", "elevation"):  # the slider and its readout hide and show together
                slider = getattr(r, name)
                assert cells[id(slider)].layout.display == slider.layout.display
                assert (slider.layout.display == "none") == (name not in r.USES[kind])
    finally:
        for e in explorers:
            e.close()
    with lab.i18n.using("en"):
        e = ReflectionExplorer(surfaces.hood(), resolution=16, live=False)
    try:
        assert e.spacing.readout and e.spacing in next(c for c in e.widget.children if isinstance(c, W.GridBox)).children
    finally:
        e.close()


def test_slider_text_writes_numbers_as_the_language_does():
    s = W.FloatLogSlider(value=0.05, base=10, min=-4, max=1)
    r = W.FloatRangeSlider(value=(-0.001, 360.0), min=-1, max=360, readout_format=".1f")
    with lab.i18n.using("de"):
        assert lab.view.explorers.controls.slider_text(s) == "0,05"
        assert lab.view.explorers.controls.slider_text(r) == "0,0 – 360,0"  # no −0,0
        s.value = 1.25
        assert lab.view.explorers.controls.slider_text(s) == "1,25"
    with lab.i18n.using("en"):
        assert lab.view.explorers.controls.slider_text(s) == "1.25"


@pytest.mark.parametrize("lang", ["en", "de"])
def test_every_dropdowns_longest_option_fits_its_width(lang):
    """A select shows its option whole when 1.1 ch per character plus one (fit_labels' estimate), its arrow and its
    label fit the cell: a 250 px grid cell (7.2 px a ch), or a row of its own as wide as it needs
    ("reflection lines (light li…", "vorzeichenbehaftet l…" were cut off)."""
    from lab.view.explorers import controls
    with lab.i18n.using(lang):
        explorers = _four_explorers()
    try:
        checked = 0
        for e in explorers:
            grid = next(c for c in e.widget.children if isinstance(c, W.GridBox))
            for d in (w for c in grid.children for w in _descendants(c) if isinstance(w, W.Dropdown)):
                checked += 1
                longest = max(len(label) for label in d._options_labels)
                label = controls._in_ch(d.style.description_width)
                need = label + 1.1 * longest + 1 + controls.SELECT_EXTRA
                if d.layout.grid_column == "1 / -1":
                    assert d in grid.children and "lab-wide" in d._dom_classes  # the CSS rule places it at first draw
                    assert float(d.layout.max_width.removesuffix("ch")) >= need
                else:
                    assert need * controls.CH <= controls.CELL_WIDTH, f"{d.description}: {need:.1f} ch in a 250 px cell"
        assert checked >= 10
        assert ".lab-controls > .lab-wide {grid-column: 1 / -1}" in controls.FULL_ROW_CSS
    finally:
        for e in explorers:
            e.close()
