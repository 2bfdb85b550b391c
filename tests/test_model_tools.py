"""The interrogation tools on a model (lab.read, lab.models): geodesics on a face that stop at its trimming loop,
reflection lines and isophotes across face borders, focal surfaces per face, pictures of a model.

The explorers on a model are tested in test_widgets.py.  OpenCASCADE (the extra "cad") writes the test's own
part; the sample parts come with Debian's occt-misc and are skipped, saying why, when missing.
"""

import os
from pathlib import Path

import numpy as np
import pytest

import lab

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
    """On the wall (OpenCASCADE's rational form of the cylinder, not in angle and height) the geodesic from
    x0 with unit tangent t0 is the helix θ(s) = θ0 + s t0·e_θ / R, z(s) = z0 + s t0·e_z, to 1e-9."""
    face = _wall(drilled)
    path = lab.geodesic(face, (np.pi / 2, 1.0), np.pi / 4, 2.0)
    assert path.end == "length" and not path.hit_boundary  # it stays clear of the holes
    d = face.surface.derivatives(np.array([np.pi / 2]), np.array([1.0]))
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
    sagitta = float(np.max(np.abs(_off_hole(face.surface.evaluate(mid[:, 0], mid[:, 1])))))
    assert 0 < sagitta < 0.02
    d = face.surface.derivatives(np.array([np.pi / 2]), np.array([ZHOLE]))
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
    whole = lab.geodesic(face.surface, (np.pi / 2, ZHOLE), alpha, 5.0)
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
