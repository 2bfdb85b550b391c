r"""Tensor-product B-spline and NURBS surfaces: validation, basis functions, knot insertion, Bézier extraction.

A surface of degrees ``(p, q)`` has a control net ``P`` of shape
``(nu, nv, d)``, knot vectors of lengths ``nu + p + 1`` and ``nv + q + 1`` and
optionally positive weights ``(nu, nv)``.  Its domain is
``[t_p, t_{nu}] x [s_q, s_{nv}]``, which covers clamped and unclamped knot
vectors alike.

.. math:: \mathbf x(u,v) = \frac{\sum_i\sum_j w_{ij}\mathbf P_{ij} N_{i,p}(u) N_{j,q}(v)}
                               {\sum_i\sum_j w_{ij} N_{i,p}(u) N_{j,q}(v)}

References: The NURBS Book (Piegl & Tiller), A2.1 (span), A2.2 and A2.3
(basis functions and their derivatives), A5.1 (knot insertion, Boehm's
algorithm); the practical's sheet (§5) for the conversion to
Bézier patches.  Surfaces are evaluated with these basis functions by
:mod:`lab.tensor` (in chunks, points grouped by knot spans, grids separably).
"""

from itertools import pairwise

import numpy as np

from . import validation as _v
from .bezier import dehomogenize, homogeneous
from .derivatives import quotient_rule

__all__ = [
    "basis_derivatives",
    "basis_rows",
    "domain",
    "find_span",
    "insert_knot",
    "partial_derivatives",
    "to_bezier",
    "validate_knots",
]


def validate_knots(knots, degree, n_points, name="knot vector"):
    """Check a knot vector against its degree and number of control points.

    Returns the knots as a float array.  Raises ``ValueError`` for a wrong
    length, non-finite or decreasing knots, a knot repeated more than
    ``degree + 1`` times, or an empty domain; ``TypeError`` for a non-integer degree.
    """
    degree = _v.as_positive_int(degree, f"degree of the {name}", minimum=1)
    if degree >= n_points:
        raise ValueError(f"degree of the {name} must be below the number of control points in that direction "
                         f"({n_points}, so at most {n_points - 1}); got {degree}")
    t = _v.as_array(knots, name, finite=False)  # text, None, an int beyond the float range: named
    if t.ndim != 1:
        raise ValueError(f"{name} must be a 1-D sequence of numbers; got {_v._short(knots)}")
    if not np.all(np.isfinite(t)):
        raise ValueError(f"{name} must contain only finite values; got {t.tolist()}")
    expected = n_points + degree + 1
    if t.size != expected:
        raise ValueError(
            f"{name} must have {expected} knots ({n_points} control points + degree {degree} + 1); got {t.size}"
        )
    if np.any(np.diff(t) < 0):
        raise ValueError(f"{name} must be non-decreasing; got {t.tolist()}")
    _, counts = np.unique(t, return_counts=True)
    if counts.max() > degree + 1:
        raise ValueError(
            f"{name}: a knot may be repeated at most degree + 1 = {degree + 1} times; got {counts.max()}"
        )
    if not t[degree] < t[n_points]:
        raise ValueError(f"{name} has an empty domain [t_{degree}, t_{n_points}] = [{t[degree]:g}, {t[n_points]:g}]")
    return t


def domain(knots, degree):
    """Parameter interval ``(t_p, t_{n})`` of a knot vector with ``n`` control points."""
    n_points = len(knots) - degree - 1
    return float(knots[degree]), float(knots[n_points])


def find_span(knots, degree, t):
    """Index ``k`` of the knot span ``[t_k, t_{k+1})`` holding each parameter (The NURBS Book, A2.1).

    Vectorised; the right end of the domain belongs to the last non-empty span.
    """
    n_points = len(knots) - degree - 1
    _, hi = domain(knots, degree)
    k = np.searchsorted(knots, t, side="right")
    k -= 1
    # At t == hi the search lands after the end of the domain; step back to the
    # last non-empty span.  Parameters outside the domain get the first or last span.
    last = np.searchsorted(knots, hi, side="left") - 1
    return np.clip(k, degree, min(n_points - 1, last), out=k if np.ndim(k) else None)


def basis_derivatives(knots, degree, span, t, n_derivatives):
    """Non-zero basis functions and their derivatives (The NURBS Book, A2.3), vectorised.

    Parameters
    ----------
    knots : (n + p + 1,) ndarray
    degree : int
    span : (k,) int ndarray
        Spans from :func:`find_span`.
    t : (k,) ndarray
        Parameters.
    n_derivatives : int
        Highest derivative order.

    Returns
    -------
    ndarray, shape ``(k, n_derivatives + 1, degree + 1)``
        ``out[:, r, i]`` is the r-th derivative of ``N_{span-p+i, p}``.
    """
    p = degree
    t = np.asarray(t, dtype=float)
    span = np.asarray(span)
    k = t.shape[0]
    ndu = np.zeros((p + 1, p + 1, k))
    ndu[0, 0] = 1.0
    left = np.zeros((p + 1, k))
    right = np.zeros((p + 1, k))
    for j in range(1, p + 1):
        left[j] = t - knots[span + 1 - j]
        right[j] = knots[span + j] - t
        saved = np.zeros(k)
        for r in range(j):
            ndu[j, r] = right[r + 1] + left[j - r]  # knot differences (lower triangle)
            temp = ndu[r, j - 1] / ndu[j, r]
            ndu[r, j] = saved + right[r + 1] * temp  # basis functions (upper triangle)
            saved = left[j - r] * temp
        ndu[j, j] = saved
    n = n_derivatives
    ders = np.zeros((n + 1, p + 1, k))
    ders[0] = ndu[:, p]
    for r in range(p + 1):
        a = np.zeros((2, p + 1, k))
        a[0, 0] = 1.0
        s1, s2 = 0, 1
        for kk in range(1, n + 1):
            d = np.zeros(k)
            rk, pk = r - kk, p - kk
            if r >= kk:
                a[s2, 0] = a[s1, 0] / ndu[pk + 1, rk]
                d = a[s2, 0] * ndu[rk, pk]
            j1 = 1 if rk >= -1 else -rk
            j2 = kk - 1 if r - 1 <= pk else p - r
            for j in range(j1, j2 + 1):
                a[s2, j] = (a[s1, j] - a[s1, j - 1]) / ndu[pk + 1, rk + j]
                d = d + a[s2, j] * ndu[rk + j, pk]
            if r <= pk:
                a[s2, kk] = -a[s1, kk - 1] / ndu[pk + 1, r]
                d = d + a[s2, kk] * ndu[r, pk]
            ders[kk, r] = d
            s1, s2 = s2, s1
    factor = p
    for kk in range(1, n + 1):
        ders[kk] *= factor
        factor *= p - kk
    return np.moveaxis(ders, -1, 0)


def basis_rows(knots, degree, span, t):
    r"""The non-zero basis functions and their first two derivatives, points last: the fast path of A2.3.

    The values come from the Cox–de Boor triangle (The NURBS Book, A2.2) run
    on whole arrays of parameters; the derivatives from the values of degree
    ``p - 1`` and ``p - 2`` (The NURBS Book, eq. 2.9)

    .. math:: N'_{i,p} = \frac{p}{t_{i+p} - t_i} N_{i,p-1} - \frac{p}{t_{i+p+1} - t_{i+1}} N_{i+1,p-1},

    applied once for the first and twice (to degree ``p - 1``, then ``p``) for
    the second derivative.  Every denominator is a difference of knots that
    spans the point's non-empty knot span, so none vanishes.  Equal to
    :func:`basis_derivatives` with ``n_derivatives=2`` (which stays the
    reference) up to rounding, with a third of its array operations.

    Parameters
    ----------
    knots : (n + p + 1,) ndarray
    degree : int
    span : (k,) int ndarray
        Spans from :func:`find_span`.
    t : (k,) ndarray
        Parameters.

    Returns
    -------
    ndarray, shape ``(3, degree + 1, k)``
        ``out[r, i]`` is the r-th derivative of ``N_{span-p+i, p}`` at every point.
    """
    p = degree
    t = np.asarray(t, dtype=float)
    left = [None] + [t - knots[span + 1 - j] for j in range(1, p + 1)]
    right = [None] + [knots[span + j] - t for j in range(1, p + 1)]
    out = np.zeros((3, p + 1) + t.shape)
    levels = [[np.ones_like(t)]]  # levels[j][r] = N_{span-j+r, j}
    for j in range(1, p + 1):
        prev, cur, saved = levels[-1], [], 0.0
        for r in range(j):
            temp = prev[r] / (right[r + 1] + left[j - r])
            cur.append(saved + right[r + 1] * temp)
            saved = left[j - r] * temp
        cur.append(saved)
        levels.append(cur)
    out[0] = levels[p]

    def differentiate(values, deg):
        """Derivatives of the degree-``deg`` functions from ``values`` of degree ``deg - 1`` (eq. 2.9)."""
        # a_i = deg / (t_{span+i} - t_{span-deg+i}), i = 1 .. deg, in terms of left/right
        terms = [deg * values[i - 1] / (right[i] + left[deg + 1 - i]) for i in range(1, deg + 1)]
        return [-terms[0]] + [terms[i - 1] - terms[i] for i in range(1, deg)] + [terms[-1]]

    if p >= 1:
        out[1] = differentiate(levels[p - 1], p)
    if p >= 2:
        out[2] = differentiate(differentiate(levels[p - 2], p - 1), p)
    return out


def partial_derivatives(P, knots_u, knots_v, degree_u, degree_v, weights, u, v, order):
    r"""Every partial derivative :math:`\partial^{i+j}\mathbf S/\partial u^i\partial v^j`, :math:`i + j \le`
    ``order``, of a B-spline or NURBS surface at the points ``(u, v)`` (flat arrays of equal length ``k``).

    The basis functions' derivatives of :func:`basis_derivatives` (The NURBS Book, A2.3; zero beyond the
    degree) contracted with each point's ``(p+1)(q+1)`` control points (A3.6), in homogeneous coordinates for
    a NURBS and then the quotient rule (eq. 4.20, :func:`lab.geometry.derivatives.quotient_rule`).  A point on a
    knot takes the span :func:`find_span` gives, as every evaluator of the lab does.  The general path for
    third derivatives (G3 across a CAD model's face edges, :func:`lab.continuity`); the six fields of
    curvature take the faster :mod:`lab.geometry.tensor`.

    Returns
    -------
    dict
        ``{(i, j): ndarray (k, 3)}``.
    """
    p, q = int(degree_u), int(degree_v)
    Pw = homogeneous(np.asarray(P, dtype=float), weights)
    u, v = np.asarray(u, dtype=float).ravel(), np.asarray(v, dtype=float).ravel()
    su, sv = find_span(knots_u, p, u), find_span(knots_v, q, v)

    def basis(knots, degree, span, t):
        out = np.zeros((t.size, order + 1, degree + 1))
        out[:, : min(order, degree) + 1] = basis_derivatives(knots, degree, span, t, min(order, degree))
        return out

    Nu, Nv = basis(knots_u, p, su, u), basis(knots_v, q, sv, v)
    rows = (su - p)[:, None] + np.arange(p + 1)[None, :]
    cols = (sv - q)[:, None] + np.arange(q + 1)[None, :]
    C = Pw[rows[:, :, None], cols[:, None, :]]  # (k, p+1, q+1, d)
    X = np.einsum("kjb,kibd->kijd", Nv, np.einsum("kia,kabd->kibd", Nu, C))  # (k, order+1, order+1, d)
    A = {(i, j): X[:, i, j] for i in range(order + 1) for j in range(order + 1 - i)}
    return A if weights is None else quotient_rule(A, order)


def _check_surface(P, knots_u, knots_v, degree_u, degree_v, weights):
    P = _v.as_control_net(P, dim=None)
    tu = validate_knots(knots_u, degree_u, P.shape[0], "knot vector in u")
    tv = validate_knots(knots_v, degree_v, P.shape[1], "knot vector in v")
    weights = _v.as_weights(weights, P.shape[:2])
    return P, tu, tv, weights


def insert_knot(Pw, knots, degree, t, times=1, axis=0):
    """Insert the knot ``t`` ``times`` times by Boehm's algorithm (The NURBS Book, A5.1).

    Works on any array of (homogeneous) control points whose control index is
    ``axis``; all other axes are carried along, so a whole surface net is
    refined in one direction at once.  The curve/surface is unchanged.

    Returns
    -------
    Pw_new : ndarray
        ``times`` more control points along ``axis``.
    knots_new : ndarray
    """
    p = degree
    Q = np.moveaxis(np.asarray(Pw, dtype=float), axis, 0)
    U = np.asarray(knots, dtype=float)
    lo, hi = domain(U, p)
    if not lo <= t <= hi:
        raise ValueError(f"knot to insert must lie in the domain [{lo:g}, {hi:g}]; got {t:g}")
    for _ in range(times):
        s = int(np.count_nonzero(U == t))
        if s >= p + 1:
            raise ValueError(f"knot {t:g} already has multiplicity {s}; at most degree + 1 = {p + 1} is allowed")
        k = int(np.searchsorted(U, t, side="right") - 1)  # U_k <= t < U_{k+1}
        new = np.empty((Q.shape[0] + 1,) + Q.shape[1:])
        new[: k - p + 1] = Q[: k - p + 1]
        new[k - s + 1 :] = Q[k - s :]
        for i in range(k - p + 1, k - s + 1):
            alpha = (t - U[i]) / (U[i + p] - U[i])
            new[i] = alpha * Q[i] + (1.0 - alpha) * Q[i - 1]
        Q = new
        U = np.insert(U, k + 1, t)
    return np.moveaxis(Q, 0, axis), U


def _to_bezier_1d(Pw, U, p, axis):
    """Insert knots along ``axis`` until every knot of the domain has multiplicity >= p; return segments."""
    lo, hi = domain(U, p)
    for x in np.unique(U[(U >= lo) & (U <= hi)]):
        s = int(np.count_nonzero(U == x))
        if s < p:
            Pw, U = insert_knot(Pw, U, p, x, times=p - s, axis=axis)
    values = np.unique(U[(U >= lo) & (U <= hi)])
    segments, intervals = [], []
    for a, b in pairwise(values):
        k = int(np.searchsorted(U, a, side="right") - 1)  # last index with U_k == a
        segments.append(np.take(Pw, np.arange(k - p, k + 1), axis=axis))
        intervals.append((float(a), float(b)))
    return segments, intervals


def to_bezier(P, knots_u, knots_v, degree_u, degree_v, weights=None):
    """Bézier patches of a B-spline / NURBS surface, one per non-empty knot span.

    Every knot inside the domain is inserted until it has multiplicity equal to
    the degree (practical, section 5: "zu jedem Parameterquadrat die
    entsprechende Bézier-Darstellung").

    Returns
    -------
    nets : ndarray, shape ``(su, sv, p+1, q+1, d)``
        ``nets[a, b]`` is the patch over the a-th u-span and b-th v-span.
    weights : ndarray of shape ``(su, sv, p+1, q+1)`` or None
    intervals_u : list of (float, float)
        The u-spans, and ``intervals_v`` likewise.
    intervals_v : list of (float, float)
    """
    P, tu, tv, weights = _check_surface(P, knots_u, knots_v, degree_u, degree_v, weights)
    Pw = homogeneous(P, weights)
    strips, intervals_u = _to_bezier_1d(Pw, tu, degree_u, axis=0)
    rows = []
    for strip in strips:
        patches, intervals_v = _to_bezier_1d(strip, tv, degree_v, axis=1)
        rows.append(np.stack(patches, axis=0))
    nets = np.stack(rows, axis=0)
    if weights is None:
        return nets, None, intervals_u, intervals_v
    nets, w = dehomogenize(nets)
    return nets, w, intervals_u, intervals_v
