"""Named example surfaces (factories), from the practical and the papers (Dill 1981, Choi & Lee, Puig-Pey et al. 2002).

Every factory returns a surface object with the common interface of
:class:`lab.Surface`; the free-form ones (Bézier, B-spline, NURBS) also have
``to_bezier_patches()``.  Quadrics and the torus are exact rational B-splines
(NURBS), so their curvature is exact; surfaces that are not rational
(catenoid, sine wave) are analytic :class:`lab.ParametricSurface` objects.
"""

import functools
import math

import numpy as np

from ..geometry.validation import COORDINATE_MAX, as_array, as_number, check_memory, format_count
from ..i18n import N_
from .surface import BezierSurface, BSplineSurface, ParametricSurface

__all__ = [
    "REGISTRY",
    "catenoid",
    "cone",
    "cylinder",
    "ellipsoid",
    "ellipsoid_umbilics",
    "hood",
    "isodistance_geodesics_example",
    "isodistance_sections_example",
    "monkey_saddle",
    "plane",
    "practical",
    "practical_height",
    "saddle",
    "sine_wave",
    "sphere",
    "torus",
]

_S = np.sqrt(0.5)


def _named(name):
    """The factory's surfaces get the ``name`` (English, marked for translation): captions, tables and messages
    show it in the lab's language (:func:`lab.model.surface.label`)."""
    def decorate(factory):
        @functools.wraps(factory)
        def make(*args, **kwargs):
            surface = factory(*args, **kwargs)
            surface.name = name
            return surface
        return make
    return decorate


#: The unit circle as a degree-2 NURBS with nine control points (The NURBS Book, example 7.2).
_CIRCLE_XY = np.array([[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1], [1, 0]], dtype=float)
_CIRCLE_W = np.array([1, _S, 1, _S, 1, _S, 1, _S, 1])
_CIRCLE_KNOTS = np.array([0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1])


def practical_height(x, y):
    """The height of the practical's example: f(x, y) = x²/5 + xy/4 + 10/(1 + x² + y²) + y/2."""
    x, y = as_array(x, "x", finite=False), as_array(y, "y", finite=False)
    try:
        shape = np.broadcast_shapes(x.shape, y.shape)
    except ValueError:
        raise ValueError(f"x and y must broadcast against each other; got shapes {x.shape} and {y.shape}") from None
    check_memory(8.0 * 4 * math.prod(shape), f"practical_height at {format_count(math.prod(shape))} points")
    x, y = as_array(x, "x"), as_array(y, "y")
    for name, t in (("x", x), ("y", y)):
        if t.size and max(-t.min(), t.max()) > COORDINATE_MAX:  # x² would overflow
            raise ValueError(f"{name} must lie within ±{COORDINATE_MAX:g}; got values up to {max(-t.min(), t.max()):.3g}")
    if not shape:
        x, y = float(x), float(y)
    return x**2 / 5 + x * y / 4 + 10 / (1 + x**2 + y**2) + y / 2


@_named(N_("practical surface"))
def practical():
    """The example surface of the practical, built exactly as its course program builds it.

    The course program of the practical (``curveature-visualization.py``)
    writes the control net as ``[[point(x, y, f(x, y)) for x in range(-5, 5)]
    for y in range(-5, 5)]`` and its spline class takes the **outer** index of
    that list along u.  So here, too, ``control_points[i, j] = (x_j, y_i,
    f(x_j, y_i))``: **u runs along y and v along x** (a 10 × 10 grid, x, y in
    -5 … 4), bicubic, knot vector ``0,0,0,0,1,2,…,6,7,7,7,7`` in each direction,
    hence 7 × 7 Bézier patches.  The practical then refines once and colours by
    Gaussian curvature with the linear map.

    Orientation (practical 2.2): x depends on v only and y on u only (the
    control points' x is ``x_j``, their y is ``y_i``), so ``b_u = (0, y_u, z_u)``,
    ``b_v = (x_v, 0, z_v)`` with ``x_v, y_u > 0``, and ``b_u × b_v`` has the
    z-component ``-x_v y_u < 0``: the unit normal ``N = b_u × b_v / |b_u × b_v|``
    points **down**.  At the top of the bump, ``(u, v) = (4, 4)``:
    ``N_z ≈ -0.89``, ``H ≈ +6.08``, ``κ1 ≈ +6.64``, ``κ2 ≈ +5.53`` – the cap
    bends towards its (downward) normal, so its normal curvatures are
    positive.  A net with x along u is the transposed one: N and H change
    sign and κ1, κ2 become ``-κ2, -κ1``; K stays the same.
    """
    x = np.arange(-5.0, 5.0)
    X, Y = np.meshgrid(x, x, indexing="xy")  # X[i, j] = x_j, Y[i, j] = y_i: the outer index (u) runs along y
    P = np.stack([X, Y, practical_height(X, Y)], axis=-1)
    knots = np.concatenate([[0, 0, 0], np.arange(8), [7, 7, 7]]).astype(float)
    return BSplineSurface(P, knots, knots, 3, 3)


@_named(N_("plane"))
def plane(size=1.0):
    """The square ``[0, size]^2`` in the plane z = 0 as a bilinear Bézier patch (K = H = 0)."""
    size = as_number(size, "size", positive=True)
    P = np.array([[[0, 0, 0], [0, size, 0]], [[size, 0, 0], [size, size, 0]]], dtype=float)
    return BezierSurface(P)


def _revolve(profile, weights, knots_profile, degree_profile, profile_first=True):
    """Surface of revolution about z of a (rational) profile curve in the (rho, z) plane.

    The revolution direction uses the nine-point NURBS circle.  With
    ``profile_first`` the profile runs along u, else along v.
    """
    rho, z = profile[:, 0], profile[:, 1]
    P = np.stack(
        [rho[:, None] * _CIRCLE_XY[None, :, 0], rho[:, None] * _CIRCLE_XY[None, :, 1], np.repeat(z[:, None], 9, 1)],
        axis=-1,
    )
    W = weights[:, None] * _CIRCLE_W[None, :]
    if profile_first:
        return BSplineSurface(P, knots_profile, _CIRCLE_KNOTS, degree_profile, 2, weights=W)
    return BSplineSurface(P.transpose(1, 0, 2), _CIRCLE_KNOTS, knots_profile, 2, degree_profile, weights=W.T)


@_named(N_("sphere"))
def sphere(radius=1.0):
    """Sphere of ``radius`` centred at the origin, as an exact biquadratic NURBS.

    u runs around the z axis, v along a meridian from the south to the north
    pole; the edges v = 0 and v = 1 collapse to the poles (degenerate points,
    where the curvature is the limit from inside).  The normal points outwards,
    so with the practical's convention ``H = k1 = k2 = -1/radius`` and ``K = 1/radius²``.
    """
    r = as_number(radius, "radius", positive=True)
    profile = r * np.array([[0, -1], [1, -1], [1, 0], [1, 1], [0, 1]], dtype=float)
    w = np.array([1, _S, 1, _S, 1])
    knots = np.array([0, 0, 0, 0.5, 0.5, 1, 1, 1])
    s = _revolve(profile, w, knots, 2, profile_first=False)
    s.periodic = (True, False)
    return s


@_named(N_("ellipsoid"))
def ellipsoid(a=3.0, b=2.0, c=1.0):
    """The ellipsoid x²/a² + y²/b² + z²/c² = 1 as an exact biquadratic NURBS (the sphere's net, stretched).

    The poles of the parametrisation (the sphere's, see :func:`sphere`) lie on
    the middle axis, so with three distinct semi-axes the four umbilics
    (:func:`ellipsoid_umbilics`) are interior points of the domain, away from
    the seam u = 0.  A cyclic exchange of the axes is a rotation, so the
    normal points outwards as on the sphere (H < 0 with the practical's
    convention).
    """
    axes = np.array([as_number(x, name, positive=True) for x, name in ((a, "a"), (b, "b"), (c, "c"))])
    if not (axes.shape == (3,) and np.all(np.isfinite(axes)) and np.all(axes > 0)):
        raise ValueError(f"semi-axes a, b, c must be positive numbers; got a={a}, b={b}, c={c}")
    s = sphere(1.0)
    middle = int(np.argsort(axes, kind="stable")[1])
    # the sphere's axis (its poles) goes to the middle axis by a cyclic exchange of coordinates
    P = np.roll(s.control_points, middle - 2, axis=-1) * axes
    e = BSplineSurface(P, s.knots_u, s.knots_v, *s.degree, weights=s.weights)
    e.periodic = (True, False)
    return e


def ellipsoid_umbilics(a=3.0, b=2.0, c=1.0):
    """The four umbilics of the ellipsoid with semi-axes a, b, c (distinct), shape (4, 3).

    With the semi-axes sorted A > B > C they lie in the plane of the largest and
    the smallest axis, at ±A √((A² − B²)/(A² − C²)) along the first and
    ±C √((B² − C²)/(A² − C²)) along the last (Hilbert and Cohn-Vossen, §27).
    """
    axes = np.array([a, b, c], dtype=float)
    order = np.argsort(axes)[::-1]
    A, B, C = axes[order]
    if not (A > B > C > 0):
        raise ValueError(f"the semi-axes must be distinct positive numbers; got a={a}, b={b}, c={c}")
    x = A * np.sqrt((A**2 - B**2) / (A**2 - C**2))
    z = C * np.sqrt((B**2 - C**2) / (A**2 - C**2))
    out = np.zeros((4, 3))
    for k, (sx, sz) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        out[k, order[0]], out[k, order[2]] = sx * x, sz * z
    return out


@_named(N_("torus"))
def torus(R=2.0, r=1.0):
    """Torus with tube radius ``r`` around a circle of radius ``R`` in the xy plane, as an exact NURBS.

    u runs around the tube, v around the z axis.  K > 0 on the outside, K < 0
    on the inside and K = 0 on the top and bottom rims (Dill, figure 7):
    ``K = cos(t) / (r (R + r cos(t)))`` where ``t`` is the angle around the tube.
    """
    R, r = as_number(R, "R", positive=True), as_number(r, "r", positive=True)
    if not R > r:
        raise ValueError(f"torus needs R > r > 0; got R={R}, r={r}")
    profile = np.column_stack([R + r * _CIRCLE_XY[:, 0], r * _CIRCLE_XY[:, 1]])
    s = _revolve(profile, _CIRCLE_W, _CIRCLE_KNOTS, 2, profile_first=True)
    s.periodic = (True, True)
    return s


@_named(N_("cylinder"))
def cylinder(r=1.0, h=2.0):
    """Cylinder of radius ``r`` and height ``h`` about the z axis (from z = 0), as an exact NURBS.

    u runs around the axis, v up; the normal points outwards, so
    ``K = 0`` and ``H = -1/(2r)``.
    """
    r, h = as_number(r, "r", positive=True), as_number(h, "h", positive=True)
    profile = np.array([[r, 0.0], [r, h]])
    s = _revolve(profile, np.ones(2), np.array([0.0, 0, 1, 1]), 1, profile_first=False)
    s.periodic = (True, False)
    return s


@_named(N_("cone"))
def cone(radius=1.0, height=1.0):
    """A quarter of a cone as a bilinear-by-quadratic rational Bézier patch whose edge v = 1 collapses to the apex.

    The mean curvature grows like 1/distance towards the apex, so there the
    curvature has no finite limit: the points are reported as degenerate.
    """
    radius, height = as_number(radius, "radius", positive=True), as_number(height, "height", positive=True)
    arc = np.array([[radius, 0, 0], [radius, radius, 0], [0, radius, 0]], dtype=float)
    apex = np.array([0.0, 0.0, height])
    P = np.stack([arc, np.repeat(apex[None], 3, 0)], axis=1)  # (3, 2, 3): u along the arc
    W = np.array([[1, 1], [_S, _S], [1, 1]])
    return BezierSurface(P, W)


#: The catenoid's accepted waist radii ``c`` (see :func:`catenoid`).
CATENOID_C = (1e-10, 1e10)


def catenoid(c=1.0, height=None):
    """Catenoid ``(c cosh(v/c) cos u, c cosh(v/c) sin u, v)``, a minimal surface (Dill, figure 8).

    ``H = 0`` everywhere and ``K = -1 / (c² cosh⁴(v/c))``, from ``-1/c²`` at
    the waist towards 0.  ``v`` runs over ``[-height/2, height/2]`` (default
    ``height = 3c``), ``u`` over ``[0, 2π]``.  ``c`` must lie in ``[1e-10, 1e10]``
    and ``height`` in ``[1e-10 c, 200 c]`` (a ``ValueError`` otherwise).
    """
    import sympy as sp

    # issue 35: below 1e-10 the fundamental forms (c^4) fall under the degeneracy tolerance and sympy's
    # simplification of v/c meets NaN; beyond 1e10, K = -1/c^2 underflows the tolerance the other way
    c = as_number(c, "c", minimum=CATENOID_C[0], maximum=CATENOID_C[1])
    # the rims at cosh(height / 2c): up to 200 c keeps them below 1e43 c (cosh(100)), inside the float range
    height = 3.0 * c if height is None else as_number(height, "height", minimum=1e-10 * c, maximum=200.0 * c)
    c, half = sp.nsimplify(c), sp.nsimplify(height) / 2
    u, v = sp.symbols("u v", real=True)
    xyz = (c * sp.cosh(v / c) * sp.cos(u), c * sp.cosh(v / c) * sp.sin(u), v)
    s = ParametricSurface.from_sympy(xyz, (u, v), ((0, 2 * sp.pi), (-half, half)), name=N_("catenoid"))
    s.periodic = (True, False)
    return s


def _bezier_from_function(f, m, n):
    """Bézier net of the polynomial graph ``(x, y, f(x, y))`` over ``[-1, 1]^2`` with ``x = 2u-1, y = 2v-1``.

    ``f`` must be a polynomial of degree at most ``m`` in x and ``n`` in y; the
    net is found by interpolation at equidistant nodes (exact up to rounding).
    """
    from ..geometry.bezier import bernstein

    tu = np.linspace(0, 1, m + 1)
    tv = np.linspace(0, 1, n + 1)
    Bu, Bv = bernstein(m, tu), bernstein(n, tv)
    U, V = np.meshgrid(tu, tv, indexing="ij")
    Z = f(2 * U - 1, 2 * V - 1)
    coeff = np.linalg.solve(Bu, np.linalg.solve(Bv, Z.T).T)
    X = np.linspace(-1, 1, m + 1)
    Y = np.linspace(-1, 1, n + 1)
    XX, YY = np.meshgrid(X, Y, indexing="ij")
    return np.stack([XX, YY, coeff], axis=-1)


@_named(N_("saddle"))
def saddle():
    """The hyperbolic paraboloid z = x² - y² over [-1, 1]² as a biquadratic Bézier patch (K < 0 everywhere)."""
    a = np.array([1.0, -1.0, 1.0])  # (2u-1)^2 in the Bernstein basis of degree 2
    x = np.array([-1.0, 0.0, 1.0])
    X, Y = np.meshgrid(x, x, indexing="ij")
    return BezierSurface(np.stack([X, Y, a[:, None] - a[None, :]], axis=-1))


@_named(N_("monkey saddle"))
def monkey_saddle():
    """The monkey saddle z = x³ - 3xy² over [-1, 1]² as a bicubic Bézier patch (a flat point at the centre)."""
    return BezierSurface(_bezier_from_function(lambda x, y: x**3 - 3 * x * y**2, 3, 3))


def sine_wave(amplitude=0.5, frequency=1.0, radius=2 * np.pi):
    """Dill's sine wave of revolution, ``z = A cos(ω ρ)`` for ρ in [0, radius], as an analytic surface.

    Parametrised by ``(ρ cos φ, ρ sin φ, A cos(ω ρ))``.  The cosine phase
    makes the crest at the centre smooth (``A sin(ω ρ)`` would have a conical
    tip there); the edge ρ = 0 collapses to the centre, a degenerate point
    where the curvature is the limit from inside, ``K = (A ω²)²``.  The rings
    alternate between elliptic (crests, troughs) and hyperbolic (flanks) points.
    """
    import sympy as sp

    rho, phi = sp.symbols("rho phi", real=True)
    big = COORDINATE_MAX  # beyond it the fundamental forms overflow
    A = sp.nsimplify(as_number(amplitude, "amplitude", minimum=-big, maximum=big))
    w = sp.nsimplify(as_number(frequency, "frequency", minimum=-big, maximum=big))
    radius = as_number(radius, "radius", positive=True)
    if radius > big:
        raise ValueError(f"radius must be at most {big:g} (the fundamental forms overflow beyond); got {radius:g}")
    xyz = (rho * sp.cos(phi), rho * sp.sin(phi), A * sp.cos(w * rho))
    s = ParametricSurface.from_sympy(xyz, (rho, phi), ((0, float(radius)), (0, 2 * sp.pi)), name=N_("sine wave"))
    s.periodic = (False, True)
    return s


@_named(N_("car hood"))
def hood():
    """A car-hood-like bicubic B-spline (right half, after Dill's figure 9) with a crease and a flat spot.

    u runs from the front (u = 0) to the windscreen, v from the centre line
    outwards.  The crown falls off towards the front and the side; a
    longitudinal crease runs along v ≈ 0.5 (control points pulled up into a
    ridge over a double knot, so the curvature is high and jumps across it);
    near the back outside corner the 4 × 4 control points of the last knot
    span are coplanar, so that patch is exactly flat (K = H = 0): the "flat
    spot" Dill's designers found on the production hood.
    """
    nu, nv = 8, 9
    x = np.linspace(0.0, 1.6, nu)  # front to back (m)
    y = np.array([0.0, 0.1, 0.2, 0.3, 0.36, 0.42, 0.55, 0.68, 0.8])  # centre line to side (m)
    X, Y = np.meshgrid(x, y, indexing="ij")
    xs, ys = X / 1.6, Y / 0.8
    Z = 0.10 + 0.05 * xs - 0.06 * (1 - xs) ** 2 - 0.07 * ys**2
    Z[:, 4] += 0.012  # the crease: a ridge of control points
    # Flat spot: the last 4 x 4 control points lie on the tangent plane of the crown there.
    i0, j0 = nu - 4, nv - 4
    xc, yc = X[i0:, j0:], Y[i0:, j0:]
    z0 = 0.10 + 0.05 - 0.07 * 0.75**2
    Z[i0:, j0:] = z0 + 0.03 * (xc - 1.4) - 0.12 * (yc - 0.7)
    P = np.stack([X, Y, Z], axis=-1)
    ku = np.concatenate([[0, 0, 0], np.arange(nu - 2), [nu - 3] * 3]).astype(float)
    kv = np.array([0, 0, 0, 0, 1, 2, 3, 3, 4, 5, 5, 5, 5], dtype=float)  # double knot 3: the crease
    return BSplineSurface(P, ku, kv, 3, 3)


@_named(N_("NURBS of Puig-Pey et al., figure 1"))
def isodistance_sections_example():
    """The first NURBS of Puig-Pey et al. (§5, figure 1), reconstructed.

    Order (4, 4), a 4 × 6 control grid, non-periodic knot vectors: one patch
    along u and three along v.  The paper does not list its control points;
    these give a gently waved sheet of about 6 × 9 units, so that normal
    sections of length 0.3 … 4.5 (the paper's s_L range) stay on or leave it
    as in the figure.
    """
    x = np.array([0.0, 2.0, 4.0, 6.0])
    y = np.array([0.0, 1.8, 3.6, 5.4, 7.2, 9.0])
    X, Y = np.meshgrid(x, y, indexing="ij")
    Z = np.array(
        [
            [0.0, 0.8, 1.5, 1.2, 0.4, 0.0],
            [0.6, 2.0, 2.6, 2.2, 1.4, 0.5],
            [0.4, 1.6, 2.4, 2.8, 1.8, 0.7],
            [0.0, 0.6, 1.2, 1.6, 1.0, 0.2],
        ]
    )
    W = np.ones((4, 6))
    W[1, 2] = W[2, 3] = 1.5
    ku = np.array([0, 0, 0, 0, 1, 1, 1, 1], dtype=float)
    kv = np.array([0, 0, 0, 0, 1, 2, 3, 3, 3, 3], dtype=float) / 3
    return BSplineSurface(np.stack([X, Y, Z], axis=-1), ku, kv, 3, 3, weights=W)


@_named(N_("NURBS of Puig-Pey et al., figures 2 and 3"))
def isodistance_geodesics_example():
    """The second NURBS of Puig-Pey et al. (§5, figures 2–3), reconstructed.

    A single bicubic rational patch on a 4 × 4 control grid, about 30 × 30
    units, so that geodesics from ``x(0.7, 0.3)`` reach the paper's distances
    1.25 … 20.  The control points are ours (the paper does not list them).
    """
    x = np.array([0.0, 10.0, 20.0, 30.0])
    X, Y = np.meshgrid(x, x, indexing="ij")
    Z = np.array(
        [
            [0.0, 4.0, 6.0, 2.0],
            [3.0, 12.0, 10.0, 5.0],
            [2.0, 9.0, 14.0, 6.0],
            [0.0, 3.0, 5.0, 1.0],
        ]
    )
    W = np.ones((4, 4))
    W[1, 1] = 2.0
    W[2, 2] = 0.8
    return BezierSurface(np.stack([X, Y, Z], axis=-1), weights=W)


#: Factories by name, with default arguments (used by the CLI and the explorers).
REGISTRY = {
    "practical": practical,
    "plane": plane,
    "sphere": sphere,
    "ellipsoid": ellipsoid,
    "torus": torus,
    "cylinder": cylinder,
    "cone": cone,
    "catenoid": catenoid,
    "saddle": saddle,
    "monkey-saddle": monkey_saddle,
    "sine-wave": sine_wave,
    "hood": hood,
    "isodistance-sections": isodistance_sections_example,
    "isodistance-geodesics": isodistance_geodesics_example,
}
