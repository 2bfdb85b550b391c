r"""Tensor-product Bézier patches: Bernstein basis, de Casteljau, derivatives, subdivision.

A control net is an array ``P`` of shape ``(..., m+1, n+1, d)``: optional batch
axes first (many patches at once), then the index ``i`` along ``u``, the index
``j`` along ``v`` and the coordinates last.  A rational patch additionally has
weights of shape ``(..., m+1, n+1)``; it is handled in homogeneous coordinates
``(w P, w)``.

.. math:: \mathbf b(u,v) = \sum_{i=0}^m \sum_{j=0}^n \mathbf b_{ij} B_i^m(u) B_j^n(v)

References: the practical's sheet (§3) for derivative nets by
forward differences; The NURBS Book (Piegl & Tiller), A1.5 (de Casteljau) and
A4.4 / eq. 4.20 (rational derivatives).
"""

import functools
import math

import numpy as np

from . import validation as _v
from .derivatives import Derivatives, from_homogeneous

__all__ = [
    "bernstein",
    "binomials",
    "corner_derivatives",
    "de_casteljau",
    "dehomogenize",
    "derivative_net",
    "derivatives",
    "evaluate",
    "homogeneous",
    "split",
    "subdivide",
]

#: The six derivative orders (du, dv) in the order of the fields of Derivatives.
DERIVATIVE_ORDERS = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))


def binomials(n):
    """The binomial coefficients C(n, 0), …, C(n, n) as floats (exact for the degrees of patches)."""
    return np.array([math.comb(n, i) for i in range(n + 1)], dtype=float)


def bernstein(n, t):
    r"""Bernstein polynomials :math:`B_i^n(t) = \binom{n}{i} t^i (1-t)^{n-i}`.

    Parameters
    ----------
    n : int
        Degree, ``n >= 0``.
    t : array_like
        Parameters.

    Returns
    -------
    ndarray, shape ``t.shape + (n+1,)``
    """
    t = np.asarray(t, dtype=float)[..., None]
    i = np.arange(n + 1)
    # 0**0 == 1 in numpy, so the end points t = 0 and t = 1 are exact.
    return binomials(n) * t**i * (1.0 - t) ** (n - i)


def de_casteljau(P, t):
    """Evaluate the Bézier curve with control points ``P`` by de Casteljau's algorithm.

    The numerically stable reference evaluator (The NURBS Book, A1.5).

    Parameters
    ----------
    P : (n+1, d) array_like
        Control polygon.
    t : array_like
        Parameters.

    Returns
    -------
    ndarray, shape ``t.shape + (d,)``
    """
    P = np.asarray(P, dtype=float)
    t = np.asarray(t, dtype=float)
    Q = np.broadcast_to(P, t.shape + P.shape).copy()
    tt = t[..., None, None]
    for k in range(P.shape[0] - 1, 0, -1):
        Q = (1.0 - tt) * Q[..., :k, :] + tt * Q[..., 1 : k + 1, :]
    return Q[..., 0, :]


def derivative_net(P, du=0, dv=0):
    r"""Control net of the partial derivative :math:`\partial^{du+dv}\mathbf b/\partial u^{du}\partial v^{dv}`.

    Forward differences scaled by the degree, as in the practical (section 3):
    :math:`\mathcal B(\mathbf b_u) = (m\,\Delta^{1,0}\mathbf b_{ij})`,
    :math:`\mathcal B(\mathbf b_{uu}) = (m(m-1)\,\Delta^{1,0}\Delta^{1,0}\mathbf b_{ij})`, and so on.
    Differentiating a direction of degree 0 gives the zero net of degree 0, so
    degrees ``m = 1`` or ``n = 1`` (and 0) are handled.

    Parameters
    ----------
    P : (..., m+1, n+1, d) array_like
        Control nets (batch axes allowed).
    du, dv : int
        Orders of differentiation in ``u`` and ``v``.

    Returns
    -------
    ndarray, shape ``(..., max(m-du, 0)+1, max(n-dv, 0)+1, d)``
    """
    D = np.asarray(P, dtype=float)
    for axis, order in ((-3, du), (-2, dv)):
        for _ in range(order):
            deg = D.shape[axis] - 1
            if deg == 0:
                shape = list(D.shape)
                shape[axis] = 1
                D = np.zeros(shape)
            else:
                D = deg * np.diff(D, axis=axis)
    return D


def homogeneous(P, weights):
    """Homogeneous control net ``(w P, w)`` of shape ``(..., d+1)``; ``P`` itself if ``weights is None``."""
    if weights is None:
        return np.asarray(P, dtype=float)
    w = np.asarray(weights, dtype=float)[..., None]
    return np.concatenate([P * w, w], axis=-1)


def dehomogenize(Pw):
    """Split a homogeneous net ``(w P, w)`` into ``(P, w)``."""
    w = Pw[..., -1]
    return Pw[..., :-1] / w[..., None], w


def _evaluate_nets(nets, u, v, paired=False):
    """Evaluate Bézier nets of possibly different degrees at the points ``(u, v)``.

    Unpaired: ``u``, ``v`` are flat arrays of length s and each net
    ``(..., a+1, b+1, d)`` gives ``(..., s, d)``.  Paired: ``u``, ``v`` have
    shape ``(k, s)``, each net ``(k, a+1, b+1, d)`` and net ``k`` is evaluated
    at its own points only, giving ``(k, s, d)``.  Bernstein matrices are
    computed once per degree.
    """
    cache = {}

    def basis(deg, t, key):
        if (key, deg) not in cache:
            cache[key, deg] = bernstein(deg, t)
        return cache[key, deg]

    if paired:
        first, second = "ksi,kijd->ksjd", "ksj,ksjd->ksd"
    else:
        first, second = "si,...ijd->...sjd", "sj,...sjd->...sd"
    out = []
    for D in nets:
        Bu = basis(D.shape[-3] - 1, u, "u")
        Bv = basis(D.shape[-2] - 1, v, "v")
        # Contract i (along u) first, then j: two small matrix products.
        T = np.einsum(first, Bu, D, optimize=True)
        out.append(np.einsum(second, Bv, T, optimize=True))
    return out


def derivatives(P, u, v, weights=None, paired=False):
    r"""Point and first and second partial derivatives of Bézier patches.

    .. math:: \mathbf b(u,v) = \sum_i \sum_j \mathbf b_{ij} B_i^m(u) B_j^n(v)

    Derivative nets come from :func:`derivative_net` (forward differences) and
    are evaluated with the Bernstein basis; rational patches are differentiated
    in homogeneous coordinates and projected by the quotient rule
    (:func:`lab.derivatives.from_homogeneous`).

    Parameters
    ----------
    P : (..., m+1, n+1, d) array_like
        Control nets; leading axes are a batch of patches.
    u, v : array_like
        Parameters in [0, 1], broadcast against each other to shape ``S``.
        Every patch of the batch is evaluated at every point.
    weights : (..., m+1, n+1) array_like, optional
        Positive weights of a rational patch.
    paired : bool
        If True, ``P`` has exactly one batch axis of length k, ``u`` and ``v``
        broadcast to ``(k, s)`` and patch ``k`` is evaluated only at its own
        points ``u[k], v[k]``.

    Returns
    -------
    Derivatives
        Fields ``b, bu, bv, buu, buv, bvv``, each of shape ``batch + S + (d,)``
        (``(k, s, d)`` when paired).
    """
    P = _v.as_control_net(P, batch=True, dim=None)
    weights = _v.as_weights(weights, P.shape[:-1])
    u, v = _v.as_parameters(u, v, ((0.0, 1.0), (0.0, 1.0)))
    Pw = homogeneous(P, weights)
    nets = [derivative_net(Pw, du, dv) for du, dv in DERIVATIVE_ORDERS]
    if paired:
        if P.ndim != 4 or u.ndim != 2 or u.shape[0] != P.shape[0]:
            raise ValueError(
                f"paired evaluation needs nets (k, m+1, n+1, d) and parameters (k, s); got {P.shape} and {u.shape}"
            )
        values = _evaluate_nets(nets, u, v, paired=True)
    else:
        values = _evaluate_nets(nets, u.ravel(), v.ravel())
        values = [x.reshape(P.shape[:-3] + u.shape + (Pw.shape[-1],)) for x in values]
    D = Derivatives(*values)
    return D if weights is None else from_homogeneous(D)


@functools.cache
def _corner_stencil(degree, order):
    """Indices and weights of the r-th forward difference at both ends of a degree-m polygon.

    The value of the ``order``-th derivative at t = 0 is
    ``m!/(m-r)! * sum_k (-1)^(r-k) C(r, k) b_k`` (indices 0..r), at t = 1 the
    same over the indices m-r..m.  Returns ``(indices (2, r+1), weights (r+1,))``;
    ``None`` when the derivative vanishes (``order > degree``).
    """
    if order > degree:
        return None
    k = np.arange(order + 1)
    weights = binomials(order) * (-1.0) ** (order - k)
    for j in range(order):
        weights = weights * (degree - j)
    return np.stack([k, degree - order + k]), weights


@functools.cache
def _both_corners(degree, order):
    """The stencil of :func:`_corner_stencil` seen from both ends: indices ``0..r`` and ``m..m-r`` (2, r+1) and
    the weights, those of the end t = 1 times ``(-1)^r`` (reading the polygon backwards); None if it vanishes."""
    stencil = _corner_stencil(degree, order)
    if stencil is None:
        return None
    k, w = stencil[0][0], stencil[1]
    return np.stack([k, degree - k]), np.stack([w, (-1.0) ** order * w])


def corner_derivatives(P, weights=None):
    """Derivatives at the four corners, read off the corners of the derivative nets (practical, figure 3).

    Because :math:`B_i^m(0) = \\delta_{i0}` and :math:`B_i^m(1) = \\delta_{im}`, the value of a
    Bézier patch at a corner is the corner control point, and the same holds for
    the forward-difference nets of its derivatives: for example
    :math:`\\mathbf b_u(0, 0) = m(\\mathbf b_{10} - \\mathbf b_{00})` and
    :math:`\\mathbf b_{uv}(1, 1) = mn(\\mathbf b_{mn} - \\mathbf b_{m-1,n} - \\mathbf b_{m,n-1} + \\mathbf b_{m-1,n-1})`.
    Only the control points next to the corners are touched, so this is the
    fast path for many patches.

    Parameters
    ----------
    P : (..., m+1, n+1, d) array_like
    weights : (..., m+1, n+1) array_like, optional

    Returns
    -------
    Derivatives
        Fields of shape ``(..., 2, 2, d)`` indexed ``[..., a, b]`` for the corner
        ``(u, v) = (a, b)``; equal to :func:`derivatives` at those points.
    """
    P = _v.as_control_net(P, batch=True, dim=None)
    weights = _v.as_weights(weights, P.shape[:-1])
    D = Derivatives(*_corner_values(homogeneous(P, weights)))
    return D if weights is None else from_homogeneous(D)


def _corner_values(Pw):
    """The six derivative fields at the corners of the (unchecked) nets ``Pw``, each ``(..., 2, 2, d)``.

    Each corner is brought to (0, 0) by reversing the net along u and/or v;
    reversing a direction flips the sign of odd derivatives along it, hence
    the factor ``(-1)^(a du + b dv)``.  The nets are first laid out control
    point by control point, ``(m+1, n+1, d, batch)``, and the stencil's control
    points are gathered for the four corners at once, so every term of a
    stencil is one array operation over all corners of all patches.
    """
    m, n = Pw.shape[-3] - 1, Pw.shape[-2] - 1
    Q = np.ascontiguousarray(np.moveaxis(Pw, (-3, -2, -1), (0, 1, 2)))  # (m+1, n+1, d, *batch)
    extra = (1,) * (Q.ndim - 2)
    fields = []
    for du, dv in DERIVATIVE_ORDERS:
        field = np.zeros((2, 2) + Q.shape[2:])
        su, sv = _both_corners(m, du), _both_corners(n, dv)
        if su is not None and sv is not None:
            # all four corners at once: G[a, k, b, l] = Q[k-th index from corner a, l-th from corner b]
            (iu, wu), (iv, wv) = su, sv
            G = Q[iu[:, :, None, None], iv[None, None, :, :]]  # (2, du+1, 2, dv+1, d, *batch)
            for k in range(du + 1):
                for l in range(dv + 1):
                    coef = (wu[:, k, None] * wv[None, :, l]).reshape((2, 2) + extra)
                    field += coef * G[:, k, :, l]
        fields.append(np.moveaxis(field, (0, 1, 2), (-3, -2, -1)))  # a view: (*batch, 2, 2, d)
    return fields


def evaluate(P, u, v, weights=None):
    """Points of Bézier patches: the field ``b`` of :func:`derivatives` (same shapes)."""
    P = _v.as_control_net(P, batch=True, dim=None)
    weights = _v.as_weights(weights, P.shape[:-1])
    u, v = _v.as_parameters(u, v, ((0.0, 1.0), (0.0, 1.0)))
    Pw = homogeneous(P, weights)
    (b,) = _evaluate_nets([Pw], u.ravel(), v.ravel())
    b = b.reshape(P.shape[:-3] + u.shape + (Pw.shape[-1],))
    return b if weights is None else b[..., :-1] / b[..., -1:]


def split(P, t=0.5, axis=-3):
    """Split Bézier nets at parameter ``t`` along one parameter direction.

    De Casteljau's algorithm run on all rows at once: the left net collects the
    first points of every level, the right net the last points.

    Parameters
    ----------
    P : ndarray
        Nets (any batch axes); homogeneous nets split rational patches exactly.
    t : float
        Split parameter in (0, 1).
    axis : int
        The axis of the control index to split along (``-3`` for u, ``-2`` for v
        in a ``(..., m+1, n+1, d)`` net).

    Returns
    -------
    left, right : ndarray
        Nets of the same shape as ``P`` for ``[0, t]`` and ``[t, 1]``.
    """
    Q = np.ascontiguousarray(np.moveaxis(np.asarray(P, dtype=float), axis, 0))  # contiguous rows: fast arithmetic
    n = Q.shape[0]
    left, right = np.empty_like(Q), np.empty_like(Q)
    left[0], right[n - 1] = Q[0], Q[n - 1]
    for level in range(1, n):
        Q = (1.0 - t) * Q[:-1] + t * Q[1:]
        left[level], right[n - 1 - level] = Q[0], Q[-1]
    return np.moveaxis(left, 0, axis), np.moveaxis(right, 0, axis)


def subdivide(P, u=0.5, v=0.5, weights=None):
    """Subdivide Bézier patches at ``(u, v)`` into four.

    Parameters
    ----------
    P : (..., m+1, n+1, d) array_like
    u, v : float
        Split parameters in (0, 1).
    weights : (..., m+1, n+1) array_like, optional

    Returns
    -------
    children : ndarray, shape ``(..., 2, 2, m+1, n+1, d)``
        ``children[..., a, b, :, :, :]`` covers ``u`` in the ``a``-th and
        ``v`` in the ``b``-th half (0 = lower).
    child_weights : ndarray of shape ``(..., 2, 2, m+1, n+1)`` or None
    """
    P = _v.as_control_net(P, batch=True, dim=None)
    weights = _v.as_weights(weights, P.shape[:-1])
    for name, t in (("u", u), ("v", v)):
        if not 0.0 < float(t) < 1.0:
            raise ValueError(f"subdivision parameter {name} must lie strictly between 0 and 1; got {t}")
    return _subdivide(P, u, v, weights)


def _subdivide(P, u, v, weights):
    """:func:`subdivide` of nets checked before (no input checks: refine calls it on every chunk)."""
    Pw = homogeneous(P, weights)
    lo, hi = split(Pw, u, axis=-3)
    halves_u = np.stack([lo, hi], axis=-4)  # (..., 2, m+1, n+1, d)
    lo, hi = split(halves_u, v, axis=-2)
    children = np.stack([lo, hi], axis=-4)  # (..., 2, 2, m+1, n+1, d)
    if weights is None:
        return children, None
    return dehomogenize(children)
