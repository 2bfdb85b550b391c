"""Parameter grids of a surface: which grid nodes are one point of the surface, decided by index, never by distance.

A grid of ``a x b`` parameter nodes covering the domain (ends included) maps
to the surface; nodes that are the same surface point are known from the
surface's structure: the last row equals the first where the surface is
periodic in u (a torus, the u seam of a sphere), the last column likewise in
v, and every node of an edge that collapses to one point (a sphere's pole,
the centre of a surface of revolution) is that one point.  Welding by these
indices is exact and linear in the number of nodes; welding by distance would
also merge points that merely come close (a surface folding back onto itself)
and costs a spatial search.
"""

from typing import NamedTuple

import numpy as np

__all__ = ["NO_SEAMS", "Seams", "weld_labels", "weld_parameters"]


class Seams(NamedTuple):
    """Where a surface closes on itself or collapses, per parameter direction.

    ``periodic[0]``: x(u_min, v) = x(u_max, v); ``collapsed[0][0]``: the edge
    u = u_min is a single point (``collapsed[0][1]`` the edge u = u_max,
    ``collapsed[1]`` the edges v = v_min and v = v_max).
    """

    periodic: tuple = (False, False)
    collapsed: tuple = ((False, False), (False, False))


NO_SEAMS = Seams()


def weld_labels(shape, seams=NO_SEAMS):
    """Labels that weld the nodes of an ``a x b`` grid into surface points.

    Parameters
    ----------
    shape : (int, int)
        Nodes along u and along v, the domain's ends included.
    seams : Seams

    Returns
    -------
    labels : (a * b,) int ndarray
        The point of each node (row-major), numbered in the order of first appearance.
    n : int
        Number of points.
    """
    a, b = shape
    ids = np.arange(a * b).reshape(a, b)
    (pu, pv), ((u0, u1), (v0, v1)) = seams
    if pu:
        ids[-1, :] = ids[0, :]
    if pv:
        ids[:, -1] = ids[:, 0]
    if u0:
        ids[0, :] = ids[0, 0]
    if u1:
        ids[-1, :] = ids[-1, 0]
    if v0:
        ids[:, 0] = ids[0, 0]
    if v1:
        ids[:, -1] = ids[0, -1]
    rep = ids.reshape(-1)
    while True:  # a node may point at one that was redirected after it was copied: follow to the end
        nxt = rep[rep]
        if np.array_equal(nxt, rep):
            break
        rep = nxt
    used = np.zeros(a * b, dtype=bool)
    used[rep] = True
    number = np.cumsum(used) - 1
    return number[rep], int(number[-1]) + 1 if a * b else 0


def weld_parameters(uv, domain, seams=NO_SEAMS):
    """Labels that weld points given by their parameters, by the same rules as :func:`weld_labels`.

    Two parameter pairs are one surface point when they are equal after
    mapping the end of a periodic direction onto its start and every
    parameter of a collapsed edge onto one; the comparison is exact, so only
    nodes that lie exactly on a seam or edge (as a triangulation's boundary
    nodes do) are welded.

    Parameters
    ----------
    uv : (k, 2) ndarray
    domain : ((u0, u1), (v0, v1))
    seams : Seams

    Returns
    -------
    labels : (k,) int ndarray
        Numbered in the order of first appearance.
    n : int
    """
    key = np.array(uv, dtype=float, copy=True)
    (pu, pv), collapsed = seams
    for axis, periodic in ((0, pu), (1, pv)):
        lo, hi = domain[axis]
        if periodic:
            key[key[:, axis] == hi, axis] = lo
    for axis in (0, 1):
        other = 1 - axis
        for end, is_collapsed in zip(domain[axis], collapsed[axis]):
            if is_collapsed:
                key[key[:, axis] == end, other] = domain[other][0]
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    rank = np.empty(len(first), dtype=int)
    rank[np.argsort(first, kind="stable")] = np.arange(len(first))  # number by first appearance
    return rank[inverse], len(first)
