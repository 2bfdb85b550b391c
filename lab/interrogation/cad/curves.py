"""A CAD edge's curves as points: a trimming loop's pcurves to a chordal tolerance, a shared edge's 3-D curve with
its tangents at given parameters.

A trimming loop's pcurve (:func:`pcurve_points`) is sampled by OpenCASCADE itself where its polyline stays
within a chordal tolerance of the curve (``GCPnts_TangentialDeflection``; a line gives its two ends): one
call per curve, the impeller's 4649 pcurves in about 0.15 s (sampling them at 24 parameters each, one
``Value`` per point, took 1.3 s; reading their poles and evaluating them in NumPy 0.6 s).

A shared edge needs its 3-D curve and both pcurves at the same parameters (:func:`curve3d_values`,
:func:`curve2d_values`): lines, circles, ellipses, B-spline and Bézier curves are read once (poles, knots,
weights, axes) and evaluated with NumPy (The NURBS Book, A2.1-A2.3 and A4.1-A4.2 for the rational ones);
any other curve falls back to OpenCASCADE's point by point evaluation.  Every curve read here is checked
against OpenCASCADE at its middle parameter (one call): a curve whose NumPy value differs (a transformation
or periodicity not understood) is evaluated by OpenCASCADE instead, so this can make a read faster but
never different.
"""

import numpy as np

from ...geometry import bspline as _bs

__all__ = ["curve2d_values", "curve3d_values", "pcurve_points", "spline_curve"]

#: NumPy and OpenCASCADE must agree on a curve to this fraction of its extent (else OpenCASCADE evaluates it).
CHECK_RTOL = 1e-10


def spline_curve(P, knots, degree, t, weights=None, derivative=False):
    """Points (and first derivatives) of a B-spline or NURBS curve.

    Parameters
    ----------
    P : (n, d) ndarray
        Control points.
    knots : (n + degree + 1,) ndarray
    degree : int
    t : (k,) ndarray
        Parameters in the knot vector's domain.
    weights : (n,) ndarray, optional
    derivative : bool
        Also return the first derivatives (quotient rule for rational curves, The NURBS Book, eq. 4.8).

    Returns
    -------
    (k, d) ndarray, or a pair of them with ``derivative``.
    """
    t = np.asarray(t, dtype=float)
    span = _bs.find_span(knots, degree, t)
    N = _bs.basis_derivatives(knots, degree, span, t, 1 if derivative else 0)  # (k, r, p+1)
    idx = span[:, None] - degree + np.arange(degree + 1)
    if weights is None:
        C = np.einsum("kri,kid->rkd", N, P[idx])
        return (C[0], C[1]) if derivative else C[0]
    w = weights[idx]
    A = np.einsum("kri,kid->rkd", N * w[:, None, :], P[idx])
    W = np.einsum("kri->rk", N * w[:, None, :])[..., None]
    C = A[0] / W[0]
    return (C, (A[1] - W[1] * C) / W[0]) if derivative else C


def _xy(p):
    return np.array([p.X(), p.Y()])


def _xyz(p):
    return np.array([p.X(), p.Y(), p.Z()])


def _conic(t, centre, x, y, a, b, derivative):
    c, s = np.cos(t)[:, None], np.sin(t)[:, None]
    points = centre + a * c * x + b * s * y
    return (points, -a * s * x + b * c * y) if derivative else points


def _spline_data(curve, coords):
    """``(P, knots, degree, weights)`` of a Geom/Geom2d B-spline or Bézier curve, or None if periodic."""
    if hasattr(curve, "IsPeriodic") and curve.IsPeriodic():
        return None
    n = curve.NbPoles()
    P = np.array([coords(curve.Pole(i)) for i in range(1, n + 1)])
    weights = np.array([curve.Weight(i) for i in range(1, n + 1)]) if curve.IsRational() else None
    p = curve.Degree()
    if hasattr(curve, "KnotSequence"):
        seq = curve.KnotSequence()
        knots = np.array([seq.Value(i) for i in range(seq.Lower(), seq.Upper() + 1)])
    else:  # Bézier: one span over [0, 1]
        knots = np.repeat([0.0, 1.0], p + 1)
    return P, knots, p, weights


def _spline_lists(curve):
    """``(poles, flat knots, degree, weights or None)`` of a Geom2d B-spline or Bézier curve as Python lists, or
    None if periodic (its knot sequence would need unrolling)."""
    if hasattr(curve, "IsPeriodic") and curve.IsPeriodic():
        return None
    n = curve.NbPoles()
    P = [(q.X(), q.Y()) for q in (curve.Pole(i) for i in range(1, n + 1))]
    w = [curve.Weight(i) for i in range(1, n + 1)] if curve.IsRational() else None
    p = curve.Degree()
    if hasattr(curve, "KnotSequence"):
        seq = curve.KnotSequence()
        knots = [seq.Value(i) for i in range(seq.Lower(), seq.Upper() + 1)]
    else:  # Bézier: one span over [0, 1]
        knots = [0.0] * (p + 1) + [1.0] * (p + 1)
    return P, knots, p, w


def _evaluate(adaptor, t, dim, derivative):
    """NumPy evaluation of an adaptor's curve, or None when its type is not one of the read ones."""
    kind = adaptor.GetType().name.removeprefix("GeomAbs_")
    coords = _xy if dim == 2 else _xyz
    if kind == "Line":
        line = adaptor.Line()
        p0, d = coords(line.Location()), coords(line.Direction())
        points = p0 + t[:, None] * d
        return (points, np.broadcast_to(d, points.shape).copy()) if derivative else points
    if kind in ("Circle", "Ellipse"):
        conic = adaptor.Circle() if kind == "Circle" else adaptor.Elips()
        a = conic.Radius() if kind == "Circle" else conic.MajorRadius()
        b = conic.Radius() if kind == "Circle" else conic.MinorRadius()
        centre = coords(conic.Location())
        x, y = coords(conic.XAxis().Direction()), coords(conic.YAxis().Direction())
        return _conic(t, centre, x, y, a, b, derivative)
    if kind in ("BSplineCurve", "BezierCurve"):
        data = _spline_data(adaptor.BSpline() if kind == "BSplineCurve" else adaptor.Bezier(), coords)
        if data is None:
            return None
        P, knots, p, w = data
        return spline_curve(P, knots, p, t, w, derivative)
    return None


def _occ_values(adaptor, t, dim, derivative):
    """OpenCASCADE's point by point evaluation (any curve type)."""
    if dim == 2:
        from OCP.gp import gp_Pnt2d as Pnt
        from OCP.gp import gp_Vec2d as Vec
    else:
        from OCP.gp import gp_Pnt as Pnt
        from OCP.gp import gp_Vec as Vec
    coords = _xy if dim == 2 else _xyz
    points, tangents = np.empty((len(t), dim)), np.empty((len(t), dim))
    p, d = Pnt(), Vec()
    for k, x in enumerate(t):
        if derivative:
            adaptor.D1(float(x), p, d)
            tangents[k] = coords(d)
        else:
            p = adaptor.Value(float(x))
        points[k] = coords(p)
    return (points, tangents) if derivative else points


def _values(adaptor, t, dim, derivative):
    t = np.asarray(t, dtype=float)
    fast = None
    try:
        fast = _evaluate(adaptor, t, dim, derivative)
    except Exception:  # noqa: BLE001 - any trouble reading the curve: OpenCASCADE evaluates it
        fast = None
    if fast is not None and len(t):
        points = fast[0] if derivative else fast
        k = len(t) // 2
        ref = _xy(adaptor.Value(float(t[k]))) if dim == 2 else _xyz(adaptor.Value(float(t[k])))
        extent = float(np.ptp(points, axis=0).max(initial=0.0)) + float(np.abs(ref).max())
        if np.all(np.isfinite(points)) and np.linalg.norm(points[k] - ref) <= CHECK_RTOL * max(extent, 1e-300):
            return fast
    return _occ_values(adaptor, t, dim, derivative)


def curve2d_values(adaptor, t):
    """Points ``(k, 2)`` of a ``Geom2dAdaptor_Curve`` / ``BRepAdaptor_Curve2d`` (a pcurve) at the parameters ``t``."""
    return _values(adaptor, t, 2, False)


def curve3d_values(adaptor, t):
    """Points and first derivatives ``(k, 3)`` of a ``BRepAdaptor_Curve`` (an edge's 3-D curve) at ``t``."""
    return _values(adaptor, t, 3, True)


def pcurve_points(adaptor, deflection, reverse=False, angle=0.3):
    """A pcurve (``BRepAdaptor_Curve2d``) as a polyline ``(k, 2)`` within about ``deflection`` of the curve.

    A line is its two ends; any other curve ``GCPnts_TangentialDeflection`` (OpenCASCADE): its tangent turns by
    at most ``angle`` (radians) and its polyline stays within ``deflection`` of it as OpenCASCADE checks that
    (at points between its samples: measured up to 1.35 times ``deflection`` in between), at least three points (with two, a slightly S-shaped pcurve whose middle lies on its chord would pass for
    straight: ``GCPnts_QuasiUniformDeflection`` measured 2.3 times its deflection on shell1.brep's face 55).
    From the curve's first to its last parameter, or the other way with ``reverse``; 24 equally spaced
    parameters if OpenCASCADE's sampling fails.
    """
    from OCP.GCPnts import GCPnts_TangentialDeflection

    lo, hi = adaptor.FirstParameter(), adaptor.LastParameter()
    if adaptor.GetType().name == "GeomAbs_Line":
        points = np.array([(q.X(), q.Y()) for q in (adaptor.Value(lo), adaptor.Value(hi))])
    else:
        sampler = GCPnts_TangentialDeflection(adaptor, float(angle), float(deflection), 3)
        if sampler.NbPoints() >= 2:
            points = np.array([(q.X(), q.Y()) for q in (sampler.Value(i) for i in range(1, sampler.NbPoints() + 1))])
        else:
            points = _occ_values(adaptor, np.linspace(lo, hi, 24), 2, False)
    return points[::-1] if reverse else points


def _cast(kind):
    """``TopoDS.Face`` (OCP 8) or ``TopoDS.Face_s`` (OCP 7)."""
    from OCP.TopoDS import TopoDS

    return getattr(TopoDS, kind + "_s", None) or getattr(TopoDS, kind)


def _shape_map(data=False):
    """An indexed map of shapes (to lists of shapes with ``data``): ``TopTools_*`` in OCP 7, collections in OCP 8."""
    try:
        from OCP import TopTools

        return getattr(TopTools, "TopTools_IndexedDataMapOfShapeListOfShape" if data else
                       "TopTools_IndexedMapOfShape")()
    except (ImportError, AttributeError):
        from OCP.OCP import collections

        return getattr(collections, "IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher" if data
                       else "IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher")()


# -- a face's surface in the file's parameters ------------------------------------------------------------


def _clip(uv, domain):
    """(u, v) points moved into the domain (pcurves may stray by OpenCASCADE's tolerance)."""
    (u0, u1), (v0, v1) = domain
    return np.column_stack([np.clip(uv[:, 0], u0, u1), np.clip(uv[:, 1], v0, v1)])
