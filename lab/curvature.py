r"""Curvature of parametric surfaces from their first and second derivatives.

Orientation as in the practical (``seeds/001``, 2.2 and 2.5):
:math:`\mathbf N = \mathbf b_u \times \mathbf b_v / \|\mathbf b_u \times \mathbf b_v\|`.
With the fundamental forms (German: *Fundamentalmatrix erster und zweiter Art*)

.. math::

    \mathbf G = \begin{pmatrix} E & F\\ F & G\end{pmatrix}
              = \begin{pmatrix} \langle b_u,b_u\rangle & \langle b_u,b_v\rangle\\
                                \langle b_v,b_u\rangle & \langle b_v,b_v\rangle\end{pmatrix},\qquad
    \mathbf H = \begin{pmatrix} e & f\\ f & g\end{pmatrix}
              = \begin{pmatrix} \langle N,b_{uu}\rangle & \langle N,b_{uv}\rangle\\
                                \langle N,b_{vu}\rangle & \langle N,b_{vv}\rangle\end{pmatrix}

the Gaussian and mean curvature are (eqs. 3, 4)

.. math::

    K = \frac{eg - f^2}{EG - F^2}, \qquad H = \frac12\,\frac{eG - 2fF + gE}{EG - F^2},

and the principal curvatures (*Hauptkrümmungen*)
:math:`\kappa_{1,2} = H \pm \sqrt{H^2 - K}` with :math:`H^2 - K` clamped at 0,
so :math:`\kappa_1 \ge \kappa_2` also at umbilics where rounding makes it
slightly negative.

Degenerate points, where :math:`\mathbf b_u \times \mathbf b_v` vanishes (a
collapsed patch edge, the pole of a sphere), have no normal.  The functions
here mark them in a ``degenerate`` mask; :func:`fill_degenerate` replaces their
values by the limit approached from inside the domain.
"""

import enum
import warnings
from typing import NamedTuple

import numpy as np

__all__ = [
    "FundamentalForms",
    "Curvature",
    "PointClass",
    "DegeneratePointWarning",
    "DEGENERATE_RTOL",
    "unit_normal",
    "fundamental_forms",
    "from_derivatives",
    "principal_curvatures",
    "strain_energy",
    "classify",
    "approach_points",
    "fill_degenerate",
    "with_limits",
]

#: A point is degenerate when |b_u x b_v| <= DEGENERATE_RTOL * (|b_u|^2 + |b_v|^2).
DEGENERATE_RTOL = 1e-10

#: Fractions of the way from a degenerate point towards the domain centre at
#: which curvature is sampled and extrapolated to 0 (see fill_degenerate).
APPROACH_STEPS = 1e-3 * np.arange(1, 7)
# Lagrange weights of the interpolating polynomial through the samples, evaluated at t = 0:
# w_k = prod_{r != k} t_r / (t_r - t_k).  Six points give (6, -15, 20, -15, 6, -1).


def _extrapolation_weights(t):
    t = np.asarray(t, dtype=float)
    w = np.ones_like(t)
    for k in range(t.size):
        for r in range(t.size):
            if r != k:
                w[k] *= t[r] / (t[r] - t[k])
    return w


_W6 = _extrapolation_weights(APPROACH_STEPS)
_W5 = _extrapolation_weights(APPROACH_STEPS[:5])


class DegeneratePointWarning(RuntimeWarning):
    """Some evaluated points have no tangent plane (|b_u x b_v| = 0)."""


class FundamentalForms(NamedTuple):
    """Coefficients of the first (E, F, G) and second (e, f, g) fundamental forms, and the unit normal N."""

    E: np.ndarray
    F: np.ndarray
    G: np.ndarray
    e: np.ndarray
    f: np.ndarray
    g: np.ndarray
    N: np.ndarray


class Curvature(NamedTuple):
    """Gaussian ``K``, mean ``H``, principal ``k1 >= k2`` curvature and the ``degenerate`` mask."""

    K: np.ndarray
    H: np.ndarray
    k1: np.ndarray
    k2: np.ndarray
    degenerate: np.ndarray

    @property
    def strain_energy(self):
        r""":math:`\kappa_1^2 + \kappa_2^2` (see :func:`strain_energy`)."""
        return strain_energy(self.k1, self.k2)

    def classify(self, tol=1e-8):
        """Point classes (see :func:`classify`)."""
        return classify(self.k1, self.k2, tol=tol)


class PointClass(enum.IntEnum):
    """Classification of surface points (practical 2.4)."""

    HYPERBOLIC = -1  #: K < 0
    FLAT = 0  #: K = 0 = k1 = k2 (Flachpunkt)
    PARABOLIC = 1  #: K = 0, not both principal curvatures 0
    ELLIPTIC = 2  #: K > 0


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def unit_normal(bu, bv):
    r"""Unit normal :math:`\mathbf N = \mathbf b_u\times\mathbf b_v / \|\mathbf b_u\times\mathbf b_v\|`.

    Returns ``(N, degenerate)``; at degenerate points ``N`` is NaN and the mask is True.
    """
    Q = np.cross(bu, bv)
    W = np.linalg.norm(Q, axis=-1)
    scale = _dot(bu, bu) + _dot(bv, bv)
    degenerate = W <= DEGENERATE_RTOL * scale
    with np.errstate(invalid="ignore", divide="ignore"):
        N = Q / np.where(degenerate, np.nan, W)[..., None]
    return N, degenerate


def fundamental_forms(d):
    """First and second fundamental forms from a :class:`~lab.derivatives.Derivatives` record.

    Returns a :class:`FundamentalForms`; ``e, f, g`` and ``N`` are NaN at degenerate points.
    """
    N, _ = unit_normal(d.bu, d.bv)
    return FundamentalForms(
        _dot(d.bu, d.bu),
        _dot(d.bu, d.bv),
        _dot(d.bv, d.bv),
        _dot(N, d.buu),
        _dot(N, d.buv),
        _dot(N, d.bvv),
        N,
    )


def principal_curvatures(K, H):
    r""":math:`\kappa_{1,2} = H \pm \sqrt{\max(H^2-K, 0)}`, so that :math:`\kappa_1 \ge \kappa_2` always."""
    root = np.sqrt(np.maximum(np.square(H) - K, 0.0))
    return H + root, H - root


def from_derivatives(d):
    """Curvature from first and second derivatives (practical eqs. 3 and 4).

    Parameters
    ----------
    d : Derivatives
        Fields of shape ``batch + (3,)``.

    Returns
    -------
    Curvature
        Fields of shape ``batch``.  At degenerate points the values are NaN and
        ``degenerate`` is True; use :func:`fill_degenerate` to replace them by
        their limits.
    """
    ff = fundamental_forms(d)
    det_I = ff.E * ff.G - ff.F**2
    with np.errstate(invalid="ignore", divide="ignore"):
        K = (ff.e * ff.g - ff.f**2) / det_I
        H = 0.5 * (ff.e * ff.G - 2.0 * ff.f * ff.F + ff.g * ff.E) / det_I
    k1, k2 = principal_curvatures(K, H)
    degenerate = np.isnan(ff.N[..., 0])
    return Curvature(K, H, k1, k2, degenerate)


def strain_energy(k1, k2):
    r"""Strain (bending) energy density :math:`\kappa_1^2 + \kappa_2^2 = 4H^2 - 2K`."""
    return np.square(k1) + np.square(k2)


def classify(k1, k2, tol=1e-8):
    """Classify points as elliptic, hyperbolic, parabolic or flat (practical 2.4).

    A principal curvature counts as zero when ``|k| <= tol`` (in units of
    1/length), so the sign of ``K = k1 k2`` is decided by the signs of the
    principal curvatures and rounding noise does not flip a class.

    Returns
    -------
    ndarray of int
        Values of :class:`PointClass`.
    """
    if tol < 0:
        raise ValueError(f"tol must be >= 0; got {tol}")
    k1 = np.asarray(k1, dtype=float)
    k2 = np.asarray(k2, dtype=float)
    z1 = np.abs(k1) <= tol
    z2 = np.abs(k2) <= tol
    same_sign = np.sign(k1) == np.sign(k2)
    out = np.where(same_sign, PointClass.ELLIPTIC, PointClass.HYPERBOLIC)
    out = np.where(z1 ^ z2, PointClass.PARABOLIC, out)
    out = np.where(z1 & z2, PointClass.FLAT, out)
    return out.astype(int)


def approach_points(u, v, centre):
    """Points on the segments from ``(u, v)`` towards ``centre`` at the fractions :data:`APPROACH_STEPS`.

    Returns arrays ``(uu, vv)`` of shape ``u.shape + (len(APPROACH_STEPS),)``.
    """
    t = APPROACH_STEPS
    uu = u[..., None] + t * (centre[0] - u[..., None])
    vv = v[..., None] + t * (centre[1] - v[..., None])
    return uu, vv


def fill_degenerate(curv, samples, *, rtol=1e-6):
    """Replace the values at degenerate points by their limits from inside the domain.

    Curvature is sampled at the points :func:`approach_points` gives, at small
    fractions ``t_k`` of the way towards the domain centre, and extrapolated to
    ``t = 0`` by the polynomial through the samples (six points, error of order
    ``t^6``).  The limit is accepted when a five-point extrapolation agrees to
    ``rtol`` relative to the sampled magnitude; otherwise (for example at the
    apex of a cone, where the mean curvature diverges) the value stays NaN.
    Either way the point keeps ``degenerate = True`` and one
    :class:`DegeneratePointWarning` says how many points were affected.

    Parameters
    ----------
    curv : Curvature
        Result of :func:`from_derivatives`.
    samples : Curvature
        Curvature at the approach points of the degenerate entries only, shape
        ``(k, len(APPROACH_STEPS))`` with ``k = curv.degenerate.sum()`` in the
        order of ``np.nonzero(curv.degenerate)``.

    Returns
    -------
    Curvature
    """
    mask = curv.degenerate
    if not np.any(mask):
        return curv
    limits = {}
    converged = ~np.any(samples.degenerate, axis=-1)
    for name in ("K", "H"):
        s = getattr(samples, name)
        lim6 = s @ _W6
        lim5 = s[..., :5] @ _W5
        scale = np.max(np.abs(s), axis=-1)
        converged &= np.abs(lim6 - lim5) <= rtol * scale + 1e-300
        limits[name] = lim6
    K = np.array(curv.K, dtype=float, copy=True)
    H = np.array(curv.H, dtype=float, copy=True)
    K[mask] = np.where(converged, limits["K"], np.nan)
    H[mask] = np.where(converged, limits["H"], np.nan)
    k1, k2 = principal_curvatures(K, H)
    n_bad = int(np.count_nonzero(~converged))
    msg = (
        f"{int(np.count_nonzero(mask))} degenerate point(s) (b_u x b_v = 0, e.g. a collapsed patch edge): "
        "curvature there is the limit from inside the domain; see the 'degenerate' mask"
    )
    if n_bad:
        msg += f"; at {n_bad} of them the curvature has no finite limit and is NaN"
    warnings.warn(msg, DegeneratePointWarning, stacklevel=3)
    return Curvature(K, H, k1, k2, mask.copy())


def with_limits(curv, u, v, centre, derivatives_at):
    """Fill the degenerate entries of ``curv`` with limits, sampling through ``derivatives_at``.

    Parameters
    ----------
    curv : Curvature
        From :func:`from_derivatives`, shape ``S``.
    u, v : ndarray
        Parameters of the entries, broadcastable to ``S``.
    centre : (float, float)
        The point of the domain the approach heads for.
    derivatives_at : callable
        ``derivatives_at(index, uu, vv)`` returns the :class:`~lab.derivatives.Derivatives`
        at the approach points ``uu, vv`` of shape ``(k, len(APPROACH_STEPS))``
        of the entries ``index = np.nonzero(curv.degenerate)``.
    """
    mask = curv.degenerate
    if not np.any(mask):
        return curv
    index = np.nonzero(mask)
    u = np.broadcast_to(u, mask.shape)[index]
    v = np.broadcast_to(v, mask.shape)[index]
    uu, vv = approach_points(u, v, centre)
    samples = from_derivatives(derivatives_at(index, uu, vv))
    return fill_degenerate(curv, samples)
