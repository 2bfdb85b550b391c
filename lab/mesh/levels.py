"""Level lines of a piecewise-linear function on a triangle mesh (marching triangles).

A tool below the topics that use it: reflection lines and isophotes (:mod:`lab.interrogation.reflection`)
and parabolic lines, K = 0 (:mod:`lab.interrogation.focal`).  Only NumPy is imported here (and SciPy's k-d tree for joining lines).
"""

import itertools

import numpy as np

__all__ = ["join_polylines", "level_lines"]


def _edge_lookup(T):
    """Sorted edge keys of all triangles with the triangle and opposite vertex of each (for neighbour queries)."""
    k = int(T.max()) + 1 if T.size else 1
    e = np.concatenate([T[:, [1, 2]], T[:, [2, 0]], T[:, [0, 1]]])
    opp = np.concatenate([T[:, 0], T[:, 1], T[:, 2]])
    tri = np.tile(np.arange(len(T)), 3)
    e.sort(axis=1)
    keys = e[:, 0].astype(np.int64) * k + e[:, 1]
    order = np.argsort(keys, kind="stable")
    return keys[order], opp[order], tri[order], k


def _chain(seg, n_nodes, closed_repeat=True):
    """Join segments (s, 2) of node ids into maximal chains; a closed chain repeats its first node at the end."""
    adj = [[] for _ in range(n_nodes)]
    for s, (i, j) in enumerate(seg):
        adj[i].append((j, s))
        adj[j].append((i, s))
    used = np.zeros(len(seg), dtype=bool)
    chains = []

    def walk(start):
        path, node = [start], start
        while True:
            nxt = next(((j, s) for j, s in adj[node] if not used[s]), None)
            if nxt is None:
                return path
            used[nxt[1]] = True
            node = nxt[0]
            path.append(node)
            if node == start or len(adj[node]) != 2:
                return path

    # open chains start at nodes of odd or > 2 degree, then the remaining (closed) loops
    starts = [i for i in range(n_nodes) if len(adj[i]) not in (0, 2)]
    for i in starts:
        while any(not used[s] for _, s in adj[i]):
            chains.append(walk(i))
    for s in range(len(seg)):
        if not used[s]:
            chains.append(walk(int(seg[s][0])))
    return chains


def level_lines(points, triangles, values, level=0.0, tol=0.0):
    r"""The curves where the piecewise-linear interpolant of ``values`` equals ``level`` (marching triangles).

    On every edge whose end values lie strictly on opposite sides of the level
    the crossing is found by linear interpolation; the crossings of a triangle
    are joined, and the segments are chained into polylines.

    Values within ``tol`` of the level count as on it.  Such a vertex belongs
    to a line only where the line separates values strictly above from values
    strictly below: a line may run through such vertices and along edges
    joining two of them (when the triangles on the two sides have a vertex
    above and one below), but a region where the values equal the level (the
    flat spot of a car hood for ``K = 0``, a whole cylinder) yields no lines,
    nor does a point touching the level.  Triangles with a NaN vertex are
    skipped (there is no value there, e.g. a ray that misses the light plane).

    Parameters
    ----------
    points : (k, 3) array_like
    triangles : (t, 3) int array_like
    values : (k,) array_like
    level : float
    tol : float

    Returns
    -------
    list of (n, 3) ndarray
        Polylines; a closed one repeats its first point at the end.
    """
    X = np.asarray(points, dtype=float)
    T = np.asarray(triangles, dtype=np.int64)
    f = np.asarray(values, dtype=float) - level
    f = np.where(np.abs(f) <= tol, 0.0, f)
    fT = f[T]
    valid = np.all(np.isfinite(fT), axis=1)
    above = fT >= 0
    n_above = above.sum(axis=1)
    cut = valid & (n_above > 0) & (n_above < 3)
    idx = np.nonzero(cut)[0]
    if idx.size == 0:
        return []
    ab = above[idx]
    # the vertex alone on its side, then the other two in cyclic order
    lonely = np.where(n_above[idx] == 1, np.argmax(ab, axis=1), np.argmin(ab, axis=1))
    order = (lonely[:, None] + np.arange(3)) % 3
    t = np.take_along_axis(T[idx], order, axis=1)
    k = len(X)

    def crossing(i, j):
        """Node key and point of the crossing on edge (i, j); at a vertex if its value is exactly 0."""
        fi, fj = f[i], f[j]
        s = fi / (fi - fj)  # fi, fj on opposite sides (one may be 0): fi != fj
        at_i, at_j = fi == 0, fj == 0
        lo, hi = np.minimum(i, j), np.maximum(i, j)
        key = np.where(at_i, i, np.where(at_j, j, k + lo * k + hi))
        pt = X[i] + s[:, None] * (X[j] - X[i])
        return key, pt

    key1, p1 = crossing(t[:, 0], t[:, 1])
    key2, p2 = crossing(t[:, 0], t[:, 2])
    ok = key1 != key2
    # a segment between two vertices on the level runs along their edge (b, c): keep it only if the
    # triangle across that edge has its third vertex strictly above (this one's lonely vertex is below)
    on_edge = ok & (key1 < k) & (key2 < k)
    if np.any(on_edge):
        keys, opp, tri, kk = _edge_lookup(T)
        b, c = t[on_edge, 1], t[on_edge, 2]
        ek = np.minimum(b, c).astype(np.int64) * kk + np.maximum(b, c)
        own = idx[on_edge]
        keep = np.zeros(len(ek), dtype=bool)
        pos = np.searchsorted(keys, ek)
        for off in (0, 1):
            p = np.minimum(pos + off, len(keys) - 1)
            match = (keys[p] == ek) & (tri[p] != own)
            fo = f[opp[p]]
            keep |= match & (fo > 0) & np.isfinite(fo)
        ok[np.nonzero(on_edge)[0][~keep]] = False
    key1, key2, p1, p2 = key1[ok], key2[ok], p1[ok], p2[ok]
    if key1.size == 0:
        return []
    allkeys = np.concatenate([key1, key2])
    ukeys, first, inv = np.unique(allkeys, return_index=True, return_inverse=True)
    pts = np.concatenate([p1, p2])[first]
    seg = np.stack([inv[: len(key1)], inv[len(key1):]], axis=1)
    return [pts[c] for c in _chain(seg, len(ukeys))]


def join_polylines(lines, tol):
    """Join open polylines whose ends lie within ``tol`` of each other (level lines of a mesh that is not welded).

    A model's mesh has one vertex set per face (:meth:`lab.Model.to_mesh`): the level lines of each face end on
    its border, and where the function is continuous across the border the line of the neighbouring face starts
    within a small gap (the two faces sample their common edge at different points).  Each end is joined to its
    nearest partner within ``tol`` (nearest pairs first, each end at most once), the two end points replaced by
    their midpoint.  Where the function jumps (a kink, G0) the ends lie apart and the lines stay broken.

    Parameters
    ----------
    lines : list of (n, 3) array_like
        Polylines; a closed one repeats its first point and is left as it is.
    tol : float
        Largest distance between two ends that are joined.

    Returns
    -------
    list of (n, 3) ndarray
        The joined polylines; a chain that closes repeats its first point at the end.
    """
    from scipy.spatial import cKDTree

    lines = [np.asarray(line, dtype=float) for line in lines if len(line)]
    closed = [line for line in lines if len(line) > 2 and np.array_equal(line[0], line[-1])]
    open_ = [line for line in lines if not (len(line) > 2 and np.array_equal(line[0], line[-1]))]
    if len(open_) == 0 or not tol > 0:
        return closed + open_
    ends = np.array([p for line in open_ for p in (line[0], line[-1])])  # end e of line e // 2 (0: start, 1: stop)
    pairs = cKDTree(ends).query_pairs(tol, output_type="ndarray")
    partner = np.full(len(ends), -1)
    if len(pairs):
        d = np.linalg.norm(ends[pairs[:, 0]] - ends[pairs[:, 1]], axis=1)
        for (a, b) in pairs[np.argsort(d, kind="stable")]:
            same_line = a // 2 == b // 2
            if partner[a] < 0 and partner[b] < 0 and not (same_line and len(open_[a // 2]) < 3):
                partner[a], partner[b] = b, a
    used = np.zeros(len(open_), dtype=bool)
    out = list(closed)

    def walk(end):
        """The chain that starts at ``end`` (an end without a partner, or any end of a cycle)."""
        pieces, e = [], end
        while True:
            k = e // 2
            if used[k]:
                return pieces, True
            used[k] = True
            line = open_[k] if e % 2 == 0 else open_[k][::-1]
            pieces.append(line)
            other = e ^ 1  # the line's other end
            if partner[other] < 0:
                return pieces, False
            e = partner[other]

    def merge(pieces, cycle):
        points = [pieces[0]]
        for a, b in itertools.pairwise(pieces):
            mid = 0.5 * (a[-1] + b[0])
            points[-1] = np.vstack([points[-1][:-1], mid[None]])
            points.append(b[1:])
        line = np.vstack(points)
        if cycle:
            mid = 0.5 * (line[-1] + line[0])
            line[0] = line[-1] = mid
        return line

    for e in range(len(ends)):  # chains with a free end first, from that end
        if partner[e] < 0 and not used[e // 2]:
            out.append(merge(*walk(e)))
    for e in range(len(ends)):  # what is left are cycles
        if not used[e // 2]:
            out.append(merge(*walk(e)))
    return out
