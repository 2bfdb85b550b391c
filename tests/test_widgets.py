"""The explorers without a browser: in-place updates, main-thread renders, messages, static fallback."""

import threading

import numpy as np
import pytest

import lab
from lab import surfaces
from lab.widgets import CurvatureExplorer, FocalExplorer, GeodesicExplorer, ReflectionExplorer


@pytest.fixture(scope="module")
def explorer():
    return CurvatureExplorer(surfaces.practical(), live=False, depth=2)


def test_recolour_changes_colours_only(explorer):
    e = explorer
    actor, mesh, lut = e.actor, e.mesh, e.lut
    e.color_map.value = "linear"
    K = np.asarray(mesh.point_data["K"])
    np.testing.assert_allclose(e.lut.scalar_range, (K.min(), K.max()))
    np.testing.assert_array_equal(mesh.point_data["display"], K)
    e.color_map.value = "symmetric"
    m = np.abs(K).max()
    np.testing.assert_allclose(e.lut.scalar_range, (-m, m))
    e.measure.value = "mean"
    np.testing.assert_array_equal(mesh.point_data["display"], mesh.point_data["H"])
    e.color_map.value = "classification"
    assert set(np.unique(mesh.point_data["display"])) <= {0.0, 0.5, 1.0}
    assert e.actor is actor and e.mesh is mesh and e.lut is lut  # nothing rebuilt
    assert e.status.value == ""
    e.measure.value = "gaussian"
    e.color_map.value = "linear"


def test_range_modes(explorer):
    e = explorer
    e.range_mode.value = "manual"
    assert not e.range.disabled
    e.range.value = (-0.5, 0.25)
    np.testing.assert_allclose(e.lut.scalar_range, (-0.5, 0.25))
    e.range_mode.value = "auto"
    assert e.range.disabled


def test_depth_updates_the_mesh_in_place():
    e = CurvatureExplorer(surfaces.practical(), live=False, depth=1)
    mesh = e.mesh
    assert mesh.n_points == 15**2
    e.depth.value = 3
    assert e.mesh is mesh and mesh.n_points == 57**2
    K = surfaces.practical().curvature(np.linspace(0, 7, 57)[:, None], np.linspace(0, 7, 57)[None, :]).K
    np.testing.assert_allclose(np.sort(mesh.point_data["K"]), np.sort(K.ravel()), rtol=1e-9, atol=1e-12)


def test_callbacks_from_other_threads_render_on_the_main_thread():
    e = CurvatureExplorer(surfaces.saddle(), live=False, depth=1)
    ran_on = []
    scheduled = []

    class Loop:
        def call_soon_threadsafe(self, func, *args):
            scheduled.append((func, args))

    e._loop = Loop()
    observer = e._callback(lambda: ran_on.append(threading.current_thread().name))
    t = threading.Thread(target=observer, name="comm-subshell")
    t.start()
    t.join()
    assert ran_on == [] and len(scheduled) == 1  # nothing ran on the subshell thread
    func, args = scheduled[0]
    func(*args)  # what the kernel's event loop does on the main thread
    assert ran_on == ["MainThread"]
    assert e.callback_threads == ["comm-subshell"]


def test_static_bundle_without_a_jupyter_session(monkeypatch):
    e = CurvatureExplorer(surfaces.saddle(), live=False, depth=1)
    monkeypatch.delenv("JPY_SESSION_NAME", raising=False)
    bundle = e._repr_mimebundle_()
    assert set(bundle) == {"image/png", "text/plain"}
    import base64
    import io

    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(base64.b64decode(bundle["image/png"]))).convert("RGB"))
    assert img.shape == (480, 640, 3) and np.mean(np.any(img < 240, axis=-1)) > 0.05
    monkeypatch.setenv("LAB_INTERACTIVE", "1")
    assert "application/vnd.jupyter.widget-view+json" in e._repr_mimebundle_()


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
    e.color_map.value = "classification"
    assert e.status.value == ""
    assert "RGB" in e.mesh.point_data
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
    assert g.domain_view.value[:4] == b"\x89PNG"


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
