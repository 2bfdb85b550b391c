r"""Principal directions from the Weingarten map, with the principal curvatures (``s.curvature(u, v, directions=True)``).

The Weingarten map (shape operator) in the parameter basis,
:math:`S = \mathbf G^{-1}\mathbf H` (:func:`lab.curvature.shape_operator`),
has the principal curvatures as eigenvalues; an eigenvector
:math:`w = (w_1, w_2)` of :math:`\kappa` gives the principal direction
:math:`\mathbf d = (w_1\mathbf b_u + w_2\mathbf b_v)/|\cdot|` in space.  With
:math:`a = (S_{11} - S_{22})/2` and :math:`r = \sqrt{a^2 + S_{12}S_{21}}`
(so :math:`\kappa_{1,2} = H \pm r`) the two rows of :math:`(S - \kappa I)w = 0`
give

.. math::
    :label: directions-1

    w^{(1)} = (r + a,\; S_{21}) \text{ or } (S_{12},\; r - a), \qquad
    w^{(2)} = (S_{12},\; -(r + a)) \text{ or } (a - r,\; S_{21}),

and of each pair the one without cancellation is taken (the first when
:math:`a \ge 0`).  ``d1`` is oriented so that :math:`\mathbf d_1\cdot\mathbf b_u \ge 0`
and ``d2`` so that :math:`(\mathbf d_1, \mathbf d_2, \mathbf N)` is right-handed
(:math:`\mathbf d_2 = \mathbf N\times\mathbf d_1` up to rounding).

At an *umbilic* (:math:`\kappa_1 = \kappa_2`: every direction is principal, as
everywhere on a sphere or a plane) the directions are undefined: they are NaN
there and the ``umbilic`` mask is True.  A point counts as umbilic when
:math:`\kappa_1 - \kappa_2 \le` ``rtol`` times
:math:`|\kappa_1| + |\kappa_2| + (|\mathbf b_{uu}| + 2|\mathbf b_{uv}| + |\mathbf b_{vv}|)/(E + G)`
(the second term is the size of second derivatives in curvature units, so that
a flat point's rounding noise does not pass for two distinct curvatures); the
direction error near an umbilic grows like rounding / (κ1 − κ2).
"""

from typing import NamedTuple

import numpy as np

from .curvature import _plain_repr, _pretty, _weingarten, classify, strain_energy

__all__ = ["UMBILIC_RTOL", "CurvatureDirections", "eigen", "from_derivatives"]

#: Default relative tolerance below which κ1 − κ2 counts as zero (an umbilic).
UMBILIC_RTOL = 1e-8


class CurvatureDirections(NamedTuple):
    """``K, H, k1 >= k2``, the ``degenerate`` mask, the unit principal directions ``d1, d2`` and the ``umbilic`` mask.

    ``d1, d2`` have shape ``batch + (3,)``; they are NaN where ``umbilic`` (κ1 = κ2) or ``degenerate``.
    """

    K: np.ndarray
    H: np.ndarray
    k1: np.ndarray
    k2: np.ndarray
    degenerate: np.ndarray
    d1: np.ndarray
    d2: np.ndarray
    umbilic: np.ndarray

    @property
    def strain_energy(self):
        r""":math:`\kappa_1^2 + \kappa_2^2`."""
        return strain_energy(self.k1, self.k2)

    def classify(self, tol=1e-8):
        """Point classes (see :func:`lab.curvature.classify`)."""
        return classify(self.k1, self.k2, tol=tol)

    def __repr__(self):
        return _plain_repr(self)

    _repr_pretty_ = _pretty

    def __str__(self):
        """At one point: the curvatures and the two directions in two lines, in the lab's language (decimal commas
        in German); for arrays of points the plain repr."""
        if np.ndim(self.K) != 0:
            return _plain_repr(self)
        from ..i18n import _, decimal, language

        sep = "; " if language() == "de" else ", "

        def num(x):
            return f"{float(np.round(x, 6)) + 0.0:.6g}"  # + 0.0: no -0

        def vec(d):
            return "(" + sep.join(num(x) for x in d) + ")"

        text = f"K = {num(self.K)}, H = {num(self.H)}, κ1 = {num(self.k1)}, κ2 = {num(self.k2)}"
        if bool(self.umbilic):
            text += "\n" + _("an umbilic: every direction is principal (d1, d2 undefined)")
        elif bool(self.degenerate):
            text += "\n" + _("a degenerate point: no normal, no directions")
        else:
            text += f"\nd1 = {vec(self.d1)}, d2 = {vec(self.d2)}"
        return decimal(text)


def _norm3(x):
    return np.sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])


def eigen(d):
    """The eigen-decomposition of the Weingarten map in the parameter basis.

    Returns ``(K, H, k1, k2, degenerate, w1, w2, gap)``: ``w1, w2`` are pairs of arrays, the parameter
    coordinates of eigenvectors of κ1 and κ2 (not normalised); ``gap`` is κ1 − κ2 relative to the
    curvature scale of the umbilic test (see the module docstring); NaN where both are 0 (a plane).
    """
    return _eigen(d)[:8]


def _eigen(d):
    """:func:`eigen`'s results, then the coordinates-first ``bu``, ``bv`` and ``Q = b_u x b_v`` (computed once)."""
    with np.errstate(invalid="ignore", divide="ignore"):  # degenerate points: NaN, flagged in ``degenerate``
        return _eigen_values(d)


def _eigen_values(d):
    S11, S12, S21, S22, K, degenerate, (bu, bv, buu, buv, bvv), Q, E, G = _weingarten(d)
    H = 0.5 * (S11 + S22)
    a = 0.5 * (S11 - S22)
    r = np.sqrt(np.maximum(a * a + S12 * S21, 0.0))
    first = a >= 0
    # eigenvectors in the parameter basis, each from the row of (S - k I) w = 0 without cancellation
    w1 = (np.where(first, r + a, S12), np.where(first, S21, r - a))
    w2 = (np.where(first, S12, a - r), np.where(first, -(r + a), S21))
    k1, k2 = H + r, H - r
    second = (_norm3(buu) + 2 * _norm3(buv) + _norm3(bvv)) / (E + G)
    with np.errstate(invalid="ignore", divide="ignore"):
        gap = (k1 - k2) / (np.abs(k1) + np.abs(k2) + second)
    return K, H, k1, k2, degenerate, w1, w2, gap, bu, bv, Q


def from_derivatives(d, *, rtol=UMBILIC_RTOL):
    """Curvature and principal directions from first and second derivatives (see the module docstring).

    Parameters
    ----------
    d : Derivatives
        Fields of shape ``batch + (3,)``.
    rtol : float
        Relative tolerance of the umbilic test.

    Returns
    -------
    CurvatureDirections
        ``K, H, k1, k2`` exactly as :func:`lab.curvature.from_derivatives` gives them.
    """
    K, H, k1, k2, degenerate, w1, w2, gap, bu, bv, Q = _eigen(d)
    with np.errstate(invalid="ignore"):
        umbilic = ~degenerate & ~(gap > rtol)  # 0/0 on a plane: umbilic too
    vectors = []
    with np.errstate(invalid="ignore", divide="ignore"):
        for w in (w1, w2):
            x = w[0] * bu + w[1] * bv
            n = _norm3(x)
            x = x / np.where(umbilic | degenerate, np.nan, n)
            vectors.append(x)
        x1, x2 = vectors
        s1 = np.where((x1 * bu).sum(0) < 0, -1.0, 1.0)
        x1 = x1 * s1
        triple = (Q[0] * (x1[1] * x2[2] - x1[2] * x2[1]) + Q[1] * (x1[2] * x2[0] - x1[0] * x2[2])
                  + Q[2] * (x1[0] * x2[1] - x1[1] * x2[0]))
        x2 = x2 * np.where(triple < 0, -1.0, 1.0)
    return CurvatureDirections(K, H, k1, k2, degenerate, np.moveaxis(x1, 0, -1), np.moveaxis(x2, 0, -1), umbilic)
