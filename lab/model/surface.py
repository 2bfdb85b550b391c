"""Thin surface classes over the math modules: Bézier, B-spline/NURBS and analytic surfaces.

All three share one interface (:class:`Surface`): ``domain``,
``evaluate(u, v)``, ``derivatives(u, v)``, ``normal(u, v)``,
``fundamental_forms(u, v)`` and ``curvature(u, v)``; parameters broadcast
against each other and results carry the broadcast shape (plus a trailing
coordinate axis for points and vectors).
"""

import numpy as np

from ..geometry import bezier, bspline
from ..geometry import curvature as _curv
from ..geometry import validation as _v
from ..geometry.derivatives import Derivatives
from .patches import BezierPatches

__all__ = ["Surface", "BezierSurface", "BSplineSurface", "ParametricSurface"]


class Surface:
    """Base class: everything follows from :meth:`derivatives` and :attr:`domain`."""

    #: ((u_min, u_max), (v_min, v_max))
    domain = ((0.0, 1.0), (0.0, 1.0))
    #: Whether the surface closes on itself in u and in v (x(u_min, v) = x(u_max, v), ...),
    #: so that paths on it may wrap around (torus, sphere in u, cylinder in u).
    periodic = (False, False)

    def _derivatives(self, u, v):  # pragma: no cover - abstract
        raise NotImplementedError

    def derivatives(self, u, v):
        """Point and partial derivatives ``b, bu, bv, buu, buv, bvv`` (shape ``broadcast(u, v).shape + (3,)``)."""
        u, v = _v.as_parameters(u, v, self.domain)
        return self._derivatives(u, v)

    def evaluate(self, u, v):
        """Surface points, shape ``broadcast(u, v).shape + (3,)``."""
        return self.derivatives(u, v).b

    def normal(self, u, v):
        """Unit normal ``b_u x b_v / |b_u x b_v|`` (NaN at degenerate points)."""
        d = self.derivatives(u, v)
        return _curv.unit_normal(d.bu, d.bv)[0]

    def fundamental_forms(self, u, v):
        """First and second fundamental forms, see :func:`lab.curvature.fundamental_forms`."""
        return _curv.fundamental_forms(self.derivatives(u, v))

    @property
    def centre(self):
        """Centre of the parameter domain."""
        (u0, u1), (v0, v1) = self.domain
        return 0.5 * (u0 + u1), 0.5 * (v0 + v1)

    def curvature(self, u, v):
        """Gaussian, mean and principal curvatures (see :mod:`lab.curvature`).

        At degenerate points (``b_u x b_v = 0``) the values are the limits
        approached from inside the domain, the ``degenerate`` mask is set and a
        :class:`~lab.curvature.DegeneratePointWarning` is issued.

        Returns
        -------
        Curvature
            Fields ``K, H, k1, k2, degenerate`` of shape ``broadcast(u, v).shape``.
        """
        u, v = _v.as_parameters(u, v, self.domain)
        curv = _curv.from_derivatives(self._derivatives(u, v))
        return _curv.with_limits(curv, u, v, self.centre, lambda index, uu, vv: self._derivatives(uu, vv))

    def grid(self, nu, nv):
        """Parameter grid ``(u, v)`` of shape ``(nu, nv)`` covering the domain, ends included."""
        nu = _v.as_positive_int(nu, "nu", minimum=2)
        nv = _v.as_positive_int(nv, "nv", minimum=2)
        (u0, u1), (v0, v1) = self.domain
        return np.meshgrid(np.linspace(u0, u1, nu), np.linspace(v0, v1, nv), indexing="ij")


class BezierSurface(Surface):
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

    def _derivatives(self, u, v):
        return bezier.derivatives(self.control_points, u, v, self.weights)

    def swap_uv(self):
        """The same patch with u and v exchanged: the orientation (and the sign of H) flips (practical 2.2)."""
        w = None if self.weights is None else self.weights.T
        return BezierSurface(self.control_points.transpose(1, 0, 2), w)

    def to_bezier_patches(self):
        """A :class:`lab.BezierPatches` holding this one patch."""
        w = None if self.weights is None else self.weights[None]
        return BezierPatches(self.control_points[None], w, grid_shape=(1, 1))

    def __repr__(self):
        kind = "rational " if self.weights is not None else ""
        return f"BezierSurface({kind}degree {self.degree})"


class BSplineSurface(Surface):
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

    def _derivatives(self, u, v):
        return bspline.derivatives(*self._args(), u, v, self.weights)

    def insert_knot(self, t, direction="u", times=1):
        """A new surface with the knot ``t`` inserted ``times`` times in ``direction`` ('u' or 'v')."""
        direction = _v.as_choice(direction, ("u", "v"), "direction")
        times = _v.as_positive_int(times, "times", minimum=1)
        axis = 0 if direction == "u" else 1
        knots = self.knots_u if axis == 0 else self.knots_v
        Pw = bezier.homogeneous(self.control_points, self.weights)
        Pw, knots = bspline.insert_knot(Pw, knots, self.degree[axis], float(t), times=times, axis=axis)
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
        nets, w, iu, iv = self.bezier_nets()
        flat_w = None if w is None else w.reshape((-1,) + w.shape[2:])
        return BezierPatches(nets.reshape((-1,) + nets.shape[2:]), flat_w, grid_shape=nets.shape[:2])

    def __repr__(self):
        kind = "NURBS" if self.weights is not None else "B-spline"
        nu, nv = self.control_points.shape[:2]
        return f"BSplineSurface({kind}, {nu}x{nv} control points, degree {self.degree})"


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

    def __init__(self, derivatives, domain, name="parametric surface"):
        if not callable(derivatives):
            raise TypeError(f"derivatives must be callable; got {type(derivatives).__name__}")
        self._func = derivatives
        self.domain = _check_domain(domain)
        self.name = name
        self.expressions = None
        self.parameters = None

    @classmethod
    def from_sympy(cls, xyz, uv, domain, name="parametric surface"):
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
        X = sp.Matrix([sp.sympify(c) for c in xyz])
        exprs = [X, X.diff(u), X.diff(v), X.diff(u, 2), X.diff(u).diff(v), X.diff(v, 2)]
        funcs = [sp.lambdify((u, v), list(e), modules="numpy") for e in exprs]

        def derivs(uu, vv):
            fields = []
            for f in funcs:
                comps = [np.broadcast_to(np.asarray(c, dtype=float), uu.shape) for c in f(uu, vv)]
                fields.append(np.stack(comps, axis=-1))
            return Derivatives(*fields)

        dom = tuple(tuple(float(sp.N(x)) for x in pair) for pair in domain)
        surface = cls(derivs, dom, name=name)
        surface.expressions = X
        surface.parameters = (u, v)
        return surface

    def _derivatives(self, u, v):
        return self._func(u, v)

    def __repr__(self):
        return f"ParametricSurface({self.name}, domain={self.domain})"


def _check_domain(domain):
    try:
        (u0, u1), (v0, v1) = domain
        dom = ((float(u0), float(u1)), (float(v0), float(v1)))
    except (TypeError, ValueError):
        raise ValueError(f"domain must be ((u_min, u_max), (v_min, v_max)); got {domain!r}") from None
    for name, (a, b) in zip("uv", dom):
        if not (np.isfinite(a) and np.isfinite(b) and a < b):
            raise ValueError(f"domain in {name} must be a finite interval with min < max; got ({a}, {b})")
    return dom
