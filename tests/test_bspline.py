"""B-spline / NURBS evaluation, knot insertion and Bézier extraction (lab.bspline)."""

import numpy as np
import pytest
from scipy.interpolate import BSpline

import lab
from lab import bspline

CLAMPED = np.array([0, 0, 0, 0, 1, 2, 2.5, 4, 4, 4, 4], dtype=float)  # 7 control points, cubic
UNCLAMPED = np.arange(-3, 8, dtype=float)  # 7 control points, cubic, uniform


@pytest.mark.parametrize("knots", [CLAMPED, UNCLAMPED], ids=["clamped", "unclamped"])
def test_basis_derivatives_match_scipy(knots):
    p = 3
    lo, hi = bspline.domain(knots, p)
    t = np.linspace(lo, hi, 37)
    span = bspline.find_span(knots, p, t)
    N = bspline.basis_derivatives(knots, p, span, t, 2)
    ref = BSpline(knots, np.eye(len(knots) - p - 1), p)
    for r in range(3):
        dense = np.zeros((len(t), len(knots) - p - 1))
        for k in range(len(t)):
            dense[k, span[k] - p : span[k] + 1] = N[k, r]
        np.testing.assert_allclose(dense, ref(t, nu=r), atol=1e-12, err_msg=f"derivative {r}")
    np.testing.assert_allclose(N[:, 0].sum(axis=1), 1.0, atol=1e-14)  # partition of unity


def test_find_span_at_ends_and_interior_knots():
    assert bspline.find_span(CLAMPED, 3, 0.0) == 3
    assert bspline.find_span(CLAMPED, 3, 4.0) == 6  # the right end belongs to the last span
    assert bspline.find_span(CLAMPED, 3, 2.0) == 5
    assert bspline.find_span(CLAMPED, 3, 1.999) == 4


def _surface(rng, weights=False, ku=CLAMPED, kv=None):
    kv = np.array([0, 0, 0, 1, 3, 3, 3], dtype=float) if kv is None else kv  # quadratic, 4 control points
    P = rng.normal(size=(len(ku) - 4, len(kv) - 3, 3))
    w = rng.uniform(0.5, 2.0, size=P.shape[:2]) if weights else None
    return lab.BSplineSurface(P, ku, kv, 3, 2, weights=w)


def test_surface_matches_scipy_tensor_product(rng):
    s = _surface(rng)
    u = np.linspace(0, 4, 9)
    v = np.linspace(0, 3, 7)
    U, V = np.meshgrid(u, v, indexing="ij")
    Bu = BSpline(s.knots_u, np.eye(7), 3)
    Bv = BSpline(s.knots_v, np.eye(4), 2)
    for name, (du, dv) in zip(("b", "bu", "bv", "buu", "buv", "bvv"), lab.bezier.DERIVATIVE_ORDERS):
        ref = np.einsum("ai,bj,ijd->abd", Bu(u, nu=du), Bv(v, nu=dv), s.control_points)
        np.testing.assert_allclose(getattr(s.derivatives(U, V), name), ref, atol=1e-12, err_msg=name)


@pytest.mark.parametrize("weights", [False, True], ids=["B-spline", "NURBS"])
def test_knot_insertion_reproduces_surface(rng, weights):
    s = _surface(rng, weights)
    U, V = np.meshgrid(np.linspace(0, 4, 13), np.linspace(0, 3, 11), indexing="ij")
    ref = s.evaluate(U, V)
    for t, direction, times in ((1.5, "u", 1), (2.0, "u", 2), (0.5, "v", 1), (2.0, "v", 2)):
        refined = s.insert_knot(t, direction, times)
        n_before = s.control_points.shape[0 if direction == "u" else 1]
        assert refined.control_points.shape[0 if direction == "u" else 1] == n_before + times
        np.testing.assert_allclose(refined.evaluate(U, V), ref, atol=1e-13)
    # curvature is unchanged too
    np.testing.assert_allclose(s.insert_knot(1.5).curvature(U, V).K, s.curvature(U, V).K, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("weights", [False, True], ids=["B-spline", "NURBS"])
def test_bezier_extraction_reproduces_surface(rng, weights):
    s = _surface(rng, weights)
    nets, w, iu, iv = s.bezier_nets()
    assert nets.shape == (4, 2, 4, 3, 3)  # spans [0,1],[1,2],[2,2.5],[2.5,4] x [0,1],[1,3]
    assert iu == [(0.0, 1.0), (1.0, 2.0), (2.0, 2.5), (2.5, 4.0)]
    assert iv == [(0.0, 1.0), (1.0, 3.0)]
    t = np.linspace(0, 1, 5)
    T, S = np.meshgrid(t, t, indexing="ij")
    for a, (u0, u1) in enumerate(iu):
        for b, (v0, v1) in enumerate(iv):
            wab = None if w is None else w[a, b]
            got = lab.bezier.evaluate(nets[a, b], T, S, wab)
            ref = s.evaluate(u0 + (u1 - u0) * T, v0 + (v1 - v0) * S)
            np.testing.assert_allclose(got, ref, atol=1e-13)


def test_unclamped_surface_to_bezier(rng):
    s = _surface(rng, False, ku=UNCLAMPED, kv=np.arange(7, dtype=float))
    assert s.domain == ((0.0, 4.0), (2.0, 4.0))
    patches = s.to_bezier_patches()
    assert len(patches) == 4 * 2
    t = np.linspace(0, 1, 4)
    got = patches.evaluate(t, t)  # (8, 4, 3)
    ref = s.evaluate(np.array([0, 1, 2, 3])[:, None, None] + t, 2 + np.array([0, 1])[None, :, None] + t)
    np.testing.assert_allclose(got, ref.reshape(8, 4, 3), atol=1e-13)


def test_continuity_across_simple_knots(rng):
    """A cubic with simple knots is C2: second derivatives agree from both sides of u = 1."""
    s = _surface(rng)
    eps = 1e-7
    left = s.derivatives(1 - eps, 0.7)
    right = s.derivatives(1 + eps, 0.7)
    np.testing.assert_allclose(left.buu, right.buu, atol=1e-5)
    np.testing.assert_allclose(left.b, right.b, atol=1e-6)


def test_validation_messages(rng):
    P = rng.normal(size=(7, 4, 3))
    kv = [0, 0, 0, 1, 3, 3, 3]
    with pytest.raises(ValueError, match=r"knot vector in u must have 11 knots \(7 control points \+ degree 3 \+ 1\); got 10"):
        lab.BSplineSurface(P, CLAMPED[:-1], kv, 3, 2)
    with pytest.raises(ValueError, match="knot vector in v must be non-decreasing"):
        lab.BSplineSurface(P, CLAMPED, [0, 0, 0, 3, 1, 3, 3], 3, 2)
    with pytest.raises(ValueError, match="knot vector in u must contain only finite values"):
        lab.BSplineSurface(P, np.r_[CLAMPED[:-1], np.inf], kv, 3, 2)
    with pytest.raises(ValueError, match=r"a knot may be repeated at most degree \+ 1 = 3 times; got 4"):
        lab.BSplineSurface(P, CLAMPED, [0, 0, 0, 0, 3, 3, 3], 3, 2)
    with pytest.raises(ValueError, match=r"weights must have shape \(7, 4\)"):
        lab.BSplineSurface(P, CLAMPED, kv, 3, 2, weights=np.ones((4, 7)))
    with pytest.raises(ValueError, match="weights must be positive"):
        lab.BSplineSurface(P, CLAMPED, kv, 3, 2, weights=np.zeros((7, 4)))
    with pytest.raises(TypeError, match="degree_u must be an integer; got float 3.0"):
        lab.BSplineSurface(P, CLAMPED, kv, 3.0, 2)
    with pytest.raises(ValueError, match=r"knot vector in u has an empty domain"):
        lab.BSplineSurface(P[:4], [0, 0, 0, 1, 1, 2, 2, 2], kv, 3, 2)
    s = lab.BSplineSurface(P, CLAMPED, kv, 3, 2)
    with pytest.raises(ValueError, match=r"v must lie in the domain \[0, 3\]; got values in \[-1, -1\]"):
        s.evaluate(1.0, -1.0)
    with pytest.raises(ValueError, match=r"knot to insert must lie in the domain \[0, 4\]; got 5"):
        s.insert_knot(5.0)
    with pytest.raises(ValueError, match="knot 4 already has multiplicity 4; at most degree \\+ 1 = 4 is allowed"):
        s.insert_knot(4.0)
    with pytest.raises(ValueError, match="unknown direction 'w'"):
        s.insert_knot(1.0, "w")


@pytest.mark.parametrize("weights", [False, True], ids=["B-spline", "NURBS"])
def test_third_derivatives_match_scipy_and_the_quotient_rule(rng, weights):
    """BSplineSurface.third_derivatives (what G3 across a CAD model's face edges compares): a non-rational spline
    against scipy's tensor product of the basis functions' third derivatives; a NURBS against the same for its
    homogeneous form A = (w S, w), then S_uuu = (A_uuu - 3 w_u S_uu - 3 w_uu S_u - w_uuu S) / w and its mixed
    analogues (Leibniz), written out here by hand.  Cubic in u (interior knots: the third derivative jumps there,
    the span after the knot is taken, as find_span does), quadratic in v (its third derivatives are 0)."""
    s = _surface(rng, weights)
    u = np.array([0.1, 0.7, 1.0, 1.9, 2.5, 3.3, 4.0])
    v = np.array([0.0, 0.4, 1.0, 2.2, 3.0, 1.7, 2.9])
    Bu, Bv = BSpline(s.knots_u, np.eye(7), 3), BSpline(s.knots_v, np.eye(4), 2)
    right = lambda B, t, nu: np.where(np.isin(t, B.t[B.k + 1:-B.k - 1])[:, None],  # at a knot: the span after it
                                      B(np.nextafter(t, np.inf), nu=nu), B(t, nu=nu))
    w = np.ones(s.control_points.shape[:2]) if s.weights is None else s.weights
    Pw = np.concatenate([s.control_points * w[..., None], w[..., None]], axis=-1)
    A = {(a, b): np.einsum("ki,kj,ijd->kd", right(Bu, u, a), right(Bv, v, b) if b <= 2 else 0 * Bv(v), Pw)
         for a in range(4) for b in range(4 - a)}
    W = {k: x[:, 3:] for k, x in A.items()}
    S = {(0, 0): A[0, 0][:, :3] / W[0, 0]}
    from math import comb
    for total in range(1, 4):
        for a in range(total + 1):
            b = total - a
            x = A[a, b][:, :3] - sum(comb(a, i) * comb(b, j) * W[i, j] * S[a - i, b - j]
                                     for i in range(a + 1) for j in range(b + 1) if i or j)
            S[a, b] = x / W[0, 0]
    got = s.third_derivatives(u, v)
    for name, key, x in zip(("buuu", "buuv", "buvv", "bvvv"), ((3, 0), (2, 1), (1, 2), (0, 3)), got):
        scale = np.abs(S[key]).max() + 1.0
        np.testing.assert_allclose(x, S[key], atol=1e-12 * scale, rtol=0, err_msg=name)
    assert np.all(got[3] == 0) or weights  # quadratic in v: no third derivative without weights


def test_third_derivatives_of_a_nurbs_match_opencascade(rng):
    """A biquartic NURBS with interior knots (simple: C3 there) against Geom_BSplineSurface.D3 of the same
    control points, weights and knots, at random points and on the knot lines: 1e-11 of the largest component."""
    pytest.importorskip("OCP")
    from OCP.gp import gp_Pnt, gp_Vec

    from tests.occ_support import occt_surface

    knots = [0.0] * 5 + [0.3, 0.55] + [1.0] * 5
    P = rng.normal(size=(7, 7, 3))
    s = lab.BSplineSurface(P, knots, knots, 4, 4, weights=rng.uniform(0.5, 2.0, size=(7, 7)))
    occ = occt_surface(s)
    u = np.concatenate([rng.uniform(0, 1, 20), [0.3, 0.55, 0.3, 0.0, 1.0]])
    v = np.concatenate([rng.uniform(0, 1, 20), [0.55, 0.3, 0.0, 1.0, 1.0]])
    got = np.stack(s.third_derivatives(u, v), axis=1)  # (points, 4, 3)
    for k in range(len(u)):
        vectors = [gp_Vec() for _ in range(9)]
        occ.D3(float(u[k]), float(v[k]), gp_Pnt(), *vectors)
        ref = np.array([[x.X(), x.Y(), x.Z()] for x in (vectors[5], vectors[7], vectors[8], vectors[6])])
        np.testing.assert_allclose(got[k], ref, atol=1e-11 * np.abs(ref).max(), rtol=0, err_msg=f"({u[k]}, {v[k]})")
