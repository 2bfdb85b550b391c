"""The named example surfaces (lab.surfaces)."""

import numpy as np
import pytest
from lab.curvature import PointClass

import lab
from lab import surfaces


def test_practical_is_exactly_the_practicals_example():
    s = surfaces.practical()
    assert isinstance(s, lab.BSplineSurface)
    assert s.degree == (3, 3)
    expected_knots = [0, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7]
    np.testing.assert_array_equal(s.knots_u, expected_knots)
    np.testing.assert_array_equal(s.knots_v, expected_knots)
    P = s.control_points
    assert P.shape == (10, 10, 3)
    np.testing.assert_array_equal(P[:, 0, 1], np.arange(-5, 5))  # y along the first index (u)
    np.testing.assert_array_equal(P[0, :, 0], np.arange(-5, 5))  # x along the second index (v)
    x, y = 4.0, -5.0  # P[0, 9]: the first row (y = -5), the last column (x = 4)
    assert P[0, 9, 2] == pytest.approx(x**2 / 5 + x * y / 4 + 10 / (1 + x**2 + y**2) + y / 2, rel=1e-15)
    assert P[5, 5, 2] == pytest.approx(10.0)  # the bump at the origin
    assert len(s.to_bezier_patches()) == 49
    assert len(s.to_bezier_patches().refine(1)) == 196


def test_practical_is_built_like_the_course_program():
    """The course program: ``[[point(x, y, f(x, y)) for x in range(-5, 5)] for y in range(-5, 5)]``, outer index = u.

    So u runs along y, the normal b_u x b_v points down, and at the bump's top
    H > 0 and k1 > 0 (the practical's course program: H ~ +6.08, k1 ~ +6.64, N_z ~ -0.89).
    """
    f = surfaces.practical_height
    course_net = np.array([[(x, y, f(x, y)) for x in range(-5, 5)] for y in range(-5, 5)], dtype=float)
    s = surfaces.practical()
    np.testing.assert_array_equal(s.control_points, course_net)
    # u runs along y, v along x
    du = s.evaluate(4.5, 3.0) - s.evaluate(3.5, 3.0)
    dv = s.evaluate(3.0, 4.5) - s.evaluate(3.0, 3.5)
    assert du[0] == pytest.approx(0, abs=1e-12) and du[1] > 0.9
    assert dv[1] == pytest.approx(0, abs=1e-12) and dv[0] > 0.9
    # at the bump's top, (u, v) = (4, 4), x = y = 0: a cap whose normal points down, H > 0
    np.testing.assert_allclose(s.evaluate(4.0, 4.0)[:2], [0, 0], atol=1e-12)
    N = s.normal(4.0, 4.0)
    c = s.curvature(4.0, 4.0)
    assert N[2] == pytest.approx(-2 / np.sqrt(5), rel=1e-12)  # (0, 1/2, -1)/|.|: -0.894
    assert float(c.H) == pytest.approx(6.0821, abs=5e-5) and float(c.H) > 0
    assert float(c.k1) == pytest.approx(6.6362, abs=5e-5)
    assert float(c.k2) == pytest.approx(5.5280, abs=5e-5)
    assert float(c.K) == pytest.approx(float(c.k1 * c.k2), rel=1e-12)
    # the normal points down everywhere (x depends on v only, y on u only: the z-component is -x_v y_u)
    U, V = np.meshgrid(np.linspace(0, 7, 15), np.linspace(0, 7, 15), indexing="ij")
    assert np.all(s.normal(U, V)[..., 2] < 0)
    # the old, transposed net (x along u) has the opposite orientation: same K, opposite H
    t = s.swap_uv()
    np.testing.assert_array_equal(t.control_points, s.control_points.transpose(1, 0, 2))
    ct = t.curvature(4.0, 4.0)
    assert float(ct.K) == pytest.approx(float(c.K), rel=1e-12)
    assert float(ct.H) == pytest.approx(-float(c.H), rel=1e-12)
    assert t.normal(4.0, 4.0)[2] > 0


def test_hood_has_a_flat_spot_and_a_crease():
    h = surfaces.hood()
    # the last knot span in both directions is the flat spot: K = H = 0 exactly (up to rounding)
    U, V = np.meshgrid(np.linspace(4, 5, 7), np.linspace(4, 5, 7), indexing="ij")
    c = h.curvature(U, V)
    np.testing.assert_allclose(c.K, 0, atol=1e-12)
    np.testing.assert_allclose(c.H, 0, atol=1e-10)
    assert np.all(c.classify() == PointClass.FLAT)
    # the crease: the curvature across it jumps at the double knot v = 3 (C1, not C2)
    eps = 1e-9
    left, right = h.curvature(2.0, 3 - eps), h.curvature(2.0, 3 + eps)
    assert abs(float(left.H) - float(right.H)) > 0.1
    # elsewhere it is C2: no jump at the simple knot v = 2
    a, b = h.curvature(2.0, 2 - eps), h.curvature(2.0, 2 + eps)
    assert abs(float(a.H) - float(b.H)) < 1e-5
    # ... and the crease is where |H| is largest across the hood
    v = np.linspace(0, 5, 501)
    H = h.curvature(2.0, v).H
    assert abs(v[np.argmax(np.abs(H))] - 3.0) < 0.05


def test_saddles():
    c = surfaces.saddle().curvature(*np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5)))
    assert np.all(c.K < 0)
    # z = x^2 - y^2 at the origin: k1 = 2, k2 = -2
    centre = surfaces.saddle().curvature(0.5, 0.5)
    assert float(centre.K) == pytest.approx(-4.0, rel=1e-14)
    np.testing.assert_allclose(surfaces.saddle().evaluate(0.75, 0.25), [0.5, -0.5, 0.0], atol=1e-15)
    monkey = surfaces.monkey_saddle()
    np.testing.assert_allclose(monkey.evaluate(0.75, 0.9)[2], 0.5**3 - 3 * 0.5 * 0.8**2, atol=1e-14)
    m = monkey.curvature(0.5, 0.5)
    assert int(lab.curvature.classify(m.k1, m.k2)) == PointClass.FLAT
    assert float(monkey.curvature(0.7, 0.5).K) < 0


def test_sine_wave_rings_alternate():
    """K = z' z'' / (rho (1 + z'^2)^2) for z = A cos(rho): the sign changes every quarter wave."""
    s = surfaces.sine_wave(0.5, 1.0)
    rho = np.array([np.pi / 4, 3 * np.pi / 4, 5 * np.pi / 4, np.pi])
    K = s.curvature(rho, 0.5).K
    assert K[0] > 0 and K[1] < 0 and K[2] > 0
    assert abs(K[3]) < 1e-15  # the trough circle is parabolic
    r = rho[:3]
    z1, z2 = -0.5 * np.sin(r), -0.5 * np.cos(r)
    np.testing.assert_allclose(K[:3], z1 * z2 / (r * (1 + z1**2) ** 2), rtol=1e-13)


def test_isodistance_examples_match_the_paper_description():
    a = surfaces.isodistance_sections_example()
    assert a.control_points.shape == (4, 6, 3) and a.degree == (3, 3) and a.weights is not None
    _nets, _, iu, iv = a.bezier_nets()
    assert (len(iu), len(iv)) == (1, 3)
    b = surfaces.isodistance_geodesics_example()
    assert b.control_points.shape == (4, 4, 3) and b.degree == (3, 3) and b.weights is not None
    # big enough for the paper's geodesic distances up to 20 from x(0.7, 0.3)
    corners = b.evaluate(np.array([0, 1]), np.array([[0], [1]]))
    p = b.evaluate(0.7, 0.3)
    assert np.all(np.linalg.norm(corners - p, axis=-1) > 12)


@pytest.mark.parametrize("name", sorted(surfaces.REGISTRY))
def test_every_registered_surface_is_regular_inside(name):
    s = surfaces.REGISTRY[name]()
    (u0, u1), (v0, v1) = s.domain
    U, V = np.meshgrid(np.linspace(u0, u1, 7)[1:-1], np.linspace(v0, v1, 7)[1:-1], indexing="ij")
    c = s.curvature(U, V)
    assert not c.degenerate.any()
    assert np.all(np.isfinite(c.K)) and np.all(c.k1 >= c.k2)


def test_factory_errors():
    with pytest.raises(ValueError, match="radius must be a positive number; got -1"):
        surfaces.sphere(-1)
    with pytest.raises(ValueError, match="torus needs R > r > 0; got R=1.0, r=2.0"):
        surfaces.torus(1, 2)
    with pytest.raises(ValueError, match="r must be a positive number; got 0"):
        surfaces.cylinder(0, 1)
