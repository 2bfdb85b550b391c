r"""Tensor-product spline evaluation in cache-sized chunks: basis rows per u and per v, two small contractions.

A B-spline / NURBS surface of degrees ``(p, q)`` (a Bézier patch is the case
of one knot span) in homogeneous coordinates

.. math:: \mathbf x^w(u, v) = \sum_{i} \sum_{j} N_{i,p}(u)\, N_{j,q}(v)\, \mathbf P^w_{ij}

has ``(p+1)(q+1)`` non-zero terms at every point, and each partial derivative
replaces ``N`` by its derivative (The NURBS Book, eq. 3.17 and A3.6).  Two
drivers evaluate the six fields ``b, bu, bv, buu, buv, bvv`` and hand them,
one chunk at a time, to a function that reduces them (to curvature, normals,
...), so the temporary memory is bounded by :data:`CHUNK`, not by the number
of points:

* :func:`map_spline_points` for parameters of any shape: the points are
  sorted by their pair of knot spans (a counting sort); per chunk the basis
  rows ``(3, p+1, k)`` of u and of v (:func:`lab.bspline.basis_rows`), their
  products, and per group of points in one pair of spans the ``(p+1)(q+1)``
  control points gathered once and one matrix product (BLAS)
  (:func:`grouped_derivatives`).  With few points per pair of spans the
  points are taken as they come, their control points gathered with one
  ``np.take`` per chunk and contracted over ``i`` and then ``j``
  (:func:`point_derivatives`, also the path of surfaces without splines,
  :func:`map_points`);
* :func:`map_grid` for a grid ``u`` vector × ``v`` vector: the basis rows once
  per u and once per v, the control points once per pair of spans, and per
  block of the grid two matrix products (BLAS).

Rational surfaces are projected per chunk with the quotient rule
(:func:`lab.derivatives.from_homogeneous`).
"""

from typing import NamedTuple

import numpy as np

from .bspline import basis_rows, find_span
from .derivatives import Derivatives, from_homogeneous

__all__ = [
    "CHUNK",
    "Spline",
    "as_grid",
    "grid_blocks",
    "grouped_derivatives",
    "map_grid",
    "map_points",
    "map_spline_points",
    "point_blocks",
    "point_derivatives",
    "runs",
    "spline",
]

#: Points per chunk: the per-chunk arrays (about 1 KiB per point) stay within a core's L2 cache.
CHUNK = 4096

#: Fewest points per pair of knot spans, on average, for the grouped evaluation (:func:`map_spline_points`).
MIN_RUN = 32

#: (du, dv) of the fields b, bu, bv, buu, buv, bvv.
_ORDERS = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))


class Spline(NamedTuple):
    """A checked tensor-product spline prepared for evaluation (see :func:`spline`)."""

    Pw: np.ndarray  #: (nu, nv, d) control points, homogeneous (w P, w) when rational
    flat: np.ndarray  #: (d, nu * nv) the same, coordinates first, for gathering
    knots_u: np.ndarray
    knots_v: np.ndarray
    degree_u: int
    degree_v: int
    rational: bool


def spline(P, knots_u, knots_v, degree_u, degree_v, weights=None):
    """Prepare a validated control net, knot vectors and optional weights for :func:`map_points` / :func:`map_grid`.

    A Bézier patch of degrees ``(m, n)`` is the spline with knots
    ``[0]*(m+1) + [1]*(m+1)`` and ``[0]*(n+1) + [1]*(n+1)``.
    """
    P = np.asarray(P, dtype=float)
    if weights is None:
        Pw = P
    else:
        w = np.asarray(weights, dtype=float)[..., None]
        Pw = np.concatenate([P * w, w], axis=-1)
    Pw = np.ascontiguousarray(Pw)
    flat = np.ascontiguousarray(Pw.reshape(-1, Pw.shape[-1]).T)
    return Spline(Pw, flat, np.asarray(knots_u, dtype=float), np.asarray(knots_v, dtype=float),
                  int(degree_u), int(degree_v), weights is not None)


def _fields(X, rational):
    """Derivatives from ``X[du, dv]`` (any layout with the coordinates on the last axis), projected if rational."""
    D = Derivatives(*(X[du][dv] for du, dv in _ORDERS))
    return from_homogeneous(D) if rational else D


def point_derivatives(s, u, v, work=None):
    """The six fields at the points ``(u, v)`` (flat arrays of one chunk), each of shape ``(k, d)``.

    Per point: the basis rows, the ``(p+1)(q+1)`` control points of its pair
    of knot spans (one ``np.take`` for the chunk) and two contractions, over
    ``i`` and then over ``j`` (products summed in a fixed order on arrays with
    the points last, so a point's value does not depend on the other points).
    The fields are views of arrays with the points last (coordinate ``c`` of
    all points is contiguous), which the curvature formulas read fastest.
    ``work`` (a dict, kept by the caller from chunk to chunk) holds the large
    intermediate arrays, so that they are allocated once per call of
    :func:`map_points` instead of once per chunk; the fields then live in
    it and are overwritten by the next chunk.
    """
    p, q = s.degree_u, s.degree_v
    nv, d, k = s.Pw.shape[1], s.Pw.shape[2], u.shape[0]
    su = find_span(s.knots_u, p, u)
    sv = find_span(s.knots_v, q, v)
    Bu = basis_rows(s.knots_u, p, su, u)  # (3, p+1, k)
    Bv = basis_rows(s.knots_v, q, sv, v)  # (3, q+1, k)
    offsets = (np.arange(p + 1)[:, None] * nv + np.arange(q + 1)[None, :])[..., None]
    index = offsets + ((su - p) * nv + (sv - q))  # (p+1, q+1, k): flat index of P_ij of each point's span
    C = np.take(s.flat, index, axis=1, out=_buffer(work, "C", (d, p + 1, q + 1, k)), mode="clip")
    # Elementwise products summed in a fixed order, so that a point's value does not depend on
    # how many points share its chunk (einsum and BLAS may reorder sums with the array sizes).
    T = _buffer(work, "T", (3, d, q + 1, k))  # over i: T[du, c, j] = sum_i N_i^(du)(u) P_ij,c
    tmp = _buffer(work, "tmp", (3, d, q + 1, k))
    np.multiply(Bu[:, None, 0, None, :], C[None, :, 0], out=T)
    for i in range(1, p + 1):
        T += np.multiply(Bu[:, None, i, None, :], C[None, :, i], out=tmp)
    X = _buffer(work, "X9", (3, 3, d, k))  # over j: X[du, dv, c] = sum_j N_j^(dv)(v) T[du, c, j]
    tmp = _buffer(work, "tmp9", (3, 3, d, k))
    np.multiply(Bv[None, :, None, 0, :], T[:, None, :, 0], out=X)
    for j in range(1, q + 1):
        X += np.multiply(Bv[None, :, None, j, :], T[:, None, :, j], out=tmp)
    return _fields(X.transpose(0, 1, 3, 2), s.rational)


def grouped_derivatives(s, u, v, first, work=None):
    """The six fields at points sorted by their pair of knot spans (flat arrays of one chunk), each ``(k, d)``.

    ``first`` (k,) is the flat index ``i * nv + j`` of the first control point
    ``P_ij`` of each point's spans (non-decreasing).  The basis rows give the
    products ``N_i(u) N_j(v)`` of every field (``W``: six rows of
    ``(p+1)(q+1)`` per point); the control points of each group of equal
    spans are gathered once and one matrix product (BLAS) gives its six fields.
    Fields and ``work`` as :func:`point_derivatives`.
    """
    p, q = s.degree_u, s.degree_v
    nv, d, k = s.Pw.shape[1], s.Pw.shape[2], u.shape[0]
    i0, j0 = np.divmod(first, nv)
    Bu = basis_rows(s.knots_u, p, i0 + p, u)  # (3, p+1, k)
    Bv = basis_rows(s.knots_v, q, j0 + q, v)  # (3, q+1, k)
    W = _buffer(work, "W", (6, p + 1, q + 1, k))
    for f, (du, dv) in enumerate(_ORDERS):
        np.multiply(Bu[du][:, None, :], Bv[dv][None, :, :], out=W[f])
    W = W.reshape(6, (p + 1) * (q + 1), k)
    X = _buffer(work, "X6", (6, d, k))
    starts = np.flatnonzero(np.r_[True, first[1:] != first[:-1]])
    for a, b in zip(starts, np.r_[starts[1:], k]):
        i, j = i0[a], j0[a]
        C = s.Pw[i : i + p + 1, j : j + q + 1].reshape(-1, d).T  # (d, (p+1)(q+1)): once per group
        X[:, :, a:b] = np.matmul(C, W[:, :, a:b])
    D = Derivatives(*X.transpose(0, 2, 1))
    return from_homogeneous(D) if s.rational else D


def _buffer(work, name, shape):
    """An array of ``shape`` from ``work`` (reused while the shape stays), or a new one without ``work``."""
    if work is None:
        return np.empty(shape)
    array = work.get(name)
    if array is None or array.shape != shape:
        array = work[name] = np.empty(shape)
    return array


def runs(span):
    """Groups of equal values of ``span`` (k,): a list of ``(value, index)`` with slices for runs of sorted input."""
    span = np.asarray(span)
    if span.size == 0:
        return []
    if np.all(span[1:] >= span[:-1]):
        cut = np.flatnonzero(span[1:] != span[:-1]) + 1
        starts, ends = np.r_[0, cut], np.r_[cut, span.size]
        return [(int(span[a]), slice(int(a), int(b))) for a, b in zip(starts, ends)]
    order = np.argsort(span, kind="stable")
    values, first = np.unique(span[order], return_index=True)
    return [(int(x), idx) for x, idx in zip(values, np.split(order, first[1:]))]


def grid_blocks(s, u, v, chunk=CHUNK):
    """The six fields on the grid ``u`` (nu,) × ``v`` (nv,), block by block.

    Yields ``(rows, cols, D)``: index (slice or array) into ``u`` and ``v``,
    and :class:`~lab.derivatives.Derivatives` with fields of shape
    ``(len(rows), len(cols), d)``; blocks hold at most about ``chunk`` points
    and never straddle a knot line, so the control points of a block are one
    ``(p+1, q+1, d)`` sub-net, gathered once.
    """
    p, q = s.degree_u, s.degree_v
    su, sv = find_span(s.knots_u, p, u), find_span(s.knots_v, q, v)
    Bu = basis_rows(s.knots_u, p, su, u)  # (3, p+1, nu): once per u
    Bv = basis_rows(s.knots_v, q, sv, v)  # (3, q+1, nv): once per v
    d = s.Pw.shape[-1]
    for b, cols_all in runs(sv):
        for cols in _pieces(cols_all, chunk):
            Bv_block = Bv[..., cols]
            nj = Bv_block.shape[-1]
            right = np.ascontiguousarray(Bv_block.transpose(1, 0, 2)).reshape(q + 1, 3 * nj)  # [j, (dv, col)]
            for a, rows_all in runs(su):
                C = s.Pw[a - p : a + 1, b - q : b + 1].reshape(p + 1, (q + 1) * d)  # once per pair of spans
                for rows in _pieces(rows_all, max(1, chunk // nj)):
                    Bu_block = Bu[..., rows]
                    ni = Bu_block.shape[-1]
                    T = np.matmul(Bu_block.transpose(0, 2, 1), C)  # over i: (3, ni, (q+1) d)
                    T = T.reshape(3, ni, q + 1, d).transpose(0, 3, 1, 2).reshape(3 * d * ni, q + 1)
                    X = (T @ right).reshape(3, d, ni, 3, nj)  # over j: [du, c, row, dv, col]
                    yield rows, cols, _fields(X.transpose(0, 3, 2, 4, 1), s.rational)


def _pieces(index, size):
    """Split a slice or index array into consecutive pieces of at most ``size`` entries."""
    if isinstance(index, slice):
        return [slice(a, min(a + size, index.stop)) for a in range(index.start, index.stop, size)]
    return [index[a : a + size] for a in range(0, len(index), size)]


def map_points(derivatives, func, u, v, chunk=CHUNK):
    """Apply ``func`` to the derivatives of the points ``(u, v)``, :data:`CHUNK` points at a time.

    Parameters
    ----------
    derivatives : callable
        ``derivatives(u, v, work=work)`` for flat arrays of one chunk, returning
        :class:`~lab.derivatives.Derivatives` with fields ``(k, d)``; ``work``
        is a dict it may keep buffers in from chunk to chunk (see :func:`point_derivatives`).
    func : callable
        ``func(D)`` returning a tuple of arrays of shape ``(k, ...)``.
    u, v : ndarray
        Parameters of the same shape ``S`` (already checked).

    Returns
    -------
    list of ndarray
        ``func``'s outputs for all points, of shapes ``S + (...)``.
    """
    shape = u.shape
    uf, vf = u.reshape(-1), v.reshape(-1)
    n = uf.size
    out, work = None, {}
    for a in range(0, max(n, 1), chunk):
        results = func(derivatives(uf[a : a + chunk], vf[a : a + chunk], work=work))
        if out is None:
            out = [np.empty((n,) + r.shape[1:], dtype=r.dtype) for r in results]
        for o, r in zip(out, results):
            o[a : a + chunk] = r
    return [o.reshape(shape + o.shape[1:]) for o in out]


def map_spline_points(s, func, u, v, chunk=CHUNK):
    """:func:`map_points` for a :class:`Spline`: points sorted by their pair of knot spans where that pays.

    When there are at least :data:`MIN_RUN` points per pair of knot spans on
    average, the points are sorted by their spans (a counting sort for up to
    65536 control points) and evaluated chunk by chunk with
    :func:`grouped_derivatives`, one gather of control points and one BLAS
    product per group; the results go back to the points' places.  With fewer
    points per pair (a large net, few points) every chunk is evaluated point
    by point (:func:`point_derivatives`).  The values agree to rounding.
    """
    p, q = s.degree_u, s.degree_v
    nu, nv = s.Pw.shape[:2]
    uf, vf = u.reshape(-1), v.reshape(-1)
    n = uf.size
    if n < MIN_RUN * (nu - p) * (nv - q):
        return map_points(lambda uu, vv, work: point_derivatives(s, uu, vv, work), func, u, v, chunk)
    first = np.empty(n, dtype=np.uint16 if nu * nv <= 2**16 else np.int64)  # uint16: numpy sorts it by radix
    for a in range(0, n, chunk):
        first[a : a + chunk] = ((find_span(s.knots_u, p, uf[a : a + chunk]) - p) * nv
                                + find_span(s.knots_v, q, vf[a : a + chunk]) - q)
    order = np.argsort(first, kind="stable")
    out, work = None, {}
    for a in range(0, n, chunk):
        index = order[a : a + chunk]
        results = func(grouped_derivatives(s, uf[index], vf[index], first[index].astype(np.int64), work))
        if out is None:
            out = [np.empty((n,) + r.shape[1:], dtype=r.dtype) for r in results]
        for o, r in zip(out, results):
            o[index] = r
    return [o.reshape(u.shape + o.shape[1:]) for o in out]


def map_grid(blocks, func, shape):
    """Apply ``func`` to the derivatives of a grid, block by block (see :func:`grid_blocks`).

    ``func(D)`` gets fields of shape ``(ni, nj, d)`` and returns arrays of
    shape ``(ni, nj, ...)``; the outputs have shape ``shape + (...)``.
    """
    out = None
    for rows, cols, D in blocks:
        results = func(D)
        if out is None:
            out = [np.empty(tuple(shape) + r.shape[2:], dtype=r.dtype) for r in results]
        # a slice and an index array mix as (ni, nj); two index arrays need np.ix_
        where = np.ix_(rows, cols) if not (isinstance(rows, slice) or isinstance(cols, slice)) else (rows, cols)
        for o, r in zip(out, results):
            o[where] = r
    return out


def point_blocks(derivatives, u, v, chunk=CHUNK):
    """Blocks of the grid ``u`` × ``v`` for surfaces without a spline structure: each block's points in one call.

    ``derivatives(u, v)`` takes flat parameters; yields ``(rows, cols, D)`` as :func:`grid_blocks`.
    """
    nu, nv = u.size, v.size
    for cols in _pieces(slice(0, nv), chunk):
        nj = cols.stop - cols.start
        for rows in _pieces(slice(0, nu), max(1, chunk // nj)):
            U, V = np.meshgrid(u[rows], v[cols], indexing="ij")
            D = derivatives(U.reshape(-1), V.reshape(-1))
            yield rows, cols, D.map(lambda x, shape=U.shape: x.reshape(shape + x.shape[1:]))


def as_grid(u, v, min_size=64):
    """Recognise parameters that form a grid: ``(u_side, v_side, transposed)``, or None.

    A grid is a pair of 2-D arrays (after broadcasting) where ``u`` is constant
    along the second axis and ``v`` along the first (``np.meshgrid(..., indexing="ij")``,
    or ``u[:, None], v[None, :]``); ``transposed`` is True for the other
    orientation (``indexing="xy"``).  Small or malformed inputs give None and
    take the point path, where they are checked.
    """
    try:
        u = np.asarray(u, dtype=float)
        v = np.asarray(v, dtype=float)
        shape = np.broadcast_shapes(u.shape, v.shape)
    except (TypeError, ValueError, OverflowError):
        return None
    if len(shape) != 2 or shape[0] * shape[1] < min_size:
        return None
    U, V = np.broadcast_to(u, shape), np.broadcast_to(v, shape)
    if _constant_along(U, 1) and _constant_along(V, 0):
        return U[:, 0], V[0, :], False
    if _constant_along(U, 0) and _constant_along(V, 1):
        return U[0, :], V[:, 0], True
    return None


def _constant_along(A, axis):
    if A.strides[axis] == 0:  # broadcast: constant by construction
        return True
    first = A[:, :1] if axis == 1 else A[:1, :]
    return bool(np.all(A == first))  # NaN compares unequal: such input takes the point path and is refused there
