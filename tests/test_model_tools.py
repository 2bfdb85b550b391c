"""The interrogation tools on a model (lab.read, lab.models): geodesics on a face that stop at its trimming loop,
reflection lines and isophotes across face borders, focal surfaces per face, pictures of a model.

The explorers on a model are tested in test_widgets.py.  OpenCASCADE (the extra "cad") writes the test's own
part; the sample parts come with Debian's occt-misc and are skipped, saying why, when missing.
"""

import os
import warnings
from pathlib import Path

import numpy as np
import pytest

import lab
from tests.picture_support import assert_like_reference

DATA = Path(os.environ.get("LAB_OCC_DATA", "/usr/share/opencascade/data"))
needs_data = pytest.mark.skipif(not (DATA / "occ" / "hammer.brep").exists(),
                                reason=f"OpenCASCADE's sample parts (Debian occt-misc) are not in {DATA}")
TESTS = Path(__file__).parent

#: the test's part: a cylinder of radius R and height 6 around z with a hole of radius RHOLE along x at z = 3
R, RHOLE, ZHOLE = 2.0, 0.6, 3.0


@pytest.fixture(scope="module")
def drilled(tmp_path_factory):
    """A cylinder with a hole across it, written as STEP by OpenCASCADE and read back by lab.read."""
    pytest.importorskip("OCP", reason="OpenCASCADE (the extra 'cad') is not installed")
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    body = BRepPrimAPI_MakeCylinder(R, 6.0).Shape()
    drill = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-5, 0, ZHOLE), gp_Dir(1, 0, 0)), RHOLE, 10.0).Shape()
    path = tmp_path_factory.mktemp("drilled") / "drilled.step"
    writer = STEPControl_Writer()
    writer.Transfer(BRepAlgoAPI_Cut(body, drill).Shape(), STEPControl_AsIs)
    writer.Write(str(path))
    return lab.read(path)


def _wall(model):
    """The cylinder's wall: the trimmed face of kind Cylinder with the holes (the larger one)."""
    walls = [f for f in model.faces if f.kind == "Cylinder"]
    return max(walls, key=lambda f: f.domain[1][1] - f.domain[1][0])


def _off_hole(X):
    """Radial distance of points from the hole's cylinder (axis x at z = ZHOLE, radius RHOLE)."""
    return np.hypot(X[..., 1], X[..., 2] - ZHOLE) - RHOLE


# ----------------------------------------------------------------------------- geodesics on a face


def test_geodesic_on_a_cylinder_face_is_a_helix(drilled):
    """On the wall (in the file's parameters, angle and height, over OpenCASCADE's rational form) the geodesic from
    x0 with unit tangent t0 is the helix θ(s) = θ0 + s t0·e_θ / R, z(s) = z0 + s t0·e_z, to 1e-9."""
    face = _wall(drilled)
    path = lab.geodesic(face, (np.pi / 2, 1.0), np.pi / 4, 2.0)
    assert path.end == "length" and not path.hit_boundary  # it stays clear of the holes
    d = face.derivatives(np.array([np.pi / 2]), np.array([1.0]))
    t0 = d.bu[0] * path.duv[0, 0] + d.bv[0] * path.duv[0, 1]
    x0 = path.points[0]
    theta0 = np.arctan2(x0[1], x0[0])
    e_theta = np.array([-np.sin(theta0), np.cos(theta0), 0.0])
    assert abs(t0[2]) == pytest.approx(np.sqrt(0.5), rel=1e-12)  # α = 45° from x_v, the axis
    theta = theta0 + path.s * (t0 @ e_theta) / R
    helix = np.column_stack([R * np.cos(theta), R * np.sin(theta), x0[2] + path.s * t0[2]])
    np.testing.assert_allclose(path.points, helix, atol=1e-9)  # the solver's tolerances are 1e-10, 1e-12


def test_geodesic_on_a_face_stops_at_its_hole(drilled):
    """A horizontal geodesic (a circle z = 3) towards the hole ends on the hole's border: where
    y² + (z − 3)² = RHOLE², at θ = π − asin(RHOLE / R), after R (θ_exit − θ0).

    The face's loops are polylines (OpenCASCADE's pcurves sampled by lab.read); the path ends on the polyline,
    so the tolerance is the loop's own largest deviation from the true hole (its chords' sagitta, measured)."""
    face = _wall(drilled)
    hole = min(face.trim.loops, key=len) if len(face.trim.loops) > 1 else face.trim.loops[0]
    mid = 0.5 * (hole[1:] + hole[:-1])
    sagitta = float(np.max(np.abs(_off_hole(face.evaluate(mid[:, 0], mid[:, 1])))))
    assert 0 < sagitta < 0.02
    d = face.derivatives(np.array([np.pi / 2]), np.array([ZHOLE]))
    for alpha in (np.pi / 2, 3 * np.pi / 2):  # the one that heads towards +θ (x_v^⊥ = −G x_u: the sign of x_u)
        path = lab.geodesic(face, (np.pi / 2, ZHOLE), alpha, 5.0)
        t0 = d.bu[0] * path.duv[0, 0] + d.bv[0] * path.duv[0, 1]
        theta0 = np.arctan2(path.points[0, 1], path.points[0, 0])
        if t0 @ np.array([-np.sin(theta0), np.cos(theta0), 0.0]) > 0:
            break
    assert path.end == "trim" and path.hit_boundary
    end = path.points[-1]
    assert abs(_off_hole(end)) <= 1.01 * sagitta
    assert end[2] == pytest.approx(ZHOLE, abs=1e-9)  # a geodesic along a parallel stays on it
    theta_exit = np.pi - np.arcsin(RHOLE / R)
    assert path.length == pytest.approx(R * (theta_exit - theta0), abs=2 * sagitta)
    # the surface's own geodesic runs on through the hole, to the surface's border
    whole = lab.geodesic(face.file_surface, (np.pi / 2, ZHOLE), alpha, 5.0)
    assert whole.end in ("length", "boundary") and whole.length > path.length + 0.5
    np.testing.assert_allclose(whole.at(path.s)[1], path.points, atol=1e-9)


def test_start_outside_the_face_is_refused(drilled):
    face = _wall(drilled)
    with pytest.raises(ValueError, match=r"lies outside the face's trimmed region"):
        lab.geodesic(face, (np.pi, ZHOLE), 0.0, 1.0)  # θ = 180°, z = 3: in the hole
    with pytest.raises(ValueError, match=r"lies outside the face's trimmed region"):
        lab.geodesic_fan(face, (np.pi, ZHOLE), 4, 1.0)


@needs_data
def test_geodesics_on_a_trimmed_bspline_face_follow_the_surfaces_own():
    """A face of the hammer (a trimmed B-spline): each path of a fan equals the surface's own geodesic up to where
    it leaves the face, and ends on the face's outer loop (within the loops' tolerance, 1e-10 of the domain)."""
    from lab.interrogation.trimming.loops import distance_to_loop

    model = lab.models.hammer()
    face = model.faces[3]
    assert face.trim is not None and face.surface.__class__.__name__ == "BSplineSurface"
    start = (-0.748, 0.838)
    fan = lab.geodesic_fan(face, start, 12, 1e5)
    whole = lab.geodesic_fan(face.surface, start, 12, 1e5)
    scale = np.hypot(*np.ptp(np.array(face.domain), axis=1))
    size = float(np.linalg.norm(np.ptp(face.surface.control_points.reshape(-1, 3), axis=0)))
    for p, q in zip(fan, whole):
        assert p.end == "trim" and p.hit_boundary and p.length <= q.length
        np.testing.assert_allclose(q.at(p.s)[1], p.points, atol=1e-9 * size)
        gap = min(distance_to_loop(p.uv[-1:], loop)[0] for loop in face.trim.loops)
        assert gap <= 2e-10 * scale
    iso = lab.polar_isodistance(fan, [100.0, 200.0])  # the isodistance curves work on the cut fan
    assert all(len(pieces) >= 1 for pieces in iso)


# ----------------------------------------------------------------------------- lines across face borders


def test_join_polylines_joins_ends_within_the_tolerance_only():
    from lab.mesh.levels import join_polylines

    a = np.array([[0.0, 0, 0], [1, 0, 0]])
    b = np.array([[1.001, 0, 0], [2, 0, 0]])  # starts 0.001 after a ends
    c = np.array([[2, 0, 0.002], [2, 1, 0]])  # 0.002 from b's end
    far = np.array([[5.0, 0, 0], [6, 0, 0]])
    joined = join_polylines([c, far, a, b], tol=0.01)
    assert len(joined) == 2
    long = max(joined, key=len)
    long = long if long[0, 1] == 0 else long[::-1]  # either direction
    np.testing.assert_allclose(long[[0, -1]], [[0, 0, 0], [2, 1, 0]])  # a, b, c in order
    np.testing.assert_allclose(long[1], [1.0005, 0, 0])  # the two ends replaced by their midpoint
    assert len(join_polylines([a, b], tol=1e-4)) == 2  # too far apart: two lines
    ring = join_polylines([a, b[::-1], np.array([[2.0, 0, 0], [1, 1, 0], [0, 0, 1e-4]])], tol=0.01)
    assert len(ring) == 1 and np.array_equal(ring[0][0], ring[0][-1])  # a cycle closes
    square = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 0, 0]])
    kept = join_polylines([square, a], tol=0.5)  # a closed line is left as it is; the short one is not closed
    assert len(kept) == 2 and any(np.array_equal(line, square) for line in kept)


@needs_data
def test_reflection_lines_run_across_tangent_face_borders_and_break_at_kinks():
    """The hammer's mesh has one vertex set per face.  Its 12 reflection lines end on face borders when each face is
    taken alone; joined, no line ends on a G1, G2 or G3 edge any more (away from the corners where a kink meets it),
    while every end on a G0 edge (a kink: the reflected light jumps) stays."""
    from scipy.spatial import cKDTree

    from lab.interrogation import meshes as M

    model = lab.models.hammer()
    rep = lab.continuity(model)
    mesh = model.to_mesh(16, 16)
    apart = mesh.copy()
    del apart.point_data["face"]  # the same mesh, not known to be a model's: lines stop at every border
    joined = M.polylines(lab.reflection_lines(mesh, count=12))
    alone = M.polylines(lab.reflection_lines(apart, count=12))
    X = np.asarray(mesh.points)
    T = M._triangles(mesh)
    h = float(np.median(np.linalg.norm(X[T] - X[np.roll(T, 1, axis=1)], axis=-1)))
    smooth = cKDTree(np.concatenate([e.points for e in rep.edges if e.achieved in ("G1", "G2", "G3")]))
    kinks = cKDTree(np.concatenate([e.points for e in rep.edges if e.achieved in ("G0", "none")]))

    def ends(lines):
        return np.array([p for line in lines if not np.array_equal(line[0], line[-1]) for p in (line[0], line[-1])])

    def on(tree, points, away_from=None):
        near = tree.query(points)[0] < 0.1 * h
        if away_from is not None:
            near &= away_from.query(points)[0] > 0.5 * h
        return int(np.count_nonzero(near))

    assert on(smooth, ends(alone), kinks) >= 10  # taken face by face, lines end on the smooth edges
    assert on(smooth, ends(joined), kinks) == 0  # joined: they run on across them
    assert on(kinks, ends(joined)) == on(kinks, ends(alone)) >= 20  # and break at every kink
    assert len(joined) < len(alone)
    iso = lab.isophotes(model, count=6)  # a model goes in as it is (16 lines per face)
    assert iso.n_lines > 0


def test_focal_surface_of_a_model_per_face(drilled):
    """F = X + a H N on every face with the face's normal: on the drilled cylinder's wall (H = ∓1/(2R) with N
    outward or inward, the same point either way) F lies on the cylinder of radius R − a/(2R), on the hole's
    wall at |RHOLE − a/(2 RHOLE)| from the drill's axis (x at z = 3); on the flat caps (H = 0) F = X."""
    a = 0.8
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        focal = lab.focal_surface(drilled, scale=a, function="mean", resolution=8)
    F = np.asarray(focal.points)
    face = np.asarray(focal.point_data["face"])
    wall = face == _wall(drilled).index
    hole = np.isin(face, [f.index for f in drilled.faces if f.kind == "Cylinder" and f is not _wall(drilled)])
    assert wall.any() and hole.any()
    np.testing.assert_allclose(np.hypot(F[wall, 0], F[wall, 1]), R - a / (2 * R), atol=1e-9)
    np.testing.assert_allclose(np.hypot(F[hole, 1], F[hole, 2] - ZHOLE), abs(RHOLE - a / (2 * RHOLE)), atol=1e-9)
    flat = ~(wall | hole)
    np.testing.assert_allclose(F[flat], focal.point_data["X"][flat], atol=1e-12)


# ----------------------------------------------------------------------------- the probe and the combs on a face


def test_probe_and_combs_on_a_face(drilled):
    """The probe on a face uses the face's normal (flipped on a reversed face); the combs run along the face's loops:
    on the wall's rims (z = 0 and z = 6, circles of radius R) every tooth has length scale / R."""
    face = _wall(drilled)
    u, v = np.pi / 2, 1.0
    p = lab.probe(face, u, v)
    c = face.curvature(u, v)
    np.testing.assert_allclose([p.K, p.H, p.k1, p.k2], [c.K, c.H, c.k1, c.k2], atol=1e-12)
    np.testing.assert_allclose(p.normal, face.normal(u, v), atol=1e-12)
    np.testing.assert_allclose(np.cross(p.d1, p.d2), p.normal, atol=1e-12)  # right-handed with the face's normal
    assert abs(p.H) == pytest.approx(1 / (2 * R), rel=1e-9)
    radial = p.point / np.linalg.norm(p.point[:2]) * [1, 1, 0]
    assert np.dot(p.normal, radial) == pytest.approx(-1.0 if face.reversed else 1.0)
    with pytest.raises(ValueError, match="the probe's point .* lies outside the face's trimmed region"):
        lab.probe(face, np.pi, ZHOLE)
    scale = 0.5
    combs = lab.border_combs(face, density=24, scale=scale, count=1)
    assert len(combs) >= len(face.trim.loops) + 2
    outer = combs[0]
    z = outer.points[:, 2]
    rim = (np.minimum(abs(z), abs(z - 6.0)) < 1e-9) & (np.abs(np.gradient(z)) < 1e-12)
    assert rim.sum() > 20
    teeth = np.linalg.norm(outer.tips[rim] - outer.points[rim], axis=1)
    np.testing.assert_allclose(teeth, scale / R, rtol=1e-6)  # the polyline's tangent there is the rim's own
    lines = lab.comb_lines(combs)  # a cylinder's combs have no inflection (the explorer's combs failed here)
    assert lines.n_lines > 0 and "inflections" not in lines.field_data
    inside = np.concatenate([cb.uv for cb in combs[len(face.trim.loops):]])
    assert np.all(face.trim.contains(inside[:, 0], inside[:, 1]))  # the iso-curves are cut to the face


# ----------------------------------------------------------------------------- pictures of a model


@pytest.fixture(scope="module")
def teapot():
    return lab.models.teapot()


def test_picture_of_a_model_matches_stored_reference(teapot, tmp_path):
    """The teapot classified by the sign of K with its face borders, in the lab's style, against a stored picture;
    one legend for all faces; the borders drawn (dark grey) without the triangles' edges."""

    from lab.view import render

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", lab.DegeneratePointWarning)
        image = render.picture(teapot, "gaussian", "classification", window_size=(480, 360), edges=True,
                               camera=(-100, 25), title="teapot, K")
        plain = render.picture(teapot, "gaussian", "classification", window_size=(480, 360), camera=(-100, 25),
                               title="teapot, K")
        mesh, legend = render._as_mesh(teapot, "gaussian", "classification", 1, None)
        assert mesh.n_points == teapot.to_mesh(16, 16).n_points  # 16 lines per face unless n says otherwise
    assert [label.split()[0] for label, _c in legend.classes] == ["K", "K", "K"]  # one classification legend
    grey = lambda im: int(np.count_nonzero(np.all(np.abs(im.astype(int) - 58) < 25, axis=-1)))
    assert grey(image) > grey(plain) + 300  # the face borders
    assert_like_reference(image, TESTS / "data" / "model_teapot_gaussian_classification.png", tmp_path)


def test_command_line_renders_a_part_from_a_file_and_a_named_one(drilled, tmp_path):
    """`curvature-lab render --file part.step` with the options it always took, and `--model NAME`."""
    import pyvista as pv

    from lab import cli

    png = tmp_path / "part.png"
    assert cli.main(["render", "--file", drilled.path, "--curvature", "mean", "--color-map", "symmetric", "--edges",
                     "--camera", "-60,35", "--window-size", "320x240", "--quiet", "-o", str(png)]) == 0
    assert png.stat().st_size > 1000
    vtp = tmp_path / "part.vtp"
    assert cli.main(["render", "--file", drilled.path, "--depth", "0", "--quiet", "-o", str(vtp)]) == 0
    mesh = pv.read(vtp)
    assert set(np.unique(mesh.point_data["face"])) == {f.index for f in drilled.faces}
    wall = np.asarray(mesh.point_data["face"]) == _wall(drilled).index
    np.testing.assert_allclose(np.abs(mesh.point_data["H"][wall]), 1 / (2 * R), rtol=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert cli.main(["render", "--model", "teapot", "--depth", "0", "--quiet", "-o", str(vtp)]) == 0
    assert np.all(np.isfinite(pv.read(vtp).point_data["N"]))  # the collapsed edges' corners got a normal
    with pytest.raises(SystemExit):
        cli.main(["render", "--model", "teapot", "--file", drilled.path, "--quiet", "-o", str(png)])


def test_geodesic_explorer_on_a_face(drilled):
    """A fan beside the hole: the paths that run into it stop on its border, the status says how many left the
    face, the parameter domain shows the face's loops; a start in the hole is refused with the reason."""
    from lab.widgets import GeodesicExplorer

    face = _wall(drilled)
    g = GeodesicExplorer(face, start=(2.3, ZHOLE), n_angles=32, step=0.4, n_curves=5, live=False)
    cut = [p for p in g.fan if p.end == "trim"]
    assert 0 < len(cut) < len(g.fan)
    hole = min(face.trim.loops, key=len)
    mid = 0.5 * (hole[1:] + hole[:-1])
    sagitta = float(np.max(np.abs(_off_hole(face.evaluate(mid[:, 0], mid[:, 1])))))
    assert all(abs(_off_hole(p.points[-1])) <= 1.01 * sagitta for p in cut)
    assert f"{len(cut)} of 32 paths leave the face before length 2" in g.status.value
    assert g.domain_view.value.count("<polygon") == len(face.trim.loops)
    g.u0.value = np.pi  # θ = 180°, z = 3: the hole's centre
    assert "lies outside the face&#x27;s trimmed region" in g.status.value  # (HTML-escaped)
    g.close()
