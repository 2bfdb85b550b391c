"""Normal sections, geodesics and polar isodistance curves (lab.geodesics, Puig-Pey et al.)."""

import numpy as np
import pytest
from lab.geodesics import (
    Fan,
    Path,
    christoffel,
    geodesic,
    geodesic_between,
    geodesic_fan,
    normal_section,
    normal_section_fan,
    polar_isodistance,
    start_direction,
)
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

import lab
from lab import surfaces
from lab.interrogation.geodesics.problem import _Problem


def skew_plane():
    """A parallelogram in the plane z = 1 with an affine, non-orthogonal parametrisation (F != 0)."""
    P = np.array([[[0, 0, 1], [1, 2, 1]], [[3, 0.5, 1], [4, 2.5, 1]]], dtype=float)
    return lab.BezierSurface(P)


def tangent_3d(surface, path):
    """dx/ds = x_u u' + x_v v' at the samples of a path."""
    d = surface.derivatives(path.uv[:, 0], path.uv[:, 1])
    return d.bu * path.duv[:, :1] + d.bv * path.duv[:, 1:]


# ---------------------------------------------------------------- formulas


def test_christoffel_symbols_agree_with_the_metric_form(rng):
    # Gamma^k_ij = g^{kl} x_l . x_ij: an independent formula for the symbols of eq. 11
    for surface in (surfaces.practical(), surfaces.torus(), surfaces.isodistance_geodesics_example()):
        (a, b), (c, d) = surface.domain
        u, v = rng.uniform(a, b, 50), rng.uniform(c, d, 50)
        D = surface.derivatives(u, v)
        J = np.stack([D.bu, D.bv], axis=-1)  # (k, 3, 2)
        g_inv = np.linalg.inv(np.einsum("kdi,kdj->kij", J, J))
        second = np.stack([np.stack([D.buu, D.buv], 1), np.stack([D.buv, D.bvv], 1)], 1)  # (k, 2, 2, 3)
        expected = np.einsum("kml,kdl,kijd->kmij", g_inv, J, second)
        Gamma = christoffel(D)
        assert Gamma.shape == (50, 2, 2, 2)
        np.testing.assert_allclose(Gamma, expected, rtol=1e-9, atol=1e-11 * np.abs(expected).max())


def test_start_direction_is_eq_10_and_matches_eqs_14_16():
    s = surfaces.practical()
    uv = (4.9, 2.1)
    alpha = np.array([0.2, 1.0, 2.5, 3.9, 5.8])  # away from the pole of eq. 16
    n, duv = start_direction(s, uv, alpha)
    d = s.derivatives(*uv)
    E, F, G = d.bu @ d.bu, d.bu @ d.bv, d.bv @ d.bv
    perp = -G * d.bu + F * d.bv  # eq. 9
    # eq. 10: unit vector at angle alpha from x_v towards x_v^perp
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1, atol=1e-14)
    np.testing.assert_allclose(n @ d.bv / np.linalg.norm(d.bv), np.cos(alpha), atol=1e-13)
    np.testing.assert_allclose(n @ perp / np.linalg.norm(perp), np.sin(alpha), atol=1e-13)
    # eqs. 14, 16 literally, with the sign that starts along +n
    c = -np.sin(alpha) * G * np.linalg.norm(d.bv) / (
        np.cos(alpha) * np.linalg.norm(perp) + np.sin(alpha) * F * np.linalg.norm(d.bv)
    )
    root = np.sqrt(E * c**2 + 2 * F * c + G)
    sign = np.sign(np.einsum("kd,kd->k", np.outer(c, d.bu) + d.bv, n))
    np.testing.assert_allclose(duv, np.column_stack([sign * c / root, sign / root]), rtol=1e-12)
    np.testing.assert_allclose(np.outer(duv[:, 0], d.bu) + np.outer(duv[:, 1], d.bv), n, atol=1e-13)
    single_n, single_duv = start_direction(s, uv, 1.0)
    assert single_n.shape == (3,) and single_duv.shape == (2,)


def test_patchwise_evaluation_reproduces_the_surface(rng):
    # the integrator evaluates each Bézier patch as a polynomial in its local parameters;
    # inside the domain that must be the surface itself
    for surface in (surfaces.practical(), surfaces.torus(), surfaces.sphere(), surfaces.isodistance_sections_example()):
        problem = _Problem(surface, "geodesic")
        (a, b), (c, d) = surface.domain
        uv = np.column_stack([rng.uniform(a, b, 300), rng.uniform(c, d, 300)])
        cell = problem.locate(uv, np.ones_like(uv))
        ours, ref = problem.derivatives(uv, cell), surface.derivatives(uv[:, 0], uv[:, 1])
        for x, y in zip(ours, ref):
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-12 * max(1.0, np.abs(y).max()))


# ---------------------------------------------------------------- plane


@pytest.mark.parametrize("kind", [geodesic, normal_section])
def test_paths_on_a_plane_are_straight_lines_at_angle_alpha(kind):
    s = skew_plane()
    uv = (0.4, 0.5)
    d = s.derivatives(*uv)
    F, G = d.bu @ d.bv, d.bv @ d.bv
    e1 = d.bv / np.linalg.norm(d.bv)
    e2 = (-G * d.bu + F * d.bv) / np.linalg.norm(-G * d.bu + F * d.bv)
    for alpha in (0.0, np.pi / 2, 2.0, 4.4):
        p = kind(s, uv, alpha, 0.6)
        assert not p.hit_boundary and p.length == 0.6
        expected = d.b + p.s[:, None] * (np.cos(alpha) * e1 + np.sin(alpha) * e2)
        np.testing.assert_allclose(p.points, expected, rtol=0, atol=1e-10)


def test_plane_paths_stop_exactly_at_the_boundary():
    s = lab.surfaces.plane(2.0)  # x = 2u, y = 2v; alpha = 0 is +y, alpha = pi/2 is -x
    uv = (0.3, 0.6)
    fan = geodesic_fan(s, uv, 16, 2.0)
    P = s.evaluate(*uv)
    for p in fan:
        direction = np.array([-np.sin(p.angle), np.cos(p.angle), 0.0])
        # exact distance along the ray to the square [0, 2]^2
        with np.errstate(divide="ignore"):
            t = [(lim - P[i]) / direction[i] for i in (0, 1) for lim in (0.0, 2.0) if direction[i] != 0]
        s_exit = min(x for x in t if x > 0)
        assert p.hit_boundary == (s_exit < 2.0)
        if p.hit_boundary:
            assert p.length == pytest.approx(s_exit, abs=1e-10)
            end = p.uv[-1]
            assert min(end.min(), 1 - end.max()) == pytest.approx(0, abs=1e-12)  # on the edge of the domain
        np.testing.assert_allclose(p.points, P + p.s[:, None] * direction, atol=1e-10)


def test_isodistance_on_a_plane_circles_closed_and_open():
    s = lab.surfaces.plane(2.0)
    uv = (0.3, 0.5)  # 0.6 from the edge x = 0, at least 1.0 from the others
    fan = geodesic_fan(s, uv, 32, 1.5)
    P = s.evaluate(*uv)
    curves = polar_isodistance(fan, [0.4, 0.8, 3.0])
    closed, = curves[0]
    assert closed.closed and closed.distance == 0.4
    np.testing.assert_allclose(closed.points[0], closed.points[-1], atol=1e-14)
    r = np.linalg.norm(closed.points - P, axis=1)
    # the spline passes through the fan's points (every samples_per_angle-th sample) exactly...
    np.testing.assert_allclose(r[::8], 0.4, atol=1e-10)
    # ...and between them interpolates a circle in alpha: cubic-spline error O((2 pi / 32)^4)
    np.testing.assert_allclose(r, 0.4, atol=2e-4 * 0.4)
    # it is the periodic cubic spline in alpha through the nodes' parameters (Puig-Pey et al., §5)
    nodes = np.array([p.at(0.4)[0] for p in fan] + [fan[0].at(0.4)[0]])
    spline = CubicSpline(np.r_[fan.angles, 2 * np.pi], nodes, bc_type="periodic")
    np.testing.assert_allclose(closed.uv, spline(closed.angles), atol=1e-13)
    # at 0.8 the paths towards x = 0 have stopped at the boundary: one open arc
    (arc,) = curves[1]
    assert not arc.closed
    np.testing.assert_allclose(np.linalg.norm(arc.points - P, axis=1)[::8], 0.8, atol=1e-10)
    reached = np.array([p.length >= 0.8 for p in fan])
    assert len(arc.points) == 8 * (reached.sum() - 1) + 1
    assert np.all(np.diff(arc.angles) > 0)
    assert np.all(arc.points[:, 0] > 0)  # away from the edge x = 0
    assert curves[2] == []  # no path is that long


def test_isodistance_pieces_and_short_runs():
    s = lab.surfaces.plane(1.0)
    # in a corner: only a quarter of the directions stay on the square for long
    fan = normal_section_fan(s, (0.05, 0.05), 12, 1.2)
    (piece,) = polar_isodistance(fan, 0.5)[0]
    assert not piece.closed
    # the run alpha = 3 pi/2 (+x) ... 2 pi (+y) goes over alpha = 0, where the fan starts
    np.testing.assert_allclose(piece.angles[[0, -1]], [1.5 * np.pi, 2 * np.pi], atol=1e-14)
    np.testing.assert_allclose(piece.points[0], fan[9].at(0.5)[1], atol=1e-10)
    np.testing.assert_allclose(piece.points[-1], fan[0].at(0.5)[1], atol=1e-10)
    np.testing.assert_allclose(piece.points[[0, -1]], [[0.55, 0.05, 0], [0.05, 0.55, 0]], atol=1e-10)
    # a fan of three: closed curves use linear interpolation, and a list of paths works like a Fan
    fan3 = geodesic_fan(s, (0.5, 0.5), 3, 0.3)
    (tri,) = polar_isodistance(list(fan3), 0.2)[0]
    assert tri.closed and len(tri.points) == 3 * 8 + 1
    # two separate runs on a thin strip: paths leave through the long edges
    strip = lab.BezierSurface(np.array([[[0, 0, 0], [0, 0.2, 0]], [[4, 0, 0], [4, 0.2, 0]]], dtype=float))
    fan = geodesic_fan(strip, (0.5, 0.5), 24, 1.0)
    pieces = polar_isodistance(fan, 0.5)[0]
    assert len(pieces) == 2 and not any(p.closed for p in pieces)
    np.testing.assert_allclose(np.abs(np.concatenate([p.points[:, 0] for p in pieces]) - 2.0), 0.5, atol=1e-3)


# ---------------------------------------------------------------- sphere, cylinder, torus


def test_geodesics_and_normal_sections_on_a_sphere_are_great_circles():
    R = 2.0
    s = surfaces.sphere(R)
    uv = (0.3, 0.45)  # crosses knot lines of the NURBS (C1 at the quarter knots)
    for fan in (geodesic_fan(s, uv, 12, 2.5), normal_section_fan(s, uv, 12, 2.5)):
        P = s.evaluate(*uv)
        for p in fan:
            assert not p.hit_boundary
            np.testing.assert_allclose(np.linalg.norm(p.points, axis=1), R, atol=1e-12)
            normal = np.cross(P, p.points[1] - P)
            normal /= np.linalg.norm(normal)
            # in a plane through the centre, at chord 2R sin(s/2R) from P; rtol = 1e-10 acts on the
            # parameters, which move ~4 pi R = 25 units per unit of u here, so allow a few 1e-9
            np.testing.assert_allclose(p.points @ normal, 0, atol=5e-9)
            np.testing.assert_allclose(np.linalg.norm(p.points - P, axis=1), 2 * R * np.sin(p.s / (2 * R)), atol=5e-9)


def test_isodistance_circles_on_a_sphere():
    R = 2.0
    s = surfaces.sphere(R)
    uv = (0.6, 0.4)
    P = s.evaluate(*uv)
    fan = geodesic_fan(s, uv, 24, 2.0)
    for (curve,), sL in zip(polar_isodistance(fan, [0.5, 1.0, 2.0]), [0.5, 1.0, 2.0]):
        assert curve.closed
        chord = np.linalg.norm(curve.points - P, axis=1)
        np.testing.assert_allclose(chord[::8], 2 * R * np.sin(sL / (2 * R)), atol=5e-9)  # the fan's points
        # between them: spline interpolation in the parameters, error O((2 pi / 24)^4 sL)
        np.testing.assert_allclose(chord, 2 * R * np.sin(sL / (2 * R)), atol=5e-3 * sL)


def test_geodesics_on_a_cylinder_are_helices():
    r, h = 1.5, 6.0
    s = surfaces.cylinder(r, h)
    uv = (0.1, 0.5)
    fan = geodesic_fan(s, uv, 12, 8.0)
    P = s.evaluate(*uv)
    phi0 = np.arctan2(P[1], P[0])
    e_phi = np.array([-np.sin(phi0), np.cos(phi0), 0.0])
    assert fan.hit_boundary.any() and not fan.hit_boundary.all()
    for p in fan:
        n = tangent_3d(s, p)[0]
        cos_b, sin_b = n @ e_phi, n[2]
        phi = phi0 + p.s * cos_b / r
        expected = np.column_stack([r * np.cos(phi), r * np.sin(phi), P[2] + p.s * sin_b])
        np.testing.assert_allclose(p.points, expected, atol=1e-9)
        if p.hit_boundary:  # stopped on the top or bottom rim
            assert min(abs(p.points[-1, 2]), abs(p.points[-1, 2] - h)) < 1e-10
        else:
            assert 0 < p.points[:, 2].min() and p.points[:, 2].max() < h


def test_normal_sections_of_a_cylinder_are_ellipses_and_wrap_around():
    r = 1.0
    s = surfaces.cylinder(r, 8.0)
    uv = (0.05, 0.5)
    P = s.evaluate(*uv)
    rho = np.array([P[0], P[1], 0.0]) / r
    e_phi = np.array([-rho[1], rho[0], 0.0])
    for alpha in (0.9, 1.3, 2.0):
        p = normal_section(s, uv, alpha, 9.0)
        n = tangent_3d(s, p)[0]
        D = np.cross(s.normal(*uv), n)
        c = n @ e_phi
        np.testing.assert_allclose((p.points - P) @ D, 0, atol=1e-9)  # in the plane spanned by N and n
        a, b = (p.points - P) @ n, (p.points - P) @ rho
        np.testing.assert_allclose((b + r) ** 2 + (a * c) ** 2, r**2, atol=1e-9)  # ellipse, semi-axes r, r/|c|
        circumference_ok = p.length == 9.0 and not p.hit_boundary
        assert circumference_ok
        assert p.uv[:, 0].min() < 0.02 and p.uv[:, 0].max() > 0.98  # crossed the seam u = 0 = 1


def test_torus_geodesic_keeps_clairauts_constant_and_wraps():
    R, r = 2.0, 0.8
    s = surfaces.torus(R, r)
    p = geodesic(s, (0.1, 0.2), 0.7, 40.0, n_samples=2001)
    assert not p.hit_boundary and p.length == 40.0
    x = p.points
    rho = np.hypot(x[:, 0], x[:, 1])
    e_phi = np.column_stack([-x[:, 1], x[:, 0], np.zeros(len(x))]) / rho[:, None]
    cos_psi = np.einsum("kd,kd->k", tangent_3d(s, p), e_phi)  # psi: angle to the parallel
    clairaut = rho * cos_psi
    np.testing.assert_allclose(clairaut, clairaut[0], atol=1e-8)
    # it goes around the tube and around the axis, wrapping the parameters into the domain
    for axis in (0, 1):
        assert p.uv[:, axis].min() < 0.01 and p.uv[:, axis].max() > 0.99
    step = np.linalg.norm(np.diff(x, axis=0), axis=1)
    assert step.max() <= (p.s[1] - p.s[0]) * (1 + 1e-9)  # no jump at the seams


# ---------------------------------------------------------------- free-form surfaces


@pytest.mark.parametrize("fan_function", [geodesic_fan, normal_section_fan])
def test_arc_length_parametrisation(fan_function):
    s = surfaces.practical()
    fan = fan_function(s, (4.9, 2.1), 8, 4.5)
    for p in fan:
        np.testing.assert_allclose(np.linalg.norm(tangent_3d(s, p), axis=1), 1, atol=1e-8)
        chords = np.linalg.norm(np.diff(p.points, axis=0), axis=1)
        # a chord is never longer than its arc; the sampled points carry the integrator's error
        # (rtol 1e-10 on coordinates of size ~10: ~1e-9), measured excess up to 9e-11 here
        assert np.all(chords <= np.diff(p.s) + 1e-9)


def test_normal_sections_lie_in_their_plane_on_a_freeform_surface():
    s = surfaces.isodistance_sections_example()  # NURBS, three patches along v
    uv = (0.5, 0.4)
    P, N = s.evaluate(*uv), s.normal(*uv)
    for p in normal_section_fan(s, uv, 10, 4.5):
        n = tangent_3d(s, p)[0]
        np.testing.assert_allclose((p.points - P) @ np.cross(N, n), 0, atol=1e-8)
        np.testing.assert_allclose(n @ N, 0, atol=1e-12)


def test_vectorised_fan_takes_the_same_steps_as_solve_ivp_per_path():
    s = surfaces.practical()
    uv = (4.9, 2.1)
    fast = geodesic_fan(s, uv, 10, 4.5)
    slow = geodesic_fan(s, uv, 10, 4.5, vectorized=False)
    assert isinstance(fast, Fan) and len(fast) == 10
    np.testing.assert_array_equal(fast.hit_boundary, slow.hit_boundary)
    assert fast.hit_boundary.any() and not fast.hit_boundary.all()
    for a, b in zip(fast, slow):
        assert a.length == pytest.approx(b.length, abs=1e-11)
        np.testing.assert_allclose(a.uv, b.uv, atol=1e-11)
    one = geodesic(s, uv, fast.angles[3], 4.5, n_samples=101)
    np.testing.assert_allclose(one.points, fast[3].points, atol=1e-10)


def test_geodesic_across_patches_matches_a_plain_solve_ivp_reference():
    # independent of the patch-by-patch machinery: eq. 11 with the public derivatives and a tight tolerance
    s = surfaces.practical()
    (u0, u1), (v0, v1) = s.domain
    uv = (4.9, 2.1)

    def rhs(t, y):
        d = s.derivatives(np.clip(y[:1], u0, u1), np.clip(y[1:2], v0, v1))
        Gamma = christoffel(d)[0]
        return np.r_[y[2:], -np.einsum("kij,i,j->k", Gamma, y[2:], y[2:])]

    def leave(t, y):
        return min(y[0] - u0, u1 - y[0], y[1] - v0, v1 - y[1])

    leave.terminal, leave.direction = True, -1
    for alpha in (1.5, 4.0):  # the first stays inside (crossing 7 knot spans), the second leaves the domain
        _, duv = start_direction(s, uv, alpha)
        ref = solve_ivp(rhs, (0, 4.5), np.r_[uv, duv], method="DOP853", rtol=1e-12, atol=1e-13, events=leave)
        p = geodesic(s, uv, alpha, 4.5)
        assert p.hit_boundary == (ref.status == 1)
        assert p.length == pytest.approx(ref.t[-1], abs=1e-8)
        np.testing.assert_allclose(p.uv[-1], ref.y[:2, -1], atol=1e-8)
        spans = np.unique(np.floor(p.uv[:-1]).astype(int), axis=0)
        assert len(spans) >= 3  # it did cross knot lines


def test_geodesic_between_two_points():
    R = 1.5
    sphere = surfaces.sphere(R)
    a, b = (0.1, 0.4), (0.35, 0.65)
    p = geodesic_between(sphere, a, b)
    xa, xb = sphere.evaluate(*a), sphere.evaluate(*b)
    assert p.length == pytest.approx(R * np.arccos(xa @ xb / R**2), rel=1e-9)  # great-circle distance
    np.testing.assert_allclose(p.points[-1], xb, atol=1e-8)
    np.testing.assert_allclose(p.points[0], xa, atol=1e-12)
    plane = skew_plane()
    q = geodesic_between(plane, (0.1, 0.2), (0.9, 0.7), n_candidates=1)
    assert q.length == pytest.approx(np.linalg.norm(plane.evaluate(0.9, 0.7) - plane.evaluate(0.1, 0.2)), rel=1e-10)


def test_geodesic_distances_agree_with_exact_polyhedral_geodesics():
    # FlipOut (Sharp & Crane 2020, potpourri3d): exact locally shortest paths on a triangle mesh,
    # started from Dijkstra's path, so independent of our ODE.  The inscribed mesh shortens lengths
    # by O(h^2): measured 5e-6 ... 4e-5 at this resolution (2e-5 ... 2e-4 at half of it).
    pp3d = pytest.importorskip("potpourri3d")
    from scipy.spatial import cKDTree

    from lab.mesh import surface_mesh

    s = surfaces.practical()
    mesh = surface_mesh(s, 141, 141).triangulate()
    V = np.asarray(mesh.points)
    F = np.asarray(mesh.faces).reshape(-1, 4)[:, 1:]
    uv = np.asarray(mesh.point_data["uv"])
    solver = pp3d.EdgeFlipGeodesicSolver(V, F)
    for a, b in [((1.0, 1.0), (6.0, 2.0)), ((1.0, 5.5), (5.5, 1.5))]:
        ia, ib = (int(np.argmin(np.linalg.norm(uv - x, axis=1))) for x in (a, b))
        np.testing.assert_allclose(uv[[ia, ib]], [a, b], atol=1e-12)  # mesh vertices at exactly A and B
        polyline = solver.find_geodesic_path(ia, ib)
        length = np.linalg.norm(np.diff(polyline, axis=0), axis=1).sum()
        ours = geodesic_between(s, a, b, n_samples=4001)
        assert ours.length == pytest.approx(length, rel=2e-4)
        gap, _ = cKDTree(ours.points).query(polyline)
        assert gap.max() < 0.01  # the same path (mesh edges are about 0.06 long)


# ---------------------------------------------------------------- results and errors


def test_path_dense_output_and_repr():
    s = surfaces.practical()
    p = geodesic(s, (3.0, 3.0), 1.0, 2.0, n_samples=11)
    assert isinstance(p, Path) and p.s.shape == (11,) and p.uv.shape == (11, 2) and p.points.shape == (11, 3)
    uv, pts = p.at(p.s)
    np.testing.assert_allclose(uv, p.uv, atol=1e-14)
    np.testing.assert_allclose(pts, p.points, atol=1e-13)
    uv, pts = p.at([[0.5, 1.5]])
    assert uv.shape == (1, 2, 2) and pts.shape == (1, 2, 3)
    with pytest.raises(ValueError, match=r"arc lengths must lie in \[0, 2\]"):
        p.at(2.5)
    assert "geodesic" in repr(p) and "Fan(3 normal sections" in repr(normal_section_fan(s, (3.0, 3.0), 3, 1.0))


def test_paths_into_a_pole_stop_there_with_a_warning():
    s = surfaces.sphere(1.0)
    # alpha = 0 runs up the meridian into the north pole, alpha = pi down into the south pole, where
    # b_u x b_v = 0 and eqs. 7 and 11 are singular; the other paths pass the poles
    for fan_function in (geodesic_fan, normal_section_fan):
        with pytest.warns(lab.DegeneratePointWarning, match=r"stopped at a degenerate point \(b_u x b_v = 0\)"):
            fan = fan_function(s, (0.0, 0.25), 8, 3.0)
        # a pole is also the domain edge v = 0 or 1: the path stops where |b_u x b_v| / (E + G) = 1e-6,
        # or on the edge if a step jumps over that
        assert [p.end for p in fan][1:4] == [p.end for p in fan][5:] == ["length"] * 3
        assert fan[0].end == "degenerate" and fan[4].end in ("degenerate", "boundary")
        assert fan[4].hit_boundary == (fan[4].end == "boundary")
        np.testing.assert_allclose(fan[0].points[-1], [0, 0, 1], atol=1e-6)
        np.testing.assert_allclose(fan[4].points[-1], [0, 0, -1], atol=1e-6)
        assert fan[0].length == pytest.approx(0.75 * np.pi, abs=1e-6)
        for p in fan:
            np.testing.assert_allclose(np.linalg.norm(p.points - fan[0].points[0], axis=1), 2 * np.sin(p.s / 2),
                                       atol=1e-9)


def plane_with_a_hole():
    """The unit square, but its derivatives are NaN for u < 0.5 (a user's surface that is undefined there)."""

    def derivatives(u, v):
        one, zero = np.where(u < 0.5, np.nan, 1.0), np.zeros_like(u)
        second = np.zeros(u.shape + (3,))
        return lab.Derivatives(np.stack([u, v, zero], -1), np.stack([one, zero, zero], -1),
                               np.stack([zero, np.ones_like(u), zero], -1), second, second, second)

    return lab.ParametricSurface(derivatives, ((0, 1), (0, 1)), name="plane with a hole")


def test_failed_solve_raises_with_the_solvers_message():
    s = plane_with_a_hole()
    message = "{} integration failed at s = 0.3 near .* Required step size is less than spacing between numbers"
    with pytest.raises(RuntimeError, match=message.format("geodesic")):
        geodesic(s, (0.8, 0.5), np.pi / 2, 0.5)  # alpha = pi/2 heads for -x
    with pytest.raises(RuntimeError, match=message.format("normal section")):
        normal_section(s, (0.8, 0.5), np.pi / 2, 0.5)
    with pytest.raises(RuntimeError, match=message.format("geodesic")):
        geodesic_fan(s, (0.8, 0.5), 4, 0.5)


@pytest.mark.parametrize(
    "call, error, message",
    [
        (lambda s: geodesic("torus", (0.5, 0.5), 0.0, 1.0), TypeError, "surface must be a lab.Surface"),
        (lambda s: geodesic(s, (7.5, 1.0), 0.0, 1.0), ValueError, r"start point must lie in the domain \[0, 7\]"),
        (lambda s: geodesic(s, (1.0,), 0.0, 1.0), ValueError, "start point must be a pair"),
        (lambda s: geodesic(s, (1.0, 1.0), 0.0, -1.0), ValueError, "length must be a positive number"),
        (lambda s: geodesic(s, (1.0, 1.0), 0.0, np.inf), ValueError, "length must be a positive number"),
        (lambda s: geodesic(s, (1.0, 1.0), [0.0, 1.0], 1.0), ValueError, "angle must be a single number"),
        (lambda s: geodesic(s, (1.0, 1.0), np.nan, 1.0), ValueError, "angle must be finite"),
        (lambda s: geodesic(s, (1.0, 1.0), 0.0, 1.0, rtol=1e-17), ValueError, "rtol must be a finite number"),
        (lambda s: geodesic(s, (1.0, 1.0), 0.0, 1.0, atol=0), ValueError, "atol must be a positive"),
        (lambda s: geodesic_fan(s, (1.0, 1.0), 0, 1.0), ValueError, "n_angles must be an integer >= 1"),
        (lambda s: geodesic_fan(s, (1.0, 1.0), 2.5, 1.0), TypeError, "n_angles must be an integer"),
        (lambda s: normal_section(s, (1.0, 1.0), 0.0, 1.0, n_samples=1), ValueError, "n_samples must be"),
        (lambda s: polar_isodistance([], 1.0), TypeError, "fan must be a Fan or a non-empty list of Path"),
        (lambda s: geodesic_between(s, (1.0, 1.0), (1.0, 1.0)), ValueError, "A and B must be different points"),
        (lambda s: geodesic_between(s, (1.0, 1.0), (9.0, 1.0)), ValueError, "point B must lie in the domain"),
    ],
)
def test_invalid_input_is_rejected_with_a_clear_message(call, error, message):
    with pytest.raises(error, match=message):
        call(surfaces.practical())


def test_degenerate_start_and_bad_distances_are_rejected():
    with pytest.raises(ValueError, match=r"start point \(u, v\) = \(0.3, 0\) is a degenerate point"):
        geodesic(surfaces.sphere(), (0.3, 0.0), 0.0, 1.0)  # the south pole
    fan = geodesic_fan(surfaces.plane(), (0.5, 0.5), 4, 0.2)
    with pytest.raises(ValueError, match="distances must be positive finite numbers"):
        polar_isodistance(fan, [0.1, -1.0])
    other = geodesic(surfaces.plane(), (0.2, 0.5), 0.0, 0.2)
    with pytest.raises(ValueError, match="must start at the same point of the same surface"):
        polar_isodistance(list(fan) + [other], 0.1)


def test_partial_fan_gives_open_isodistance_curves():
    """A fan over part of the circle (as the explorer's angle range) never closes its isodistance curves."""
    plane = lab.surfaces.plane(10.0)
    angles = np.radians(np.linspace(0.0, 90.0, 7))
    fan = lab.geodesic_fan(plane, (0.5, 0.5), None, 2.0, angles=angles)
    assert not fan.full_circle and len(fan) == 7
    np.testing.assert_allclose([p.angle for p in fan], angles)
    (pieces,) = lab.polar_isodistance(fan, [1.5])
    assert len(pieces) == 1 and not pieces[0].closed
    # on a plane the points at distance 1.5 lie on a circle around the start
    np.testing.assert_allclose(np.linalg.norm(pieces[0].points[::8] - plane.evaluate(0.5, 0.5), axis=1), 1.5, rtol=1e-9)
    full = lab.geodesic_fan(plane, (0.5, 0.5), 8, 2.0)
    assert full.full_circle and lab.polar_isodistance(full, [1.5])[0][0].closed


def test_partial_fan_errors():
    plane = lab.surfaces.plane(10.0)
    with pytest.raises(ValueError, match="angles must increase strictly and span less than one turn"):
        lab.geodesic_fan(plane, (0.5, 0.5), None, 1.0, angles=[0.0, 7.0])
    with pytest.raises(ValueError, match=r"n_angles \(3\) must equal the number of angles given \(2\)"):
        lab.geodesic_fan(plane, (0.5, 0.5), 3, 1.0, angles=[0.0, 1.0])


def test_isodistance_figure_draws_a_png():
    from lab import figures

    s = surfaces.isodistance_sections_example()
    fan = normal_section_fan(s, (0.1, 0.5), 12, 1.0)
    image = figures.isodistance_figure(fan, polar_isodistance(fan, [0.3, 0.9]), title="t")
    assert image.data[:4] == b"\x89PNG"
    with pytest.raises(TypeError, match="fan must be a lab.Fan; got list"):
        figures.isodistance_figure(list(fan), [])
