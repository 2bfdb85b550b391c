r"""Exact one-sided derivatives of Bézier patches on their borders, up to the third order, and the derivative of the
normal curvature along a geodesic: what :func:`lab.continuity` compares across an edge (G2 and G3).

On a border a patch and its cross derivatives are Bézier curves (the first rows of control points by forward
differences, practical, section 3), so every limit is exact and one-sided; rational patches in homogeneous
coordinates, then the quotient rule to any order.  numpy only.
"""

import numpy as np

from ..geometry import bezier
from ..geometry.derivatives import Derivatives, quotient_rule

__all__ = ["border"]  # curvature_derivative: continuity's helper, not a road to a task's curvature


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _bernstein_derivatives(n, t, order=2):
    """Bernstein bases of degree n at ``t`` and their derivatives up to ``order``, each ``(len(t), n+1)``.

    The k-th derivative is ``n (n-1) … (n-k+1)`` times the k-th backward difference of the degree-(n-k) basis."""
    out = [bezier.bernstein(n, t)]
    for k in range(1, order + 1):
        if k > n:
            out.append(np.zeros_like(out[0]))
            continue
        x = bezier.bernstein(n - k, t)
        for _step in range(k):
            x = np.pad(x, ((0, 0), (1, 0))) - np.pad(x, ((0, 0), (0, 1)))
        out.append(float(np.prod(np.arange(n - k + 1, n + 1))) * x)
    return out


def border(nets, w, axis, end, t, order=2):
    """Exact one-sided derivatives of patches ``nets`` (..., p+1, q+1, 3) on their border ``axis`` (0: u = end,
    1: v = end) at ``t``: fields ``(...) + t.shape + (3,)``.

    On a border the surface and its cross derivatives are Bézier curves: the first ``order + 1`` rows of control
    points by forward differences (practical, section 3), evaluated with the Bernstein basis and its
    derivatives along the border; rational patches in homogeneous coordinates, then the quotient rule.
    Returns :class:`Derivatives`; with ``order=3`` also the third derivatives ``(buuu, buuv, buvv, bvvv)``.
    """
    from math import comb

    Pw = bezier.homogeneous(nets, w)
    if axis == 1:  # make the border a row: the cross direction first
        Pw = np.swapaxes(Pw, -3, -2)
    m, n = Pw.shape[-3] - 1, Pw.shape[-2] - 1
    rows = Pw[..., ::-1, :, :] if end == 1.0 else Pw  # rows[0] on the border, rows[1], rows[2] inwards
    sign = -1.0 if end == 1.0 else 1.0  # differences taken inwards: d/du at u = 1 has the opposite sign
    basis = _bernstein_derivatives(n, t, order)
    A = {}
    for k in range(order + 1):  # the k-th cross derivative's control row
        if k > m:
            R = 0 * rows[..., 0, :, :]
        else:
            R = sum((-1) ** (k - j) * comb(k, j) * rows[..., j, :, :] for j in range(k + 1))
            R = sign ** k * float(np.prod(np.arange(m - k + 1, m + 1))) * R
        for a in range(order + 1 - k):  # (k across, a along) -> (u, v) exponents
            A[(k, a) if axis == 0 else (a, k)] = np.matmul(basis[a], R)
    S = A if w is None else quotient_rule(A, order)
    d = Derivatives(S[0, 0], S[1, 0], S[0, 1], S[2, 0], S[1, 1], S[0, 2])
    return d if order < 3 else (d, (S[3, 0], S[2, 1], S[1, 2], S[0, 3]))


def curvature_derivative(d, third, N, c):
    r"""The derivative :math:`d\kappa_n/ds` of the normal curvature along the geodesic that leaves each point in the
    tangent direction ``c``, from the derivatives ``d`` and ``third = (buuu, buuv, buvv, bvvv)`` at the point.

    Along a unit-speed geodesic :math:`\gamma(s)` the acceleration is normal, :math:`\gamma'' = \kappa_n \mathbf N`,
    so :math:`\kappa_n' = \mathbf N\cdot\gamma'''` (as :math:`\mathbf N'\perp\mathbf N`).  With
    :math:`\gamma' = \mathbf b_u u' + \mathbf b_v v'` (``(u', v')`` the coordinates of ``c``, made unit in I) and
    :math:`(u'', v'')` from :math:`\mathrm I\,(u'', v'')^T = -(\mathbf b_u\cdot\mathbf Q, \mathbf b_v\cdot\mathbf Q)^T`,
    :math:`\mathbf Q = \mathbf b_{uu}u'^2 + 2\mathbf b_{uv}u'v' + \mathbf b_{vv}v'^2` (the geodesic equation),

    .. math::

        \kappa_n' = \mathbf N\cdot(\mathbf b_{uuu}u'^3 + 3\mathbf b_{uuv}u'^2v' + 3\mathbf b_{uvv}u'v'^2
        + \mathbf b_{vvv}v'^3) + 3\,(e\,u'u'' + f\,(u''v' + u'v'') + g\,v'v'').

    A geometric quantity (1/length²): the same for every parametrization of the surface, so a G3 surface gives the
    same value on both sides of an edge.  ``N`` the unit normal (its sign is the sign of the result), ``c``
    tangent; all arrays ``(k, 3)``.
    """
    E, F, G = _dot(d.bu, d.bu), _dot(d.bu, d.bv), _dot(d.bv, d.bv)
    det = E * G - F * F
    a, b = _dot(c, d.bu), _dot(c, d.bv)
    w1, w2 = (G * a - F * b) / det, (E * b - F * a) / det
    speed = np.sqrt(E * w1 * w1 + 2 * F * w1 * w2 + G * w2 * w2)
    w1, w2 = w1 / speed, w2 / speed
    Q = d.buu * (w1 * w1)[..., None] + 2 * d.buv * (w1 * w2)[..., None] + d.bvv * (w2 * w2)[..., None]
    qa, qb = -_dot(d.bu, Q), -_dot(d.bv, Q)
    a2, b2 = (G * qa - F * qb) / det, (E * qb - F * qa) / det
    buuu, buuv, buvv, bvvv = third
    cubic = (_dot(N, buuu) * w1 ** 3 + 3 * _dot(N, buuv) * w1 * w1 * w2 + 3 * _dot(N, buvv) * w1 * w2 * w2
             + _dot(N, bvvv) * w2 ** 3)
    e, f, g = _dot(N, d.buu), _dot(N, d.buv), _dot(N, d.bvv)
    return cubic + 3 * (e * w1 * a2 + f * (a2 * w2 + w1 * b2) + g * w2 * b2)
