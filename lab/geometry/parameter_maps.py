r"""Exact maps between a CAD surface's own parameters and those of its NURBS form, one direction at a time.

A cylinder, cone, sphere, torus or surface of revolution is parametrised by angles in a CAD file; its exact
NURBS form (OpenCASCADE's ``GeomConvert``, ``Convert_*ToBSplineSurface``) runs a circle arc as a rational
quadratic B-spline with the ``Convert_TgtThetaOver2`` parametrisation (``Convert_ConicToBSplineCurve.cxx``):
the arc is cut into equal spans of opening :math:`2h` (at most 150°, :math:`n = \lfloor 1.2\,\Delta/\pi\rfloor + 1`
spans over an opening :math:`\Delta`; a full periodic circle gets three spans from 0), the knots are the
angles of the span ends, and each span is the rational quadratic Bézier arc with weights
:math:`1, \cos h, 1`.  On such a span with middle angle :math:`m`, the Bézier parameter
:math:`\tau = (s - s_0)/(2h)` and the angle :math:`\theta` satisfy

.. math:: \tan\frac{\theta - m}{2} = (2\tau - 1)\,\tan\frac h2,

(put :math:`\tau = (1 + \sigma)/2` in the arc :math:`(\cos h, \mp\sin h), (1/\cos h, 0), (\cos h, \pm\sin h)`:
:math:`x = (\cos h\,(1 + \sigma^2) + 1 - \sigma^2)/2`, :math:`y = \sigma \sin h`,
:math:`w = (1 + \sigma^2 + (1 - \sigma^2)\cos h)/2` and :math:`\tan(\varphi/2) = y/(x + w) = \sigma\tan(h/2)`).
So the NURBS parameter of the angle :math:`\theta` is, with :math:`c = h/\tan(h/2)` and
:math:`T = \tan((\theta - m)/2)`,

.. math::

    s = m + c\,T, \qquad s' = \frac c2 (1 + T^2), \qquad s'' = \frac c2\,T\,(1 + T^2),

equal to :math:`\theta` at every knot.  An ellipse's angle is converted the same way; a hyperbola's
parameter (``Convert_HyperbolaToBSplineCurve``: one span, middle weight :math:`\cosh h`) the same with
``tanh`` for ``tan`` and :math:`s'' = -\frac c2 T (1 - T^2)`.  Lines, parabolas and B-spline curves keep
their parameter (identity); a Bézier curve cut to :math:`[a, b]` is re-parametrised affinely onto
:math:`[0, 1]`.  :class:`ParameterMap` is one such map, vectorised; :mod:`lab.interrogation.cad.occ`
chooses the one that reproduces the file's surface and checks it at sample points.
"""

from typing import NamedTuple

import numpy as np

from .bspline import find_span

__all__ = ["KINDS", "ParameterMap", "circle_spans"]

#: The kinds of maps, in the order they are tried.
KINDS = ("identity", "circle", "affine", "hyperbola")


def circle_spans(opening):
    """The number of spans and the half opening ``h`` that ``Convert_TgtThetaOver2`` gives an arc of ``opening``.

    ``n = trunc(1.2 opening / pi) + 1`` (spans of at most 150°), ``h = opening / (2 n)``.
    """
    n = int(np.trunc(1.2 * opening / np.pi)) + 1
    return n, opening / (2 * n)


class ParameterMap(NamedTuple):
    r"""A map :math:`t \mapsto s` from a file's parameter to its NURBS's, with its first three derivatives.

    Fields
    ------
    kind : str
        ``"identity"`` (:math:`s = t`), ``"affine"`` (:math:`s = a + b\,t`), ``"circle"`` or ``"hyperbola"``
        (see the module docstring).
    a, b : float
        ``"affine"``: offset and scale.  ``"circle"``: ``a`` is the shift added to the file's angle (a
        multiple of :math:`2\pi` when the NURBS starts a period later) and ``b`` is unused.
    origin, half : float
        ``"circle"``: the spans are :math:`[o + 2kh, o + 2(k+1)h]`; ``"hyperbola"``: the one span's middle and
        half width.
    knots : ndarray or None
        The NURBS's knot vector in this direction and ``degree`` its degree: where an angle falls on a knot,
        the map takes the span that the NURBS's evaluator takes (:func:`lab.bspline.find_span`), so that the
        second derivatives of the two agree one-sidedly.
    degree : int
    period : float
        ``"circle"`` with ``knots``, for a NURBS that covers one whole period: angles are first taken modulo
        ``period`` into the angles the NURBS covers, which start at the angle of its first knot (a face that
        winds round its axis more than once, a thread, has file parameters beyond one period; a periodic
        circle cut by ``CheckAndSegment`` at a parameter that is not a knot starts at a slightly different
        angle than the file's range); 0 for none.
    """

    kind: str = "identity"
    a: float = 0.0
    b: float = 1.0
    origin: float = 0.0
    half: float = 1.0
    knots: object = None
    degree: int = 0
    period: float = 0.0

    @classmethod
    def identity(cls):
        return cls("identity")

    @classmethod
    def affine(cls, a, b):
        """:math:`s = a + b\\,t` (``b > 0``)."""
        if not b > 0:
            raise ValueError(f"an affine parameter map must increase; got scale {b:g}")
        return cls("affine", float(a), float(b))

    @classmethod
    def circle(cls, origin, half, shift=0.0, knots=None, degree=0, period=0.0):
        """The ``TgtThetaOver2`` arcs of half opening ``half`` from ``origin``, for angles ``t + shift``."""
        if not 0 < half < np.pi / 2:
            raise ValueError(f"a circle's spans must open less than 180 degrees; got half opening {half:g}")
        if period and knots is None:
            raise ValueError("a circle map that wraps angles into one period needs the NURBS's knots")
        return cls("circle", float(shift), 1.0, float(origin), float(half),
                   None if knots is None else np.asarray(knots, dtype=float), int(degree), float(period))

    @classmethod
    def hyperbola(cls, lo, hi):
        """A hyperbola's one span ``[lo, hi]`` (``Convert_HyperbolaToBSplineCurve``)."""
        if not hi > lo:
            raise ValueError(f"a hyperbola's span must have lo < hi; got [{lo:g}, {hi:g}]")
        return cls("hyperbola", 0.0, 1.0, 0.5 * (lo + hi), 0.5 * (hi - lo))

    def __call__(self, t):
        """``(s, ds/dt, d2s/dt2)`` at the file's parameters ``t`` (arrays of ``t``'s shape)."""
        return self.derivatives(t)[:3]

    def third(self, t):
        r"""``d3s/dt3`` at ``t``: :math:`\frac c4 (1 + T^2)(1 + 3T^2)` for a circle, :math:`-\frac c4 (1 - T^2)
        (1 - 3T^2)` for a hyperbola (the derivatives of :math:`s''` with :math:`T' = (1 \pm T^2)/2`), 0 else."""
        return self.derivatives(t)[3]

    def derivatives(self, t):
        """``(s, ds/dt, d2s/dt2, d3s/dt3)`` at the file's parameters ``t`` (arrays of ``t``'s shape)."""
        t = np.asarray(t, dtype=float)
        if self.kind == "identity":
            return t, np.ones_like(t), np.zeros_like(t), np.zeros_like(t)
        if self.kind == "affine":
            return self.a + self.b * t, np.full_like(t, self.b), np.zeros_like(t), np.zeros_like(t)
        h = self.half
        if self.kind == "hyperbola":
            c = h / np.tanh(h / 2)
            T = np.tanh((t - self.origin) / 2)
            return (self.origin + c * T, 0.5 * c * (1 - T * T), -0.5 * c * T * (1 - T * T),
                    -0.25 * c * (1 - T * T) * (1 - 3 * T * T))
        theta = t + self.a
        if self.period:  # angles outside the turn the NURBS covers move by whole periods (its ends stay)
            lo = self._angle(self.knots[self.degree])
            outside = (theta < lo) | (theta > lo + self.period)
            theta = np.where(outside, lo + np.mod(theta - lo, self.period), theta)
        c = h / np.tan(h / 2)
        mid = self._middle(np.floor((theta - self.origin) / (2 * h)))
        s = mid + c * np.tan((theta - mid) / 2)
        if self.knots is not None:  # at a knot: the span of the NURBS's evaluator (s'' jumps there)
            span = find_span(self.knots, self.degree, s)
            centre = 0.5 * (self.knots[span] + self.knots[np.minimum(span + 1, len(self.knots) - 1)])
            inside = (s >= self.knots[self.degree]) & (s <= self.knots[-self.degree - 1])
            mid = np.where(inside, self._middle(np.floor((centre - self.origin) / (2 * h))), mid)
        T = np.tan((theta - mid) / 2)
        return mid + c * T, 0.5 * c * (1 + T * T), 0.5 * c * T * (1 + T * T), 0.25 * c * (1 + T * T) * (1 + 3 * T * T)

    def _middle(self, k):
        return self.origin + (2 * k + 1) * self.half

    def inverse(self, s):
        """The file's parameters ``t`` of the NURBS parameters ``s`` (in the first period of a wrapping map)."""
        s = np.asarray(s, dtype=float)
        if self.kind == "identity":
            return s.copy()
        if self.kind == "affine":
            return (s - self.a) / self.b
        h = self.half
        if self.kind == "hyperbola":
            return self.origin + 2 * np.arctanh((s - self.origin) * np.tanh(h / 2) / h)
        return self._angle(s) - self.a

    def _angle(self, s):
        """The angle of the NURBS parameter ``s`` of a circle map (equal to ``s`` at the knots)."""
        h = self.half
        mid = self._middle(np.floor((s - self.origin) / (2 * h)))
        return mid + 2 * np.arctan((s - mid) * np.tan(h / 2) / h)

    def __repr__(self):
        if self.kind == "identity":
            return "ParameterMap(identity)"
        if self.kind == "affine":
            return f"ParameterMap(affine: s = {self.a:.6g} + {self.b:.6g} t)"
        if self.kind == "hyperbola":
            return f"ParameterMap(hyperbola: span {self.origin - self.half:.6g} .. {self.origin + self.half:.6g})"
        shift = f", angle = t + {self.a:.6g}" if self.a else ""
        return f"ParameterMap(circle: spans of {np.degrees(2 * self.half):.6g} deg from {self.origin:.6g}{shift})"
