r"""Trimmed surfaces: trimming loops in the parameter domain and their triangulation (``seeds/002``, section 2).

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
which also gives the exact curvature at every vertex (:mod:`lab.trimmed_mesh`).

Only NumPy, SciPy and (inside :func:`triangulate`) ``triangle`` are imported here.
"""

from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from . import _validation as _v
from . import bspline

__all__ = [
    "BSplineLoop",
    "TrimmedSurface",
    "Triangulation",
    "trimmed",
    "circle",
    "circle_curve",
    "rectangle",
    "signed_area",
    "loop_intersections",
    "loops_intersections",
    "point_in_loop",
    "distance_to_loop",
    "validate_loops",
    "triangulate",
    "boundary_edges",
    "TRIM_RTOL",
]

#: Geometric tolerance relative to the diagonal of the domain: points closer
#: than this are the same point, a point this close to a loop lies on it.
TRIM_RTOL = 1e-10

#: Largest minimum angle (degrees) that Triangle's quality refinement is
#: guaranteed to reach; it may not terminate much above this (Triangle's manual).
MAX_MIN_ANGLE = 33.0

_CHUNK = 1 << 20  # pair-wise work is done in blocks of about this many entries


# -- loops ------------------------------------------------------------------------


class BSplineLoop:
    r"""A closed B-spline or NURBS curve :math:`B(t) = (u(t), v(t))` in the parameter domain (``seeds/002`` eq. 3).

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
        t = np.concatenate([np.linspace(a, b, 5)[:-1] for a, b in zip(bp[:-1], bp[1:])] + [bp[-1:]])
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


def loop_intersections(loop, scale=None):
    """Pairs of segments of one closed polyline that meet (other than neighbours at their shared point).

    Neighbouring segments count as meeting when they overlap, i.e. the loop
    turns back on itself.  Candidate pairs are found with a k-d tree of the
    segments' midpoints (two segments can meet only if their midpoints are
    at most the longest segment apart), then tested exactly.

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
    lengths = np.linalg.norm(A1 - A0, axis=1)
    tree = cKDTree(0.5 * (A0 + A1))
    pairs = tree.query_pairs(lengths.max() * (1 + 1e-9) + np.sqrt(eps), output_type="ndarray")
    pairs = np.sort(pairs.reshape(-1, 2), axis=1)
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


# -- validation ---------------------------------------------------------------------


def _domain_scale(domain):
    (u0, u1), (v0, v1) = domain
    return float(np.hypot(u1 - u0, v1 - v0))


def _as_loop(loop, name, domain, tol):
    """A validated polyline (k, 2) from a polyline or a :class:`BSplineLoop` (sampled within ``tol``)."""
    sampled = isinstance(loop, BSplineLoop)
    expected = f"{name} must be a (k, 2) array of (u, v) points or a BSplineLoop"
    if sampled:
        P = loop.sample(tol=tol)
    else:
        if isinstance(loop, (str, bytes)):
            raise TypeError(f"{expected}; got {type(loop).__name__}")
        try:
            P = np.array(loop, dtype=float)
        except (TypeError, ValueError):
            raise TypeError(f"{expected}; got {type(loop).__name__}") from None
        if P.ndim != 2 or P.shape[1] != 2:
            raise ValueError(f"{expected}; got shape {P.shape}")
    if not np.all(np.isfinite(P)):
        raise ValueError(f"{name} must contain only finite values; got NaN or inf")
    scale = _domain_scale(domain)
    # drop repeated consecutive points (the later of each pair) and an explicit closing point,
    # so that indices in messages are those of the input as long as it has no repeats
    if len(P):
        keep = np.ones(len(P), dtype=bool)
        keep[1:] = np.linalg.norm(np.diff(P, axis=0), axis=1) > TRIM_RTOL * scale
        if len(P) > 1 and np.linalg.norm(P[-1] - P[0]) <= TRIM_RTOL * scale:
            keep[-1] = False
        P = P[keep]
    if len(P) < 3:
        raise ValueError(f"{name} must have at least 3 distinct points; got {len(P)}")
    (u0, u1), (v0, v1) = domain
    slack = TRIM_RTOL * scale
    bad = (P[:, 0] < u0 - slack) | (P[:, 0] > u1 + slack) | (P[:, 1] < v0 - slack) | (P[:, 1] > v1 + slack)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{name}: points must lie in the surface's domain [{u0:g}, {u1:g}] x [{v0:g}, {v1:g}]; "
            f"{np.count_nonzero(bad)} of {len(P)} do not, e.g. point {i} = ({P[i, 0]:g}, {P[i, 1]:g})"
        )
    P = np.column_stack([np.clip(P[:, 0], u0, u1), np.clip(P[:, 1], v0, v1)])
    of = " of the sampled polyline" if sampled else ""
    pairs, where = loop_intersections(P, scale)
    if len(pairs):
        (i, j), (x, y) = pairs[0], where[0]
        more = f" ({len(pairs)} pairs in all)" if len(pairs) > 1 else ""
        raise ValueError(
            f"{name} intersects itself: segments {i} and {j}{of} meet near ({x:g}, {y:g}){more}; "
            "a trimming loop must be a simple closed curve"
        )
    return P


def validate_loops(outer, holes, domain, tol=None):
    """Check and normalise trimming loops: the work behind :func:`trimmed`.

    Parameters
    ----------
    outer : (k, 2) array_like or BSplineLoop or None
        Counter-clockwise outer loop; ``None`` means the boundary of the domain.
    holes : sequence of ((k, 2) array_like or BSplineLoop)
        Clockwise holes, strictly inside the outer loop and apart from each other.
    domain : ((u_min, u_max), (v_min, v_max))
    tol : float, optional
        Chordal tolerance for sampling B-spline loops (default ``1e-4`` times
        the diagonal of the domain).

    Returns
    -------
    outer : (k, 2) ndarray
    holes : list of (k_i, 2) ndarray

    Raises
    ------
    ValueError
        Fewer than 3 points, points outside the domain, a loop that intersects
        itself, a clockwise outer loop or a counter-clockwise hole, a hole
        that crosses or lies outside the outer loop, holes that meet or nest.
    """
    (u0, u1), (v0, v1) = domain
    scale = _domain_scale(domain)
    if tol is None:
        tol = 1e-4 * scale
    if outer is None:
        outer = rectangle((u0, v0), (u1, v1))
    if holes is None or isinstance(holes, BSplineLoop) or (isinstance(holes, np.ndarray) and holes.ndim != 3):
        raise TypeError("holes must be a list of loops (each a (k, 2) array or a BSplineLoop)")
    holes = list(holes)
    O = _as_loop(outer, "outer loop", domain, tol)
    H = [_as_loop(h, f"hole {n}", domain, tol) for n, h in enumerate(holes)]
    tiny = TRIM_RTOL * scale**2
    area = signed_area(O)
    if abs(area) <= tiny:
        raise ValueError("outer loop has zero area")
    if area < 0:
        raise ValueError(
            f"outer loop runs clockwise (signed area {area:.6g}); the outer loop must run counter-clockwise: "
            "reverse it (loop[::-1], or .reversed() for a BSplineLoop)"
        )
    for n, h in enumerate(H):
        a = signed_area(h)
        if abs(a) <= tiny:
            raise ValueError(f"hole {n} has zero area")
        if a > 0:
            raise ValueError(
                f"hole {n} runs counter-clockwise (signed area {a:.6g}); holes must run clockwise: "
                "reverse it (loop[::-1], or .reversed() for a BSplineLoop)"
            )
    for n, h in enumerate(H):
        pairs, where = loops_intersections(h, O, scale)
        if len(pairs):
            (i, j), (x, y) = pairs[0], where[0]
            raise ValueError(
                f"hole {n} meets the outer loop: its segment {i} meets segment {j} of the outer loop "
                f"near ({x:g}, {y:g}); a hole must lie strictly inside the outer loop"
            )
        if not point_in_loop(h[:1], O)[0]:
            raise ValueError(f"hole {n} lies outside the outer loop; a hole must lie strictly inside it")
    for a in range(len(H)):
        for b in range(a + 1, len(H)):
            pairs, where = loops_intersections(H[a], H[b], scale)
            if len(pairs):
                (i, j), (x, y) = pairs[0], where[0]
                raise ValueError(
                    f"holes {a} and {b} intersect: segment {i} of hole {a} meets segment {j} of hole {b} "
                    f"near ({x:g}, {y:g})"
                )
            for inner, outer_ in ((b, a), (a, b)):
                if point_in_loop(H[inner][:1], H[outer_])[0]:
                    raise ValueError(
                        f"hole {inner} lies inside hole {outer_}; holes must not nest (islands are not supported)"
                    )
    return O, H


# -- triangulation ------------------------------------------------------------------


class Triangulation(NamedTuple):
    """A triangulation of the trimmed region in the parameter domain.

    ``uv`` : (k, 2) ndarray, the vertices; the boundary nodes come first,
    the outer loop's then each hole's, in loop order (see :func:`triangulate`).
    ``triangles`` : (t, 3) int ndarray, counter-clockwise in ``(u, v)``.
    """

    uv: np.ndarray
    triangles: np.ndarray


def _iso_lines(domain, n_u, n_v):
    (u0, u1), (v0, v1) = domain
    return np.linspace(u0, u1, n_u), np.linspace(v0, v1, n_v)


def _insert_crossings(loop, us, vs, gap):
    """Insert the intersections of the iso-parameter lines ``u = us``, ``v = vs`` with the loop's segments.

    The "v value table" of ``seeds/002``, 2.2: every iso-line crossing of a
    boundary segment becomes a boundary node (set exactly onto the iso-line),
    unless it lies closer than ``gap`` to an end of its segment or to the
    crossing before it on the segment.
    """
    A0, A1 = _segments(loop)
    k = len(A0)
    D = A1 - A0
    L = np.linalg.norm(D, axis=1)
    seg, t, axes, values = [], [], [], []
    for axis, lines in ((0, us), (1, vs)):
        lo = np.minimum(A0[:, axis], A1[:, axis])
        hi = np.maximum(A0[:, axis], A1[:, axis])
        first = np.searchsorted(lines, lo, side="right")  # lines strictly between lo and hi
        count = np.maximum(np.searchsorted(lines, hi, side="left") - first, 0)
        s = np.repeat(np.arange(k), count)
        j = np.repeat(first, count) + np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        seg.append(s)
        values.append(lines[j])
        t.append((lines[j] - A0[s, axis]) / D[s, axis])
        axes.append(np.full(len(s), axis))
    seg, t, axes, values = (np.concatenate(a) for a in (seg, t, axes, values))
    ok = (t * L[seg] >= gap) & ((1 - t) * L[seg] >= gap)
    seg, t, axes, values = seg[ok], t[ok], axes[ok], values[ok]
    order = np.lexsort((t, seg))
    seg, t, axes, values = seg[order], t[order], axes[order], values[order]
    close = np.zeros(len(seg), dtype=bool)
    close[1:] = (seg[1:] == seg[:-1]) & ((t[1:] - t[:-1]) * L[seg[1:]] < gap)
    seg, t, axes, values = seg[~close], t[~close], axes[~close], values[~close]
    P = A0[seg] + t[:, None] * D[seg]
    P[np.arange(len(P)), axes] = values  # exactly on the iso-line
    # merge: each original point (t = -1) before the crossings of its segment
    all_seg = np.concatenate([np.arange(k), seg])
    all_t = np.concatenate([np.full(k, -1.0), t])
    return np.concatenate([A0, P])[np.lexsort((all_t, all_seg))]


def _split_long_segments(loop, spacing):
    """Split every segment longer than ``spacing`` into equal pieces (the new points lie on the segment)."""
    A0, A1 = _segments(loop)
    pieces = np.maximum(1, np.ceil(np.linalg.norm(A1 - A0, axis=1) / spacing * (1 - 1e-12))).astype(int)
    if np.all(pieces == 1):
        return loop
    out = [a + np.arange(k)[:, None] / k * (b - a) for a, b, k in zip(A0, A1, pieces)]
    return np.concatenate(out)


def _interior_point(loop):
    """A point strictly inside a simple polygon: the centroid of the largest triangle of its triangulation."""
    import triangle

    k = len(loop)
    seg = np.column_stack([np.arange(k), (np.arange(k) + 1) % k])
    res = triangle.triangulate({"vertices": loop, "segments": seg}, "p")
    X = res["vertices"][res["triangles"]]
    area = np.abs(_cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]))
    return X[np.argmax(area)].mean(axis=0)


def triangulate(outer, holes, domain, n_u=32, n_v=32, max_area=None, min_angle=20.0, iso_nodes=True):
    """Constrained Delaunay triangulation of a trimmed region in the parameter domain (``seeds/002``, 2.2-2.4).

    Boundary nodes are the loop points, the crossings of the iso-parameter
    lines with the loops and, where a segment is still longer than the grid
    spacing (or ``1.5 sqrt(max_area)``), equidistant points on it.  Inner
    nodes are the nodes of the ``n_u x n_v`` iso-parameter grid inside the
    region that keep at least half a grid spacing from the loops (nearer ones
    would make slivers).  The boundary segments are constrained (Triangle's
    ``p``) and never split (``Y``), so the mesh boundary is exactly these
    nodes and the triangles cover exactly the polygon bounded by the loops;
    quality refinement (``q``) and ``max_area`` (``a``) add inner points only.

    Parameters
    ----------
    outer : (k, 2) ndarray
        Validated counter-clockwise outer loop (see :func:`validate_loops`).
    holes : list of (k_i, 2) ndarray
        Validated clockwise holes.
    domain : ((u_min, u_max), (v_min, v_max))
    n_u, n_v : int
        Number of iso-parameter lines in u and v (over the whole domain, ends included).
    max_area : float, optional
        Largest triangle area in the ``(u, v)`` domain (Triangle's ``a``).
    min_angle : float or None
        Smallest angle in degrees (Triangle's ``q``), at most 33; ``None``
        switches quality refinement off.  Angles between input segments
        smaller than this are kept.
    iso_nodes : bool
        Insert the iso-parameter nodes (grid and crossings); with ``False``
        only the loop points (and refinement points) are used.

    Returns
    -------
    Triangulation
        ``uv`` (k, 2) and counter-clockwise ``triangles`` (t, 3).
    """
    try:
        import triangle
    except ImportError:  # pragma: no cover - depends on the installation
        raise ImportError(
            "triangulating a trimmed surface needs the package 'triangle' (pip install triangle)"
        ) from None
    n_u = _v.as_positive_int(n_u, "n_u", minimum=2)
    n_v = _v.as_positive_int(n_v, "n_v", minimum=2)
    opts = "pY"  # PSLG; no Steiner points on the boundary: the loops below are the mesh boundary
    if min_angle is not None:
        min_angle = float(min_angle)
        if not 0 < min_angle <= MAX_MIN_ANGLE:
            raise ValueError(f"min_angle must be in (0, {MAX_MIN_ANGLE:g}] degrees or None; got {min_angle:g}")
        opts += f"q{min_angle:.17g}"
    if max_area is not None:
        max_area = float(max_area)
        if not max_area > 0:
            raise ValueError(f"max_area must be positive; got {max_area:g}")
        opts += f"a{max_area:.17g}"
    us, vs = _iso_lines(domain, n_u, n_v)
    h = min(np.diff(us).min(), np.diff(vs).min())
    spacing = h if max_area is None else min(h, 1.5 * np.sqrt(max_area))
    loops = [outer] + list(holes)
    if iso_nodes:
        loops = [_insert_crossings(L, us, vs, 0.25 * h) for L in loops]
    loops = [_split_long_segments(L, spacing) for L in loops]
    sizes = [len(L) for L in loops]
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    segments = np.concatenate(
        [s + np.column_stack([np.arange(k), (np.arange(k) + 1) % k]) for s, k in zip(starts, sizes)]
    )
    vertices = np.concatenate(loops)
    if iso_nodes:
        U, V = np.meshgrid(us, vs, indexing="ij")
        G = np.column_stack([U.ravel(), V.ravel()])
        inside = point_in_loop(G, outer)
        for H in holes:
            inside &= ~point_in_loop(G, H)
        G = G[inside]
        clear = np.ones(len(G), dtype=bool)
        for L in loops:
            clear &= distance_to_loop(G, L) >= 0.5 * h
        vertices = np.concatenate([vertices, G[clear]])
    data = {"vertices": vertices, "segments": segments}
    if holes:
        data["holes"] = np.array([_interior_point(H) for H in holes])
    res = triangle.triangulate(data, opts)
    uv = np.asarray(res["vertices"], dtype=float)
    tri = np.asarray(res["triangles"], dtype=np.int64)
    # drop vertices no triangle uses (none are expected); the order, input first, is kept
    used = np.zeros(len(uv), dtype=bool)
    used[tri.ravel()] = True
    if not np.all(used):
        new = np.cumsum(used) - 1
        uv, tri = uv[used], new[tri]
    return Triangulation(uv, tri)


def boundary_edges(triangles):
    """Edges ``(m, 2)`` that belong to exactly one triangle, oriented as in their triangle."""
    T = np.asarray(triangles)
    E = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    key = np.sort(E, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return E[counts[inverse.ravel()] == 1]


# -- the trimmed surface -------------------------------------------------------------


class TrimmedSurface:
    """A base surface restricted to the region bounded by trimming loops in its domain (``seeds/002``, section 2).

    Build it with :func:`trimmed`.  The loops are stored as validated
    polylines: :attr:`outer` (counter-clockwise) and :attr:`holes` (clockwise).

    Parameters
    ----------
    surface : lab.Surface
        The base surface (anything with ``domain``, ``derivatives`` and ``curvature``).
    outer : (k, 2) array_like or BSplineLoop or None
        Outer loop, counter-clockwise; ``None`` is the boundary of the domain.
    holes : sequence of ((k, 2) array_like or BSplineLoop)
        Holes, clockwise.
    tol : float, optional
        Chordal tolerance for sampling B-spline loops (default ``1e-4`` times
        the diagonal of the domain).
    """

    def __init__(self, surface, outer=None, holes=(), tol=None):
        for attr in ("domain", "derivatives", "curvature"):
            if not hasattr(surface, attr):
                raise TypeError(f"surface must be a lab.Surface (with domain, derivatives, curvature); got {surface!r}")
        self.surface = surface
        self.domain = tuple(tuple(float(x) for x in pair) for pair in surface.domain)
        self.outer, self.holes = validate_loops(outer, holes, self.domain, tol)

    @property
    def loops(self):
        """The outer loop followed by the holes, as polylines."""
        return [self.outer] + self.holes

    @property
    def area_uv(self):
        """Area of the trimmed region in the parameter domain (outer minus holes, as polygons)."""
        return signed_area(self.outer) + sum(signed_area(h) for h in self.holes)

    def contains(self, u, v, atol=None):
        """Whether ``(u, v)`` lies in the trimmed region; points on a loop (within ``atol``) count as inside.

        Parameters
        ----------
        u, v : array_like
            Broadcast against each other (need not lie in the domain).
        atol : float, optional
            Default :data:`TRIM_RTOL` times the diagonal of the domain.

        Returns
        -------
        bool ndarray of shape ``broadcast(u, v).shape``
        """
        uu, vv = np.broadcast_arrays(_v._as_float_array(u, "u"), _v._as_float_array(v, "v"))
        X = np.column_stack([uu.ravel(), vv.ravel()])
        if atol is None:
            atol = TRIM_RTOL * _domain_scale(self.domain)
        inside = point_in_loop(X, self.outer)
        for h in self.holes:
            inside &= ~point_in_loop(X, h)
        near = np.zeros(len(X), dtype=bool)
        for L in self.loops:
            near |= distance_to_loop(X, L) <= atol
        return (inside | near).reshape(uu.shape)

    def _inside(self, u, v, what):
        u, v = _v.as_parameters(u, v, self.domain)
        ok = self.contains(u, v)
        if not np.all(ok):
            i = int(np.flatnonzero(~ok.ravel())[0])
            raise ValueError(
                f"{what}: {np.count_nonzero(~ok)} of {ok.size} (u, v) points lie outside the trimmed region, "
                f"e.g. ({u.ravel()[i]:g}, {v.ravel()[i]:g}); select points with contains(u, v)"
            )
        return u, v

    def derivatives(self, u, v):
        """Derivatives of the base surface at ``(u, v)`` inside the trimmed region (``ValueError`` outside)."""
        return self.surface.derivatives(*self._inside(u, v, "derivatives"))

    def evaluate(self, u, v):
        """Surface points at ``(u, v)`` inside the trimmed region (``ValueError`` outside)."""
        return self.derivatives(u, v).b

    def curvature(self, u, v, outside="raise"):
        """Curvature of the base surface (fields ``K, H, k1, k2, degenerate``) at ``(u, v)``.

        Trimming does not change the surface, so the values are the base
        surface's.  Points outside the trimmed region raise a ``ValueError``
        (``outside="raise"``) or get NaN values with ``degenerate`` False
        (``outside="nan"``).
        """
        outside = _v.as_choice(outside, ("raise", "nan"), "outside")
        if outside == "raise":
            return self.surface.curvature(*self._inside(u, v, "curvature"))
        u, v = _v.as_parameters(u, v, self.domain)
        c = self.surface.curvature(u, v)
        ok = self.contains(u, v)
        return type(c)(*(np.where(ok, f, np.nan) for f in c[:4]), np.where(ok, c.degenerate, False))

    def triangulate(self, n_u=32, n_v=32, max_area=None, min_angle=20.0, iso_nodes=True):
        """Triangulate the trimmed region in ``(u, v)``; see :func:`triangulate`."""
        return triangulate(self.outer, self.holes, self.domain, n_u, n_v, max_area, min_angle, iso_nodes)

    def to_mesh(self, n_u=32, n_v=32, max_area=None, min_angle=20.0, curvature_mode=None, color_map=None):
        """A :class:`pyvista.PolyData` with exact curvature point data; see :func:`lab.trimmed_mesh.trimmed_mesh`."""
        from .trimmed_mesh import trimmed_mesh

        return trimmed_mesh(self, n_u=n_u, n_v=n_v, max_area=max_area, min_angle=min_angle,
                            curvature_mode=curvature_mode, color_map=color_map)

    def __repr__(self):
        return f"TrimmedSurface({self.surface!r}, outer loop of {len(self.outer)} points, {len(self.holes)} holes)"


def trimmed(surface, outer=None, holes=(), *, tol=None):
    """A trimmed surface: ``surface`` restricted to the region inside ``outer`` and outside the ``holes``.

    Parameters
    ----------
    surface : lab.Surface
    outer : (k, 2) array_like or BSplineLoop or None
        Counter-clockwise outer loop in the parameter domain; ``None`` is the domain's boundary.
    holes : sequence of ((k, 2) array_like or BSplineLoop)
        Clockwise holes strictly inside the outer loop.
    tol : float, optional
        Chordal tolerance for sampling B-spline loops (default ``1e-4`` times
        the diagonal of the domain).

    Returns
    -------
    TrimmedSurface

    Examples
    --------
    >>> import lab
    >>> from lab import trimming
    >>> s = trimming.trimmed(lab.surfaces.plane(), trimming.circle((0.5, 0.5), 0.4, n=128),
    ...                      holes=[trimming.circle((0.5, 0.5), 0.1, n=32, clockwise=True)])
    >>> bool(s.contains(0.5, 0.5)), bool(s.contains(0.5, 0.75))
    (False, True)
    """
    return TrimmedSurface(surface, outer, holes, tol=tol)
