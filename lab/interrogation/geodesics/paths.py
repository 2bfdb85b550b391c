r"""Normal sections, geodesics and polar isodistance curves (Puig-Pey, Gálvez, Iglesias 2002).

A path starts at a surface point :math:`\mathbf P = \mathbf x(u_0, v_0)` in the
tangent direction of angle :math:`\alpha` (eq. 10)

.. math::
    :label: geodesics-1

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

from ...geometry import validation as _v
from ...geometry.curvature import DegeneratePointWarning, unit_normal
from ...i18n import _, decimal, number_list
from ...model.surface import Surface
from .. import export
from .faces import TRIM_SAMPLES, as_surface, check_inside, trim_ends
from .integrator import _integrate_fan, _solve_one
from .problem import (
    _BOUNDARY,
    _DEGENERATE,
    _ENDS,
    _TRIM,
    ATOL,
    GEODESIC,
    NORMAL_SECTION,
    RTOL,
    _as_angles,
    _check_length,
    _check_point,
    _check_surface,
    _check_tolerances,
    _direction,
    _fmt,
    _problem,
    _regular_derivatives,
)

__all__ = ["Fan", "Path", "geodesic", "geodesic_fan", "normal_section", "normal_section_fan"]

#: Memory a path plans for: per sample (parameters, point, tangent) and for the solver's steps (dense output).
PATH_BYTES_PER_SAMPLE, PATH_BYTES = 80, 100_000


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
        The path stopped where it left the domain (or a face's trimmed region), before the requested length.
    end : str
        Why it ended: ``"length"`` (reached it), ``"boundary"`` (the surface's domain), ``"trim"`` (a face's
        trimming loop, for paths on a :class:`lab.Face`: see :mod:`lab.interrogation.geodesics.faces`) or
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

    def _table(self):
        """One row per sample: arc length, (u, v), the point; kind, angle, origin, length and end in the header."""
        columns = {"s": self.s, "u": self.uv[:, 0], "v": self.uv[:, 1], "x": self.points[:, 0],
                   "y": self.points[:, 1], "z": self.points[:, 2]}
        length = _("length")
        units = {"s": length, "u": _("parameter"), "v": _("parameter"), "x": length, "y": length, "z": length}
        meta = {"kind": self.kind, "angle": repr(float(self.angle)), "origin": " ".join(map(repr, map(float, self.origin))),
                "length": repr(self.length), "end": self.end}
        return export.Table(_("samples of a path on the surface"), columns, units, meta)

    to_csv = export.to_csv
    to_pandas = export.to_pandas

    def __repr__(self):
        end = {"length": _("full length"), "boundary": _("hit the boundary"), "trim": _("left the face"),
               "degenerate": _("stopped at a degenerate point"), "umbilic": _("stopped before an umbilic")}
        kinds = {"geodesic": _("geodesic"), "normal-section": _("normal section"),
                 "line of curvature (k1)": _("line of curvature (k1)"), "line of curvature (k2)": _("line of curvature (k2)")}
        if not np.isfinite(self.angle):  # a line of curvature starts along a principal direction, not at an angle
            return "Path({})".format(decimal(_("{kind}, length={length}, {end}, {n} samples").format(
                kind=kinds.get(self.kind, self.kind), length=f"{self.length:.6g}", end=end.get(self.end, self.end),
                n=len(self.s))))
        return "Path({})".format(decimal(_("{kind}, angle={angle}, length={length}, {end}, {n} samples").format(
            kind=kinds.get(self.kind, self.kind), angle=f"{self.angle:.6g}", length=f"{self.length:.6g}",
            end=end.get(self.end, self.end), n=len(self.s))))


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

    def _table(self):
        """One row per path: its start angle, the length it reached, why it ended and its end point."""
        length = _("length")
        columns = {"angle": [float(p.angle) for p in self.paths], "length": [p.length for p in self.paths],
                   "end": [p.end for p in self.paths], "hit_boundary": [bool(p.hit_boundary) for p in self.paths],
                   "end_u": [float(p.uv[-1, 0]) for p in self.paths], "end_v": [float(p.uv[-1, 1]) for p in self.paths],
                   "end_x": [float(p.points[-1, 0]) for p in self.paths],
                   "end_y": [float(p.points[-1, 1]) for p in self.paths],
                   "end_z": [float(p.points[-1, 2]) for p in self.paths]}
        units = {"angle": _("radian"), "length": length, "end_u": _("parameter"), "end_v": _("parameter"),
                 "end_x": length, "end_y": length, "end_z": length}
        meta = {"kind": self.kind, "origin": " ".join(map(repr, map(float, self.origin))),
                "requested length": repr(float(self.length))}
        return export.Table(_("lengths of the paths of a fan"), columns, units, meta)

    to_csv = export.to_csv
    to_pandas = export.to_pandas

    def __repr__(self):
        kinds = {"geodesic": _("geodesics"), "normal-section": _("normal sections")}
        return "Fan({})".format(_("{n} {kind} from {origin}, length {length}, {hit} hit the boundary").format(
            n=len(self), kind=kinds.get(self.kind, f"{self.kind}s"), origin=_pair(self.origin), length=decimal(f"{self.length:g}"),
            hit=int(self.hit_boundary.sum())))


# --------------------------------------------------------------------------- public entry points


#: A path may be at most this many times the surface's size long: on a closed surface (torus, sphere) no boundary
#: ends it, and the integrator's work grows with the length (a geodesic of length 1e7 on the torus never ended;
#: 1000 took 44 s here, so 100 sizes, 870 on the default torus, stay within a minute).
MAX_LENGTH_PER_SIZE = 100
#: And at least this many: below it the arc length is rounding to the surface's coordinates (the line-of-curvature
#: integrator failed on 1e-300 with "required step size is less than spacing between numbers").
MIN_LENGTH_PER_SIZE = 1e-12


def _pair(uv):
    """``(u, v)`` as the current language writes it: "(0.5, 0.25)", in German "(0,5; 0,25)"."""
    return f"({number_list(uv)})"


def _check_length_cap(surface, L, kind):
    """Refuse a length beyond :data:`MAX_LENGTH_PER_SIZE` or below :data:`MIN_LENGTH_PER_SIZE` times the surface's
    size (its points' bounding box)."""
    (u0, u1), (v0, v1) = surface.domain
    U, V = np.meshgrid(np.linspace(u0, u1, 9), np.linspace(v0, v1, 9), indexing="ij")
    size = float(np.linalg.norm(np.ptp(surface.evaluate(U, V).reshape(-1, 3), axis=0)))
    if L < MIN_LENGTH_PER_SIZE * size:
        raise ValueError(f"length must be at least {MIN_LENGTH_PER_SIZE:g} times the surface's size ({size:.3g}), i.e. "
                         f">= {MIN_LENGTH_PER_SIZE * size:.3g}; got {L:g}: a shorter {kind} is below the rounding of its "
                         "points")
    if L > MAX_LENGTH_PER_SIZE * size:
        raise ValueError(
            f"length must be at most {MAX_LENGTH_PER_SIZE} times the surface's size ({size:.3g}), i.e. "
            f"<= {MAX_LENGTH_PER_SIZE * size:.3g}; got {L:g}: on a closed surface (a torus, a sphere) no boundary "
            f"would end the {kind} and it would wind round about {L / max(size, 1e-300):.3g} times")


def _check_paths_memory(k, n_samples, kind):
    """``n_samples`` checked, and ``k`` paths of that many samples refused before anything is allocated if too big."""
    n_samples = _v.as_positive_int(n_samples, "n_samples", minimum=2)
    _v.check_memory(k * (PATH_BYTES_PER_SAMPLE * n_samples + PATH_BYTES), f"{k} {kind}(s) of {n_samples} samples each")
    return n_samples


def _prepare(surface, uv, angles, length, kind, rtol, atol, n_samples):
    surface = _check_surface(surface)
    u0, v0 = _check_point(surface, uv, "start point")
    L = _check_length(length)
    _check_length_cap(surface, L, kind)
    rtol, atol = _check_tolerances(rtol, atol)
    n_samples = _check_paths_memory(len(angles), n_samples, kind)
    d = _regular_derivatives(surface, u0, v0, "start point")
    n, duv = _direction(d, angles)  # (k, 3), (k, 2)
    problem = _problem(surface, kind)
    k = len(angles)
    start = np.tile([u0, v0], (k, 1))
    if kind == GEODESIC:
        y0, D = np.concatenate([start, duv], axis=1), None
    else:
        N, _bad = unit_normal(d.bu, d.bv)
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
        paths.append(Path(si, uv[sl], points[sl], duv[sl], bool(stops[k] in (_BOUNDARY, _TRIM)), _ENDS[int(stops[k])],
                          float(angles[k]), problem.kind, origin, problem.surface, state, problem.wrap))
    return paths


def _single(surface, uv, angle, length, kind, rtol, atol, method, n_samples):
    alpha = _as_angles(angle)
    if alpha.ndim != 0:
        raise ValueError(f"angle must be a single number; got shape {alpha.shape} (use the *_fan functions for many)")
    surface, trim = as_surface(surface)
    problem, origin, L, rtol, atol, n_samples, y0, D, cell0 = _prepare(
        surface, uv, alpha[None], length, kind, rtol, atol, n_samples)
    check_inside(trim, origin)
    state, end, stop = _solve_one(problem, y0[0], cell0[0], L, None if D is None else D[0], rtol, atol, method)
    ends, stops = [end], [stop]
    if trim is not None:
        ends, stops = trim_ends([state], ends, stops, trim, problem.wrap, n_check=max(8 * n_samples, TRIM_SAMPLES),
                                stop_code=_TRIM)
    return _make_paths(problem, [state], ends, stops, alpha[None], origin, D, n_samples)[0]


def geodesic(surface, uv, angle, length, *, rtol=RTOL, atol=ATOL, method="DOP853", n_samples=201):
    r"""The geodesic from ``x(u0, v0)`` in the direction of angle α, by arc length (Puig-Pey et al., eqs. 11, 12, 14–17).

    .. math::

        u'' = -\Gamma^1_{11}u'^2 - 2\Gamma^1_{12}u'v' - \Gamma^1_{22}v'^2, \qquad
        v'' = -\Gamma^2_{11}u'^2 - 2\Gamma^2_{12}u'v' - \Gamma^2_{22}v'^2 \quad (11)

    with the Christoffel symbols of :func:`christoffel`, ``(u, v)(0) = (u0, v0)``
    (eq. 12) and ``(u', v')(0)`` from eqs. 14 and 16 (:func:`start_direction`).
    Solved by :func:`scipy.integrate.solve_ivp` patch by patch (see the module
    docstring); it stops exactly where it leaves the domain.

    Parameters
    ----------
    surface : Surface or lab.Face
        A surface, or a face of a model (:func:`lab.read`): the path runs on the face's surface in its (u, v)
        and stops where it leaves the face's trimmed region (``end == "trim"``; see
        :mod:`lab.interrogation.geodesics.faces`).
    uv : (float, float)
        Start point ``(u0, v0)`` in the domain (on a face: inside its trimmed region); not a degenerate point.
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
    r"""The normal section from ``x(u0, v0)`` in the direction of angle α, by arc length (Puig-Pey et al., eqs. 7–10).

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


def _fan_angles(n_angles, angles, n_samples, kind):
    """The start angles of a fan: 2πk/n, or the given increasing angles within one turn."""
    if angles is None:
        n_angles = _v.as_positive_int(n_angles, "n_angles", minimum=1)
        _check_paths_memory(n_angles, n_samples, kind)  # before the angles are allocated
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
    angles, full_circle = _fan_angles(n_angles, angles, n_samples, kind)
    n_angles = len(angles)
    surface, trim = as_surface(surface)
    problem, origin, L, rtol, atol, n_samples, y0, D, cell0 = _prepare(
        surface, uv, angles, length, kind, rtol, atol, n_samples)
    check_inside(trim, origin)
    if vectorized:
        states, ends, stops = _integrate_fan(problem, y0, cell0, L, D, rtol, atol)
    else:
        states, ends, stops = [], [], []
        for k in range(n_angles):
            state, end, stop = _solve_one(problem, y0[k], cell0[k], L, None if D is None else D[k], rtol, atol, "DOP853")
            states.append(state)
            ends.append(end)
            stops.append(stop)
    if trim is not None:
        ends, stops = trim_ends(states, ends, stops, trim, problem.wrap, n_check=max(8 * n_samples, TRIM_SAMPLES),
                                stop_code=_TRIM)
    paths = _make_paths(problem, states, ends, stops, angles, origin, D, n_samples)
    return Fan(paths, angles, origin, L, kind, problem.surface, full_circle)


def geodesic_fan(surface, uv, n_angles, length, *, angles=None, rtol=RTOL, atol=ATOL, n_samples=101, vectorized=True):
    """Geodesics from ``x(u0, v0)`` at the angles α_k = 2πk/n, k = 0 … n-1 (Puig-Pey et al., §3.2 and 4).

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
    """Normal sections from ``x(u0, v0)`` at the angles α_k = 2πk/n (Puig-Pey et al., §3.1, figure 1).

    Integrated together as in :func:`geodesic_fan`; parameters as there.
    """
    return _fan(surface, uv, n_angles, length, NORMAL_SECTION, rtol, atol, n_samples, vectorized, angles)


