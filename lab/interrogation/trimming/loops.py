r"""Trimmed surfaces: trimming loops in the parameter domain and their triangulation (Choi & Lee, §2).

A trimmed surface is a base surface :math:`\mathbf S(u, v)` over its
rectangular domain :math:`D` together with trimming loops
:math:`B(t) = (u(t), v(t))` in :math:`D` (Choi & Lee, eqs. 1-4): one outer
loop that runs counter-clockwise and any number of holes that run clockwise,
so that the trimmed region always lies to the left of a loop.  A loop is a
polyline, an ``(k, 2)`` array of ``(u, v)`` points (closed implicitly; a
repeated first point at the end is dropped), or a closed B-spline / NURBS
curve in the domain (:class:`BSplineLoop`), which is sampled into a polyline
within a chordal tolerance (section 2.1, "boundary curve tessellation").

Segment ``i`` of a loop with ``k`` points runs from point ``i`` to point
``(i + 1) mod k``; error messages name segments by these indices.

The trimmed region is triangulated in the ``(u, v)`` domain by a constrained
Delaunay triangulation (Shewchuk's Triangle, through the ``triangle``
package) whose nodes are the loop points, the intersections of the
iso-parameter lines with the loops, and the nodes of the iso-parameter grid
that lie inside the region (section 2.2); the loops are kept as constrained
segments.  The triangulation is then mapped to 3-D by the base surface,
which also gives the exact curvature at every vertex (:func:`lab.mesh.trimmed_mesh`).

Only NumPy, SciPy and (inside :func:`triangulate`) ``triangle`` are imported here.
"""

from itertools import pairwise

import numpy as np
from scipy.spatial import cKDTree

from ...geometry import bspline
from ...geometry import validation as _v

__all__ = [
    "TRIM_RTOL",
    "BSplineLoop",
    "circle",
    "circle_curve",
    "distance_to_loop",
    "loop_intersections",
    "loops_intersections",
    "point_in_loop",
    "rectangle",
    "signed_area",
]


#: Geometric tolerance relative to the diagonal of the domain: points closer
#: than this are the same point, a point this close to a loop lies on it.
TRIM_RTOL = 1e-10


_CHUNK = 1 << 20  # pair-wise work is done in blocks of about this many entries


# -- loops ------------------------------------------------------------------------


class BSplineLoop:
    r"""A closed B-spline or NURBS curve :math:`B(t) = (u(t), v(t))` in the parameter domain (Choi & Lee, eq. 3).

    .. math:: B(t) = \frac{\sum_i w_i \mathbf P_i N_{i,p}(t)}{\sum_i w_i N_{i,p}(t)}

    Parameters
    ----------
    control_points : (n, 2) array_like
        Control points in ``(u, v)``.
    knots : (n + degree + 1,) array_like
        Knot vector (clamped or unclamped); the curve is evaluated over
        ``[t_p, t_n]`` and must end where it starts.
    degree : int
    weights : (n,) array_like, optional
        Positive weights (a rational curve, e.g. an exact circle).
    """

    def __init__(self, control_points, knots, degree, weights=None):
        P = _v._as_float_array(control_points, "control points of the trimming curve")
        if P.ndim != 2 or P.shape[1] != 2 or P.shape[0] < 2:
            raise ValueError(f"control points of the trimming curve must have shape (n, 2) with n >= 2; got {P.shape}")
        if not np.all(np.isfinite(P)):
            raise ValueError("control points of the trimming curve must contain only finite values; got NaN or inf")
        self.degree = _v.as_positive_int(degree, "degree of the trimming curve", minimum=1)
        self.knots = bspline.validate_knots(knots, self.degree, P.shape[0], "knot vector of the trimming curve")
        self.control_points = P
        self.weights = _v.as_weights(weights, (P.shape[0],), "weights of the trimming curve")
        self.domain = bspline.domain(self.knots, self.degree)
        ends = self.evaluate(np.array(self.domain))
        gap = float(np.linalg.norm(ends[1] - ends[0]))
        size = float(np.linalg.norm(np.ptp(P, axis=0)))
        if gap > TRIM_RTOL * max(size, 1.0):
            raise ValueError(
                f"a B-spline trimming loop must be closed; it starts at ({ends[0, 0]:g}, {ends[0, 1]:g}) "
                f"and ends at ({ends[1, 0]:g}, {ends[1, 1]:g})"
            )

    def evaluate(self, t):
        """Points ``B(t)``, shape ``np.shape(t) + (2,)``; ``t`` in :attr:`domain` (The NURBS Book, A2.1, A2.2)."""
        t = _v._as_float_array(t, "t")
        lo, hi = self.domain
        slack = 1e-12 * max(1.0, hi - lo)
        if t.size and (not np.all(np.isfinite(t)) or t.min() < lo - slack or t.max() > hi + slack):
            raise ValueError(f"t must lie in the curve's domain [{lo:g}, {hi:g}]")
        shape = t.shape
        tf = np.clip(t.ravel(), lo, hi)
        p = self.degree
        span = bspline.find_span(self.knots, p, tf)
        N = bspline.basis_derivatives(self.knots, p, span, tf, 0)[:, 0]  # (k, p+1)
        idx = span[:, None] - p + np.arange(p + 1)
        if self.weights is None:
            out = np.einsum("ki,kid->kd", N, self.control_points[idx])
        else:
            w = self.weights[idx]
            out = np.einsum("ki,kid->kd", N * w, self.control_points[idx]) / np.einsum("ki->k", N * w)[:, None]
        return out.reshape(shape + (2,))

    def breakpoints(self):
        """The distinct knots inside the domain, ends included."""
        lo, hi = self.domain
        k = self.knots
        return np.unique(k[(k >= lo) & (k <= hi)])

    def sample(self, n=None, tol=None, max_points=200_000):
        """The loop as a polyline, without the repeated end point.

        Parameters
        ----------
        n : int, optional
            Number of parameters spaced evenly over the domain; the
            breakpoints (distinct knots, where the curve may have corners) are
            always added.
        tol : float, optional
            Chordal tolerance: segments are halved until the curve's point at
            the middle parameter lies within ``tol`` of the chord (starting
            from four segments per knot span).  Used when ``n`` is not given;
            default ``1e-4`` times the size of the control polygon.
        max_points : int
            Refuse to produce more points than this.

        Returns
        -------
        (k, 2) ndarray
        """
        bp = self.breakpoints()
        if n is not None:
            n = _v.as_positive_int(n, "n", minimum=3)
            t = np.union1d(np.linspace(bp[0], bp[-1], n + 1), bp)
            return self.evaluate(t)[:-1]
        if tol is None:
            tol = 1e-4 * max(float(np.linalg.norm(np.ptp(self.control_points, axis=0))), 1e-300)
        tol = float(tol)
        if not tol > 0:
            raise ValueError(f"tol must be positive; got {tol}")
        t = np.concatenate([np.linspace(a, b, 5)[:-1] for a, b in pairwise(bp)] + [bp[-1:]])
        X = self.evaluate(t)
        while True:
            tm = 0.5 * (t[:-1] + t[1:])
            Xm = self.evaluate(tm)
            d = _point_segment_distance(Xm, X[:-1], X[1:])
            split = d > tol
            if not np.any(split):
                break
            if t.size + np.count_nonzero(split) > max_points:
                raise ValueError(
                    f"sampling the trimming curve within tol={tol:g} needs more than max_points={max_points} points"
                )
            t = np.insert(t, np.flatnonzero(split) + 1, tm[split])
            X = np.insert(X, np.flatnonzero(split) + 1, Xm[split], axis=0)
        return X[:-1]

    def reversed(self):
        """The same curve run backwards (counter-clockwise <-> clockwise)."""
        lo, hi = self.domain
        knots = (lo + hi) - self.knots[::-1]
        w = None if self.weights is None else self.weights[::-1]
        return BSplineLoop(self.control_points[::-1], knots, self.degree, w)

    def __repr__(self):
        kind = "NURBS" if self.weights is not None else "B-spline"
        return f"BSplineLoop({kind}, {len(self.control_points)} control points, degree {self.degree})"


_S = np.sqrt(0.5)


def circle(centre, radius, n=64, clockwise=False):
    """A circle in the parameter domain as an ``(n, 2)`` polyline (counter-clockwise unless ``clockwise``)."""
    n = _v.as_positive_int(n, "n", minimum=3)
    c, r = _centre_radius(centre, radius)
    phi = 2 * np.pi * np.arange(n) / n
    if clockwise:
        phi = -phi
    return c + r * np.column_stack([np.cos(phi), np.sin(phi)])


def circle_curve(centre, radius, clockwise=False):
    """A circle in the parameter domain as an exact NURBS :class:`BSplineLoop` (nine control points, degree 2).

    The NURBS Book, example 7.2 (the same circle as the sphere's and torus's in :mod:`lab.surfaces`).
    """
    c, r = _centre_radius(centre, radius)
    xy = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], dtype=float)
    if clockwise:
        xy[:, 1] = -xy[:, 1]
    w = np.array([1, _S, 1, _S, 1, _S, 1, _S, 1])
    knots = np.array([0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1])
    return BSplineLoop(c + r * xy, knots, 2, w)


def rectangle(lower, upper, clockwise=False):
    """The rectangle ``[u0, u1] x [v0, v1]`` with ``lower = (u0, v0)``, ``upper = (u1, v1)`` as a 4-point loop."""
    (u0, v0), (u1, v1) = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    if not (u0 < u1 and v0 < v1):
        raise ValueError(f"rectangle needs lower < upper in u and v; got lower={lower!r}, upper={upper!r}")
    loop = np.array([[u0, v0], [u1, v0], [u1, v1], [u0, v1]])
    return loop[::-1].copy() if clockwise else loop


def _centre_radius(centre, radius):
    c = np.asarray(centre, dtype=float)
    if c.shape != (2,):
        raise ValueError(f"centre must be a (u, v) pair; got shape {c.shape}")
    r = float(radius)
    if not r > 0:
        raise ValueError(f"radius must be positive; got {radius}")
    return c, r


# -- geometry of polylines ------------------------------------------------------------


def signed_area(loop):
    r"""Signed area of a closed polyline (shoelace formula): positive when it runs counter-clockwise.

    .. math:: A = \frac12 \sum_i (u_i v_{i+1} - u_{i+1} v_i)

    Parameters
    ----------
    loop : (k, 2) array_like

    Returns
    -------
    float
    """
    P = np.asarray(loop, dtype=float)
    Q = np.roll(P, -1, axis=0)
    # centring first keeps the sum accurate far from the origin
    P, Q = P - P.mean(axis=0), Q - P.mean(axis=0)
    return 0.5 * float(np.sum(P[:, 0] * Q[:, 1] - Q[:, 0] * P[:, 1]))


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _point_segment_distance(X, A, B):
    """Distance of points X from segments AB, all broadcast, shape ``broadcast.shape[:-1]``."""
    AB = B - A
    L2 = np.einsum("...i,...i->...", AB, AB)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(L2 > 0, np.einsum("...i,...i->...", X - A, AB) / np.where(L2 > 0, L2, 1.0), 0.0)
    s = np.clip(s, 0.0, 1.0)
    return np.linalg.norm(X - (A + s[..., None] * AB), axis=-1)


def _segments(loop):
    P = np.asarray(loop, dtype=float)
    return P, np.roll(P, -1, axis=0)


def _intersect(A0, A1, B0, B1, eps):
    """Whether closed segments A0A1 and B0B1 meet (vectorised over the leading axis), and where.

    Uses the orientation tests of the segment endpoints against each other;
    orientations within ``eps`` (an area) of zero count as collinear, so
    segments that touch count as meeting.
    """
    dA, dB = A1 - A0, B1 - B0
    d1 = _cross(dB, A0 - B0)
    d2 = _cross(dB, A1 - B0)
    d3 = _cross(dA, B0 - A0)
    d4 = _cross(dA, B1 - A0)
    z1, z2, z3, z4 = (np.abs(d) <= eps for d in (d1, d2, d3, d4))
    proper = (d1 * d2 < 0) & (d3 * d4 < 0) & ~(z1 | z2 | z3 | z4)

    def on(P, S0, S1, zero):
        lo, hi = np.minimum(S0, S1), np.maximum(S0, S1)
        slack = np.sqrt(eps)
        return zero & np.all((P >= lo - slack) & (P <= hi + slack), axis=-1)

    t1, t2 = on(A0, B0, B1, z1), on(A1, B0, B1, z2)
    t3, t4 = on(B0, A0, A1, z3), on(B1, A0, A1, z4)
    hit = proper | t1 | t2 | t3 | t4
    with np.errstate(invalid="ignore", divide="ignore"):
        s = np.where(proper, d1 / np.where(proper, d1 - d2, 1.0), 0.0)
    where = np.where(proper[:, None], A0 + s[:, None] * dA, np.nan)
    for touch, P in ((t1, A0), (t2, A1), (t3, B0), (t4, B1)):
        where = np.where((touch & np.isnan(where[:, 0]))[:, None], P, where)
    return hit, where


def _eps(scale):
    return (TRIM_RTOL * scale) ** 2


def _box_pairs(A0, A1, slack):
    """Pairs ``i < j`` of segments whose bounding boxes, grown by ``slack``, overlap (sweep and prune).

    Two segments can meet only if their boxes do.  The boxes are sorted by their lower x; each box pairs
    with the boxes that start before it ends in x, then the pairs are kept whose y intervals overlap too.
    One long segment (a pcurve that is a straight line across the face) pairs only with the boxes it
    spans, where a radius around midpoints would pair every segment with every other.
    """
    lo, hi = np.minimum(A0, A1) - slack, np.maximum(A0, A1) + slack
    order = np.argsort(lo[:, 0], kind="stable")
    start = lo[order, 0]
    count = np.searchsorted(start, hi[order, 0], side="right") - np.arange(1, len(order) + 1)
    count = np.maximum(count, 0)
    first = np.repeat(np.arange(len(order)), count)
    second = first + 1 + np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
    i, j = order[first], order[second]
    keep = (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1])
    return np.sort(np.column_stack([i[keep], j[keep]]), axis=1)


def loop_intersections(loop, scale=None):
    """Pairs of segments of one closed polyline that meet (other than neighbours at their shared point).

    Neighbouring segments count as meeting when they overlap, i.e. the loop
    turns back on itself.  Candidate pairs are those whose bounding boxes
    overlap (a sweep over the boxes sorted in x), then tested exactly.

    Parameters
    ----------
    loop : (k, 2) array_like
    scale : float, optional
        Length scale for the tolerance (default: the loop's size).

    Returns
    -------
    pairs : (m, 2) int ndarray
        Segment indices ``i < j``, sorted.
    points : (m, 2) ndarray
        A point where each pair meets.
    """
    A0, A1 = _segments(loop)
    k = len(A0)
    if scale is None:
        scale = float(np.linalg.norm(np.ptp(A0, axis=0)))
    eps = _eps(scale)
    pairs = _box_pairs(A0, A1, np.sqrt(eps))
    adjacent = (pairs[:, 1] - pairs[:, 0] == 1) | ((pairs[:, 0] == 0) & (pairs[:, 1] == k - 1))
    far = pairs[~adjacent]
    hit, where = _intersect(A0[far[:, 0]], A1[far[:, 0]], A0[far[:, 1]], A1[far[:, 1]], eps)
    # neighbours i, i+1 share point i+1: they overlap when they are collinear and turn back
    i = np.arange(k)
    j = (i + 1) % k
    a, b, c = A0[i], A1[i], A1[j]
    fold = (np.abs(_cross(a - b, c - b)) <= eps * 1e2) & (np.einsum("ij,ij->i", a - b, c - b) > 0)
    fold_pairs = np.sort(np.column_stack([i, j])[fold], axis=1)
    pairs = np.concatenate([far[hit], fold_pairs])
    points = np.concatenate([where[hit], b[fold]])
    order = np.lexsort((pairs[:, 1], pairs[:, 0])) if len(pairs) else np.zeros(0, int)
    return pairs[order], points[order]


def loops_intersections(loop_a, loop_b, scale=None):
    """Pairs ``(i, j)`` such that segment ``i`` of ``loop_a`` meets segment ``j`` of ``loop_b``, and where.

    Returns ``(pairs (m, 2) int ndarray, points (m, 2) ndarray)``, sorted.
    """
    A0, A1 = _segments(loop_a)
    B0, B1 = _segments(loop_b)
    if scale is None:
        scale = float(np.linalg.norm(np.ptp(np.concatenate([A0, B0]), axis=0)))
    eps = _eps(scale)
    r = 0.5 * (np.linalg.norm(A1 - A0, axis=1).max() + np.linalg.norm(B1 - B0, axis=1).max())
    ta, tb = cKDTree(0.5 * (A0 + A1)), cKDTree(0.5 * (B0 + B1))
    pairs = ta.sparse_distance_matrix(tb, r * (1 + 1e-9) + np.sqrt(eps), output_type="ndarray")
    pairs = np.column_stack([pairs["i"], pairs["j"]]).astype(int).reshape(-1, 2)
    hit, where = _intersect(A0[pairs[:, 0]], A1[pairs[:, 0]], B0[pairs[:, 1]], B1[pairs[:, 1]], eps)
    pairs, where = pairs[hit], where[hit]
    order = np.lexsort((pairs[:, 1], pairs[:, 0])) if len(pairs) else np.zeros(0, int)
    return pairs[order], where[order]


def _blocks(m, k):
    step = max(1, _CHUNK // max(k, 1))
    return [slice(a, min(a + step, m)) for a in range(0, m, step)]


def point_in_loop(points, loop):
    """Whether points lie inside a closed polyline (crossing number; either orientation).

    Points on the polyline itself may come out either way; use
    :func:`distance_to_loop` to find them.

    Parameters
    ----------
    points : (m, 2) array_like
    loop : (k, 2) array_like

    Returns
    -------
    (m,) bool ndarray
    """
    X = np.asarray(points, dtype=float).reshape(-1, 2)
    A0, A1 = _segments(loop)
    out = np.zeros(len(X), dtype=bool)
    for blk in _blocks(len(X), len(A0)):
        x, y = X[blk, 0:1], X[blk, 1:2]
        ya, yb = A0[None, :, 1], A1[None, :, 1]
        straddle = (ya > y) != (yb > y)
        with np.errstate(invalid="ignore", divide="ignore"):
            xc = A0[None, :, 0] + (y - ya) * (A1[None, :, 0] - A0[None, :, 0]) / (yb - ya)
        out[blk] = np.count_nonzero(straddle & (x < xc), axis=1) % 2 == 1
    return out


def distance_to_loop(points, loop):
    """Distance of points ``(m, 2)`` from a closed polyline ``(k, 2)``, shape ``(m,)``.

    The distance to the nearest vertex bounds the distance from above; only
    segments whose midpoints lie within that bound plus half the longest
    segment can be nearer, and only those are measured exactly.
    """
    X = np.asarray(points, dtype=float).reshape(-1, 2)
    A0, A1 = _segments(loop)
    out = np.full(len(X), np.inf)
    if not len(X):
        return out
    bound, _ = cKDTree(A0).query(X)
    half = 0.5 * np.linalg.norm(A1 - A0, axis=1).max()
    radius = (bound + half) * (1 + 1e-9) + 1e-300
    tree = cKDTree(0.5 * (A0 + A1))
    step = max(1, _CHUNK // 64)
    for a in range(0, len(X), step):
        b = min(a + step, len(X))
        cand = tree.query_ball_point(X[a:b], radius[a:b], return_sorted=False)
        counts = np.fromiter((len(c) for c in cand), dtype=int, count=b - a)
        p = np.repeat(np.arange(a, b), counts)
        s = np.fromiter((i for c in cand for i in c), dtype=int, count=int(counts.sum()))
        np.minimum.at(out, p, _point_segment_distance(X[p], A0[s], A1[s]))
    return out


