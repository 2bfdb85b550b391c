r"""Curvature of parametric surfaces from their first and second derivatives.

Orientation as in the practical's sheet (§2.2 and §2.5):
:math:`\mathbf N = \mathbf b_u \times \mathbf b_v / \|\mathbf b_u \times \mathbf b_v\|`.
With the matrices of the first and second fundamental forms (German: *erste und zweite
Fundamentalform*; the practical calls the matrices *Fundamentalmatrix erster bzw. zweiter Art*)

.. math::
    :label: curvature-1

    \mathbf G = \begin{pmatrix} E & F\\ F & G\end{pmatrix}
              = \begin{pmatrix} \langle b_u,b_u\rangle & \langle b_u,b_v\rangle\\
                                \langle b_v,b_u\rangle & \langle b_v,b_v\rangle\end{pmatrix},\qquad
    \mathbf H = \begin{pmatrix} e & f\\ f & g\end{pmatrix}
              = \begin{pmatrix} \langle N,b_{uu}\rangle & \langle N,b_{uv}\rangle\\
                                \langle N,b_{vu}\rangle & \langle N,b_{vv}\rangle\end{pmatrix}

the Gaussian and mean curvature are (the practical's sheet, §2.5)

.. math::
    :label: curvature-2

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

from ..i18n import N_, _, decimal, language
from . import validation as _v
from .colormaps import ZERO_TOL

__all__ = [
    "DEGENERATE_RTOL",
    "Curvature",
    "CurvatureMode",
    "DegeneratePointWarning",
    "FundamentalForms",
    "PointClass",
    "approach_points",
    "as_mode",
    "classify",
    "curvature_values",
    "fill_degenerate",
    "from_derivatives",
    "fundamental_forms",
    "principal_curvatures",
    "shape_operator",
    "strain_energy",
    "unit_normal",
    "with_limits",
    "zero_tolerance",
]

#: A point is degenerate when |b_u x b_v| <= DEGENERATE_RTOL * (|b_u|^2 + |b_v|^2).
DEGENERATE_RTOL = 1e-10

#: Fractions of the way from a degenerate point towards the domain centre at
#: which curvature is sampled and extrapolated to 0 (see fill_degenerate): two
#: runs of six equidistant steps, a short one (for curvature that varies fast
#: near the point) and a long one (for parametrisations whose rounding error
#: grows like 1/t^2 towards the point, such as the poles of a rational sphere).
APPROACH_RUNS = (2e-3 * np.arange(1, 7), 1e-2 * np.arange(1, 7))
APPROACH_STEPS = np.concatenate(APPROACH_RUNS)


def _extrapolation_weights(t):
    """Lagrange weights of the polynomial through samples at ``t``, evaluated at 0:
    ``w_k = prod_{r != k} t_r / (t_r - t_k)``; six equidistant points give (6, -15, 20, -15, 6, -1)."""
    t = np.asarray(t, dtype=float)
    w = np.ones_like(t)
    for k in range(t.size):
        for r in range(t.size):
            if r != k:
                w[k] *= t[r] / (t[r] - t[k])
    return w


_W6 = _extrapolation_weights(APPROACH_RUNS[0])  # the same for both runs: they are scaled copies
_W5 = _extrapolation_weights(APPROACH_RUNS[0][:5])


class DegeneratePointWarning(RuntimeWarning):
    """Some evaluated points have no tangent plane (``|b_u x b_v| = 0``)."""


def _plain_repr(record, notation="en"):
    """``Name(field=value, …)`` with plain numbers (``-0.25``, not ``np.float64(-0.25)``) for notebooks; with
    ``notation="de"`` as German writes numbers: decimal commas, so fields and elements apart by semicolons."""
    sep = "; " if notation == "de" else ", "

    def plain(x):
        x = np.asarray(x)
        text = repr(x.item()) if x.ndim == 0 else np.array2string(x, separator=sep, threshold=24)
        return decimal(text) if notation == "de" else text

    fields = sep.join(f"{name}={plain(value)}" for name, value in zip(record._fields, record))
    return f"{type(record).__name__}({fields})"


def _pretty(record, p, cycle):
    """IPython's display of a record (``_repr_pretty_``): its plain repr in the lab's language's notation
    ("Curvature(K=-0,25; H=0,5; …)" in German); ``repr`` itself stays Python's notation."""
    p.text(_plain_repr(record, language()))


class FundamentalForms(NamedTuple):
    """Coefficients of the first (E, F, G) and second (e, f, g) fundamental forms, and the unit normal N."""

    E: np.ndarray
    F: np.ndarray
    G: np.ndarray
    e: np.ndarray
    f: np.ndarray
    g: np.ndarray
    N: np.ndarray

    def __repr__(self):
        return _plain_repr(self)

    _repr_pretty_ = _pretty


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

    def __repr__(self):
        return _plain_repr(self)

    _repr_pretty_ = _pretty


class PointClass(enum.IntEnum):
    """Classification of surface points (practical 2.4)."""

    HYPERBOLIC = -1  #: K < 0
    FLAT = 0  #: K = 0 = k1 = k2 (Flachpunkt)
    PARABOLIC = 1  #: K = 0, not both principal curvatures 0
    ELLIPTIC = 2  #: K > 0

    @property
    def label(self):
        """The class as people read it, in the lab's language ("hyperbolic", German "hyperbolisch"); the member's
        name and value stay what code compares."""
        return _(_POINT_CLASS_LABELS[self])


#: the point classes' names for people, marked for translation (:attr:`PointClass.label`)
_POINT_CLASS_LABELS = {PointClass.HYPERBOLIC: N_("hyperbolic"), PointClass.FLAT: N_("flat"),
                       PointClass.PARABOLIC: N_("parabolic"), PointClass.ELLIPTIC: N_("elliptic")}


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


def fundamental_forms(d, N=None):
    """First and second fundamental forms from a :class:`~lab.derivatives.Derivatives` record.

    Returns a :class:`FundamentalForms`; ``e, f, g`` and ``N`` are NaN at degenerate points unless the
    normal ``N`` is given (e.g. its limit there, :func:`normal_limits`).
    """
    if N is None:
        N, _bad = unit_normal(d.bu, d.bv)
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

    ``K`` and ``H`` are the practical's formulas.  The principal curvatures
    are :math:`H \\pm \\sqrt{D}` with the discriminant :math:`D = H^2 - K`
    computed as :math:`((S_{11} - S_{22})/2)^2 + S_{12} S_{21}` from the shape
    operator :math:`S = \\mathbf G^{-1}\\mathbf H` (Weingarten map): the same
    number in exact arithmetic, but without the cancellation of
    :math:`H^2 - K` near umbilics, so :math:`\\kappa_1 - \\kappa_2` is
    accurate to rounding instead of to its square root.

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
    S11, S12, S21, S22, K, degenerate = shape_operator(d)
    H = 0.5 * (S11 + S22)
    root = np.sqrt(np.maximum(0.25 * (S11 - S22) ** 2 + S12 * S21, 0.0))
    return Curvature(K, H, H + root, H - root, degenerate)


def shape_operator(d):
    r"""The Weingarten map :math:`S = \mathbf G^{-1}\mathbf H` in the parameter basis, with K and the degenerate mask.

    Returns ``(S11, S12, S21, S22, K, degenerate)``, arrays of the batch shape;
    :math:`S` maps the parameter coordinates of a tangent vector
    :math:`w_1 \mathbf b_u + w_2 \mathbf b_v` to those of :math:`-\mathrm dN(w)`,
    so its eigenvalues are :math:`\kappa_1, \kappa_2` and its eigenvectors the
    principal directions.  NaN (and ``degenerate`` True) where ``b_u x b_v = 0``.
    """
    return _weingarten(d)[:6]


def _weingarten(d):
    """:func:`shape_operator`'s six results, then ``(bu, bv, buu, buv, bvv)`` with the coordinates first, ``Q``
    (the coordinates of b_u x b_v), ``E`` and ``G``: what the principal directions reuse instead of recomputing."""
    # Dill's unnormalised form: Q = b_u x b_v, A, B, C = Q . (b_uu, b_uv, b_vv), e = A/|Q| ...;
    # EG - F^2 = |Q|^2 (Lagrange's identity) without the cancellation of EG - F^2.
    # Written out per coordinate on views with the coordinates first: the operations of np.cross
    # and of the dot products, in their order, without their temporaries of shape batch + (3,).
    bu, bv, buu, buv, bvv = (np.moveaxis(np.asarray(x), -1, 0) for x in d[1:])
    Q = (bu[1] * bv[2] - bu[2] * bv[1], bu[2] * bv[0] - bu[0] * bv[2], bu[0] * bv[1] - bu[1] * bv[0])
    W2 = _dot3(Q, Q)
    E, F, G = _dot3(bu, bu), _dot3(bu, bv), _dot3(bv, bv)
    # NaN or inf derivatives (a function undefined there) are flagged as well: no curvature, never a silent NaN
    degenerate = (W2 <= (DEGENERATE_RTOL * (E + G)) ** 2) | ~np.isfinite(W2)
    with np.errstate(invalid="ignore", divide="ignore"):
        W2 = np.where(degenerate, np.nan, W2)
        W = np.sqrt(W2)
        e, f, g = _dot3(Q, buu) / W, _dot3(Q, buv) / W, _dot3(Q, bvv) / W
        K = (e * g - f**2) / W2
        S11 = (G * e - F * f) / W2
        S12 = (G * f - F * g) / W2
        S21 = (E * f - F * e) / W2
        S22 = (E * g - F * f) / W2
    return S11, S12, S21, S22, K, degenerate, (bu, bv, buu, buv, bvv), Q, E, G


def _dot3(a, b):
    """Dot product of two vectors given by their three coordinate arrays."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


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
    tol = _v.as_number(tol, "tol", minimum=0)
    k1, k2 = _v.as_broadcast_arrays(k1=k1, k2=k2)
    _v.check_memory(64 * k1.size, f"classifying {_v.format_count(k1.size)} points", None)  # views until here
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
    ``t = 0`` by the polynomial through six samples (error of order ``t^6``),
    once with short and once with long steps (:data:`APPROACH_RUNS`); the run
    whose five- and six-point extrapolations agree better is kept.  The limit
    is accepted when they agree to ``rtol`` relative to the sampled
    magnitude; otherwise (for example at the
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
    n = len(APPROACH_RUNS[0])
    sampled = {"K": samples.K, "H": samples.H, "D": (0.5 * (samples.k1 - samples.k2)) ** 2}
    # For each run: the six-point limit and, as its error estimate, the change from the five-point one.
    estimates = {}
    for name, s in sampled.items():
        runs = [s[..., i * n : (i + 1) * n] for i in range(len(APPROACH_RUNS))]
        estimates[name] = [(r @ _W6, np.abs(r @ _W6 - r[..., :5] @ _W5), np.max(np.abs(r), axis=-1)) for r in runs]
    # Choose per point the run whose K and H estimates are more consistent.
    errors = np.stack(
        [estimates["K"][i][1] / (estimates["K"][i][2] + 1e-300) + estimates["H"][i][1] / (estimates["H"][i][2] + 1e-300)
         for i in range(len(APPROACH_RUNS))]
    )
    best = np.argmin(errors, axis=0)
    converged = ~np.any(samples.degenerate, axis=-1)
    for name in sampled:
        lim = np.choose(best, [e[0] for e in estimates[name]])
        err = np.choose(best, [e[1] for e in estimates[name]])
        scale = np.choose(best, [e[2] for e in estimates[name]])
        if name != "D":  # D is the square of a small difference near umbilics: judged through K and H
            converged &= err <= rtol * scale + 1e-300
        limits[name] = lim
    K = np.array(curv.K, dtype=float, copy=True)
    H = np.array(curv.H, dtype=float, copy=True)
    root = np.zeros_like(K)
    K[mask] = np.where(converged, limits["K"], np.nan)
    H[mask] = np.where(converged, limits["H"], np.nan)
    root[mask] = np.sqrt(np.maximum(limits["D"], 0.0))
    # elsewhere keep the principal curvatures from_derivatives computed
    k1 = np.where(mask, H + root, curv.k1)
    k2 = np.where(mask, H - root, curv.k2)
    n_bad = int(np.count_nonzero(~converged))
    msg = _("{n} degenerate point(s) (b_u x b_v = 0, e.g. a collapsed patch edge): curvature there is the limit "
            "from inside the domain; see the 'degenerate' mask").format(n=int(np.count_nonzero(mask)))
    if n_bad:
        msg += _("; at {n} of them the curvature has no finite limit and is NaN").format(n=n_bad)
    warnings.warn(msg, DegeneratePointWarning, stacklevel=3)
    return Curvature(K, H, k1, k2, mask.copy())


def normal_limits(N, degenerate, u, v, centre, derivatives_at):
    """``N`` with its degenerate entries replaced by the limit of the unit normal approached from inside.

    The normals at the first run of :data:`APPROACH_STEPS` towards ``centre``
    are extrapolated to the point (as the curvature in :func:`fill_degenerate`)
    and normalised; NaN where the approach meets degenerate points too.  Warns
    once with :class:`DegeneratePointWarning`.  ``derivatives_at(uu, vv)``
    returns the derivatives at approach points of shape ``(k, len(APPROACH_STEPS))``.
    """
    degenerate = np.asarray(degenerate)
    if not np.any(degenerate):
        return N
    shape = degenerate.shape
    flat = np.array(np.reshape(N, (-1, 3)), dtype=float)
    index = np.flatnonzero(degenerate)
    uu, vv = approach_points(np.broadcast_to(u, shape).reshape(-1)[index],
                             np.broadcast_to(v, shape).reshape(-1)[index], centre)
    d = derivatives_at(uu, vv)
    n = len(APPROACH_RUNS[0])
    Ns, bad = unit_normal(d.bu[:, :n], d.bv[:, :n])
    limit = np.einsum("kti,t->ki", Ns, _W6)
    with np.errstate(invalid="ignore", divide="ignore"):
        limit /= np.linalg.norm(limit, axis=-1, keepdims=True)
    limit[np.any(bad, axis=-1)] = np.nan
    flat[index] = limit
    n_bad = int(np.count_nonzero(~np.all(np.isfinite(limit), axis=-1)))
    msg = _("{n} degenerate point(s) (b_u x b_v = 0, e.g. a pole): the normal there is its limit from inside the "
            "domain").format(n=index.size)
    if n_bad:
        msg += _("; at {n} of them it has no limit and is NaN").format(n=n_bad)
    warnings.warn(msg, DegeneratePointWarning, stacklevel=3)
    return flat.reshape(np.shape(N))


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
    shape = np.shape(mask)
    flat = Curvature(*(np.reshape(x, -1) for x in curv))  # one code path for scalars and arrays
    index = np.nonzero(flat.degenerate)
    u = np.broadcast_to(u, shape).reshape(-1)[index]
    v = np.broadcast_to(v, shape).reshape(-1)[index]
    uu, vv = approach_points(u, v, centre)
    orig_index = np.unravel_index(index[0], shape) if shape else index
    samples = from_derivatives(derivatives_at(orig_index, uu, vv))
    filled = fill_degenerate(flat, samples)
    return Curvature(*(np.reshape(x, shape) for x in filled))


class CurvatureMode(str, enum.Enum):
    """Which curvature to visualise."""

    GAUSSIAN = "gaussian"  #: K
    AVERAGE = "mean"  #: H (the practical's "mittlere Krümmung")
    PRINCIPAL_MAX = "k1"  #: κ1
    PRINCIPAL_MIN = "k2"  #: κ2
    STRAIN_ENERGY = "strain-energy"  #: κ1² + κ2²


def as_mode(mode):
    """``mode`` as a :class:`CurvatureMode`; a ``ValueError`` naming the plain choices (``'gaussian'``, ...) otherwise."""
    return CurvatureMode(_v.as_choice(mode, list(CurvatureMode), "curvature mode"))


def curvature_values(curv, mode):
    """The values of ``curv`` (a :class:`lab.curvature.Curvature`) for a :class:`CurvatureMode`."""
    mode = as_mode(mode)
    if mode is CurvatureMode.STRAIN_ENERGY:
        return curv.strain_energy
    return {"gaussian": curv.K, "mean": curv.H, "k1": curv.k1, "k2": curv.k2}[mode.value]


def zero_tolerance(mode, size):
    """Tolerance below which a curvature value of ``mode`` counts as 0, for a model of extent ``size``.

    Curvature has units 1/length (K and the strain energy 1/length²), and its
    rounding noise scales with them, so the tolerance does too.
    """
    power = 2 if CurvatureMode(mode) in (CurvatureMode.GAUSSIAN, CurvatureMode.STRAIN_ENERGY) else 1
    scale = float(size) ** power
    # a model that is one point (size 0, or so small that the power underflows) has no length to scale by
    return ZERO_TOL / scale if scale > 0 else ZERO_TOL
