"""Curvature against analytic values, sympy-exact values and geometric properties (lab.curvature)."""

import re
import warnings

import numpy as np
import pytest
import sympy as sp
from lab.curvature import DegeneratePointWarning, PointClass

import lab
from lab import analytic, surfaces
from tests.conftest import rotation

GRID = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 9), indexing="ij")


def curvature_quiet(surface, u, v):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DegeneratePointWarning)
        return surface.curvature(u, v)


def test_plane_is_flat(no_warnings):
    c = surfaces.plane(3.0).curvature(*GRID)
    for field in (c.K, c.H, c.k1, c.k2):
        np.testing.assert_array_equal(field, 0.0)
    assert np.all(c.classify() == PointClass.FLAT)


@pytest.mark.parametrize("radius", [0.5, 2.0, 7.0])
def test_sphere(radius):
    s = surfaces.sphere(radius)
    c = curvature_quiet(s, *GRID)
    # 1e-9 relative: the poles are limits from inside (see test_degenerate_*); elsewhere it is ~1e-15.
    np.testing.assert_allclose(c.K, 1 / radius**2, rtol=1e-9)
    np.testing.assert_allclose(np.abs(c.H), 1 / radius, rtol=1e-9)
    np.testing.assert_allclose(c.k1, c.k2, atol=1e-8 / radius)
    interior = ~c.degenerate
    np.testing.assert_allclose(c.K[interior], 1 / radius**2, rtol=1e-13)
    np.testing.assert_allclose(np.linalg.norm(s.evaluate(*GRID), axis=-1), radius, rtol=1e-14)
    assert np.all(c.classify() == PointClass.ELLIPTIC)


def test_cylinder(no_warnings):
    r = 1.5
    c = surfaces.cylinder(r, 4.0).curvature(*GRID)
    np.testing.assert_allclose(c.K, 0.0, atol=1e-14)
    np.testing.assert_allclose(np.abs(c.H), 1 / (2 * r), rtol=1e-13)
    np.testing.assert_allclose(np.abs(c.k1 + c.k2), 1 / r, rtol=1e-13)
    assert np.all(c.classify() == PointClass.PARABOLIC)


def test_torus_signs_and_values(no_warnings):
    R, r = 3.0, 1.0
    t = surfaces.torus(R, r)
    U, V = np.meshgrid(np.linspace(0, 1, 33), np.linspace(0, 1, 17), indexing="ij")
    c = t.curvature(U, V)
    p = t.evaluate(U, V)
    cos_t = (np.hypot(p[..., 0], p[..., 1]) - R) / r  # cosine of the angle around the tube
    np.testing.assert_allclose(c.K, cos_t / (r * (R + r * cos_t)), atol=1e-14)
    np.testing.assert_allclose(np.abs(c.H), np.abs((R + 2 * r * cos_t) / (2 * r * (R + r * cos_t))), rtol=1e-13)
    outside, inside = cos_t > 1e-6, cos_t < -1e-6
    assert np.all(c.K[outside] > 0) and np.all(c.K[inside] < 0)
    # u = 1/4 and 3/4 are the top and bottom rims (tube angle 90 and 270 degrees): K = 0 there.
    rims = t.curvature(np.array([0.25, 0.75])[:, None], np.linspace(0, 1, 7))
    np.testing.assert_allclose(rims.K, 0.0, atol=1e-15)
    assert np.all(rims.classify() == PointClass.PARABOLIC)
    assert np.all(c.classify()[outside] == PointClass.ELLIPTIC)
    assert np.all(c.classify()[inside] == PointClass.HYPERBOLIC)


@pytest.mark.parametrize("c0", [1.0, 2.5])
def test_catenoid(c0, no_warnings):
    s = surfaces.catenoid(c0)
    U, V = s.grid(9, 11)
    c = s.curvature(U, V)
    np.testing.assert_allclose(c.H, 0.0, atol=1e-14 / c0)
    np.testing.assert_allclose(c.K, -1 / (c0**2 * np.cosh(V / c0) ** 4), rtol=1e-12)
    waist = s.curvature(1.0, 0.0)
    assert waist.K == pytest.approx(-1 / c0**2, rel=1e-14)
    np.testing.assert_allclose(c.k1, -c.k2, atol=1e-14)


@pytest.mark.parametrize("m,n", [(2, 3), (3, 2), (3, 5), (1, 3)])
def test_random_nets_against_sympy_exact(rng, m, n):
    P = analytic.random_rational_net(rng, m, n)
    s = lab.BezierSurface(P)
    points = [(0, 0), (0, 1), (1, 0), (1, 1), (0.375, 0.625), (0.8125, 0.25)]
    for u, v in points:
        exact = analytic.to_float(analytic.bezier_curvature_exact(P, u, v))
        got = s.curvature(u, v)
        for name in ("K", "H", "k1", "k2"):
            e, g = getattr(exact, name), float(getattr(got, name))
            assert abs(g - e) <= 1e-12 * max(1.0, abs(e)), f"{name} at {(u, v)} of {m}x{n}: {g} vs exact {e}"


def test_rational_patch_against_sympy_quotient(rng):
    """A rational patch against the curvature of its sympy quotient x(u, v) = sum w P B / sum w B."""
    m, n = 2, 3
    P = analytic.random_rational_net(rng, m, n)
    w = rng.integers(1, 9, size=(m + 1, n + 1)) / 4
    u, v = sp.symbols("u v")
    B = lambda k, i, t: sp.binomial(k, i) * t**i * (1 - t) ** (k - i)
    den = sum(sp.Rational(w[i, j]) * B(m, i, u) * B(n, j, v) for i in range(m + 1) for j in range(n + 1))
    xyz = [
        sum(sp.Rational(w[i, j]) * sp.Rational(P[i, j, c]) * B(m, i, u) * B(n, j, v) for i in range(m + 1) for j in range(n + 1))
        / den
        for c in range(3)
    ]
    s = lab.BezierSurface(P, w)
    for point in ((sp.Rational(1, 3), sp.Rational(3, 4)), (0, 1), (1, sp.Rational(1, 2))):
        exact = analytic.to_float(analytic.exact_curvature(xyz, (u, v), point))
        got = s.curvature(float(point[0]), float(point[1]))
        for name in ("K", "H", "k1", "k2"):
            assert float(getattr(got, name)) == pytest.approx(getattr(exact, name), rel=1e-12, abs=1e-13), name


def test_rigid_motion_keeps_curvature(rng):
    P = rng.normal(size=(4, 4, 3))
    s = lab.BezierSurface(P)
    Rm = rotation(rng)
    moved = lab.BezierSurface(P @ Rm.T + rng.normal(size=3))
    a, b = s.curvature(*GRID), moved.curvature(*GRID)
    for name in ("K", "H", "k1", "k2"):
        np.testing.assert_allclose(getattr(b, name), getattr(a, name), rtol=1e-9, atol=1e-9)


def test_swapping_u_and_v_flips_H_only(rng):
    s = lab.BezierSurface(rng.normal(size=(3, 5, 3)), weights=rng.uniform(0.5, 2, size=(3, 5)))
    t = s.swap_uv()
    U, V = GRID
    a, b = s.curvature(U, V), t.curvature(V, U)
    np.testing.assert_allclose(b.K, a.K, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(b.H, -a.H, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(b.k1, -a.k2, rtol=1e-10, atol=1e-12)


def test_umbilics_have_no_nan_and_ordered_principal_curvatures(rng):
    """On spheres H^2 - K is rounding noise, sometimes negative: k1 >= k2 without NaN anyway."""
    U, V = np.meshgrid(np.linspace(0.01, 0.99, 40), np.linspace(0.01, 0.99, 40), indexing="ij")
    c = surfaces.sphere(3.0).curvature(U, V)
    assert np.any(c.H**2 - c.K < 0), "test needs umbilics where rounding makes H^2 - K negative"
    assert not np.any(np.isnan(c.k1)) and not np.any(np.isnan(c.k2))
    assert np.all(c.k1 >= c.k2)
    np.testing.assert_allclose(c.k1, -1 / 3, rtol=1e-7)


def test_degenerate_sphere_pole_is_limit_with_mask_and_one_warning():
    s = surfaces.sphere(2.0)
    u = np.linspace(0, 1, 5)
    v = np.array([0.0, 0.5, 1.0])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        c = s.curvature(u[:, None], v[None, :])
    messages = [w for w in caught if issubclass(w.category, DegeneratePointWarning)]
    assert len(messages) == 1
    assert "10 degenerate point(s)" in str(messages[0].message)
    np.testing.assert_array_equal(c.degenerate, np.isin(v, [0, 1])[None, :].repeat(5, 0))
    np.testing.assert_allclose(c.K[c.degenerate], 0.25, rtol=1e-9)
    np.testing.assert_allclose(c.H[c.degenerate], -0.5, rtol=1e-9)
    assert not np.any(np.isnan(c.K))


def test_degenerate_without_finite_limit_is_reported_not_silent():
    cone = surfaces.cone()
    with pytest.warns(DegeneratePointWarning, match="at 3 of them the curvature has no finite limit and is NaN"):
        c = cone.curvature(np.array([0.0, 0.5, 1.0]), 1.0)
    assert np.all(c.degenerate)
    assert np.all(np.isnan(c.H))
    # away from the apex the cone is an ordinary developable surface
    inner = cone.curvature(0.5, 0.5)
    assert abs(float(inner.K)) < 1e-12 and not inner.degenerate


def test_sine_wave_centre_limit(no_warnings):
    A, w = 0.5, 1.0
    s = surfaces.sine_wave(A, w)
    with pytest.warns(DegeneratePointWarning, match="1 degenerate point"):
        c = s.curvature(0.0, 1.0)
    assert float(c.K) == pytest.approx((A * w**2) ** 2, rel=1e-9)
    assert abs(float(c.H)) == pytest.approx(A * w**2, rel=1e-9)


def test_strain_energy_and_fundamental_forms(rng):
    s = lab.BezierSurface(rng.normal(size=(3, 3, 3)))
    c = s.curvature(*GRID)
    np.testing.assert_allclose(c.strain_energy, 4 * c.H**2 - 2 * c.K, rtol=1e-10, atol=1e-12)
    ff = s.fundamental_forms(0.3, 0.6)
    d = s.derivatives(0.3, 0.6)
    assert ff.E == pytest.approx(d.bu @ d.bu) and ff.G == pytest.approx(d.bv @ d.bv)
    np.testing.assert_allclose(ff.N, s.normal(0.3, 0.6))
    assert float(ff.N @ d.bu) == pytest.approx(0, abs=1e-14)


def test_parametric_surface_matches_sympy_exact():
    u, v = sp.symbols("u v", real=True)
    xyz = ((3 + sp.cos(u)) * sp.cos(v), (3 + sp.cos(u)) * sp.sin(v), sp.sin(u) + u * v / 5)
    s = lab.ParametricSurface.from_sympy(xyz, (u, v), ((0, 2 * sp.pi), (0, 2 * sp.pi)))
    for point in ((sp.Rational(1, 2), sp.Rational(1, 3)), (sp.pi / 3, 2)):
        exact = analytic.to_float(analytic.exact_curvature(xyz, (u, v), point))
        got = s.curvature(float(point[0]), float(point[1]))
        for name in ("K", "H", "k1", "k2"):
            assert float(getattr(got, name)) == pytest.approx(getattr(exact, name), rel=1e-12), name


def test_classify_tolerance_and_errors():
    k1 = np.array([1.0, 1.0, 1e-12, 1.0, 0.0])
    k2 = np.array([0.5, -1.0, -1e-12, 1e-12, -2.0])
    np.testing.assert_array_equal(
        lab.curvature.classify(k1, k2),
        [PointClass.ELLIPTIC, PointClass.HYPERBOLIC, PointClass.FLAT, PointClass.PARABOLIC, PointClass.PARABOLIC],
    )
    with pytest.raises(ValueError, match="tol must be >= 0; got -1"):
        lab.curvature.classify(k1, k2, tol=-1)
    # the classes' labels for people, in the lab's language; names and values (what code compares) stay
    assert [c.label for c in PointClass] == ["hyperbolic", "flat", "parabolic", "elliptic"]
    with lab.i18n.using("de"):
        assert [c.label for c in PointClass] == ["hyperbolisch", "flach", "parabolisch", "elliptisch"]
        assert [(c.name, int(c)) for c in PointClass] == [("HYPERBOLIC", -1), ("FLAT", 0), ("PARABOLIC", 1),
                                                           ("ELLIPTIC", 2)]


def test_parametric_surface_errors():
    u, v = sp.symbols("u v")
    with pytest.raises(ValueError, match="xyz must hold three coordinate expressions; got 2"):
        lab.ParametricSurface.from_sympy((u, v), (u, v), ((0, 1), (0, 1)))
    with pytest.raises(ValueError, match=r"domain in v must be a finite interval with min < max; got \(1.0, 0.0\)"):
        lab.ParametricSurface.from_sympy((u, v, u * v), (u, v), ((0, 1), (1, 0)))
    with pytest.raises(TypeError, match="derivatives must be callable; got int"):
        lab.ParametricSurface(3, ((0, 1), (0, 1)))


def test_records_print_plain_numbers():
    """Notebooks show ``Curvature(K=0.25, …)``, not ``np.float64(0.25)`` reprs."""
    sphere = lab.surfaces.sphere(2.0)
    text = repr(sphere.curvature(0.3, 0.4))
    assert "np.float64" not in text and "np.False_" not in text
    assert text.startswith("Curvature(K=0.2499999999999999, H=-0.4999") and "degenerate=False" in text
    arrays = repr(sphere.curvature(np.array([0.3, 0.6]), 0.4))
    assert "K=[0.25, 0.25]" in arrays and "array(" not in arrays
    assert "np.float64" not in repr(sphere.fundamental_forms(0.3, 0.4))


def test_records_display_in_the_languages_notation():
    """A notebook's display of a record (IPython's pretty printer): Python's repr in English; in German the same
    fields with decimal commas, so semicolons between them (issue 36)."""
    from IPython.lib.pretty import pretty

    sphere = lab.surfaces.sphere(2.0)
    one, two = sphere.curvature(0.3, 0.4), sphere.curvature(np.array([0.3, 0.6]), 0.4)
    assert pretty(one) == repr(one) and pretty(two) == repr(two)
    with lab.i18n.using("de"):
        texts = [pretty(one), pretty(two), pretty(sphere.fundamental_forms(0.3, 0.4)),
                 pretty(sphere.curvature(0.3, 0.4, directions=True))]
    assert texts[0].startswith("Curvature(K=0,2499999999999999; H=-0,4999") and texts[0].endswith("; degenerate=False)")
    assert "K=[0,25; 0,25]" in texts[1] and texts[3].startswith("CurvatureDirections(K=0,2499999999999999; ")
    assert not any(re.search(r"\d\.\d", t) for t in texts), texts



def test_random_nets_of_the_checks_have_no_degenerate_point():
    """The checks' random nets: b_u x b_v != 0 at every corner (a draw with a degenerate corner once made the
    visualize_curvature check raise instead of report); _regular_grid holds, which covers every subpatch too."""
    from lab.geometry import analytic

    rng = np.random.default_rng(20261201)
    for _ in range(400):
        m, n = (int(k) for k in rng.integers(1, 5, 2))
        P = analytic.random_rational_net(rng, m, n)
        assert analytic._regular_grid(P[..., :2]), P
        for i in (0, m):
            for j in (0, n):
                bu = m * (P[i, j] - P[i - 1, j]) if i else m * (P[1, j] - P[0, j])
                bv = n * (P[i, j] - P[i, j - 1]) if j else n * (P[i, 1] - P[i, 0])
                assert np.linalg.norm(np.cross(bu, bv)) > 0.1, (P, i, j)
