"""Geodesics and normal sections as ODEs in the parameter domain (Puig-Pey et al., eqs. 7, 9-16), patch by patch.

The right-hand sides (eq. 11 with the Christoffel symbols, eq. 7 for normal
sections), the start direction of angle α (eqs. 9, 10, 14-16), and
:class:`_Problem`: a surface prepared for integration (its Bézier patches as
polynomials, cells, periodic wrap, event functions, crossings).  Also the
input checks shared by the entry points.
"""

import numpy as np

from ...geometry import validation as _v
from ...geometry.curvature import unit_normal
from ...geometry.directions import eigen as _eigen
from ...model.surface import BezierSurface, BSplineSurface, Surface, _SplineSurface
from .polynomials import _geodesic_rhs_fast, _PatchEvaluator, _regularity_fast

__all__ = ["ATOL", "RTOL", "christoffel", "start_direction"]

#: Default relative and absolute tolerances of the ODE solver (per path, as in solve_ivp).
RTOL = 1e-10
ATOL = 1e-12

GEODESIC = "geodesic"
NORMAL_SECTION = "normal section"
#: Lines of curvature of κ1 and κ2 (:mod:`.lines`).
LINES = {"k1": "line of curvature (k1)", "k2": "line of curvature (k2)"}
#: A line of curvature stops where (κ1 − κ2) / curvature scale falls below this (just before an umbilic).
_UMBILIC_STOP = 1e-6

#: A patch edge counts as crossed once a path is this far (relative to the patch width) beyond it.
#: The margin keeps a path that starts on, or runs along, a knot line from triggering a crossing.
_CROSS_MARGIN = 1e-12
#: A path stops where |b_u x b_v| / (E + G) falls below this (just before a degenerate point).
_DEGENERATE_STOP = 1e-6
_EPS = np.finfo(float).eps
#: Why a path ended (besides reaching its length); ``_TRIM``: it left a face's trimmed region (:mod:`.faces`).
_BOUNDARY, _DEGENERATE, _TRIM = 1, 2, 3
_ENDS = {0: "length", _BOUNDARY: "boundary", _DEGENERATE: "degenerate", _TRIM: "trim"}


# --------------------------------------------------------------------------- differential geometry


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def christoffel(d):
    r"""Christoffel symbols of the second kind from exact first and second derivatives.

    Puig-Pey et al. (after eq. 11) call them "first kind Christoffel symbols";
    the :math:`\Gamma^k_{ij}` of eq. 11 are those of the **second** kind (the
    first kind, :math:`\Gamma_{ijk} = \mathbf x_{ij}\cdot\mathbf x_k`, has all
    indices down).  With :math:`E_u = 2\,\mathbf x_u\cdot\mathbf x_{uu}`,
    :math:`E_v = 2\,\mathbf x_u\cdot\mathbf x_{uv}`,
    :math:`F_u = \mathbf x_{uu}\cdot\mathbf x_v + \mathbf x_u\cdot\mathbf x_{uv}`,
    :math:`F_v = \mathbf x_{uv}\cdot\mathbf x_v + \mathbf x_u\cdot\mathbf x_{vv}`,
    :math:`G_u = 2\,\mathbf x_v\cdot\mathbf x_{uv}`,
    :math:`G_v = 2\,\mathbf x_v\cdot\mathbf x_{vv}` and the denominator
    :math:`2\det\mathbf G = 2(EG - F^2)` (Struik, *Lectures on Classical Differential
    Geometry*, chapter 4, the reference [18] that Puig-Pey et al. give for eq. 11):

    .. math::

        \Gamma^1_{11} &= (G E_u - 2F F_u + F E_v)/(2\det\mathbf G), &
        \Gamma^2_{11} &= (2E F_u - E E_v - F E_u)/(2\det\mathbf G),\\
        \Gamma^1_{12} &= (G E_v - F G_u)/(2\det\mathbf G), &
        \Gamma^2_{12} &= (E G_u - F E_v)/(2\det\mathbf G),\\
        \Gamma^1_{22} &= (2G F_v - G G_u - F G_v)/(2\det\mathbf G), &
        \Gamma^2_{22} &= (E G_v - 2F F_v + F G_u)/(2\det\mathbf G).

    Computed in the equivalent form :math:`\Gamma^k_{ij} = g^{kl}\,(\mathbf x_{ij}\cdot\mathbf x_l)`,
    in which the terms that cancel above are left out (see :func:`_second_kind`).

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
    Gamma = _second_kind(d)  # (..., 3, 2): [ij = 11, 12, 22; k]
    first = np.stack([Gamma[..., 0:2, 0], Gamma[..., 1:3, 0]], -2)
    second = np.stack([Gamma[..., 0:2, 1], Gamma[..., 1:3, 1]], -2)
    return np.stack([first, second], -3)


def _christoffel_symbols(d):
    """The six distinct symbols Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂ (see :func:`christoffel`)."""
    Gamma = _second_kind(d)
    return tuple(Gamma[..., ij, k] for k in range(2) for ij in range(3))


def _second_kind(d):
    r"""Christoffel symbols of the second kind as an array ``(..., 3, 2)``: ``[..., ij, k]`` for ij = 11, 12, 22.

    Computed as :math:`\Gamma^k_{ij} = g^{kl}\,\Gamma_{l,ij}` from those of the first kind,
    :math:`\Gamma_{l,ij} = \mathbf x_{ij}\cdot\mathbf x_l` (Struik, chapter 4): the formulas of
    :func:`christoffel` with the derivatives of E, F, G written out and the terms that cancel
    left out, so two small matrix products for all points.
    """
    fields = (d.bu, d.bv, d.buu, d.buv, d.bvv)
    if any(np.shape(x) != np.shape(d.bu) for x in fields):
        fields = np.broadcast_arrays(*fields)
    return _second_kind_of(np.stack(fields, axis=-2))


def _second_kind_of(V):
    """:func:`_second_kind` from the stacked vectors ``V = (x_u, x_v, x_uu, x_uv, x_vv)``, shape ``(..., 5, 3)``."""
    tangents = V[..., :2, :]
    g = tangents @ np.swapaxes(tangents, -1, -2)  # (..., 2, 2): E, F; F, G
    first = V[..., 2:, :] @ np.swapaxes(tangents, -1, -2)  # (..., 3, 2): x_ij . x_l
    E, F, G = g[..., 0, 0], g[..., 0, 1], g[..., 1, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        inverse = np.stack([np.stack([G, -F], -1), np.stack([-F, E], -1)], -2) / (E * G - F * F)[..., None, None]
    return first @ inverse


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
    return _geodesic_rhs_of(_second_kind(d), y)


def _geodesic_rhs_of(Gamma, y):
    """Eq. 11 from the Christoffel symbols ``Gamma`` (k, 3, 2) of :func:`_second_kind`."""
    p, q = y[:, 2], y[:, 3]
    w = np.stack([p * p, 2 * p * q, q * q], axis=-1)[:, None, :]  # (k, 1, 3)
    out = np.empty_like(y)
    out[:, :2] = y[:, 2:4]
    out[:, 2:] = -(w @ Gamma)[:, 0]
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


def _line_direction(d, first):
    """Unit-speed parameter velocities ``(k, 2)`` along the principal direction of κ1 (``first``) or κ2, unoriented."""
    _, _, _, _, _, w1, w2, _ = _eigen(d)
    w = np.stack(w1 if first else w2, axis=-1)
    E, F, G = _dot(d.bu, d.bu), _dot(d.bu, d.bv), _dot(d.bv, d.bv)
    with np.errstate(invalid="ignore", divide="ignore"):
        speed = np.sqrt(E * w[:, 0] ** 2 + 2 * F * w[:, 0] * w[:, 1] + G * w[:, 1] ** 2)
        return w / speed[:, None], (E, F, G)


def _line_rhs(d, y, first, rate):
    r"""Lines of curvature for states ``y = (u, v, p, q)``: :math:`(u', v') = \pm w`, the unit principal direction,
    with the sign that agrees with the carried direction ``(p, q)``, and :math:`(p', q') = \lambda (\pm w - (p, q))`.

    The carried direction only decides the sign of the line field (which has none of its own); it follows the
    field with the relaxation rate :math:`\lambda` = ``rate`` (k, 1), so the path itself is the line of curvature
    whatever the lag.
    """
    w, (E, F, G) = _line_direction(d, first)
    p, q = y[:, 2], y[:, 3]
    agree = E * w[:, 0] * p + F * (w[:, 0] * q + w[:, 1] * p) + G * w[:, 1] * q
    w = w * np.where(agree < 0, -1.0, 1.0)[:, None]
    out = np.empty_like(y)
    out[:, :2] = w
    out[:, 2:] = rate * (w - y[:, 2:4])
    return out


def _umbilic_gap(d):
    """(κ1 − κ2) / curvature scale minus ``_UMBILIC_STOP``: negative just before an umbilic."""
    return np.nan_to_num(_eigen(d)[7], nan=0.0) - _UMBILIC_STOP


def _regularity(d):
    """|b_u x b_v| / (E + G): 1/2 for an orthonormal parametrisation, 0 at a degenerate point."""
    return np.linalg.norm(np.cross(d.bu, d.bv), axis=-1) / (_dot(d.bu, d.bu) + _dot(d.bv, d.bv))


# --------------------------------------------------------------------------- the surface, patch by patch


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
        self.m = 2 if kind == NORMAL_SECTION else 4
        (u0, u1), (v0, v1) = surface.domain
        self.lo = np.array([u0, v0], dtype=float)
        self.hi = np.array([u1, v1], dtype=float)
        self.period = self.hi - self.lo
        self.periodic = tuple(bool(p) for p in surface.periodic)
        self.patches = None
        # the patch polynomials stand in for the surface only where they are its definition
        own = type(surface)._derivatives is _SplineSurface._derivatives  # evaluation not overridden
        if own and isinstance(surface, BSplineSurface):
            nets, w, iu, iv = surface.bezier_nets()
            self.breaks = [_breaks(iu), _breaks(iv)]
        elif own and isinstance(surface, BezierSurface):
            nets = surface.control_points[None, None]
            w = None if surface.weights is None else surface.weights[None, None]
            self.breaks = [np.array([u0, u1]), np.array([v0, v1])]
        else:
            nets = None
            self.breaks = [np.array([u0, u1]), np.array([v0, v1])]
        if nets is not None:
            self.patches = _PatchEvaluator(nets, w, np.diff(self.breaks[0]), np.diff(self.breaks[1]))
        self.n_spans = np.array([len(b) - 1 for b in self.breaks])
        self._bounds_cache = (None, None)

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
        """Lower and upper unwrapped parameter of each cell: two (k, 2) arrays.

        Remembered for the last cells asked for: the stages of a step all ask for the same cells.
        """
        return self._cell_data(cell)[:2]

    def _cell_data(self, cell):
        """``(lower, upper, span, 1 / width, C)`` of the cells, remembered for the last cells asked for.

        ``C``: the patches' coefficient blocks for eq. 11 (:attr:`_PatchEvaluator.vector_coeffs`), or None.
        """
        key = (cell.shape, cell.tobytes())
        cached = self._bounds_cache  # one read: the problem is shared between threads (explorers)
        if cached[0] == key:
            return cached[1]
        lower, upper = self._cell_bounds(cell)
        span = cell.copy()
        for axis in range(2):
            if self.periodic[axis]:
                span[:, axis] = np.mod(cell[:, axis], self.n_spans[axis])
        C = None
        if self.kind == GEODESIC and self.patches is not None:
            C = self.patches.vector_coeffs[span[:, 0], span[:, 1]]
        data = (lower, upper, span, 1.0 / (upper - lower), C)
        self._bounds_cache = (key, data)
        return data

    def _cell_bounds(self, cell):
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
        V = self._fast_vectors(y, cell)
        if V is not None:  # as rhs(..., regular=True) computes it, so that the two agree to the last bit
            return _regularity_fast(V) - _DEGENERATE_STOP
        d = self.derivatives(y[:, :2], cell)
        if self.kind in LINES.values():
            return np.minimum(_regularity(d) - _DEGENERATE_STOP, _umbilic_gap(d))
        return _regularity(d) - _DEGENERATE_STOP

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
        lower, upper = self.cell_bounds(cell)
        bad = None if np.isfinite(uv).all() else ~np.all(np.isfinite(uv), axis=1)
        if bad is not None:  # a failing step: evaluate somewhere harmless, report NaN
            uv = np.where(bad[:, None], 0.5 * (lower + upper), uv)
        if self.patches is not None:
            span, local = self._local(uv, cell)
            d = self.patches(span[:, 0], span[:, 1], local[:, 0], local[:, 1])
        else:
            w = self.wrap(uv)
            d = self.surface.derivatives(w[:, 0], w[:, 1])
        if bad is not None:
            d = d.map(lambda x: np.where(bad[:, None], np.nan, x))
        return d

    def rhs(self, y, cell, D=None, regular=False):
        """Right-hand side of eq. 11 (geodesics) or eq. 7 (normal sections, plane normals ``D`` (k, 3)).

        With ``regular=True`` also the second event function :meth:`regular` at the same points.
        """
        V = self._fast_vectors(y, cell)
        if V is not None:  # the common case, in as few array operations as possible: patch polynomials -> eq. 11
            f = _geodesic_rhs_fast(V, y, regular)
            return (f[0], f[1] - _DEGENERATE_STOP) if regular else f
        d = self.derivatives(y[:, :2], cell)
        if self.kind in LINES.values():
            f = _line_rhs(d, y, self.kind == LINES["k1"], D)
            return (f, np.minimum(_regularity(d) - _DEGENERATE_STOP, _umbilic_gap(d))) if regular else f
        f = _geodesic_rhs(d, y) if self.kind == GEODESIC else _section_rhs(d, D)
        return (f, _regularity(d) - _DEGENERATE_STOP) if regular else f

    def _fast_vectors(self, y, cell):
        """``x_u, x_v, x_uu, x_uv, x_uv, x_vv`` (k, 6, 3) from the patch polynomials for geodesics, else None."""
        if self.kind != GEODESIC or self.patches is None or not np.isfinite(y[:, :2]).all():
            return None
        lower, _, _, inv_width, C = self._cell_data(cell)
        return self.patches.vectors(C, (y[:, :2] - lower) * inv_width)

    def _local(self, uv, cell):
        """The patch (span index per direction) of each cell and the local parameters in it."""
        lower, _, span, inv_width, _ = self._cell_data(cell)
        return span, (uv - lower) * inv_width

    def tangent(self, y, D=None):
        """``(du/ds, dv/ds)`` at states ``y`` (k, m), evaluated with the public surface derivatives."""
        if self.kind == GEODESIC:
            return y[:, 2:4].copy()
        w = self.wrap(y[:, :2])
        if self.kind in LINES.values():
            return _line_rhs(self.surface.derivatives(w[:, 0], w[:, 1]), y, self.kind == LINES["k1"], D)[:, :2]
        return _section_rhs(self.surface.derivatives(w[:, 0], w[:, 1]), D)


def _problem(surface, kind):
    """The :class:`_Problem` of ``surface`` for paths of ``kind``, built once per surface and reused
    (its patch polynomials cost a knot insertion per knot; see :meth:`lab.Surface.cached`)."""
    return surface.cached(f"path problem: {kind}", lambda: _Problem(surface, kind))


def _breaks(intervals):
    lo = np.array([a for a, _ in intervals])
    hi = np.array([b for _, b in intervals])
    if not np.allclose(lo[1:], hi[:-1], rtol=0, atol=1e-14 * max(1.0, abs(hi[-1]))):
        raise ValueError(f"knot spans must be contiguous; got {intervals}")  # pragma: no cover - bezier_nets guarantees it
    return np.concatenate([lo, hi[-1:]])


# --------------------------------------------------------------------------- validation


def _fmt(uv):
    return "(" + ", ".join(f"{float(x):.6g}" for x in uv) + ")"


def _check_surface(surface):
    if not isinstance(surface, Surface):
        raise TypeError(f"surface must be a lab.Surface (Bézier, B-spline or parametric); got {type(surface).__name__}")
    (u0, u1), (v0, v1) = surface.domain
    grid = np.linspace(0.0, 1.0, 5)
    with np.errstate(all="ignore"):
        points = np.asarray(surface.evaluate(u0 + (u1 - u0) * grid[:, None], v0 + (v1 - v0) * grid[None, :]))
    extent = float(np.max(np.ptp(points.reshape(-1, points.shape[-1]), axis=0))) if np.isfinite(points).all() else None
    if extent is not None and extent == 0.0:
        raise ValueError(f"surface {surface!r} is degenerate: it has zero size (all its points coincide at "
                         f"{tuple(float(x) for x in points.reshape(-1, points.shape[-1])[0])}), so it has no "
                         "tangent plane and no geodesics")
    return surface


def _check_point(surface, uv, name):
    try:
        u, v = (float(x) for x in uv)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be a pair of parameters (u, v); got {uv!r}") from None
    (u0, u1), (v0, v1) = surface.domain
    slack_u, slack_v = 1e-12 * max(1.0, u1 - u0), 1e-12 * max(1.0, v1 - v0)
    if not (np.isfinite(u) and np.isfinite(v) and u0 - slack_u <= u <= u1 + slack_u and v0 - slack_v <= v <= v1 + slack_v):
        raise ValueError(f"{name} must lie in the domain [{u0:g}, {u1:g}] x [{v0:g}, {v1:g}]; got (u, v) = ({u:g}, {v:g})")
    return min(max(u, u0), u1), min(max(v, v0), v1)


def _regular_derivatives(surface, u, v, name):
    d = surface.derivatives(np.array([u]), np.array([v]))
    bad = [field for field, x in zip(d._fields, d) if not np.all(np.isfinite(x))]
    if bad:  # a user's surface undefined there (issue 35: not a solver's RuntimeError or a hang on NaN)
        raise ValueError(
            f"{name} (u, v) = ({u:g}, {v:g}) is a degenerate point of the surface: its derivatives {', '.join(bad)} "
            "are not finite (NaN or inf: the surface is not defined or not differentiable there); choose a point "
            "where it is")
    _, degenerate = unit_normal(d.bu, d.bv)
    if degenerate[0]:
        raise ValueError(
            f"{name} (u, v) = ({u:g}, {v:g}) is a degenerate point (b_u x b_v = 0): "
            "it has no tangent plane in which to measure the angle"
        )
    return d


def _as_angles(angle):
    alpha = _v.as_array(angle, "angle", finite=False)  # radians; text ('1.5'), None, complex: TypeError
    if not np.all(np.isfinite(alpha)):
        raise ValueError(f"angle must be finite; got {angle}")
    return alpha


def _check_length(length, name="length"):
    return _v.as_number(length, name, positive=True)


def _check_tolerances(rtol, atol):
    rtol = _v.as_number(rtol, "rtol")
    if not rtol >= 100 * _EPS:
        raise ValueError(f"rtol must be a finite number >= 100 * machine epsilon ({100 * _EPS:.3g}); got {rtol}")
    return rtol, _v.as_number(atol, "atol", positive=True)


