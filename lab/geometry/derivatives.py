r"""The record of a surface point with its first and second partial derivatives.

Every surface type (Bézier, B-spline, analytic) produces a :class:`Derivatives`
and every curvature formula consumes one, so this small module is the contract
between the evaluators and :mod:`lab.curvature`.
"""

from typing import NamedTuple

import numpy as np

__all__ = ["THIRD", "Derivatives", "from_homogeneous", "quotient_rule"]

#: The keys ``(i, j)`` of the third derivatives :math:`\partial^3/\partial u^i\partial v^j` in the order the lab
#: passes them: ``buuu, buuv, buvv, bvvv``.
THIRD = ((3, 0), (2, 1), (1, 2), (0, 3))


class Derivatives(NamedTuple):
    """Point ``b`` and partial derivatives ``bu, bv, buu, buv, bvv``.

    Each field has shape ``batch + (d,)`` with the coordinates on the last axis.
    """

    b: np.ndarray
    bu: np.ndarray
    bv: np.ndarray
    buu: np.ndarray
    buv: np.ndarray
    bvv: np.ndarray

    def map(self, func):
        """Apply ``func`` to every field and return a new record."""
        return Derivatives(*(func(x) for x in self))


def from_homogeneous(Dw):
    r"""Derivatives of a rational surface from those of its homogeneous form.

    With :math:`A = w\,S` (first ``d`` coordinates of ``Dw``) and the weight
    :math:`w` (last coordinate), the quotient rule gives (The NURBS Book,
    eq. 4.20 and Algorithm A4.4)

    .. math::

        S_u &= (A_u - w_u S)/w, \qquad S_v = (A_v - w_v S)/w,\\
        S_{uu} &= (A_{uu} - 2 w_u S_u - w_{uu} S)/w,\\
        S_{uv} &= (A_{uv} - w_u S_v - w_v S_u - w_{uv} S)/w,\\
        S_{vv} &= (A_{vv} - 2 w_v S_v - w_{vv} S)/w.

    Parameters
    ----------
    Dw : Derivatives
        Fields of shape ``batch + (d+1,)``, the weight last.

    Returns
    -------
    Derivatives
        Fields of shape ``batch + (d,)``.
    """
    A = [x[..., :-1] for x in Dw]
    w = [x[..., -1:] for x in Dw]
    S = A[0] / w[0]
    Su = (A[1] - w[1] * S) / w[0]
    Sv = (A[2] - w[2] * S) / w[0]
    Suu = (A[3] - 2 * w[1] * Su - w[3] * S) / w[0]
    Suv = (A[4] - w[1] * Sv - w[2] * Su - w[4] * S) / w[0]
    Svv = (A[5] - 2 * w[2] * Sv - w[5] * S) / w[0]
    return Derivatives(S, Su, Sv, Suu, Suv, Svv)


def quotient_rule(A, order):
    """Derivatives ``{(i, j): S_(u^i v^j)}`` of a rational surface from those of its homogeneous form ``A`` (same
    keys, last coordinate the weight) by the Leibniz rule, :math:`A^{(a,b)} = \\sum \\binom{a}{i}\\binom{b}{j}
    w^{(i,j)} S^{(a-i,b-j)}` solved for :math:`S^{(a,b)}` (The NURBS Book, eq. 4.20 to any order)."""
    from math import comb

    w = {k: x[..., -1:] for k, x in A.items()}
    S = {}
    for total in range(order + 1):
        for a in range(total, -1, -1):
            b = total - a
            x = A[a, b][..., :-1].copy()
            for i in range(a + 1):
                for j in range(b + 1):
                    if i or j:
                        x -= comb(a, i) * comb(b, j) * w[i, j] * S[a - i, b - j]
            S[a, b] = x / w[0, 0]
    return S
