r"""Exact curvature references with sympy: the ground truth of tests and checks.

Two kinds of input:

* symbolic surfaces :math:`\mathbf x(u, v)` (sympy expressions), differentiated
  exactly (:func:`curvature_exprs`, :func:`exact_curvature`);
* Bézier nets with rational coordinates (any float is a binary rational, so
  every float net is one), evaluated in exact rational arithmetic
  (:func:`bezier_curvature_exact`, :func:`bezier_corner_curvature_exact`).

With :math:`\mathbf Q = \mathbf b_u\times\mathbf b_v`, :math:`q = |\mathbf Q|^2 = EG - F^2`
and :math:`A, B, C = \mathbf Q\cdot(\mathbf b_{uu}, \mathbf b_{uv}, \mathbf b_{vv})`
(Dill 1981, appendix)

.. math::

    K = \frac{AC - B^2}{q^2},\qquad H = \frac{AG - 2BF + CE}{2\,q^{3/2}},\qquad
    \kappa_{1,2} = H \pm\sqrt{H^2 - K},

so for a rational net ``K`` and ``H^2 - K`` are exact rational numbers, and
``H``, :math:`\kappa_{1,2}` need one square root each, which is taken to
:data:`SQRT_DIGITS` significant digits (mpmath).
"""

from fractions import Fraction
from math import comb
from typing import NamedTuple

import mpmath
import numpy as np
import sympy as sp

from .derivatives import Derivatives, from_homogeneous

#: Significant digits of the square roots in exact curvature of rational nets.
SQRT_DIGITS = 50

__all__ = [
    "ExactCurvature",
    "bezier_corner_curvature_exact",
    "bezier_curvature_exact",
    "bezier_derivatives_exact",
    "curvature_exprs",
    "curvature_from_derivatives",
    "exact_curvature",
    "random_rational_net",
    "to_float",
]


class ExactCurvature(NamedTuple):
    """Exact ``K, H, k1, k2`` as sympy numbers or expressions."""

    K: sp.Expr
    H: sp.Expr
    k1: sp.Expr
    k2: sp.Expr


def curvature_from_derivatives(bu, bv, buu, buv, bvv):
    """Exact curvature from exact first and second derivatives (sympy 3-vectors).

    Raises ``ValueError`` at a degenerate point (``b_u x b_v = 0``), where the
    formulas have no value.
    """
    bu, bv, buu, buv, bvv = (sp.Matrix(x) for x in (bu, bv, buu, buv, bvv))
    Q = bu.cross(bv)
    q = Q.dot(Q)
    if q == 0:
        raise ValueError("degenerate point: b_u x b_v = 0, the curvature formulas have no value there")
    E, F, G = bu.dot(bu), bu.dot(bv), bv.dot(bv)
    A, B, C = Q.dot(buu), Q.dot(buv), Q.dot(bvv)
    K = (A * C - B**2) / q**2
    num = A * G - 2 * B * F + C * E
    disc = num**2 / (4 * q**3) - K
    if q.is_Rational and num.is_Rational:
        # K and H^2 - K are exact rationals; H and the root are one square root each, taken to
        # SQRT_DIGITS significant digits with mpmath.  (sympy's exact sqrt of a huge rational factors
        # it to pull out squares: slow, and for some numbers it fails inside sympy's factorint.)
        with mpmath.workdps(SQRT_DIGITS + 10):
            H = sp.Float(mpmath.mpf(num.p) / mpmath.mpf(num.q) / (2 * _mp_sqrt(q) ** 3), SQRT_DIGITS)
            root = sp.Float(_mp_sqrt(disc) if disc > 0 else 0, SQRT_DIGITS)
    else:
        H = num / (2 * q * sp.sqrt(q))
        root = sp.sqrt(disc)
    return ExactCurvature(K, H, H + root, H - root)


def _mp_sqrt(r):
    return mpmath.sqrt(mpmath.mpf(r.p) / mpmath.mpf(r.q))


def curvature_exprs(xyz, uv):
    """Symbolic ``K, H, k1, k2`` of the surface ``xyz`` in the parameters ``uv`` (not simplified)."""
    X = sp.Matrix([sp.sympify(c) for c in xyz])
    u, v = uv
    return curvature_from_derivatives(X.diff(u), X.diff(v), X.diff(u, 2), X.diff(u).diff(v), X.diff(v, 2))


def exact_curvature(xyz, uv, point):
    """Exact curvature of a symbolic surface at a point (substituted before the algebra).

    Parameters
    ----------
    xyz : sequence of three sympy expressions
    uv : (Symbol, Symbol)
    point : (number, number)
        Exact values are kept exact (use ``sympy.Rational`` or ``sympy.pi``).
    """
    X = sp.Matrix([sp.sympify(c) for c in xyz])
    u, v = uv
    at = {u: sp.nsimplify(point[0]) if isinstance(point[0], float) else point[0],
          v: sp.nsimplify(point[1]) if isinstance(point[1], float) else point[1]}
    derivs = [X.diff(u), X.diff(v), X.diff(u, 2), X.diff(u).diff(v), X.diff(v, 2)]
    return curvature_from_derivatives(*(d.subs(at) for d in derivs))


def _fractions(array):
    return np.vectorize(lambda x: x if isinstance(x, Fraction) else Fraction(x), otypes=[object])(np.asarray(array))


def _bernstein_exact(n, t, order):
    """Values of the ``order``-th derivative of all B_i^n at the Fraction t (via forward differences)."""
    if order > n:
        return None
    deg = n - order
    base = [comb(deg, i) * t**i * (1 - t) ** (deg - i) for i in range(deg + 1)]
    factor = 1
    for k in range(order):
        factor *= n - k
    # d^r/dt^r sum b_i B_i^n = n!/(n-r)! sum Δ^r b_i B_i^{n-r}; expand Δ^r into weights of b_i.
    out = [Fraction(0)] * (n + 1)
    for i, B in enumerate(base):
        for k in range(order + 1):
            out[i + k] += factor * (-1) ** (order - k) * comb(order, k) * B
    return out


def bezier_derivatives_exact(P, u, v, weights=None):
    """Exact point and derivatives of a (rational) Bézier patch at rational ``(u, v)``.

    Parameters
    ----------
    P : (m+1, n+1, 3) array_like of numbers
        Floats are taken at their exact binary value; Fractions and ints exactly.
    u, v : number
        Converted to :class:`fractions.Fraction` exactly.
    weights : (m+1, n+1) array_like, optional

    Returns
    -------
    list of six 3-vectors of Fractions: ``b, bu, bv, buu, buv, bvv``.
    """
    P = _fractions(P)
    m, n = P.shape[0] - 1, P.shape[1] - 1
    u, v = Fraction(u), Fraction(v)
    if weights is None:
        Pw = P
    else:
        w = _fractions(weights)
        Pw = np.concatenate([P * w[..., None], w[..., None]], axis=-1)
    orders = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))
    fields = []
    for du, dv in orders:
        Bu = _bernstein_exact(m, u, du)
        Bv = _bernstein_exact(n, v, dv)
        if Bu is None or Bv is None:
            fields.append([Fraction(0)] * Pw.shape[-1])
            continue
        fields.append(
            [sum(Bu[i] * Bv[j] * Pw[i, j, c] for i in range(m + 1) for j in range(n + 1)) for c in range(Pw.shape[-1])]
        )
    if weights is None:
        return fields
    # the quotient rule of the float code, here on object arrays of Fractions (exact)
    projected = from_homogeneous(Derivatives(*(np.array(f, dtype=object) for f in fields)))
    return [list(x) for x in projected]


def _sympy_vector(vec):
    return sp.Matrix([sp.Rational(x.numerator, x.denominator) for x in vec])


def bezier_curvature_exact(P, u, v, weights=None):
    """Exact :class:`ExactCurvature` of a (rational) Bézier patch at rational ``(u, v)``."""
    d = bezier_derivatives_exact(P, u, v, weights)
    return curvature_from_derivatives(*(_sympy_vector(x) for x in d[1:]))


def bezier_corner_curvature_exact(P, weights=None):
    """Exact curvature at the four corners: a dict ``{(a, b): ExactCurvature}`` for ``(u, v) = (a, b)``."""
    return {(a, b): bezier_curvature_exact(P, a, b, weights) for a in (0, 1) for b in (0, 1)}


def to_float(exact, digits=30):
    """Float values of an :class:`ExactCurvature` (evaluated to ``digits`` significant digits first)."""
    return ExactCurvature(*(float(sp.N(x, digits)) for x in exact))


def _regular_grid(xy):
    """Whether the plane part ``xy`` (m+1, n+1, 2) of a net makes every point of its patch regular.

    Every u-difference of the net lies in the cone x > |y| and every v-difference in y > |x|; the
    derivatives b_u, b_v (and those of every subpatch) are positive combinations of them, so the
    plane parts of b_u and b_v are never parallel and b_u x b_v != 0 everywhere.
    """
    du, dv = np.diff(xy, axis=0), np.diff(xy, axis=1)
    return bool(np.all(du[..., 0] > np.abs(du[..., 1])) and np.all(dv[..., 1] > np.abs(dv[..., 0])))


def random_rational_net(rng, m, n, denominator=8, scale=4, flatness=None):
    """A random control net with rational coordinates ``k / denominator`` (exact in binary if a power of 2).

    The net is a perturbed grid over ``[0, m] x [0, n]``, redrawn in the rare case that its patch would
    have a degenerate point (:func:`_regular_grid`); heights are random in ``[-scale, scale]``.

    Parameters
    ----------
    rng : numpy.random.Generator
    m, n : int
        Degrees.
    denominator : int
    scale : float
    flatness : float, optional
        If given, heights are multiplied by it (0 gives a flat patch).

    Returns
    -------
    ndarray of float, shape ``(m+1, n+1, 3)``
    """
    i, j = np.meshgrid(np.arange(m + 1), np.arange(n + 1), indexing="ij")
    while True:  # redraw the rare grid whose patch has a degenerate point (see _regular_grid)
        jitter = rng.integers(-denominator // 4, denominator // 4 + 1, size=(m + 1, n + 1, 2)) / denominator
        if _regular_grid(np.stack([i + jitter[..., 0], j + jitter[..., 1]], axis=-1)):
            break
    z = rng.integers(-scale * denominator, scale * denominator + 1, size=(m + 1, n + 1)) / denominator
    if flatness is not None:
        z = z * flatness
    return np.stack([i + jitter[..., 0], j + jitter[..., 1], z], axis=-1)
