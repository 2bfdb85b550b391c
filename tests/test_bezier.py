"""Bézier evaluation, derivative nets, subdivision (lab.bezier)."""

from fractions import Fraction

import numpy as np
import pytest

from lab import analytic, bezier


def naive_surface(P, u, v, weights=None):
    """Slow reference: de Casteljau along v for every row, then along u."""
    Pw = bezier.homogeneous(P, weights)
    rows = np.array([bezier.de_casteljau(row, v) for row in Pw])
    p = bezier.de_casteljau(rows, u)
    return p if weights is None else p[:-1] / p[-1]


def test_bernstein_partition_of_unity_and_endpoints():
    t = np.linspace(0, 1, 11)
    for n in range(8):
        B = bezier.bernstein(n, t)
        np.testing.assert_allclose(B.sum(axis=-1), 1.0, atol=1e-14)
        np.testing.assert_array_equal(B[0], np.eye(n + 1)[0])
        np.testing.assert_array_equal(B[-1], np.eye(n + 1)[-1])


def test_evaluate_matches_de_casteljau(rng):
    P = rng.normal(size=(4, 6, 3))
    w = rng.uniform(0.5, 2.0, size=(4, 6))
    u, v = rng.uniform(size=(2, 20))
    for weights in (None, w):
        got = bezier.evaluate(P, u, v, weights)
        ref = np.array([naive_surface(P, a, b, weights) for a, b in zip(u, v)])
        np.testing.assert_allclose(got, ref, atol=1e-14, rtol=0)


def test_derivatives_exact_against_rational_arithmetic(rng):
    """Every derivative field against exact Fraction arithmetic, polynomial and rational, unequal degrees."""
    for m, n in ((2, 3), (3, 5), (1, 2), (1, 1)):
        P = analytic.random_rational_net(rng, m, n)
        w = rng.integers(1, 6, size=(m + 1, n + 1)) / 4
        for weights in (None, w):
            u, v = Fraction(3, 8), Fraction(5, 16)
            exact = analytic.bezier_derivatives_exact(P, u, v, weights)
            got = bezier.derivatives(P, float(u), float(v), weights)
            for name, e, g in zip(got._fields, exact, got):
                np.testing.assert_allclose(g, np.array(e, dtype=float), rtol=1e-13, atol=1e-13, err_msg=f"{name} {m}x{n}")


def test_derivative_net_forward_differences():
    P = np.arange(4 * 3 * 1, dtype=float).reshape(4, 3, 1) ** 2
    bu = bezier.derivative_net(P, 1, 0)
    np.testing.assert_array_equal(bu, 3 * (P[1:] - P[:-1]))
    buu = bezier.derivative_net(P, 2, 0)
    np.testing.assert_array_equal(buu, 3 * 2 * (P[2:] - 2 * P[1:-1] + P[:-2]))
    bvv = bezier.derivative_net(P, 0, 2)
    np.testing.assert_array_equal(bvv, 2 * 1 * (P[:, 2:] - 2 * P[:, 1:-1] + P[:, :-2]))
    # degree 1: the second derivative is the zero net of degree 0
    lin = np.ones((2, 3, 3))
    assert bezier.derivative_net(lin, 2, 0).shape == (1, 3, 3)
    assert not bezier.derivative_net(lin, 2, 0).any()


def test_derivatives_degree_one_and_zero_cases():
    """A bilinear patch has b_uu = b_vv = 0 and constant b_uv."""
    P = np.array([[[0, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 1]]], dtype=float)
    d = bezier.derivatives(P, [0.2, 0.7], [0.9, 0.1])
    np.testing.assert_array_equal(d.buu, 0)
    np.testing.assert_array_equal(d.bvv, 0)
    np.testing.assert_allclose(d.buv, [[0, 0, 1], [0, 0, 1]])
    np.testing.assert_allclose(d.b[..., 2], [0.2 * 0.9, 0.7 * 0.1])


def test_batch_and_paired_evaluation_agree(rng):
    P = rng.normal(size=(5, 3, 4, 3))
    u, v = rng.uniform(size=(2, 5, 7))
    paired = bezier.derivatives(P, u, v, paired=True)
    for k in range(5):
        single = bezier.derivatives(P[k], u[k], v[k])
        for a, b in zip(paired, single):
            np.testing.assert_allclose(a[k], b, atol=1e-14)
    batch = bezier.derivatives(P, u[0], v[0])
    assert batch.b.shape == (5, 7, 3)
    np.testing.assert_allclose(batch.b[2], bezier.evaluate(P[2], u[0], v[0]), atol=1e-14)


def test_shapes_broadcast():
    P = np.zeros((3, 4, 3))
    d = bezier.derivatives(P, np.zeros((2, 1)), np.zeros(5))
    assert all(x.shape == (2, 5, 3) for x in d)
    assert bezier.evaluate(P, 0.5, 0.5).shape == (3,)


@pytest.mark.parametrize("t", [0.5, 0.3])
def test_split_reproduces_curve(rng, t):
    P = rng.normal(size=(6, 3))
    left, right = bezier.split(P, t, axis=0)
    s = np.linspace(0, 1, 9)
    np.testing.assert_allclose(bezier.de_casteljau(left, s), bezier.de_casteljau(P, t * s), atol=1e-14)
    np.testing.assert_allclose(bezier.de_casteljau(right, s), bezier.de_casteljau(P, t + (1 - t) * s), atol=1e-14)


@pytest.mark.parametrize("weighted", [False, True])
def test_subdivide_reproduces_patch(rng, weighted):
    P = rng.normal(size=(2, 3, 4, 3))  # a batch of two patches
    w = rng.uniform(0.5, 2, size=(2, 3, 4)) if weighted else None
    u0, v0 = 0.4, 0.7
    children, cw = bezier.subdivide(P, u0, v0, w)
    assert children.shape == (2, 2, 2, 3, 4, 3)
    s = np.linspace(0, 1, 5)
    S, T = np.meshgrid(s, s, indexing="ij")
    for a, (ulo, uhi) in enumerate(((0, u0), (u0, 1))):
        for b, (vlo, vhi) in enumerate(((0, v0), (v0, 1))):
            cwab = None if cw is None else cw[:, a, b]
            got = bezier.evaluate(children[:, a, b], S, T, cwab)
            ref = bezier.evaluate(P, ulo + (uhi - ulo) * S, vlo + (vhi - vlo) * T, w)
            np.testing.assert_allclose(got, ref, atol=1e-13)


def test_errors_name_expected_and_received():
    with pytest.raises(ValueError, match=r"control net must have shape \(\.\.\., m\+1, n\+1, d\); got \(4,\)"):
        bezier.derivatives(np.zeros(4), 0.5, 0.5)
    with pytest.raises(ValueError, match=r"weights must have shape \(3, 3\) \(one per control point\); got \(2, 2\)"):
        bezier.derivatives(np.zeros((3, 3, 3)), 0.5, 0.5, np.ones((2, 2)))
    with pytest.raises(ValueError, match="weights must be positive; got minimum -1"):
        bezier.derivatives(np.zeros((2, 2, 3)), 0.5, 0.5, [[1, 1], [1, -1]])
    with pytest.raises(ValueError, match=r"u must lie in the domain \[0, 1\]; got values in \[0, 1.5\]"):
        bezier.evaluate(np.zeros((2, 2, 3)), [0, 1.5], 0.5)
    with pytest.raises(ValueError, match="control net must contain only finite values"):
        bezier.evaluate(np.full((2, 2, 3), np.nan), 0.5, 0.5)
    with pytest.raises(TypeError, match="control net must be an array of numbers; got str"):
        bezier.evaluate("abc", 0.5, 0.5)
    with pytest.raises(ValueError, match="subdivision parameter u must lie strictly between 0 and 1; got 1.0"):
        bezier.subdivide(np.zeros((2, 2, 3)), 1.0, 0.5)
    with pytest.raises(ValueError, match="u and v must broadcast against each other"):
        bezier.evaluate(np.zeros((2, 2, 3)), [0.1, 0.2], [0.1, 0.2, 0.3])
