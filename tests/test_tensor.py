"""Chunked tensor-product evaluation (lab.tensor): the fast paths against a slow reference, grids, memory."""

import numpy as np
import pytest
from lab.bezier import DERIVATIVE_ORDERS, homogeneous
from lab.curvature import from_derivatives
from lab.derivatives import Derivatives, from_homogeneous

import lab
from lab import bspline, surfaces, tensor
from tests.measure import traced_peak


def naive_derivatives(s, u, v):
    """The slow, obviously correct reference: A2.3 basis functions, every point's control points gathered, einsum."""
    P, tu, tv, p, q = s._args()
    Pw = homogeneous(P, s.weights)
    uf, vf = np.ravel(u), np.ravel(v)
    su, sv = bspline.find_span(tu, p, uf), bspline.find_span(tv, q, vf)
    Nu, Nv = bspline.basis_derivatives(tu, p, su, uf, 2), bspline.basis_derivatives(tv, q, sv, vf, 2)
    iu = su[:, None] - p + np.arange(p + 1)
    iv = sv[:, None] - q + np.arange(q + 1)
    local = Pw[iu[:, :, None], iv[:, None, :]]
    D = Derivatives(*(np.einsum("ki,kj,kijd->kd", Nu[:, a], Nv[:, b], local) for a, b in DERIVATIVE_ORDERS))
    return D if s.weights is None else from_homogeneous(D)


def random_nurbs(rng):
    """A bicubic-by-quadratic NURBS with random knots, weights and control points (a gently waved sheet, no folds)."""
    nu, nv = 8, 9
    P = 0.4 * rng.normal(size=(nu, nv, 3))
    P[..., 0] += 2 * np.arange(nu)[:, None]
    P[..., 1] += 2 * np.arange(nv)[None, :]
    ku = np.r_[[0.0] * 4, np.sort(rng.uniform(0, 1, nu - 4)), [1.0] * 4]
    kv = np.r_[[0.0] * 3, np.sort(rng.uniform(0, 1, nv - 3)), [1.0] * 3]  # quadratic in v
    return lab.BSplineSurface(P, ku, kv, 3, 2, weights=rng.uniform(0.5, 2.0, (nu, nv)))


def cases(rng):
    return {"practical": surfaces.practical(), "NURBS": random_nurbs(rng), "torus": surfaces.torus()}


def relative(a, b):
    return np.max(np.abs(np.asarray(a) - np.asarray(b))) / np.max(np.abs(b))


@pytest.mark.parametrize("knots, p", [
    (np.array([0, 0, 0, 0, 1, 2, 2.5, 4, 4, 4, 4.0]), 3),
    (np.array([0, 0, 0, 0.2, 0.2, 0.5, 1, 1, 1.0]), 2),  # a double knot
    (np.r_[[0.0] * 5, 0.5, [1.0] * 5], 4),
    (np.array([0, 0, 0.3, 0.6, 1, 1.0]), 1),
    (np.arange(-3, 8, dtype=float), 3),  # unclamped
])
def test_basis_rows_match_the_a23_reference(knots, p):
    lo, hi = bspline.domain(knots, p)
    t = np.r_[np.linspace(lo, hi, 41), knots[p + 1 : -p - 1]]  # also exactly on every interior knot
    span = bspline.find_span(knots, p, t)
    rows = bspline.basis_rows(knots, p, span, t)
    ref = np.moveaxis(bspline.basis_derivatives(knots, p, span, t, 2), 0, -1)  # (3, p+1, k)
    assert rows.shape == (3, p + 1, len(t))
    np.testing.assert_allclose(rows, ref, rtol=0, atol=1e-13 * np.abs(ref).max())
    np.testing.assert_allclose(rows[0].sum(axis=0), 1.0, atol=1e-14)  # partition of unity
    np.testing.assert_allclose(rows[1:].sum(axis=1), 0.0, atol=1e-12 * np.abs(ref).max())  # its derivatives


@pytest.mark.parametrize("name", ["practical", "NURBS", "torus"])
def test_point_paths_agree_with_the_reference(rng, name):
    s = cases(rng)[name]
    (u0, u1), (v0, v1) = s.domain
    n = 20000  # enough points per pair of spans for the grouped evaluation
    u, v = rng.uniform(u0, u1, n), rng.uniform(v0, v1, n)
    ref = naive_derivatives(s, u, v)
    fast = s.derivatives(u, v)
    for a, b in zip(fast, ref):
        assert relative(a, b) <= 1e-14
    # curvature unchanged to 1e-14 against the reference's, relative to the curvature scale: max |K| for K,
    # max(|k1|, |k2|) for H, k1, k2 (H, a mean of curvatures of both signs, is smaller than its rounding scale)
    c_ref, c = from_derivatives(ref), s.curvature(u, v)
    scale = {"K": np.max(np.abs(c_ref.K))}
    scale["H"] = scale["k1"] = scale["k2"] = max(np.max(np.abs(c_ref.k1)), np.max(np.abs(c_ref.k2)))
    for field in ("K", "H", "k1", "k2"):
        assert np.max(np.abs(getattr(c, field) - getattr(c_ref, field))) <= 1e-14 * scale[field], field
    # the per-point path (few points per span) and the grouped path agree as well
    sp = s._spline()
    per_point, = tensor.map_points(lambda uu, vv, work: tensor.point_derivatives(sp, uu, vv, work),
                                   lambda D: (D.buv,), u, v, chunk=1000)
    grouped, = tensor.map_spline_points(sp, lambda D: (D.buv,), u, v, chunk=777)
    assert relative(per_point, ref.buv) <= 1e-14 and relative(grouped, ref.buv) <= 1e-14


def test_grid_path_agrees_and_is_recognised(rng):
    s = random_nurbs(rng)
    u = np.sort(rng.uniform(0, 1, 37))
    v = np.linspace(0, 1, 29)
    c = s.curvature_grid(u, v)
    assert c.K.shape == (37, 29)
    U, V = np.meshgrid(u, v, indexing="ij")
    ref = from_derivatives(naive_derivatives(s, U, V))
    scale = {"K": np.max(np.abs(ref.K))}
    scale["H"] = scale["k1"] = scale["k2"] = max(np.max(np.abs(ref.k1)), np.max(np.abs(ref.k2)))
    for field in ("K", "H", "k1", "k2"):
        assert np.max(np.abs(getattr(c, field) - getattr(ref, field).reshape(37, 29))) <= 1e-14 * scale[field]
    # curvature() takes the grid path by itself for meshgrids (either indexing) and open grids: same values
    for uu, vv, transpose in ((U, V, False), (u[:, None], v[None, :], False), (*np.meshgrid(u, v), True)):
        got = s.curvature(uu, vv).K
        np.testing.assert_array_equal(got, c.K.T if transpose else c.K)
    # unsorted sides, and a grid that is not one (random 2-D parameters) take the right paths
    perm = rng.permutation(37)
    np.testing.assert_array_equal(s.curvature_grid(u[perm], v).H, c.H[perm])
    Ur = rng.uniform(0, 1, (9, 11))
    np.testing.assert_allclose(s.curvature(Ur, Ur.T[:9, :9].mean() + 0 * Ur).K,
                               from_derivatives(naive_derivatives(s, Ur, Ur.T[:9, :9].mean() + 0 * Ur)).K.reshape(9, 11),
                               rtol=1e-13)
    with pytest.raises(ValueError, match=r"u must be a 1-D array of parameters \(one side of the grid\); got shape \(37, 29\)"):
        s.curvature_grid(U, v)
    with pytest.raises(ValueError, match=r"v must lie in the domain \[0, 1\]; got values in \[0, 2\]"):
        s.curvature_grid(u, 2 * v)


def test_one_code_path_for_scalars_and_arrays(rng):
    s = surfaces.practical()
    u, v = rng.uniform(0, 7, 5), rng.uniform(0, 7, 5)
    c = s.curvature(u, v)
    for k in range(5):
        ck = s.curvature(u[k], v[k])
        assert np.shape(ck.K) == () and ck.K == c.K[k] and ck.k2 == c.k2[k]  # bit for bit in one chunk
    assert s.curvature(u[:, None], v[None, :3]).K.shape == (5, 3)
    assert s.curvature(np.empty((0, 4)), 1.0).K.shape == (0, 4)
    # a point's value does not depend on the other points in its call (to rounding: a few units in the last place)
    big_u, big_v = np.r_[u, rng.uniform(0, 7, 30000)], np.r_[v, rng.uniform(0, 7, 30000)]
    np.testing.assert_allclose(s.curvature(big_u, big_v).K[:5], c.K, rtol=1e-14, atol=1e-16)


@pytest.mark.parametrize("grid", [False, True])
def test_temporary_memory_per_point_is_bounded(grid):
    # the bound: at most 150 bytes of temporaries per point (the result, 33 bytes per point, excluded)
    s = surfaces.torus()
    n_side = 400
    if grid:
        u = v = np.linspace(0, 1, n_side)
        call = lambda: s.curvature_grid(u, v)
    else:
        rng = np.random.default_rng(1)
        u, v = rng.uniform(0, 1, n_side**2), rng.uniform(0, 1, n_side**2)
        call = lambda: s.curvature(u, v)
    call()
    peak, c = traced_peak(call)
    n = n_side**2
    result = sum(np.asarray(x).nbytes for x in c)
    assert result == 33 * n
    assert (peak - result) / n <= 150


def test_chunk_size_does_not_change_the_values(rng):
    s = surfaces.practical()
    u, v = rng.uniform(0, 7, 5000), rng.uniform(0, 7, 5000)
    sp = s._spline()
    a = tensor.map_spline_points(sp, from_derivatives, u, v, chunk=4096)
    b = tensor.map_spline_points(sp, from_derivatives, u, v, chunk=333)
    for x, y in zip(a[:4], b[:4]):
        np.testing.assert_allclose(x, y, rtol=1e-14, atol=1e-15)
    np.testing.assert_array_equal(a[4], b[4])


def test_degenerate_points_on_the_grid_path_get_their_limits():
    s = surfaces.sphere(2.0)
    with pytest.warns(lab.DegeneratePointWarning):
        c = s.curvature_grid(np.linspace(0, 1, 9), np.linspace(0, 1, 11))
    np.testing.assert_allclose(c.K, 0.25, rtol=1e-9)
    assert c.degenerate[:, 0].all() and c.degenerate[:, -1].all() and not c.degenerate[:, 1:-1].any()
