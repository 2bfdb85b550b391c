"""Validation of trimming loops and the constrained Delaunay triangulation of the trimmed region (Choi & Lee, §2.2)."""

from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from ...geometry import validation as _v
from ...i18n import _, decimal
from .loops import (
    TRIM_RTOL,
    BSplineLoop,
    _cross,
    _point_segment_distance,
    _segments,
    loop_intersections,
    loops_intersections,
    point_in_loop,
    rectangle,
    signed_area,
)

__all__ = ["MAX_MIN_ANGLE", "Triangulation", "boundary_edges", "triangulate", "validate_loops"]

#: Largest minimum angle (degrees) that Triangle's quality refinement is
#: guaranteed to reach; it may not terminate much above this (Triangle's manual).
MAX_MIN_ANGLE = 33.0


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
            P = np.asarray(loop)  # the shape first: a broadcast view of a huge shape is refused before it is copied
        except (TypeError, ValueError, OverflowError):
            raise TypeError(f"{expected}; got {type(loop).__name__}") from None
        if P.ndim != 2 or P.shape[1] != 2:
            raise ValueError(f"{expected}; got shape {P.shape}")
        try:
            P = np.array(P, dtype=float)
        except (TypeError, ValueError, OverflowError):
            raise TypeError(f"{expected}; got {type(loop).__name__} of {P.dtype}") from None
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
    tol = 1e-4 * scale if tol is None else _v.as_number(tol, "tol", positive=True)
    if outer is None:
        outer = rectangle((u0, v0), (u1, v1))
    if (holes is None or isinstance(holes, (BSplineLoop, str, bytes)) or not hasattr(holes, "__iter__")
            or (isinstance(holes, np.ndarray) and holes.ndim != 3)):
        raise TypeError(f"holes must be a list of loops (each a (k, 2) array or a BSplineLoop); got "
                        f"{_v._short(holes)}")
    holes = list(holes)
    O = _as_loop(outer, "outer loop", domain, tol)
    H = [_as_loop(h, f"hole {n}", domain, tol) for n, h in enumerate(holes)]
    tiny = TRIM_RTOL * scale**2
    area = signed_area(O)
    if abs(area) <= tiny:
        raise ValueError("outer loop has zero area")
    if area < 0:
        raise ValueError(_(
            "outer loop runs clockwise (signed area {area}); the outer loop must run counter-clockwise: "
            "reverse it (loop[::-1], or .reversed() for a BSplineLoop)").format(area=_number(area)))
    for n, h in enumerate(H):
        a = signed_area(h)
        if abs(a) <= tiny:
            raise ValueError(f"hole {n} has zero area")
        if a > 0:
            raise ValueError(_(
                "hole {n} runs counter-clockwise (signed area {area}); holes must run clockwise: "
                "reverse it (loop[::-1], or .reversed() for a BSplineLoop)").format(n=n, area=_number(a)))
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



def _number(x):
    """A number in a message, with the decimal comma in German."""
    return decimal(f"{x:.6g}")


# -- triangulation ------------------------------------------------------------------


class Triangulation(NamedTuple):
    """A triangulation of the trimmed region in the parameter domain.

    ``uv`` : (k, 2) ndarray, the vertices; the boundary nodes come first,
    the outer loop's then each hole's, in loop order (see :func:`triangulate`).
    ``triangles`` : (t, 3) int ndarray, counter-clockwise in ``(u, v)``.
    """

    uv: np.ndarray
    triangles: np.ndarray

    @property
    def areas(self):
        """(t,) ndarray: the triangles' areas in ``(u, v)`` (positive: counter-clockwise)."""
        a, b, c = (self.uv[self.triangles[:, k]] for k in range(3))
        return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))

    @property
    def angles(self):
        """(t, 3) ndarray: the triangles' angles in degrees at their three corners, in ``(u, v)``."""
        P = self.uv[self.triangles]
        e1, e2 = np.roll(P, -1, axis=1) - P, np.roll(P, -2, axis=1) - P
        cos = np.einsum("tij,tij->ti", e1, e2) / (np.linalg.norm(e1, axis=2) * np.linalg.norm(e2, axis=2))
        return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def _iso_lines(domain, n_u, n_v):
    (u0, u1), (v0, v1) = domain
    return np.linspace(u0, u1, n_u), np.linspace(v0, v1, n_v)


def _insert_crossings(loop, us, vs, gap):
    """Insert the intersections of the iso-parameter lines ``u = us``, ``v = vs`` with the loop's segments.

    The "v value table" of Choi & Lee, §2.2: every iso-line crossing of a
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
    segment = np.repeat(np.arange(len(A0)), pieces)  # piece i of segment s starts at A0 + i / k (A1 - A0)
    k = pieces[segment]
    i = np.arange(len(segment)) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    return A0[segment] + (i / k)[:, None] * (A1 - A0)[segment]


def _interior_point(loop):
    """A point strictly inside a simple polygon: the centroid of the largest triangle of its triangulation."""
    import triangle

    k = len(loop)
    seg = np.column_stack([np.arange(k), (np.arange(k) + 1) % k])
    res = triangle.triangulate({"vertices": loop, "segments": seg}, "p")
    X = res["vertices"][res["triangles"]]
    area = np.abs(_cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]))
    return X[np.argmax(area)].mean(axis=0)


#: Bytes per node a triangulation plans for (grid tests, Triangle's arrays, the 3-D mesh made from it).
TRIANGULATION_BYTES_PER_NODE = 1000


def triangulate(outer, holes, domain, n_u=32, n_v=32, max_area=None, min_angle=20.0, iso_nodes=True, *,
                memory_limit=None):
    """Constrained Delaunay triangulation of a trimmed region in the parameter domain (Choi & Lee, §2.2-2.4).

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
    memory_limit : int or str, optional
        The estimated memory (grid nodes, and two nodes per ``max_area`` of
        the domain) must stay below it (default :func:`lab.memory_limit`).

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
    (u0, u1), (v0, v1) = domain
    nodes = n_u * n_v + (0 if max_area is None else 2 * (u1 - u0) * (v1 - v0) / max_area)
    _v.check_memory(TRIANGULATION_BYTES_PER_NODE * nodes, f"a triangulation with about {nodes:.3g} nodes",
                    memory_limit)
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
            # a node whose nearest loop point is farther than 0.5 h + half the longest segment is clear of
            # every segment (a segment's points lie within half its length of one of its ends): measured
            # exactly are only the nodes near the loop
            A0, A1 = _segments(L)
            half = 0.5 * float(np.linalg.norm(A1 - A0, axis=1).max())
            near, _ = cKDTree(L).query(G, distance_upper_bound=0.5 * h + half)
            near = np.flatnonzero(np.isfinite(near))
            for block in np.array_split(near, max(1, len(near) * len(A0) // 2**16)):  # exact, all segments
                d = _point_segment_distance(G[block, None], A0[None], A1[None]).min(axis=1)
                clear[block] &= d >= 0.5 * h
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


