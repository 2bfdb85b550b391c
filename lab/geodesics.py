r"""Normal sections, geodesics and polar isodistance curves (Puig-Pey, Gálvez, Iglesias, ``seeds/003``).

A path starts at a surface point :math:`\mathbf P = \mathbf x(u_0, v_0)` in the
tangent direction of angle :math:`\alpha` (eq. 10)

.. math::

    \mathbf n = \cos\alpha\,\frac{\mathbf x_v}{|\mathbf x_v|}
              + \sin\alpha\,\frac{\mathbf x_v^\perp}{|\mathbf x_v^\perp|},
    \qquad \mathbf x_v^\perp = -G\,\mathbf x_u + F\,\mathbf x_v \quad (9),

and is integrated in the parameter domain with the arc length :math:`s` on the
surface as the integration variable:

* a *normal section* (eq. 7) is the curve cut by the plane through
  :math:`\mathbf P` spanned by :math:`\mathbf N` and :math:`\mathbf n`, i.e. the
  plane normal to :math:`\mathbf D = \mathbf N \times \mathbf n`;
* a *geodesic* (eq. 11) solves
  :math:`u'' = -\Gamma^1_{11}u'^2 - 2\Gamma^1_{12}u'v' - \Gamma^1_{22}v'^2`
  (and likewise :math:`v''`) with :math:`(u'(0), v'(0))` from eqs. 14 and 16.

Joining the points at the same distance :math:`s_L` along a fan of paths gives
the *polar isodistance curves* (sections 3 and 5).

Numerics (section 4 of the paper): the ODE is solved patch by patch.  On a
B-spline/NURBS surface the derivatives are only C² (or C¹ at multiple knots)
across knot lines, so the right-hand side has kinks there that would force an
adaptive solver into many rejected steps.  As the paper prescribes, the model
is applied inside one Bézier patch at a time (evaluated as a polynomial, also a
little beyond its edges, so every step sees a smooth right-hand side); when a
path crosses a knot line (found by root finding on the dense output, as a
terminal event) the integration restarts in the neighbouring patch from the
crossing point.  The domain boundary is such a crossing without a neighbour:
the path stops there with ``hit_boundary`` set.  In periodic directions
(``surface.periodic``) the neighbour of the last patch is the first one, so the
path wraps around.  At a degenerate point (:math:`\mathbf x_u\times\mathbf x_v = 0`,
a sphere's pole) eqs. 7 and 11 are singular: a path that runs into one stops
just before it (``end == "degenerate"``) with a warning.

:func:`geodesic` and :func:`normal_section` use :func:`scipy.integrate.solve_ivp`
(``DOP853`` by default).  The fans integrate all their paths together with a
vectorised Dormand–Prince 8(5,3) stepper that makes exactly the decisions
``solve_ivp``'s ``DOP853`` makes for each path (same coefficients, error norm,
step-size control, dense output and event location), but evaluates the surface
once per stage for all paths: see :func:`geodesic_fan`.
"""

import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import DOP853, solve_ivp
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from . import _validation as _v
from . import bezier
from .curvature import DegeneratePointWarning, unit_normal
from .derivatives import Derivatives, from_homogeneous
from .surface import BezierSurface, BSplineSurface, Surface

__all__ = [
    "ATOL",
    "RTOL",
    "Fan",
    "Isodistance",
    "Path",
    "christoffel",
    "geodesic",
    "geodesic_between",
    "geodesic_fan",
    "normal_section",
    "normal_section_fan",
    "polar_isodistance",
    "start_direction",
]

#: Default relative and absolute tolerances of the ODE solver (per path, as in solve_ivp).
RTOL = 1e-10
ATOL = 1e-12

GEODESIC = "geodesic"
NORMAL_SECTION = "normal section"

#: A patch edge counts as crossed once a path is this far (relative to the patch width) beyond it.
#: The margin keeps a path that starts on, or runs along, a knot line from triggering a crossing.
_CROSS_MARGIN = 1e-12
#: A path stops where |b_u x b_v| / (E + G) falls below this (just before a degenerate point).
_DEGENERATE_STOP = 1e-6
_EPS = np.finfo(float).eps
#: Why a path ended (besides reaching its length).
_BOUNDARY, _DEGENERATE = 1, 2
_ENDS = {0: "length", _BOUNDARY: "boundary", _DEGENERATE: "degenerate"}


# --------------------------------------------------------------------------- results


@dataclass(frozen=True, eq=False)
class Path:
    """A normal section or geodesic starting at ``origin``.

    Attributes
    ----------
    s : (k,) ndarray
        Arc length of the samples, from 0 to :attr:`length`.
    uv : (k, 2) ndarray
        Parameters of the samples, wrapped into the domain in periodic directions.
    points : (k, 3) ndarray
        Surface points ``x(u(s), v(s))``.
    duv : (k, 2) ndarray
        Unit-speed tangent in the domain, ``(du/ds, dv/ds)``.
    hit_boundary : bool
        The path stopped where it left the domain, before the requested length.
    end : str
        Why it ended: ``"length"`` (reached it), ``"boundary"`` or
        ``"degenerate"`` (ran into a degenerate point such as a sphere's pole,
        where eqs. 7 and 11 are singular: it stops where
        ``|b_u x b_v| / (E + G)`` falls to 1e-6, and a
        :class:`~lab.curvature.DegeneratePointWarning` is issued).
    angle : float
        Start angle α (eq. 10).
    kind : str
        ``"geodesic"`` or ``"normal section"``.
    origin : (float, float)
        Start parameters ``(u0, v0)``.
    surface : Surface
    """

    s: np.ndarray
    uv: np.ndarray
    points: np.ndarray
    duv: np.ndarray
    hit_boundary: bool
    end: str
    angle: float
    kind: str
    origin: tuple
    surface: Surface = field(repr=False)
    _state: object = field(repr=False)
    _wrap: object = field(repr=False)

    @property
    def length(self):
        """Arc length reached: the requested length, or less if the path stopped earlier (see :attr:`end`)."""
        return float(self.s[-1])

    def at(self, s):
        """Parameters and surface points at arc lengths ``s`` (dense output of the solver, exact to its tolerance).

        Parameters
        ----------
        s : array_like
            Arc lengths in ``[0, length]``.

        Returns
        -------
        uv : ndarray, shape ``s.shape + (2,)``
        points : ndarray, shape ``s.shape + (3,)``
        """
        s = np.asarray(s, dtype=float)
        if not np.all(np.isfinite(s)) or (s.size and (s.min() < 0 or s.max() > self.length * (1 + 1e-14))):
            raise ValueError(f"arc lengths must lie in [0, {self.length:g}] (the path's length); got {s}")
        flat = np.clip(s.ravel(), 0.0, self.length)
        uv = self._wrap(self._state(flat)[:, :2])
        points = self.surface.evaluate(uv[:, 0], uv[:, 1])
        return uv.reshape(s.shape + (2,)), points.reshape(s.shape + (3,))

    def __repr__(self):
        end = {"length": "full length", "boundary": "hit the boundary", "degenerate": "stopped at a degenerate point"}
        return (f"Path({self.kind}, angle={self.angle:.6g}, length={self.length:.6g}, {end[self.end]}, "
                f"{len(self.s)} samples)")


@dataclass(frozen=True, eq=False)
class Fan:
    """Paths from one point at ``n`` equally spaced angles α_k = 2πk/n; iterate or index it for the paths.

    Attributes
    ----------
    paths : list of Path
    angles : (n,) ndarray
    origin : (float, float)
    length : float
        The requested length of every path.
    kind : str
    surface : Surface
    full_circle : bool
        True for angles 2πk/n around the whole circle; False for a partial fan.
    """

    paths: list
    angles: np.ndarray
    origin: tuple
    length: float
    kind: str
    surface: Surface = field(repr=False)
    full_circle: bool = True

    def __len__(self):
        return len(self.paths)

    def __iter__(self):
        return iter(self.paths)

    def __getitem__(self, index):
        return self.paths[index]

    @property
    def hit_boundary(self):
        """``(n,)`` bool: which paths stopped at the domain boundary."""
        return np.array([p.hit_boundary for p in self.paths], dtype=bool)

    def __repr__(self):
        return (
            f"Fan({len(self)} {self.kind}s from {self.origin}, length {self.length:g}, "
            f"{int(self.hit_boundary.sum())} hit the boundary)"
        )


@dataclass(frozen=True, eq=False)
class Isodistance:
    """One piece of a polar isodistance curve (seeds/003 section 3).

    Attributes
    ----------
    distance : float
        The arc length s_L from the origin along the paths.
    uv : (k, 2) ndarray
        Parameters of the samples (wrapped into the domain in periodic directions).
    points : (k, 3) ndarray
        Surface points; for a closed curve the last sample repeats the first.
    angles : (k,) ndarray
        Start angle α of each sample (increasing; may exceed 2π on a piece that runs over α = 0).
    closed : bool
        True when every path of the fan reached the distance.
    """

    distance: float
    uv: np.ndarray
    points: np.ndarray
    angles: np.ndarray
    closed: bool

    def __repr__(self):
        kind = "closed" if self.closed else "open"
        return f"Isodistance({kind}, distance={self.distance:g}, {len(self.points)} points)"


# --------------------------------------------------------------------------- differential geometry


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def christoffel(d):
    r"""Christoffel symbols of the second kind from exact first and second derivatives.

    With :math:`E_u = 2\,\mathbf x_u\cdot\mathbf x_{uu}`,
    :math:`E_v = 2\,\mathbf x_u\cdot\mathbf x_{uv}`,
    :math:`F_u = \mathbf x_{uu}\cdot\mathbf x_v + \mathbf x_u\cdot\mathbf x_{uv}`,
    :math:`F_v = \mathbf x_{uv}\cdot\mathbf x_v + \mathbf x_u\cdot\mathbf x_{vv}`,
    :math:`G_u = 2\,\mathbf x_v\cdot\mathbf x_{uv}`,
    :math:`G_v = 2\,\mathbf x_v\cdot\mathbf x_{vv}` and
    :math:`\Delta = 2(EG - F^2)` (Struik, *Lectures on Classical Differential
    Geometry*, chapter 4, the reference [18] that ``seeds/003`` gives for eq. 11):

    .. math::

        \Gamma^1_{11} &= (G E_u - 2F F_u + F E_v)/\Delta, &
        \Gamma^2_{11} &= (2E F_u - E E_v - F E_u)/\Delta,\\
        \Gamma^1_{12} &= (G E_v - F G_u)/\Delta, &
        \Gamma^2_{12} &= (E G_u - F E_v)/\Delta,\\
        \Gamma^1_{22} &= (2G F_v - G G_u - F G_v)/\Delta, &
        \Gamma^2_{22} &= (E G_v - 2F F_v + F G_u)/\Delta.

    Parameters
    ----------
    d : Derivatives
        Fields ``bu, bv, buu, buv, bvv`` of shape ``S + (3,)`` (``b`` is not used).

    Returns
    -------
    Gamma : ndarray, shape ``S + (2, 2, 2)``
        ``Gamma[..., k, i, j]`` is :math:`\Gamma^{k+1}_{i+1\,j+1}` (symmetric in i, j);
        infinite or NaN at degenerate points (EG - F² = 0).
    """
    g111, g112, g122, g211, g212, g222 = _christoffel_symbols(d)
    first = np.stack([np.stack([g111, g112], -1), np.stack([g112, g122], -1)], -2)
    second = np.stack([np.stack([g211, g212], -1), np.stack([g212, g222], -1)], -2)
    return np.stack([first, second], -3)


def _christoffel_symbols(d):
    """The six distinct symbols Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂ (see :func:`christoffel`)."""
    V = np.stack(np.broadcast_arrays(d.bu, d.bv, d.buu, d.buv, d.bvv), axis=-2)  # (..., 5, 3)
    M = np.einsum("...id,...jd->...ij", V, V)  # all dot products at once
    E, F, G = M[..., 0, 0], M[..., 0, 1], M[..., 1, 1]
    Eu, Ev = 2 * M[..., 0, 2], 2 * M[..., 0, 3]
    Fu, Fv = M[..., 2, 1] + M[..., 0, 3], M[..., 3, 1] + M[..., 0, 4]
    Gu, Gv = 2 * M[..., 1, 3], 2 * M[..., 1, 4]
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 0.5 / (E * G - F * F)
        return (
            (G * Eu - 2 * F * Fu + F * Ev) * inv,
            (G * Ev - F * Gu) * inv,
            (2 * G * Fv - G * Gu - F * Gv) * inv,
            (2 * E * Fu - E * Ev - F * Eu) * inv,
            (E * Gu - F * Ev) * inv,
            (E * Gv - 2 * F * Fv + F * Gu) * inv,
        )


def _frame(d):
    r"""The orthonormal frame :math:`\mathbf x_v/|\mathbf x_v|,\ \mathbf x_v^\perp/|\mathbf x_v^\perp|` (eqs. 9, 10)
    and the coefficients that express it in the basis :math:`\mathbf x_u, \mathbf x_v` (eq. 15)."""
    E, F, G = _dot(d.bu, d.bu), _dot(d.bu, d.bv), _dot(d.bv, d.bv)
    norm_v = np.sqrt(G)
    norm_perp = np.sqrt(G * (E * G - F * F))  # |-G x_u + F x_v|
    e1 = d.bv / norm_v[..., None]
    e2 = (-G[..., None] * d.bu + F[..., None] * d.bv) / norm_perp[..., None]
    # e1 = 0 x_u + (1/|x_v|) x_v ;  e2 = (-G/|x_v^perp|) x_u + (F/|x_v^perp|) x_v
    c1 = np.stack([np.zeros_like(G), 1.0 / norm_v], -1)
    c2 = np.stack([-G / norm_perp, F / norm_perp], -1)
    return e1, e2, c1, c2


def start_direction(surface, uv, angle):
    r"""Unit tangent :math:`\mathbf n` of angle α (eq. 10) and the initial values :math:`(u'(0), v'(0))`.

    The angle is measured from :math:`\mathbf x_v` towards
    :math:`\mathbf x_v^\perp = -G\mathbf x_u + F\mathbf x_v` (eq. 9).  The
    coefficients of :math:`\mathbf n` in the basis :math:`\mathbf x_u, \mathbf x_v`
    (eq. 15) are the arc-length derivatives of eq. 14 with
    :math:`c = u'/v'` from eq. 16 and the sign that makes the path start along
    :math:`+\mathbf n`; taking them from eq. 15 directly avoids the pole of
    eq. 16 where :math:`\mathbf n \parallel \mathbf x_u`.

    Parameters
    ----------
    surface : Surface
    uv : (float, float)
        A regular point of the domain.
    angle : array_like
        Angles α in radians.

    Returns
    -------
    n : ndarray, shape ``angle.shape + (3,)``
    duv : ndarray, shape ``angle.shape + (2,)``
        ``(u'(0), v'(0))`` with :math:`E u'^2 + 2F u'v' + G v'^2 = 1`.
    """
    surface = _check_surface(surface)
    u0, v0 = _check_point(surface, uv, "start point")
    alpha = _as_angles(angle)
    d = _regular_derivatives(surface, u0, v0, "start point")
    n, duv = _direction(d, alpha.ravel())
    return n.reshape(alpha.shape + (3,)), duv.reshape(alpha.shape + (2,))


def _direction(d, alpha):
    e1, e2, c1, c2 = _frame(d)
    ca, sa = np.cos(alpha)[..., None], np.sin(alpha)[..., None]
    return ca * e1 + sa * e2, ca * c1 + sa * c2


def _geodesic_rhs(d, y):
    """Eq. 11 for states ``y = (u, v, u', v')`` of shape (k, 4) with derivatives d at (u, v)."""
    g111, g112, g122, g211, g212, g222 = _christoffel_symbols(d)
    p, q = y[:, 2], y[:, 3]
    pp, pq, qq = p * p, 2 * p * q, q * q
    out = np.empty_like(y)
    out[:, :2] = y[:, 2:4]
    out[:, 2] = -(g111 * pp + g112 * pq + g122 * qq)
    out[:, 3] = -(g211 * pp + g212 * pq + g222 * qq)
    return out


def _section_rhs(d, D):
    r"""Eq. 7 with the + sign: :math:`(u', v') = (\mathbf x_v\cdot\mathbf D, -\mathbf x_u\cdot\mathbf D)/W`.

    The tangent :math:`(\mathbf x_v\cdot\mathbf D)\mathbf x_u - (\mathbf x_u\cdot\mathbf D)\mathbf x_v
    = \mathbf D\times(\mathbf x_u\times\mathbf x_v)` equals
    :math:`|\mathbf x_u\times\mathbf x_v|\,\mathbf n` at the start point (where
    :math:`\mathbf D = \mathbf N\times\mathbf n`), so this sign starts the section along +n.
    """
    a, b = _dot(d.bu, D), _dot(d.bv, D)
    E, F, G = _dot(d.bu, d.bu), _dot(d.bu, d.bv), _dot(d.bv, d.bv)
    with np.errstate(divide="ignore", invalid="ignore"):
        W = np.sqrt(E * b * b - 2 * F * a * b + G * a * a)
        return np.stack([b / W, -a / W], axis=1)


def _regularity(d):
    """|b_u x b_v| / (E + G): 1/2 for an orthonormal parametrisation, 0 at a degenerate point."""
    return np.linalg.norm(np.cross(d.bu, d.bv), axis=-1) / (_dot(d.bu, d.bu) + _dot(d.bv, d.bv))


# --------------------------------------------------------------------------- the surface, patch by patch


class _PatchEvaluator:
    """Derivatives of the Bézier patches of a (rational) B-spline surface at local parameters, extended beyond [0, 1].

    Built from :meth:`lab.BSplineSurface.bezier_nets` (or the one net of a
    :class:`lab.BezierSurface`).  Each patch is converted once from the
    Bernstein to the monomial basis in its local parameters ``(s, t)``, so that
    all six fields ``b, bu, bv, buu, buv, bvv`` come from one tensor
    contraction; being a polynomial (in homogeneous coordinates), a patch
    continues smoothly a little outside its span.  Chain rule: ``d/du = (1/h_u) d/ds``.
    """

    def __init__(self, nets, weights, widths_u, widths_v):
        Pw = bezier.homogeneous(nets, weights)
        self.rational = weights is not None
        p, q = Pw.shape[-3] - 1, Pw.shape[-2] - 1
        self.coeffs = np.einsum("ik,jl,...ijd->...kld", _bernstein_to_monomial(p), _bernstein_to_monomial(q), Pw)
        self.powers = (np.arange(p + 1), np.arange(q + 1))
        self.inv_widths = (1.0 / widths_u, 1.0 / widths_v)

    @staticmethod
    def _basis(x, k, inv_width):
        """Rows (x^k, d/du x^k, d²/du² x^k) for local parameters x: shape (n, 3, len(k))."""
        x = x[:, None]
        out = np.zeros((len(x), 3, len(k)))
        out[:, 0] = x**k
        out[:, 1, 1:] = k[1:] * out[:, 0, :-1] * inv_width[:, None]
        out[:, 2, 2:] = k[2:] * (k[2:] - 1) * out[:, 0, :-2] * (inv_width**2)[:, None]
        return out

    def __call__(self, iu, iv, su, sv):
        Su = self._basis(su, self.powers[0], self.inv_widths[0][iu])
        Sv = self._basis(sv, self.powers[1], self.inv_widths[1][iv])
        X = np.einsum("kai,kbj,kijd->kabd", Su, Sv, self.coeffs[iu, iv])
        d = Derivatives(X[:, 0, 0], X[:, 1, 0], X[:, 0, 1], X[:, 2, 0], X[:, 1, 1], X[:, 0, 2])
        return from_homogeneous(d) if self.rational else d


def _bernstein_to_monomial(n):
    """Matrix M with B_i^n(t) = sum_k M[i, k] t^k."""
    from math import comb

    M = np.zeros((n + 1, n + 1))
    for i in range(n + 1):
        for k in range(i, n + 1):
            M[i, k] = comb(n, i) * comb(n - i, k - i) * (-1) ** (k - i)
    return M


class _Problem:
    """A surface prepared for path integration: patch structure, periodicity, right-hand sides and events.

    Cells are patches (knot spans) indexed by integers per direction; in a
    periodic direction the index runs over all integers, cell ``c`` being span
    ``c mod S`` shifted by ``(c // S)`` periods, so that unwrapped parameters
    and the patch polynomials stay continuous around the surface.
    """

    def __init__(self, surface, kind):
        self.surface = surface
        self.kind = kind
        self.m = 4 if kind == GEODESIC else 2
        (u0, u1), (v0, v1) = surface.domain
        self.lo = np.array([u0, v0], dtype=float)
        self.hi = np.array([u1, v1], dtype=float)
        self.period = self.hi - self.lo
        self.periodic = tuple(bool(p) for p in surface.periodic)
        self.patches = None
        # the patch polynomials stand in for the surface only where they are its definition
        own = type(surface)._derivatives
        if own is BSplineSurface._derivatives:
            nets, w, iu, iv = surface.bezier_nets()
            self.breaks = [_breaks(iu), _breaks(iv)]
        elif own is BezierSurface._derivatives:
            nets = surface.control_points[None, None]
            w = None if surface.weights is None else surface.weights[None, None]
            self.breaks = [np.array([u0, u1]), np.array([v0, v1])]
        else:
            nets = None
            self.breaks = [np.array([u0, u1]), np.array([v0, v1])]
        if nets is not None:
            self.patches = _PatchEvaluator(nets, w, np.diff(self.breaks[0]), np.diff(self.breaks[1]))
        self.n_spans = np.array([len(b) - 1 for b in self.breaks])

    # -- parameters and cells

    def wrap(self, uv):
        """Parameters into the domain: modulo the period in periodic directions, clipped otherwise."""
        uv = np.array(uv, dtype=float, copy=True)
        for axis in range(2):
            x = uv[..., axis]
            if self.periodic[axis]:
                x = self.lo[axis] + np.mod(x - self.lo[axis], self.period[axis])
            uv[..., axis] = np.clip(x, self.lo[axis], self.hi[axis])
        return uv

    def cell_bounds(self, cell):
        """Lower and upper unwrapped parameter of each cell: two (k, 2) arrays."""
        lower, upper = np.empty(cell.shape), np.empty(cell.shape)
        for axis in range(2):
            S = self.n_spans[axis]
            c = cell[:, axis]
            j, shift = (np.mod(c, S), np.floor_divide(c, S) * self.period[axis]) if self.periodic[axis] else (c, 0.0)
            lower[:, axis] = self.breaks[axis][j] + shift
            upper[:, axis] = self.breaks[axis][j + 1] + shift
        return lower, upper

    def locate(self, uv, duv):
        """Cells holding the points ``uv`` (k, 2); on a knot line, the cell the direction ``duv`` points into."""
        cell = np.empty(uv.shape, dtype=int)
        for axis in range(2):
            S, br = self.n_spans[axis], self.breaks[axis]
            x = uv[:, axis]
            k = np.floor((x - self.lo[axis]) / self.period[axis]) if self.periodic[axis] else np.zeros_like(x)
            xw = x - k * self.period[axis]
            j = np.clip(np.searchsorted(br, xw, side="right") - 1, 0, S - 1)
            back = (xw == br[j]) & (duv[:, axis] < 0)
            j = j - back
            if self.periodic[axis]:
                cell[:, axis] = (k.astype(int) * S) + j
            else:
                cell[:, axis] = np.maximum(j, 0)
        return cell

    def gap(self, y, cell):
        """First event function: distance of the points to the edge of their cell, relative to its width, plus a margin.

        Positive inside the cell; it becomes negative a hair (``_CROSS_MARGIN``)
        beyond an edge, which is where the path leaves the patch.
        """
        lower, upper = self.cell_bounds(cell)
        width = upper - lower
        rel = np.minimum(y[:, :2] - lower, upper - y[:, :2]) / width
        return rel.min(axis=1) + _CROSS_MARGIN

    def regular(self, y, cell):
        """Second event function: :func:`_regularity` minus ``_DEGENERATE_STOP``.

        It becomes negative just before a degenerate point (a sphere's pole),
        where the Christoffel symbols and eq. 7 are singular.
        """
        return _regularity(self.derivatives(y[:, :2], cell)) - _DEGENERATE_STOP

    def cross(self, y, cell):
        """After a gap event: the neighbouring cell across the edge crossed, and whether that edge is the domain boundary."""
        lower, upper = self.cell_bounds(cell)
        width = upper - lower
        gaps = np.concatenate([(y[:, :2] - lower) / width, (upper - y[:, :2]) / width], axis=1)  # (k, 4)
        face = np.argmin(gaps, axis=1)
        axis, step = face % 2, np.where(face < 2, -1, 1)
        new = cell.copy()
        new[np.arange(len(cell)), axis] += step
        leaves = np.zeros(len(cell), dtype=bool)
        for a in range(2):
            if not self.periodic[a]:
                leaves |= (axis == a) & ((new[:, a] < 0) | (new[:, a] >= self.n_spans[a]))
        return new, leaves

    # -- evaluation

    def derivatives(self, uv, cell):
        """Surface derivatives at unwrapped parameters ``uv`` (k, 2) using the polynomial of each path's cell."""
        bad = ~np.all(np.isfinite(uv), axis=1)
        lower, upper = self.cell_bounds(cell)
        if np.any(bad):  # a failing step: evaluate somewhere harmless, report NaN
            uv = np.where(bad[:, None], 0.5 * (lower + upper), uv)
        if self.patches is not None:
            span = np.empty_like(cell)
            for axis in range(2):
                span[:, axis] = np.mod(cell[:, axis], self.n_spans[axis]) if self.periodic[axis] else cell[:, axis]
            local = (uv - lower) / (upper - lower)
            d = self.patches(span[:, 0], span[:, 1], local[:, 0], local[:, 1])
        else:
            w = self.wrap(uv)
            d = self.surface.derivatives(w[:, 0], w[:, 1])
        if np.any(bad):
            d = d.map(lambda x: np.where(bad[:, None], np.nan, x))
        return d

    def rhs(self, y, cell, D=None, regular=False):
        """Right-hand side of eq. 11 (geodesics) or eq. 7 (normal sections, plane normals ``D`` (k, 3)).

        With ``regular=True`` also the second event function :meth:`regular` at the same points.
        """
        d = self.derivatives(y[:, :2], cell)
        f = _geodesic_rhs(d, y) if self.kind == GEODESIC else _section_rhs(d, D)
        return (f, _regularity(d) - _DEGENERATE_STOP) if regular else f

    def tangent(self, y, D=None):
        """``(du/ds, dv/ds)`` at states ``y`` (k, m), evaluated with the public surface derivatives."""
        if self.kind == GEODESIC:
            return y[:, 2:4].copy()
        w = self.wrap(y[:, :2])
        return _section_rhs(self.surface.derivatives(w[:, 0], w[:, 1]), D)


def _breaks(intervals):
    lo = np.array([a for a, _ in intervals])
    hi = np.array([b for _, b in intervals])
    if not np.allclose(lo[1:], hi[:-1], rtol=0, atol=1e-14 * max(1.0, abs(hi[-1]))):
        raise ValueError(f"knot spans must be contiguous; got {intervals}")  # pragma: no cover - bezier_nets guarantees it
    return np.concatenate([lo, hi[-1:]])


# --------------------------------------------------------------------------- dense output


class _Pieces:
    """Continuous state of one path: DOP853 interpolants of its steps (same polynomial as scipy's ``Dop853DenseOutput``)."""

    def __init__(self, t_old, t_hi, h, y_old, F):
        self.t_old, self.t_hi, self.h, self.y_old, self.F = t_old, t_hi, h, y_old, F

    def __call__(self, s):
        s = np.atleast_1d(np.asarray(s, dtype=float))
        i = np.clip(np.searchsorted(self.t_hi, s, side="left"), 0, len(self.t_hi) - 1)
        return _dop853_poly((s - self.t_old[i]) / self.h[i], self.y_old[i], self.F[i])


def _dop853_poly(x, y_old, F):
    """Evaluate DOP853 dense-output polynomials: x (q,), y_old (q, m), F (q, 7, m)."""
    x = x[:, None]
    y = np.zeros_like(y_old)
    for i in range(F.shape[1] - 1, -1, -1):
        y = y + F[:, i]
        y = y * (x if (F.shape[1] - 1 - i) % 2 == 0 else (1 - x))
    return y + y_old


class _Segments:
    """Continuous state of one path from consecutive ``solve_ivp`` solutions (one per patch)."""

    def __init__(self, ends, solutions):
        self.ends = np.asarray(ends)
        self.solutions = solutions

    def __call__(self, s):
        s = np.atleast_1d(np.asarray(s, dtype=float))
        i = np.clip(np.searchsorted(self.ends, s, side="left"), 0, len(self.ends) - 1)
        out = None
        for k in np.unique(i):
            sel = i == k
            values = self.solutions[k](s[sel]).T
            if out is None:
                out = np.empty((len(s), values.shape[1]))
            out[sel] = values
        return out


# --------------------------------------------------------------------------- one path: solve_ivp


def _solve_one(problem, y0, cell0, length, D, rtol, atol, method):
    """Integrate one path with solve_ivp, restarting at every patch edge (terminal event)."""
    t0, y, cell = 0.0, np.asarray(y0, dtype=float), np.asarray(cell0)[None]
    Drow = None if D is None else D[None]
    ends, sols, first_step, stop = [], [], None, 0
    while True:

        def fun(t, yy, cell=cell):
            return problem.rhs(yy[None], cell, Drow)[0]

        def gap(t, yy, cell=cell):
            return problem.gap(yy[None], cell)[0]

        def regular(t, yy, cell=cell):
            return problem.regular(yy[None], cell)[0]

        for event in (gap, regular):
            event.terminal, event.direction = True, -1
        res = solve_ivp(fun, (t0, length), y, method=method, rtol=rtol, atol=atol, events=(gap, regular),
                        dense_output=True, first_step=first_step)
        if res.status == -1:
            raise RuntimeError(
                f"{problem.kind} integration failed at s = {res.t[-1]:.6g} near (u, v) = "
                f"{_fmt(problem.wrap(res.y[:2, -1]))}: {res.message}"
            )
        sols.append(res.sol)
        if res.status == 0:
            ends.append(length)
            break
        if res.t_events[1].size:  # the earlier of the two terminal events is recorded
            ends.append(float(res.t_events[1][0]))
            stop = _DEGENERATE
            break
        t0, y = float(res.t_events[0][0]), res.y_events[0][0]
        ends.append(t0)
        cell, leaves = problem.cross(y[None], cell)
        if leaves[0]:
            stop = _BOUNDARY
            break
        if t0 >= length:
            break
        last = res.sol.interpolants[-1]
        first_step = min(abs(last.t - last.t_old), length - t0)
    return _Segments(ends, sols), ends[-1], stop


# --------------------------------------------------------------------------- many paths: vectorised DOP853


_A, _B, _C = DOP853.A, DOP853.B, DOP853.C
_E3, _E5, _Dd = DOP853.E3, DOP853.E5, DOP853.D
_A_EXTRA, _C_EXTRA = DOP853.A_EXTRA, DOP853.C_EXTRA
_N_STAGES = DOP853.n_stages
_ERR_EXP = -1.0 / (DOP853.error_estimator_order + 1)
_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0


def _rms(x):
    return np.sqrt(np.mean(x * x, axis=1))


def _initial_step(problem, y0, cell, f0, length, D, rtol, atol):
    """:func:`scipy.integrate._ivp.common.select_initial_step` (Hairer, Nørsett, Wanner II.4) for every path at once.

    ``length`` (n,) is each path's interval of integration.
    """
    scale = atol + np.abs(y0) * rtol
    d0, d1 = _rms(y0 / scale), _rms(f0 / scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / d1)
    h0 = np.minimum(h0, length)
    f1 = problem.rhs(y0 + h0[:, None] * f0, cell, D)
    d2 = _rms((f1 - f0) / scale) / h0
    with np.errstate(divide="ignore", invalid="ignore"):
        h1 = np.where((d1 <= 1e-15) & (d2 <= 1e-15), np.maximum(1e-6, h0 * 1e-3),
                      (0.01 / np.maximum(d1, d2)) ** (1.0 / (DOP853.error_estimator_order + 1)))
    return np.minimum(np.minimum(100 * h0, h1), length)


def _integrate_fan(problem, y0, cell0, length, D, rtol, atol):
    """Integrate n paths together; each makes the step decisions ``solve_ivp(method="DOP853")`` makes for it alone.

    Every iteration attempts one step for every unfinished path, each with its
    own step size: the 12 stages (plus 3 for the dense output of the accepted
    steps) are evaluated for all of them at once.  Accepted steps are checked
    for a patch-edge crossing (event function :meth:`_Problem.gap`) or the
    approach of a degenerate point (:meth:`_Problem.regular`), roots by
    Brent's method on the dense output, as solve_ivp does.  A path that
    crosses an edge continues from the crossing point in the neighbouring
    patch, or stops if the edge is the domain boundary.

    Parameters
    ----------
    problem : _Problem
    y0 : (n, m) ndarray
        Initial states.
    cell0 : (n, 2) int ndarray
        Initial cells (:meth:`_Problem.locate`).
    length : float or (n,) array_like
        Arc length to integrate, per path.
    D : (n, 3) ndarray or None
        Plane normals of normal sections.
    rtol, atol : float

    Returns
    -------
    pieces : list of _Pieces
    ends : (n,) ndarray
        Arc length reached by each path.
    stops : (n,) int ndarray
        Why each path ended: 0 (its length), ``_BOUNDARY`` or ``_DEGENERATE``.
    """
    n, m = y0.shape
    length = np.broadcast_to(np.asarray(length, dtype=float), (n,)).copy()
    t = np.zeros(n)
    y = y0.astype(float).copy()
    cell = cell0.copy()
    f, g2 = problem.rhs(y, cell, D, regular=True)
    h_abs = _initial_step(problem, y, cell, f, length, D, rtol, atol)
    g1 = problem.gap(y, cell)  # the two event functions, at the start of each path's next step
    rejected = np.zeros(n, dtype=bool)
    active = np.ones(n, dtype=bool)
    stops = np.zeros(n, dtype=int)
    ends = length.copy()
    store = [[] for _ in range(n)]  # per path: (t_old, t_hi, h, y_old, F)
    while np.any(active):
        idx = np.flatnonzero(active)
        ti, yi, fi, ci = t[idx], y[idx], f[idx], cell[idx]
        Dk = None if D is None else D[idx]
        min_step = 10 * np.abs(np.nextafter(ti, np.inf) - ti)
        ha = np.where(rejected[idx], h_abs[idx], np.maximum(h_abs[idx], min_step))
        too_small = ha < min_step
        if np.any(too_small):
            j = idx[np.flatnonzero(too_small)[0]]
            raise RuntimeError(
                f"{problem.kind} integration failed at s = {t[j]:.6g} near (u, v) = {_fmt(problem.wrap(y[j, :2]))}: "
                "Required step size is less than spacing between numbers."
            )
        Li = length[idx]
        t_new = np.minimum(ti + ha, Li)
        h = t_new - ti
        ha = np.abs(h)
        K = np.empty((_N_STAGES + 1, len(idx), m))
        K[0] = fi
        for s in range(1, _N_STAGES):
            dy = np.einsum("skm,s->km", K[:s], _A[s, :s]) * h[:, None]
            K[s] = problem.rhs(yi + dy, ci, Dk)
        y_new = yi + h[:, None] * np.einsum("skm,s->km", K[:-1], _B)
        f_new, g2_new = problem.rhs(y_new, ci, Dk, regular=True)
        K[-1] = f_new
        scale = atol + np.maximum(np.abs(yi), np.abs(y_new)) * rtol
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            e5 = np.sum((np.einsum("skm,s->km", K, _E5) / scale) ** 2, axis=1)
            e3 = np.sum((np.einsum("skm,s->km", K, _E3) / scale) ** 2, axis=1)
            err = np.where((e5 == 0) & (e3 == 0), 0.0, ha * e5 / np.sqrt((e5 + 0.01 * e3) * m))
            grow = _SAFETY * err**_ERR_EXP
        ok = err < 1
        factor = np.where(err == 0, _MAX_FACTOR, np.minimum(_MAX_FACTOR, grow))
        factor = np.where(rejected[idx], np.minimum(1.0, factor), factor)
        shrink = np.where(np.isnan(grow), _MIN_FACTOR, np.maximum(_MIN_FACTOR, grow))
        h_abs[idx] = np.where(ok, ha * factor, ha * shrink)
        rejected[idx] = ~ok
        if not np.any(ok):
            continue
        # accepted steps: dense output (3 extra stages), then events
        a = np.flatnonzero(ok)
        ia, ha_, ya_old, ya_new, ca = idx[a], h[a], yi[a], y_new[a], ci[a]
        Da = None if D is None else Dk[a]
        Kx = np.empty((_N_STAGES + 4, len(a), m))
        Kx[: _N_STAGES + 1] = K[:, a]
        for s, (arow, c) in enumerate(zip(_A_EXTRA, _C_EXTRA), start=_N_STAGES + 1):
            dy = np.einsum("skm,s->km", Kx[:s], arow[:s]) * ha_[:, None]
            Kx[s] = problem.rhs(ya_old + dy, ca, Da)
        delta = ya_new - ya_old
        F = np.empty((len(a), 7, m))
        F[:, 0] = delta
        F[:, 1] = ha_[:, None] * K[0, a] - delta
        F[:, 2] = 2 * delta - ha_[:, None] * (K[-1, a] + K[0, a])
        F[:, 3:] = ha_[:, None, None] * np.einsum("ps,skm->kpm", _Dd, Kx)
        # events as solve_ivp finds them: a sign change from >= 0 to <= 0 over the step (direction -1),
        # its root by Brent's method on the dense output; the earlier of the two terminates the path
        g1_new, g2_new = problem.gap(ya_new, ca), g2_new[a]
        hit1 = (g1[ia] >= 0) & (g1_new <= 0)
        hit2 = (g2[ia] >= 0) & (g2_new <= 0)
        t_old = ti[a]
        t_hi = t_new[a].copy()
        degenerate = np.zeros(len(a), dtype=bool)
        for r in np.flatnonzero(hit1 | hit2):
            j = ia[r]

            def state_at(tt, t0=t_old[r], h=ha_[r], y0=ya_old[r : r + 1], Fr=F[r : r + 1]):
                return _dop853_poly(np.array([(tt - t0) / h]), y0, Fr)

            roots = [np.inf, np.inf]
            for e, (hit, func) in enumerate(((hit1, problem.gap), (hit2, problem.regular))):
                if hit[r]:
                    roots[e] = brentq(lambda tt, func=func, j=j: func(state_at(tt), cell[j : j + 1])[0],
                                      t_old[r], t_hi[r], xtol=4 * _EPS, rtol=4 * _EPS)
            degenerate[r] = roots[1] <= roots[0]
            t_hi[r] = min(roots)
        crossed = hit1 | hit2
        for r, j in enumerate(ia):
            store[j].append((t_old[r], t_hi[r], ha_[r], ya_old[r], F[r]))
        # paths without events: advance
        plain = ~crossed
        jp = ia[plain]
        t[jp], y[jp], f[jp] = t_new[a][plain], ya_new[plain], K[-1, a][plain]
        g1[jp], g2[jp] = g1_new[plain], g2_new[plain]
        done = jp[t[jp] >= length[jp]]
        active[done] = False
        # paths at a degenerate point stop there
        jd = ia[degenerate]
        ends[jd], stops[jd], active[jd] = t_hi[degenerate], _DEGENERATE, False
        # paths that crossed a patch edge: restart in the neighbour (or stop at the boundary)
        edge = crossed & ~degenerate
        if np.any(edge):
            rc = np.flatnonzero(edge)
            jc = ia[rc]
            yc = _dop853_poly((t_hi[rc] - t_old[rc]) / ha_[rc], ya_old[rc], F[rc])
            new_cell, leaves = problem.cross(yc, cell[jc])
            stop = leaves | (t_hi[rc] >= length[jc])
            ends[jc[stop]] = t_hi[rc][stop]
            stops[jc[leaves]] = _BOUNDARY
            active[jc[stop]] = False
            go = ~stop
            if np.any(go):
                jg = jc[go]
                t[jg], y[jg], cell[jg] = t_hi[rc][go], yc[go], new_cell[go]
                Dg = None if D is None else D[jg]
                f[jg], g2[jg] = problem.rhs(y[jg], cell[jg], Dg, regular=True)
                g1[jg] = problem.gap(y[jg], cell[jg])
                # as a restarted solve_ivp with first_step = the step just taken
                h_abs[jg] = np.minimum(ha_[rc][go], length[jg] - t[jg])
                rejected[jg] = False
    pieces = []
    for j in range(n):
        cols = list(zip(*store[j]))
        pieces.append(_Pieces(*(np.array(c) for c in cols)))
    return pieces, ends, stops


# --------------------------------------------------------------------------- validation


def _fmt(uv):
    return "(" + ", ".join(f"{float(x):.6g}" for x in uv) + ")"


def _check_surface(surface):
    if not isinstance(surface, Surface):
        raise TypeError(f"surface must be a lab.Surface (Bézier, B-spline or parametric); got {type(surface).__name__}")
    return surface


def _check_point(surface, uv, name):
    try:
        u, v = (float(x) for x in uv)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair of parameters (u, v); got {uv!r}") from None
    (u0, u1), (v0, v1) = surface.domain
    slack_u, slack_v = 1e-12 * max(1.0, u1 - u0), 1e-12 * max(1.0, v1 - v0)
    if not (np.isfinite(u) and np.isfinite(v) and u0 - slack_u <= u <= u1 + slack_u and v0 - slack_v <= v <= v1 + slack_v):
        raise ValueError(f"{name} must lie in the domain [{u0:g}, {u1:g}] x [{v0:g}, {v1:g}]; got (u, v) = ({u:g}, {v:g})")
    return min(max(u, u0), u1), min(max(v, v0), v1)


def _regular_derivatives(surface, u, v, name):
    d = surface.derivatives(np.array([u]), np.array([v]))
    _, degenerate = unit_normal(d.bu, d.bv)
    if degenerate[0]:
        raise ValueError(
            f"{name} (u, v) = ({u:g}, {v:g}) is a degenerate point (b_u x b_v = 0): "
            "it has no tangent plane in which to measure the angle"
        )
    return d


def _as_angles(angle):
    try:
        alpha = np.asarray(angle, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"angle must be a number (radians); got {type(angle).__name__}") from None
    if not np.all(np.isfinite(alpha)):
        raise ValueError(f"angle must be finite; got {angle}")
    return alpha


def _check_length(length, name="length"):
    try:
        L = float(length)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number; got {type(length).__name__}") from None
    if not (np.isfinite(L) and L > 0):
        raise ValueError(f"{name} must be a positive finite number; got {length}")
    return L


def _check_tolerances(rtol, atol):
    try:
        rtol, atol = float(rtol), float(atol)
    except (TypeError, ValueError):
        raise TypeError(f"rtol and atol must be numbers; got {type(rtol).__name__} and {type(atol).__name__}") from None
    if not (np.isfinite(rtol) and rtol >= 100 * _EPS):
        raise ValueError(f"rtol must be a finite number >= 100 * machine epsilon ({100 * _EPS:.3g}); got {rtol}")
    if not (np.isfinite(atol) and atol > 0):
        raise ValueError(f"atol must be a positive finite number; got {atol}")
    return rtol, atol


# --------------------------------------------------------------------------- public entry points


def _prepare(surface, uv, angles, length, kind, rtol, atol, n_samples):
    surface = _check_surface(surface)
    u0, v0 = _check_point(surface, uv, "start point")
    L = _check_length(length)
    rtol, atol = _check_tolerances(rtol, atol)
    n_samples = _v.as_positive_int(n_samples, "n_samples", minimum=2)
    d = _regular_derivatives(surface, u0, v0, "start point")
    n, duv = _direction(d, angles)  # (k, 3), (k, 2)
    problem = _Problem(surface, kind)
    k = len(angles)
    start = np.tile([u0, v0], (k, 1))
    if kind == GEODESIC:
        y0, D = np.concatenate([start, duv], axis=1), None
    else:
        N, _ = unit_normal(d.bu, d.bv)
        y0, D = start, np.cross(N, n)  # D = N x n (section 3.1)
    cell0 = problem.locate(start, duv)
    return problem, (u0, v0), L, rtol, atol, n_samples, y0, D, cell0


def _make_paths(problem, states, ends, stops, angles, origin, D, n_samples):
    """Sample every path at n_samples equally spaced arc lengths; one surface evaluation for all of them."""
    stops = np.asarray(stops, dtype=int)
    if np.any(stops == _DEGENERATE):
        k = int(np.flatnonzero(stops == _DEGENERATE)[0])
        end_uv = problem.wrap(states[k](np.array([ends[k]]))[:, :2])[0]
        warnings.warn(
            f"{int(np.sum(stops == _DEGENERATE))} {problem.kind}(s) stopped at a degenerate point "
            f"(b_u x b_v = 0), e.g. at angle {angles[k]:.6g} near (u, v) = {_fmt(end_uv)}",
            DegeneratePointWarning,
            stacklevel=4,
        )
    s = [np.linspace(0.0, end, n_samples) for end in ends]
    Y = np.concatenate([state(si) for state, si in zip(states, s)])
    uv = problem.wrap(Y[:, :2])
    points = problem.surface.evaluate(uv[:, 0], uv[:, 1])
    DY = None if D is None else np.repeat(D, n_samples, axis=0)
    duv = problem.tangent(Y, DY)
    paths = []
    for k, (state, si) in enumerate(zip(states, s)):
        sl = slice(k * n_samples, (k + 1) * n_samples)
        paths.append(Path(si, uv[sl], points[sl], duv[sl], bool(stops[k] == _BOUNDARY), _ENDS[int(stops[k])],
                          float(angles[k]), problem.kind, origin, problem.surface, state, problem.wrap))
    return paths


def _single(surface, uv, angle, length, kind, rtol, atol, method, n_samples):
    alpha = _as_angles(angle)
    if alpha.ndim != 0:
        raise ValueError(f"angle must be a single number; got shape {alpha.shape} (use the *_fan functions for many)")
    problem, origin, L, rtol, atol, n_samples, y0, D, cell0 = _prepare(
        surface, uv, alpha[None], length, kind, rtol, atol, n_samples)
    state, end, stop = _solve_one(problem, y0[0], cell0[0], L, None if D is None else D[0], rtol, atol, method)
    return _make_paths(problem, [state], [end], [stop], alpha[None], origin, D, n_samples)[0]


def geodesic(surface, uv, angle, length, *, rtol=RTOL, atol=ATOL, method="DOP853", n_samples=201):
    r"""The geodesic from ``x(u0, v0)`` in the direction of angle α, by arc length (seeds/003 eqs. 11, 12, 14–17).

    .. math::

        u'' = -\Gamma^1_{11}u'^2 - 2\Gamma^1_{12}u'v' - \Gamma^1_{22}v'^2, \qquad
        v'' = -\Gamma^2_{11}u'^2 - 2\Gamma^2_{12}u'v' - \Gamma^2_{22}v'^2 \quad (11)

    with the Christoffel symbols of :func:`christoffel`, ``(u, v)(0) = (u0, v0)``
    (eq. 12) and ``(u', v')(0)`` from eqs. 14 and 16 (:func:`start_direction`).
    Solved by :func:`scipy.integrate.solve_ivp` patch by patch (see the module
    docstring); it stops exactly where it leaves the domain.

    Parameters
    ----------
    surface : Surface
    uv : (float, float)
        Start point ``(u0, v0)`` in the domain; not a degenerate point.
    angle : float
        α of eq. 10, from ``x_v`` towards ``x_v^perp = -G x_u + F x_v`` (radians).
    length : float
        Arc length to integrate, > 0.
    rtol, atol : float
        Tolerances of the solver (per path).
    method : str
        A ``solve_ivp`` method; a high-order one (``"DOP853"``) suits these smooth problems.
    n_samples : int
        Number of samples in the returned path (equally spaced in arc length).

    Returns
    -------
    Path

    Raises
    ------
    RuntimeError
        If the solver fails (e.g. at a degenerate point such as a sphere's pole), with its message.

    Examples
    --------
    >>> import lab, numpy as np
    >>> p = geodesic(lab.surfaces.plane(2.0), (0.5, 0.5), np.pi / 2, 0.5)
    >>> np.round(p.points[-1], 12)  # alpha = pi/2 points along x_v^perp = -G x_u, i.e. -x
    array([0.5, 1. , 0. ])
    """
    return _single(surface, uv, angle, length, GEODESIC, rtol, atol, method, n_samples)


def normal_section(surface, uv, angle, length, *, rtol=RTOL, atol=ATOL, method="DOP853", n_samples=201):
    r"""The normal section from ``x(u0, v0)`` in the direction of angle α, by arc length (seeds/003 eqs. 7–10).

    The plane through :math:`\mathbf P` containing the normal :math:`\mathbf N`
    (eq. 2) and the direction :math:`\mathbf n` (eq. 10) has the normal
    :math:`\mathbf D = \mathbf N\times\mathbf n`; the section satisfies (eq. 7)

    .. math::

        \frac{du}{ds} = \frac{\mathbf x_v\cdot\mathbf D}{W}, \quad
        \frac{dv}{ds} = -\frac{\mathbf x_u\cdot\mathbf D}{W}, \quad
        W = \sqrt{E(\mathbf x_v\cdot\mathbf D)^2 - 2F(\mathbf x_u\cdot\mathbf D)(\mathbf x_v\cdot\mathbf D)
                  + G(\mathbf x_u\cdot\mathbf D)^2},

    with the sign that starts it along :math:`+\mathbf n`.  Parameters, return
    value and errors as :func:`geodesic`; the solver also fails where the plane
    touches the surface (:math:`\mathbf D \parallel \mathbf N`, W = 0), a singular
    case the paper excludes.
    """
    return _single(surface, uv, angle, length, NORMAL_SECTION, rtol, atol, method, n_samples)


def _fan_angles(n_angles, angles):
    """The start angles of a fan: 2πk/n, or the given increasing angles within one turn."""
    if angles is None:
        n_angles = _v.as_positive_int(n_angles, "n_angles", minimum=1)
        return 2 * np.pi * np.arange(n_angles) / n_angles, True
    a = np.asarray(angles, dtype=float)
    if a.ndim != 1 or a.size < 1 or not np.all(np.isfinite(a)):
        raise ValueError(f"angles must be a non-empty 1-D array of finite numbers (radians); got {angles!r}")
    if n_angles is not None and n_angles != a.size:
        raise ValueError(f"n_angles ({n_angles}) must equal the number of angles given ({a.size}), or be None")
    if np.any(np.diff(a) <= 0) or a[-1] - a[0] >= 2 * np.pi:
        raise ValueError("angles must increase strictly and span less than one turn (2π)")
    return a, False


def _fan(surface, uv, n_angles, length, kind, rtol, atol, n_samples, vectorized, angles=None):
    angles, full_circle = _fan_angles(n_angles, angles)
    n_angles = len(angles)
    problem, origin, L, rtol, atol, n_samples, y0, D, cell0 = _prepare(
        surface, uv, angles, length, kind, rtol, atol, n_samples)
    if vectorized:
        states, ends, stops = _integrate_fan(problem, y0, cell0, L, D, rtol, atol)
    else:
        states, ends, stops = [], [], []
        for k in range(n_angles):
            state, end, stop = _solve_one(problem, y0[k], cell0[k], L, None if D is None else D[k], rtol, atol, "DOP853")
            states.append(state)
            ends.append(end)
            stops.append(stop)
    paths = _make_paths(problem, states, ends, stops, angles, origin, D, n_samples)
    return Fan(paths, angles, origin, L, kind, problem.surface, full_circle)


def geodesic_fan(surface, uv, n_angles, length, *, angles=None, rtol=RTOL, atol=ATOL, n_samples=101, vectorized=True):
    """Geodesics from ``x(u0, v0)`` at the angles α_k = 2πk/n, k = 0 … n-1 (seeds/003 sections 3.2 and 4).

    All paths are integrated together: one vectorised Dormand–Prince 8(5,3)
    stepper in which every path keeps its own step size and takes exactly the
    steps ``solve_ivp(..., method="DOP853")`` would take for it alone, while
    the surface is evaluated once per stage for all paths.  (One ``solve_ivp``
    system of size 4n would share one step size, set by whichever path is
    crossing a knot line, and stop entirely at the first path's boundary event.)

    Parameters
    ----------
    surface, uv, length, rtol, atol, n_samples
        As :func:`geodesic`.
    n_angles : int or None
        Number of paths, >= 1, at the angles 2πk/n.
    angles : (n,) array_like, optional
        Start angles in radians instead (increasing, spanning less than a
        turn): a partial fan; ``n_angles`` is then None or ``len(angles)``.
    vectorized : bool
        False integrates each path with its own :func:`scipy.integrate.solve_ivp`
        call instead (the reference, used by the benchmark).

    Returns
    -------
    Fan
    """
    return _fan(surface, uv, n_angles, length, GEODESIC, rtol, atol, n_samples, vectorized, angles)


def normal_section_fan(surface, uv, n_angles, length, *, angles=None, rtol=RTOL, atol=ATOL, n_samples=101,
                       vectorized=True):
    """Normal sections from ``x(u0, v0)`` at the angles α_k = 2πk/n (seeds/003 section 3.1, figure 1).

    Integrated together as in :func:`geodesic_fan`; parameters as there.
    """
    return _fan(surface, uv, n_angles, length, NORMAL_SECTION, rtol, atol, n_samples, vectorized, angles)


# --------------------------------------------------------------------------- polar isodistance curves


def _as_paths(fan):
    paths = list(fan.paths) if isinstance(fan, Fan) else list(fan) if isinstance(fan, (list, tuple)) else None
    if not paths or not all(isinstance(p, Path) for p in paths):
        raise TypeError(f"fan must be a Fan or a non-empty list of Path objects; got {type(fan).__name__}")
    first = paths[0]
    for p in paths[1:]:
        if p.surface is not first.surface or not np.allclose(p.origin, first.origin, rtol=0, atol=1e-12):
            raise ValueError("all paths of a fan must start at the same point of the same surface")
    return sorted(paths, key=lambda p: np.mod(p.angle, 2 * np.pi))


def polar_isodistance(fan, distances, *, samples_per_angle=8):
    r"""Polar isodistance curves: the points at arc length s_L along every path of a fan (seeds/003 sections 3, 5).

    For each distance the point of every path that reaches it is taken from
    the solver's dense output.  If all paths reach it, the curve is closed and
    interpolated in α by a periodic cubic spline through the parameters
    ``(u, v)`` (the paper's "closed cyclic cubic spline"); otherwise each run of
    consecutive angles whose paths reach it (cyclically) becomes an open piece:
    a not-a-knot cubic spline in α with at least four points, linear
    interpolation in ``(u, v)`` with two or three, a single point with one.
    The splines live in the parameter domain (unwrapped across periodic seams)
    and are mapped onto the surface.

    Parameters
    ----------
    fan : Fan or list of Path
        Paths from one point (from :func:`geodesic_fan` or :func:`normal_section_fan`).
    distances : float or (d,) array_like
        Positive arc lengths s_L.
    samples_per_angle : int
        Samples per angle interval of the fan.

    Returns
    -------
    list of list of Isodistance
        One list per distance: a single closed curve, or the open pieces
        (empty when no path reaches the distance).  The spline passes exactly
        through the paths' points; between them it interpolates.
    """
    paths = _as_paths(fan)
    surface = paths[0].surface
    if isinstance(fan, Fan):
        full_circle = fan.full_circle
    else:  # a list of paths: cyclic when its angles are equally spaced around the circle
        a = np.sort(np.mod([p.angle for p in paths], 2 * np.pi))
        full_circle = len(a) >= 2 and np.allclose(np.diff(np.append(a, a[0] + 2 * np.pi)), 2 * np.pi / len(a))
    dist = np.atleast_1d(np.asarray(distances, dtype=float))
    if dist.ndim != 1 or not np.all(np.isfinite(dist)) or np.any(dist <= 0):
        raise ValueError(f"distances must be positive finite numbers; got {distances}")
    per = _v.as_positive_int(samples_per_angle, "samples_per_angle", minimum=1)
    n = len(paths)
    alpha = np.array([np.mod(p.angle, 2 * np.pi) for p in paths])
    wrap = paths[0]._wrap
    out = []
    for sL in dist:
        reached = np.array([p.length >= sL * (1 - 1e-13) for p in paths])
        nodes = np.full((n, 2), np.nan)
        for k in np.flatnonzero(reached):
            nodes[k] = paths[k]._state(np.array([min(sL, paths[k].length)]))[0, :2]
        pieces = []
        if reached.all() and n >= 3 and full_circle:
            a = np.append(alpha, alpha[0] + 2 * np.pi)
            spline = CubicSpline(a, np.vstack([nodes, nodes[:1]]), bc_type="periodic")
            fine = np.linspace(a[0], a[-1], n * per + 1)
            pieces.append(_piece(surface, wrap, sL, fine, spline(fine), closed=True))
        elif reached.all() and full_circle:
            a = np.append(alpha, alpha[0] + 2 * np.pi)
            pieces.append(_linear_piece(surface, wrap, sL, a, np.vstack([nodes, nodes[:1]]), per, closed=True))
        else:
            for run in (_runs(reached) if full_circle else _linear_runs(reached)):
                a = alpha[run] + 2 * np.pi * np.cumsum(np.r_[0, np.diff(alpha[run]) < 0])  # increasing across α = 0
                pts = nodes[run]
                if len(run) >= 4:
                    spline = CubicSpline(a, pts)
                    fine = np.linspace(a[0], a[-1], (len(run) - 1) * per + 1)
                    pieces.append(_piece(surface, wrap, sL, fine, spline(fine), closed=False))
                else:
                    pieces.append(_linear_piece(surface, wrap, sL, a, pts, per, closed=False))
        out.append(pieces)
    return out


def _linear_runs(mask):
    """Maximal runs of consecutive True entries of a (non-cyclic) boolean mask, as index arrays."""
    runs, current = [], []
    for k, m in enumerate(mask):
        if m:
            current.append(k)
        elif current:
            runs.append(np.array(current))
            current = []
    if current:
        runs.append(np.array(current))
    return runs


def _runs(mask):
    """Maximal runs of consecutive True entries of a cyclic boolean mask, as index arrays (not all True)."""
    n = len(mask)
    start = int(np.flatnonzero(~mask)[0])
    order = (np.arange(n) + start) % n  # begins at a False entry, so no run is split
    return [order[run] for run in _linear_runs(np.asarray(mask)[order])]


def _piece(surface, wrap, sL, angles, uv, closed):
    uvw = wrap(uv)
    return Isodistance(float(sL), uvw, surface.evaluate(uvw[:, 0], uvw[:, 1]), angles, closed)


def _linear_piece(surface, wrap, sL, a, pts, per, closed):
    if len(pts) == 1:
        return _piece(surface, wrap, sL, a, pts, closed)
    fine = np.linspace(a[0], a[-1], (len(a) - 1) * per + 1)
    uv = np.stack([np.interp(fine, a, pts[:, 0]), np.interp(fine, a, pts[:, 1])], axis=1)
    return _piece(surface, wrap, sL, fine, uv, closed)


# --------------------------------------------------------------------------- geodesic between two points


def geodesic_between(surface, uv_a, uv_b, *, tol=1e-9, n_candidates=4, rtol=RTOL, atol=ATOL, n_samples=201):
    r"""A geodesic from ``A = x(uv_a)`` to ``B = x(uv_b)``, by shooting on the start angle α and the length L.

    The unknowns ``(α, L)`` solve :math:`\mathbf x(u(L), v(L)) = \mathbf B`, three
    equations in the least-squares sense, by damped Gauss–Newton steps.  The
    derivative in L is the unit tangent at the end point; the one in α is a
    forward difference from a second geodesic integrated together with the
    first.  Initial guesses: the straight line from A to B projected into the
    tangent plane at A (length |AB|), and the closest approaches to B of a
    coarse fan of geodesics from A; all guesses are iterated together (one
    vectorised integration per step, see :func:`geodesic_fan`).  Of the
    converged geodesics the shortest is returned: a locally shortest path,
    and the shortest path from A to B unless all guesses missed a shorter geodesic.

    Parameters
    ----------
    surface : Surface
    uv_a, uv_b : (float, float)
        Parameters of A (a regular point) and of B, two different points.
    tol : float
        Required distance of the end point from B, relative to max(1, |AB|).
    n_candidates : int
        Number of initial guesses (the first is the tangent-plane guess).
    rtol, atol, n_samples
        As :func:`geodesic`.

    Returns
    -------
    Path
        Integrated by :func:`geodesic`; it ends at B within ``tol``, and its
        ``angle`` is the start angle α at A.

    Raises
    ------
    ValueError
        If no guess converges (e.g. every geodesic towards B leaves the domain).
    """
    surface = _check_surface(surface)
    a = _check_point(surface, uv_a, "point A")
    b = _check_point(surface, uv_b, "point B")
    n_candidates = _v.as_positive_int(n_candidates, "n_candidates", minimum=1)
    rtol, atol = _check_tolerances(rtol, atol)
    tol = _check_length(tol, "tol")
    d = _regular_derivatives(surface, *a, "point A")
    xa = d.b[0]
    xb = surface.evaluate(b[0], b[1])
    chord = float(np.linalg.norm(xb - xa))
    scale = max(1.0, chord)
    if chord <= 1e-12 * scale:
        raise ValueError(f"points A and B must be different points of the surface; got {a} and {b}")
    problem = _Problem(surface, GEODESIC)

    def shoot(alphas, lengths, rtol=rtol, atol=atol):
        """End points, unit end tangents and 'reached the length' flags of geodesics from A (one integration)."""
        alphas, lengths = np.asarray(alphas, dtype=float), np.asarray(lengths, dtype=float)
        _, duv = _direction(d, alphas)
        start = np.tile(a, (len(alphas), 1))
        pieces, s_end, _ = _integrate_fan(problem, np.concatenate([start, duv], axis=1), problem.locate(start, duv),
                                          lengths, None, rtol, atol)
        Y = np.array([p(np.array([min(L, e)]))[0] for p, L, e in zip(pieces, lengths, s_end)])
        uvw = problem.wrap(Y[:, :2])
        dd = surface.derivatives(uvw[:, 0], uvw[:, 1])
        return dd.b, dd.bu * Y[:, 2:3] + dd.bv * Y[:, 3:4], s_end >= lengths * (1 - 1e-12), pieces, s_end

    # initial guesses: the tangent plane, then the closest approaches of a coarse fan
    e1, e2, _, _ = _frame(d)
    w = xb - xa
    guesses = [(float(np.arctan2(w @ e2[0], w @ e1[0])), chord)]
    if n_candidates > 1:
        n_fan = 36
        fan_alpha = 2 * np.pi * np.arange(n_fan) / n_fan
        _, _, _, pieces, s_end = shoot(fan_alpha, np.full(n_fan, 3.0 * chord), rtol=max(rtol, 1e-6),
                                       atol=max(atol, 1e-8))
        best = []
        for k, (p, e) in enumerate(zip(pieces, s_end)):
            s = np.linspace(0, e, 200)
            uvw = problem.wrap(p(s)[:, :2])
            dist = np.linalg.norm(surface.evaluate(uvw[:, 0], uvw[:, 1]) - xb, axis=1)
            i = int(np.argmin(dist))
            best.append((dist[i], fan_alpha[k], max(s[i], 1e-3 * chord)))
        for _, alpha_k, s_k in sorted(best):
            if len(guesses) >= n_candidates:
                break
            if all(abs(np.angle(np.exp(1j * (alpha_k - g[0])))) > 3 * np.pi / n_fan for g in guesses):
                guesses.append((float(alpha_k), float(s_k)))

    x = np.array(guesses)  # (c, 2): alpha, L
    c = len(x)
    delta = 1e-6
    min_length, max_length = 1e-9 * scale, 4.0 * chord
    goal = 0.1 * tol * scale

    def residuals(x):
        k = len(x)
        pts, tangent, _, _, _ = shoot(np.r_[x[:, 0], x[:, 0] + delta], np.r_[x[:, 1], x[:, 1]])
        r = pts[:k] - xb
        J = np.stack([(pts[k:] - pts[:k]) / delta, tangent[:k]], axis=-1)  # (k, 3, 2)
        return r, J

    r, J = residuals(x)
    damping = np.ones(c)
    for _ in range(40):
        norm = np.linalg.norm(r, axis=1)
        converged = norm <= goal
        # a candidate much longer than a geodesic already found will not become the shortest
        shortest = x[converged, 1].min() if np.any(converged) else np.inf
        live = ~converged & (damping > 1e-4) & (x[:, 1] <= min(max_length, 1.5 * shortest))
        if not np.any(live):
            break
        lv = np.flatnonzero(live)
        step = np.array([np.linalg.lstsq(J[k], -r[k], rcond=None)[0] for k in lv])
        trial = x[lv] + damping[lv, None] * step
        trial[:, 1] = np.clip(trial[:, 1], min_length, 2 * max_length)
        r_t, J_t = residuals(trial)
        better = np.linalg.norm(r_t, axis=1) < norm[lv]
        kb = lv[better]
        x[kb], r[kb], J[kb] = trial[better], r_t[better], J_t[better]
        damping[lv] = np.where(better, np.minimum(1.0, 2 * damping[lv]), damping[lv] / 4)
    ok = np.linalg.norm(r, axis=1) <= tol * scale
    if np.any(ok):  # the end point must be reached, not a boundary stop that happens to lie near B
        _, _, reached, _, _ = shoot(x[ok, 0], x[ok, 1])
        ok[np.flatnonzero(ok)[~reached]] = False
    if not np.any(ok):
        raise ValueError(
            f"no geodesic from A = {a} to B = {b} found by shooting from {c} initial guesses "
            "(they leave the domain or do not converge)"
        )
    k = np.flatnonzero(ok)[np.argmin(x[ok, 1])]
    path = geodesic(surface, a, float(np.mod(x[k, 0], 2 * np.pi)), float(x[k, 1]), rtol=rtol, atol=atol,
                    n_samples=n_samples)
    miss = float(np.linalg.norm(path.points[-1] - xb))
    if path.hit_boundary or miss > tol * scale:  # pragma: no cover - the two integrators agree far below tol
        raise ValueError(f"the geodesic from A to B misses B by {miss:.3g}")
    return path
