"""Thin surface classes over the math modules: Bézier, B-spline/NURBS and analytic surfaces.

All three share one interface (:class:`Surface`): ``domain``,
``evaluate(u, v)``, ``derivatives(u, v)``, ``normal(u, v)``,
``fundamental_forms(u, v)`` and ``curvature(u, v)``; parameters broadcast
against each other and results carry the broadcast shape (plus a trailing
coordinate axis for points and vectors).
"""

import warnings
from typing import ClassVar

import numpy as np

from ..geometry import bezier, bspline
from ..geometry import curvature as _curv
from ..geometry import directions as _dirs
from ..geometry import tensor as _tensor
from ..geometry import validation as _v
from ..geometry.derivatives import THIRD, Derivatives
from ..geometry.grids import Seams
from ..i18n import N_, _
from .checks import checked_derivatives
from .patches import BezierPatches

__all__ = ["BSplineSurface", "BezierSurface", "ParametricSurface", "Surface"]


#: The lab's surface classes as people read them, for a surface without a name of its own (captions, tables).
CLASS_NAMES = {"BezierSurface": N_("Bézier surface"), "BSplineSurface": N_("B-spline surface"),
               "ParametricSurface": N_("parametric surface"), "BezierPatches": N_("Bézier patches"),
               "TrimmedSurface": N_("trimmed surface")}


def label(obj):
    """The name people read for a surface (or a model, patches …) in captions and tables, in the lab's language: its
    own ``name`` (the named surfaces of :mod:`lab.surfaces` have one: "torus", "car hood" …), else its class's
    ("B-spline surface")."""
    name = getattr(obj, "name", None)
    if isinstance(name, str) and name:
        return _(name)
    kind = type(obj).__name__
    return _(CLASS_NAMES[kind]) if kind in CLASS_NAMES else kind


class Surface:
    """Base class: everything follows from :meth:`derivatives` and :attr:`domain`.

    Evaluation runs in chunks of :data:`lab.tensor.CHUNK` points (see
    :mod:`lab.tensor`), so the temporary memory of :meth:`curvature`,
    :meth:`derivatives` and :meth:`evaluate` is bounded by the chunk size.
    When ``u`` and ``v`` form a grid (``np.meshgrid`` with either indexing,
    or an open grid such as ``u[:, None], v[None, :]``) the separable path of
    :meth:`curvature_grid` is taken by itself; spline surfaces evaluate their
    basis functions there once per u and once per v.
    """

    #: ((u_min, u_max), (v_min, v_max))
    domain = ((0.0, 1.0), (0.0, 1.0))
    #: Whether the surface closes on itself in u and in v (x(u_min, v) = x(u_max, v), ...),
    #: so that paths on it may wrap around (torus, sphere in u, cylinder in u).
    periodic = (False, False)

    #: Bytes per point that curvature, derivatives and meshes plan for (results and parameter copies).
    BYTES_PER_POINT: ClassVar[dict] = {"curvature": 80, "derivatives": 200, "directions": 160}

    def _derivatives(self, u, v):  # pragma: no cover - abstract
        """Derivatives at checked parameters of any (equal) shape."""
        raise NotImplementedError

    def _defining(self):
        """The objects that define the surface (a cached result is rebuilt when one of them is replaced)."""
        return (self.domain, self.periodic)

    def cached(self, name, build):
        """``build()``, computed once per surface and kept (evaluators, meshes for path finding).

        Surfaces are values: a result is rebuilt when an attribute that defines
        the surface (control points, knots, weights, domain, periodicity) is
        replaced, not when an array is changed in place; make a new surface
        to change one.
        """
        defining = self._defining()
        key = tuple(x if isinstance(x, tuple) else id(x) for x in defining)
        cache = self.__dict__.setdefault("_cache", {})
        entry = cache.get(name)
        if entry is None or entry[0] != key:
            entry = cache[name] = (key, defining, build())  # keeping the objects keeps their ids unique
        return entry[2]

    def _point_derivatives(self, u, v, work=None):
        """Derivatives at the flat parameters of one chunk, fields ``(k, 3)`` (spline surfaces override it)."""
        return self._derivatives(u, v)

    def _grid_blocks(self, u, v):
        """Blocks ``(rows, cols, Derivatives)`` of the grid ``u`` × ``v`` (spline surfaces override it)."""
        return _tensor.point_blocks(self._point_derivatives, u, v)

    def sample(self, func, u, v, *, grid=None, memory_limit=None, bytes_per_point=None):
        """Apply ``func`` to the derivatives at ``(u, v)`` chunk by chunk and assemble its outputs.

        Parameters
        ----------
        func : callable
            ``func(D)`` gets a :class:`~lab.derivatives.Derivatives` of one chunk
            (fields ``batch + (3,)``) and returns a tuple of arrays of shape ``batch + (...)``.
        u, v : array_like
            Parameters, broadcast against each other; or, with ``grid=True``,
            the two 1-D sides of a grid.
        grid : bool, optional
            True: ``u`` and ``v`` are the sides of a grid and the outputs have
            shape ``(len(u), len(v), ...)``.  None (default): detect a grid in
            broadcast 2-D parameters (see the class docstring).
        memory_limit : int or str, optional
            Refuse (``ValueError``) when the estimated memory exceeds it (default: :func:`lab.memory_limit`).
        bytes_per_point : int, optional
            The estimate per point (default: that of :meth:`derivatives`).

        Returns
        -------
        u, v : ndarray
            The checked parameters, broadcastable to the output shape.
        outputs : list of ndarray
        """
        per_point = self.BYTES_PER_POINT["derivatives"] if bytes_per_point is None else bytes_per_point
        if grid is None:
            found = _tensor.as_grid(u, v)
            if found is not None:
                uu, vv, transposed = found
                u_out, v_out, outputs = self.sample(func, uu, vv, grid=True, memory_limit=memory_limit,
                                                    bytes_per_point=bytes_per_point)
                if transposed:
                    return v_out.T, u_out.T, [np.swapaxes(o, 0, 1) for o in outputs]
                return u_out, v_out, outputs
        if grid:
            (lo_u, lo_v) = self.domain
            u = _v.as_parameter_vector(u, lo_u, "u")
            v = _v.as_parameter_vector(v, lo_v, "v")
            n = u.size * v.size
            _v.check_memory(n * per_point, f"evaluating the surface on a {u.size} x {v.size} grid", memory_limit)
            if n:
                outputs = _tensor.map_grid(self._grid_blocks(u, v), func, (u.size, v.size))
                return u[:, None], v[None, :], outputs
            u, v = np.broadcast_arrays(u[:, None], v[None, :])
        else:
            u, v = _v.as_parameters(u, v, self.domain)
            _v.check_memory(u.size * per_point, f"evaluating the surface at {u.size} points", memory_limit)
        return u, v, self._map_points(func, u, v)

    def _map_points(self, func, u, v):
        """``func`` applied chunk by chunk to the derivatives at the checked points ``u``, ``v`` (equal shapes)."""
        return _tensor.map_points(self._point_derivatives, func, u, v)

    def derivatives(self, u, v):
        """Point and partial derivatives ``b, bu, bv, buu, buv, bvv`` (shape ``broadcast(u, v).shape + (3,)``)."""
        _, _, fields = self.sample(tuple, u, v)
        return Derivatives(*fields)

    def third_derivatives(self, u, v):
        """The third partial derivatives ``(buuu, buuv, buvv, bvvv)``, each of shape ``broadcast(u, v).shape + (3,)``:
        what G3 across an edge compares (:func:`lab.continuity`).  Spline surfaces and their reparametrizations
        (a CAD model's faces) have them exactly; other surfaces raise :class:`NotImplementedError`."""
        raise NotImplementedError(f"{type(self).__name__} has no third derivatives")

    def evaluate(self, u, v):
        """Surface points, shape ``broadcast(u, v).shape + (3,)``."""
        _, _, (b,) = self.sample(lambda d: (d.b,), u, v, bytes_per_point=60)
        return b

    def normal(self, u, v):
        """Unit normal ``b_u x b_v / |b_u x b_v|``; at degenerate points (a pole) its limit from inside, with a
        :class:`~lab.curvature.DegeneratePointWarning` (see :func:`lab.curvature.normal_limits`)."""
        u, v, (N, degenerate) = self.sample(lambda d: _curv.unit_normal(d.bu, d.bv), u, v, bytes_per_point=61)
        return _curv.normal_limits(N, degenerate, u, v, self.centre, self._derivatives)

    def fundamental_forms(self, u, v):
        """First and second fundamental forms, see :func:`lab.curvature.fundamental_forms`; at degenerate points
        ``e, f, g`` and ``N`` are taken with the limit of the normal (:meth:`normal`)."""
        return _curv.fundamental_forms(self.derivatives(u, v), N=self.normal(u, v))

    @property
    def centre(self):
        """Centre of the parameter domain."""
        (u0, u1), (v0, v1) = self.domain
        return 0.5 * (u0 + u1), 0.5 * (v0 + v1)

    def curvature(self, u, v, *, directions=False, memory_limit=None):
        """Gaussian, mean and principal curvatures (see :mod:`lab.curvature`).

        With ``directions=True`` also the unit principal directions ``d1, d2``
        (3-vectors of κ1 and κ2, from the Weingarten map: see
        :mod:`lab.geometry.directions`) and the ``umbilic`` mask; at umbilics
        (κ1 = κ2) and degenerate points the directions are NaN and flagged.

        At degenerate points (``b_u x b_v = 0``) the values are the limits
        approached from inside the domain, the ``degenerate`` mask is set and a
        :class:`~lab.curvature.DegeneratePointWarning` is issued.  Grids take
        the separable path of :meth:`curvature_grid` (see the class docstring).

        Returns
        -------
        Curvature or CurvatureDirections
            Fields ``K, H, k1, k2, degenerate`` of shape ``broadcast(u, v).shape``; with
            ``directions=True`` also ``d1, d2`` (shape ``... + (3,)``) and ``umbilic``.
        """
        if directions:
            return self._directions(u, v, None, memory_limit)
        return self._curvature(u, v, None, memory_limit)

    def curvature_grid(self, u, v, *, memory_limit=None):
        """Curvature on the grid ``u`` × ``v`` (1-D arrays): fields of shape ``(len(u), len(v))``.

        The same values as ``curvature(*np.meshgrid(u, v, indexing="ij"))``;
        spline surfaces evaluate their basis functions once per u and once per v
        and gather the control points once per pair of knot spans.
        """
        return self._curvature(u, v, True, memory_limit)

    def _curvature(self, u, v, grid, memory_limit):
        u, v, fields = self.sample(_curv.from_derivatives, u, v, grid=grid, memory_limit=memory_limit,
                                   bytes_per_point=self.BYTES_PER_POINT["curvature"])
        curv = _curv.Curvature(*fields)
        return _curv.with_limits(curv, u, v, self.centre, lambda index, uu, vv: self._derivatives(uu, vv))

    def _directions(self, u, v, grid, memory_limit):
        u, v, fields = self.sample(_dirs.from_derivatives, u, v, grid=grid, memory_limit=memory_limit,
                                   bytes_per_point=self.BYTES_PER_POINT["directions"])
        curv = _curv.with_limits(_curv.Curvature(*fields[:5]), u, v, self.centre,
                                 lambda index, uu, vv: self._derivatives(uu, vv))
        return _dirs.CurvatureDirections(*curv, *fields[5:])

    def sample_grid(self, u, v, *, memory_limit=None):
        """Points, unit normals and curvature on the grid ``u`` × ``v`` in one pass (what a mesh needs).

        Returns
        -------
        b : ndarray, shape ``(len(u), len(v), 3)``
        N : ndarray, shape ``(len(u), len(v), 3)``
            ``b_u x b_v / |b_u x b_v|``, NaN at degenerate points.
        curvature : Curvature
            As :meth:`curvature_grid`, degenerate points filled with their limits.
        """
        return self._sample_mesh(u, v, True, memory_limit)

    def sample_points(self, u, v, *, memory_limit=None):
        """Points, unit normals and curvature at the points ``(u, v)`` in one pass (a triangle mesh's vertices).

        As :meth:`sample_grid` with ``u``, ``v`` broadcast against each other; fields of shape
        ``broadcast(u, v).shape`` (plus ``(3,)`` for ``b`` and ``N``).
        """
        return self._sample_mesh(u, v, False, memory_limit)

    def _sample_mesh(self, u, v, grid, memory_limit):
        def fields(d):
            N, _ = _curv.unit_normal(d.bu, d.bv)
            return (d.b, N, *_curv.from_derivatives(d))

        u, v, (b, N, *curv) = self.sample(fields, u, v, grid=grid, memory_limit=memory_limit,
                                          bytes_per_point=self.BYTES_PER_POINT["curvature"] + 48)
        curv = _curv.with_limits(_curv.Curvature(*curv), u, v, self.centre,
                                 lambda index, uu, vv: self._derivatives(uu, vv))
        return b, N, curv

    @property
    def seams(self):
        """Where the surface closes on itself or collapses: a :class:`lab.grids.Seams`.

        ``periodic`` is :attr:`periodic`; an edge counts as collapsed when the
        surface evaluated at 17 parameters along it gives one point exactly
        (spline surfaces look at their control points instead, see there).
        Meshes weld their grid nodes by these indices, never by distance.
        """
        collapsed = []
        for axis in (0, 1):
            ends = []
            for end in self.domain[axis]:
                t = np.linspace(*self.domain[1 - axis], 17)
                u, v = (np.full_like(t, end), t) if axis == 0 else (t, np.full_like(t, end))
                points = self._derivatives(u, v).b
                ends.append(bool(np.all(points == points[:1])))
            collapsed.append(tuple(ends))
        return Seams(tuple(bool(p) for p in self.periodic), tuple(collapsed))

    def grid(self, nu, nv, *, memory_limit=None):
        """Parameter grid ``(u, v)`` of shape ``(nu, nv)`` covering the domain, ends included."""
        nu = _v.as_positive_int(nu, "nu", minimum=2)
        nv = _v.as_positive_int(nv, "nv", minimum=2)
        _v.check_memory(16 * nu * nv, f"a {nu} x {nv} parameter grid", memory_limit)
        (u0, u1), (v0, v1) = self.domain
        return np.meshgrid(np.linspace(u0, u1, nu), np.linspace(v0, v1, nv), indexing="ij")


class _SplineSurface(Surface):
    """Shared evaluation of Bézier and B-spline surfaces: the chunked tensor-product paths of :mod:`lab.tensor`."""

    def _spline_args(self):  # pragma: no cover - abstract
        raise NotImplementedError

    def _defining(self):
        return self._spline_args() + (self.domain, self.periodic)

    def _spline(self):
        """The :class:`lab.tensor.Spline` of this surface, built once."""
        return self.cached("spline", lambda: _tensor.spline(*self._spline_args()))

    def _point_derivatives(self, u, v, work=None):
        return _tensor.point_derivatives(self._spline(), u, v, work)

    def _grid_blocks(self, u, v):
        return _tensor.grid_blocks(self._spline(), u, v)

    def _map_points(self, func, u, v):
        return _tensor.map_spline_points(self._spline(), func, u, v)

    @property
    def seams(self):
        """As :attr:`Surface.seams`; an edge counts as collapsed when the knots are clamped there and the
        control points of the edge's row are all the same point (then the edge, a spline curve of that row, is it)."""
        P, knots_u, knots_v, p, q, _ = self._spline_args()
        collapsed = []
        for axis, (knots, degree) in enumerate(((knots_u, p), (knots_v, q))):
            rows = (P[0], P[-1]) if axis == 0 else (P[:, 0], P[:, -1])
            clamped = (np.all(knots[: degree + 1] == knots[0]), np.all(knots[-degree - 1 :] == knots[-1]))
            collapsed.append(tuple(bool(c and np.all(r == r[:1])) for c, r in zip(clamped, rows)))
        return Seams(tuple(bool(x) for x in self.periodic), tuple(collapsed))

    def _derivatives(self, u, v):
        return Derivatives(*_tensor.map_points(self._point_derivatives, tuple, u, v))

    def third_derivatives(self, u, v):
        """As :meth:`Surface.third_derivatives`: exact, from the basis functions' third derivatives (a point on a
        knot line takes the span after it, as every evaluator of the lab does)."""
        u, v = _v.as_parameters(u, v, self.domain)
        P, knots_u, knots_v, p, q, weights = self._spline_args()
        _v.check_memory(u.size * 8 * (4 * (p + 1) * (q + 1) + 64), f"third derivatives at {u.size} points", None)
        S = bspline.partial_derivatives(P, knots_u, knots_v, p, q, weights, u, v, 3)
        return tuple(S[k].reshape(u.shape + (3,)) for k in THIRD)


class BezierSurface(_SplineSurface):
    r"""A tensor-product (rational) Bézier patch over ``[0, 1]^2``.

    Parameters
    ----------
    P : (m+1, n+1, 3) array_like
        Control net :math:`\mathbf b_{ij}`, first index along ``u``.
    weights : (m+1, n+1) array_like, optional
        Positive weights; makes the patch rational.
    """

    def __init__(self, P, weights=None):
        self.control_points = _v.as_control_net(P)
        self.weights = _v.as_weights(weights, self.control_points.shape[:2])

    @property
    def degree(self):
        """Degrees ``(m, n)`` in u and v."""
        return self.control_points.shape[0] - 1, self.control_points.shape[1] - 1

    def _spline_args(self):
        m, n = self.degree
        if getattr(self, "_bezier_knots", (None,))[0] != (m, n):  # a Bézier patch is a spline with one span
            self._bezier_knots = ((m, n), np.repeat([0.0, 1.0], m + 1), np.repeat([0.0, 1.0], n + 1))
        return self.control_points, self._bezier_knots[1], self._bezier_knots[2], m, n, self.weights

    def swap_uv(self):
        """The same patch with u and v exchanged: the orientation (and the sign of H) flips (practical 2.2)."""
        w = None if self.weights is None else self.weights.T
        return BezierSurface(self.control_points.transpose(1, 0, 2), w)

    def to_bezier_patches(self):
        """A :class:`lab.BezierPatches` holding this one patch."""
        w = None if self.weights is None else self.weights[None]
        return BezierPatches(self.control_points[None], w, grid_shape=(1, 1), seams=self.seams)

    def __repr__(self):
        text = _("rational, degree {degree}") if self.weights is not None else _("degree {degree}")
        return f"BezierSurface({text.format(degree=self.degree)})"


class BSplineSurface(_SplineSurface):
    """A tensor-product B-spline or NURBS surface.

    Parameters
    ----------
    P : (nu, nv, 3) array_like
        Control net, first index along ``u``.
    knots_u, knots_v : array_like
        Knot vectors, lengths ``nu + degree_u + 1`` and ``nv + degree_v + 1``;
        clamped or unclamped.
    degree_u, degree_v : int
    weights : (nu, nv) array_like, optional
        Positive weights (NURBS).
    """

    def __init__(self, P, knots_u, knots_v, degree_u, degree_v, weights=None):
        self.control_points = _v.as_control_net(P)
        nu, nv = self.control_points.shape[:2]
        self.degree = (
            _v.as_positive_int(degree_u, "degree_u", minimum=1),
            _v.as_positive_int(degree_v, "degree_v", minimum=1),
        )
        self.knots_u = bspline.validate_knots(knots_u, self.degree[0], nu, "knot vector in u")
        self.knots_v = bspline.validate_knots(knots_v, self.degree[1], nv, "knot vector in v")
        self.weights = _v.as_weights(weights, (nu, nv))
        self.domain = (bspline.domain(self.knots_u, self.degree[0]), bspline.domain(self.knots_v, self.degree[1]))

    def _args(self):
        return (self.control_points, self.knots_u, self.knots_v, *self.degree)

    def _spline_args(self):
        return (*self._args(), self.weights)

    def insert_knot(self, t, direction="u", times=1):
        """A new surface with the knot ``t`` inserted ``times`` times in ``direction`` ('u' or 'v')."""
        direction = _v.as_choice(direction, ("u", "v"), "direction")
        times = _v.as_positive_int(times, "times", minimum=1)
        axis = 0 if direction == "u" else 1
        knots = self.knots_u if axis == 0 else self.knots_v
        Pw = bezier.homogeneous(self.control_points, self.weights)
        Pw, knots = bspline.insert_knot(Pw, knots, self.degree[axis], _v.as_number(t, "t"), times=times, axis=axis)
        P, w = (Pw, None) if self.weights is None else bezier.dehomogenize(Pw)
        ku, kv = (knots, self.knots_v) if axis == 0 else (self.knots_u, knots)
        return BSplineSurface(P, ku, kv, *self.degree, weights=w)

    def swap_uv(self):
        """The same surface with u and v exchanged: the orientation (and the sign of H) flips (practical 2.2)."""
        w = None if self.weights is None else self.weights.T
        return BSplineSurface(self.control_points.transpose(1, 0, 2), self.knots_v, self.knots_u,
                              self.degree[1], self.degree[0], weights=w)

    def bezier_nets(self):
        """Bézier nets per knot span: see :func:`lab.bspline.to_bezier`."""
        return bspline.to_bezier(*self._args(), self.weights)

    def to_bezier_patches(self):
        """One Bézier patch per non-empty knot span, as a :class:`lab.BezierPatches` (practical, section 5)."""
        nets, w, _, _ = self.bezier_nets()
        flat_w = None if w is None else w.reshape((-1,) + w.shape[2:])
        return BezierPatches(nets.reshape((-1,) + nets.shape[2:]), flat_w, grid_shape=nets.shape[:2], seams=self.seams)

    def __repr__(self):
        kind = "NURBS" if self.weights is not None else "B-spline"
        nu, nv = self.control_points.shape[:2]
        return "BSplineSurface({})".format(_("{kind}, {nu}x{nv} control points, degree {degree}").format(
            kind=kind, nu=nu, nv=nv, degree=self.degree))


class ParametricSurface(Surface):
    """A surface given by a function that returns its derivatives.

    Usually built with :meth:`from_sympy`, which differentiates symbolic
    coordinate functions exactly and evaluates them with NumPy.

    Parameters
    ----------
    derivatives : callable
        ``derivatives(u, v)`` with broadcast float arrays, returning a
        :class:`~lab.derivatives.Derivatives` with fields of shape ``u.shape + (3,)``.
    domain : ((float, float), (float, float))
    """

    def __init__(self, derivatives, domain, name=CLASS_NAMES["ParametricSurface"]):
        if not callable(derivatives):
            raise TypeError(f"derivatives must be callable; got {type(derivatives).__name__}")
        self._func = derivatives
        self.domain = _check_domain(domain)
        self.name = name
        self.expressions = None
        self.parameters = None

    @classmethod
    def from_sympy(cls, xyz, uv, domain, name=CLASS_NAMES["ParametricSurface"]):
        """Analytic surface from sympy expressions.

        Parameters
        ----------
        xyz : sequence of three sympy expressions
            Coordinates ``x(u, v), y(u, v), z(u, v)``.
        uv : (Symbol, Symbol)
            The parameters.
        domain : ((u_min, u_max), (v_min, v_max))
            May contain sympy numbers such as ``pi``.

        Examples
        --------
        >>> import sympy as sp
        >>> u, v = sp.symbols("u v", real=True)
        >>> s = ParametricSurface.from_sympy((u, v, u**2 + v**2), (u, v), ((-1, 1), (-1, 1)))
        >>> round(float(s.curvature(0.0, 0.0).K), 12)
        4.0
        """
        import sympy as sp

        if len(xyz) != 3:
            raise ValueError(f"xyz must hold three coordinate expressions; got {len(xyz)}")
        u, v = uv
        try:
            X = sp.Matrix([sp.sympify(c, strict=True) for c in xyz])
        except (sp.SympifyError, TypeError, ValueError):
            raise TypeError(f"xyz must hold three sympy expressions (or numbers); got {xyz!r}") from None
        free = sorted(map(str, X.free_symbols - {u, v}))
        if free:
            raise ValueError(f"xyz may depend only on the parameters {u} and {v}; got the free symbol(s) "
                             f"{', '.join(free)}: substitute a number for each (expr.subs({free[0]}, 1))")
        undefined = sorted(map(str, X.atoms(sp.core.function.AppliedUndef)))
        if undefined:
            raise ValueError(f"xyz must be explicit expressions in {u} and {v}; got undefined {', '.join(undefined)}")
        exprs = [X, X.diff(u), X.diff(v), X.diff(u, 2), X.diff(u).diff(v), X.diff(v, 2)]
        funcs = [sp.lambdify((u, v), list(e), modules="numpy") for e in exprs]

        def derivs(uu, vv):
            fields = []
            with np.errstate(all="ignore"):  # poles and overflow become inf/NaN, reported by _derivatives
                for f in funcs:
                    comps = [np.broadcast_to(np.asarray(c, dtype=float), uu.shape) for c in f(uu, vv)]
                    fields.append(np.stack(comps, axis=-1))
            return Derivatives(*fields)

        try:
            dom = tuple(tuple(float(sp.N(x)) for x in pair) for pair in domain)
        except (TypeError, ValueError, AttributeError, sp.SympifyError):
            raise TypeError(f"domain must be ((u_min, u_max), (v_min, v_max)), numbers or sympy numbers such as "
                            f"pi; got {domain!r}") from None
        surface = cls(derivs, dom, name=name)
        surface.expressions = X
        surface.parameters = (u, v)
        return surface

    def _derivatives(self, u, v):
        d = checked_derivatives(self._func(u, v), np.shape(u), self.name)
        with np.errstate(invalid="ignore"):  # NaN compares False: not usable
            usable = np.all(np.abs(np.concatenate(d, axis=-1)) <= _v.COORDINATE_MAX, axis=-1)
        if not np.all(usable):
            k = np.unravel_index(np.flatnonzero(~usable)[0], usable.shape)
            u0, v0 = np.broadcast_to(u, usable.shape)[k], np.broadcast_to(v, usable.shape)[k]
            warnings.warn(
                f"{self.name}: the derivatives are not finite at {int(np.count_nonzero(~usable))} of {usable.size} "
                f"point(s), e.g. (u, v) = ({u0:.6g}, {v0:.6g}): the function is not defined or not differentiable "
                f"there (or its derivatives exceed {_v.COORDINATE_MAX:g}, where the fundamental forms overflow); "
                "curvature there is NaN and marked in the 'degenerate' mask", _curv.DegeneratePointWarning,
                stacklevel=3)
            d = d.map(lambda x: np.where(usable[..., None], x, np.nan))  # inf would make numpy warn later
        return d

    def _defining(self):
        return (self._func, self.domain, self.periodic)

    def __repr__(self):
        return f"ParametricSurface({self.name}, domain={self.domain})"


def _check_domain(domain):
    try:
        (u0, u1), (v0, v1) = domain
        dom = ((float(u0), float(u1)), (float(v0), float(v1)))
    except (TypeError, ValueError, OverflowError):  # (an int beyond the float range)
        raise ValueError(f"domain must be ((u_min, u_max), (v_min, v_max)) of finite numbers; got "
                         f"{_v._short(domain)}") from None
    for name, (a, b) in zip("uv", dom):
        if not (np.isfinite(a) and np.isfinite(b) and a < b):
            raise ValueError(f"domain in {name} must be a finite interval with min < max; got ({a}, {b})")
    return dom
