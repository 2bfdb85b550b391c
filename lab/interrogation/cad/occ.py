"""STEP, IGES and BREP files through OpenCASCADE (``cadquery-ocp-novtk``, the lab's extra ``cad``).

Only :func:`read_occ` imports ``OCP``, and only when it is called, so ``import lab`` stays free of it.

**Parameters stay those of the file.**  A B-spline face's surface becomes a :class:`lab.BSplineSurface`
with the file's poles, weights, knots and parameters (a periodic surface gets its clamped, non-periodic
form with the same parameters).  An analytic face (plane, cylinder, cone, sphere, torus, revolution,
extrusion, offset, Bézier) is converted exactly to NURBS as ``BRepBuilderAPI_NurbsConvert`` would convert
it (``GeomConvert::SurfaceToBSplineSurface`` of the surface cut to the face's (u, v) bounds), but its
pcurves are not rewritten: the face keeps the file's (u, v) through one exact map per direction from the
file's parameter to the NURBS's (:mod:`lab.geometry.parameter_maps`: identity for lines, a
tan-half-angle relation per span for circle arcs), found by trying the few maps OpenCASCADE's conversions
produce and accepting the one whose NURBS reproduces the file's surface at 25 points to 1e-9 of the face's
size.  ``face.file_surface`` (a :class:`lab.ReparametrizedSurface` over the NURBS) evaluates in the file's
parameters, so the trimming loops, the shared edges' (u, v) and ``face.curvature`` are read straight from
the file's pcurves.  Where no exact map exists (an offset of a B-spline surface, whose NURBS OpenCASCADE
can only approximate), the NURBS is OpenCASCADE's approximation over the same parameters; the face says so
(``face.exact`` False, ``face.deviation`` measured).

**Shared edges and sewing** (:mod:`.sewing`).  A file whose faces are not sewn (IGES files usually: each
face has its own edges) is sewn with ``BRepBuilderAPI_Sewing`` only to *find* the edges two faces share; the
model's faces stay the file's (order, surfaces, parameters, loops and orientation), see :func:`read_occ`.
"""

import os
import re
import warnings

import numpy as np

from ...geometry.parameter_maps import ParameterMap, circle_spans
from ...model.reparametrized import ReparametrizedSurface
from ...model.surface import BSplineSurface
from ..trimming import trimmed
from ..trimming.loops import signed_area
from .curves import _cast, _clip, _shape_map, pcurve_points
from .model import Face, Model, Problem

__all__ = ["EXTENSIONS", "lab_surface", "occ_shape", "read_occ", "require_ocp"]

#: File name endings read through OpenCASCADE.
EXTENSIONS = {".step": "STEP", ".stp": "STEP", ".iges": "IGES", ".igs": "IGES", ".brep": "BREP", ".brp": "BREP"}

#: Chordal tolerance of a trimming loop's polyline: this fraction of the smaller side of its face's (u, v) box
#: (:func:`lab.interrogation.cad.curves.pcurve_points`; a line is its two ends).
PCURVE_RTOL = 1e-3

#: A parameter map is accepted when the NURBS at the mapped parameters is the file's surface to this
#: fraction of the face's size (measured: 1e-15 for the exact maps, 1e-3 and more for a wrong one).
MAP_RTOL = 1e-9

#: Tolerance of the NURBS approximation of a face without an exact NURBS form (an offset of a B-spline
#: surface), relative to the face's size.
APPROX_RTOL = 1e-10

_KINDS = ("Plane", "Cylinder", "Cone", "Sphere", "Torus", "BezierSurface", "BSplineSurface",
          "SurfaceOfRevolution", "SurfaceOfExtrusion", "OffsetSurface", "OtherSurface")


def require_ocp():
    """Import OCP or raise an ImportError that says how to install it."""
    try:
        import OCP  # noqa: F401
    except ImportError:
        raise ImportError(
            'reading and writing STEP, IGES and BREP files needs OpenCASCADE, the extra "cad" of curvature-lab: '
            'pip install "curvature-lab[cad]" (in a checkout: pip install -e ".[cad]", which make setup does)'
        ) from None


def _quiet():
    """OpenCASCADE's readers print progress ("Total number of loaded entities") to stdout: failures only."""
    from OCP.Message import Message, Message_Gravity

    printers = Message.DefaultMessenger_s().Printers()
    if printers.Size():
        printers.First().SetTraceLevel(Message_Gravity.Message_Fail)


def occ_shape(path):
    """The ``TopoDS_Shape`` of a STEP, IGES or BREP file (``ValueError`` naming the file when it cannot be read)."""
    require_ocp()
    from OCP.BRep import BRep_Builder
    from OCP.BRepTools import BRepTools
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.TopoDS import TopoDS_Shape

    _quiet()
    path = os.fspath(path)
    kind = EXTENSIONS[os.path.splitext(path)[1].lower()]
    if os.path.getsize(path) == 0:
        raise ValueError(f"{path}: the file is empty; expected a {kind} file")
    if kind == "BREP":
        shape = TopoDS_Shape()
        ok = BRepTools.Read_s(shape, path, BRep_Builder())
        if not ok or shape.IsNull():
            raise ValueError(f"{path}: OpenCASCADE could not read it as a BREP file (corrupt or not BREP)")
        return shape
    if kind == "STEP":
        from OCP.STEPControl import STEPControl_Reader as Reader
    else:
        from OCP.IGESControl import IGESControl_Reader as Reader
    reader = Reader()
    status = reader.ReadFile(path)
    if status != IFSelect_RetDone:
        raise ValueError(f"{path}: OpenCASCADE could not read it as a {kind} file ({status.name})")
    if reader.TransferRoots() == 0:
        raise ValueError(f"{path}: the {kind} file holds no entity that OpenCASCADE can turn into a shape")
    shape = reader.OneShape()
    if shape.IsNull():
        raise ValueError(f"{path}: the {kind} file gave an empty shape")
    return shape


def _kind(surface):
    from OCP.GeomAdaptor import GeomAdaptor_Surface

    name = GeomAdaptor_Surface(surface).GetType().name  # GeomAbs_Plane, ...
    return name.removeprefix("GeomAbs_")


def _weight_values(bs):
    """The weights as an ndarray, read one by one.

    ``Geom_BSplineSurface.Weights()`` must not be called from Python: OCP hands
    out the surface's own array as a pointer it then frees (a double free).
    """
    nu, nv = bs.NbUPoles(), bs.NbVPoles()
    return np.array([[bs.Weight(i, j) for j in range(1, nv + 1)] for i in range(1, nu + 1)])


def _weights(bs):
    """The weights as an ``Array2_double`` (to build a copy of the surface) and an ndarray."""
    from OCP.OCP.collections import Array2_double

    w = _weight_values(bs)
    nu, nv = w.shape
    W = Array2_double(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            W.SetValue(i + 1, j + 1, float(w[i, j]))
    return W, w


def lab_surface(bs):
    """A :class:`lab.BSplineSurface` with the poles, weights, knots and degrees of a ``Geom_BSplineSurface``."""
    nu, nv = bs.NbUPoles(), bs.NbVPoles()
    poles = bs.Poles()
    P = np.array([[(q.X(), q.Y(), q.Z()) for q in (poles.Value(i, j) for j in range(1, nv + 1))]
                  for i in range(1, nu + 1)], dtype=float).reshape(nu, nv, 3)
    weights = _weight_values(bs) if (bs.IsURational() or bs.IsVRational()) else None
    ku, kv = bs.UKnotSequence(), bs.VKnotSequence()
    knots_u = np.array([ku.Value(k) for k in range(ku.Lower(), ku.Upper() + 1)])
    knots_v = np.array([kv.Value(k) for k in range(kv.Lower(), kv.Upper() + 1)])
    return BSplineSurface(P, knots_u, knots_v, bs.UDegree(), bs.VDegree(), weights=weights)


def _conversion_bounds(face, surface):
    """The face's (u, v) bounds in the file and as ``BRepTools_NurbsConvertModification::NewSurface`` converts.

    ``BRepTools.UVBounds_s`` (the pcurves' box), moved onto the surface's own bounds where within a tenth of
    the face's tolerance and cut to them in a direction that is not periodic (a sphere's latitude never
    passes its pole): the file's domain.  The conversion takes at most one period of a periodic direction
    (a thread's face winds round its cylinder more than once; its NURBS covers one turn).
    """
    from OCP.BRep import BRep_Tool
    from OCP.BRepTools import BRepTools
    from OCP.GeomAdaptor import GeomAdaptor_Surface

    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    if not all(abs(x) < 1e50 for x in (u0, u1, v0, v1)):  # OpenCASCADE's "infinite" is 1e100
        raise ValueError(f"the face's (u, v) bounds are not finite ({u0:.3g}..{u1:.3g} x {v0:.3g}..{v1:.3g}): "
                         "its edges have no pcurves on its surface")
    adaptor = GeomAdaptor_Surface(surface)
    snap = 0.1 * BRep_Tool.Tolerance_s(face)
    file, conversion = [], []
    for (a, b), (lo, hi), periodic, period in (
            ((u0, u1), (adaptor.FirstUParameter(), adaptor.LastUParameter()), surface.IsUPeriodic(),
             surface.UPeriod() if surface.IsUPeriodic() else None),
            ((v0, v1), (adaptor.FirstVParameter(), adaptor.LastVParameter()), surface.IsVPeriodic(),
             surface.VPeriod() if surface.IsVPeriodic() else None)):
        a = lo if abs(a - lo) <= snap else a
        b = hi if abs(b - hi) <= snap else b
        if not periodic:
            a, b = max(a, lo), min(b, hi)
        if not b > a:
            raise ValueError(f"the face's (u, v) bounds are empty: [{a:g}, {b:g}]")
        file.append((float(a), float(b)))
        conversion.append((float(a), float(min(b, a + period)) if periodic else float(b)))
    return tuple(file), tuple(conversion)


def _clamped(bs):
    """A non-periodic copy of a periodic ``Geom_BSplineSurface`` (same parameters), else ``bs`` itself."""
    from OCP.Geom import Geom_BSplineSurface

    if not (bs.IsUPeriodic() or bs.IsVPeriodic()):
        return bs
    copy = Geom_BSplineSurface(bs.Poles(), _weights(bs)[0], bs.UKnots(), bs.VKnots(), bs.UMultiplicities(),
                               bs.VMultiplicities(), bs.UDegree(), bs.VDegree(), bs.IsUPeriodic(),
                               bs.IsVPeriodic())
    if copy.IsUPeriodic():
        copy.SetUNotPeriodic()
    if copy.IsVPeriodic():
        copy.SetVNotPeriodic()
    return copy


def _map_candidates(file_range, knots, degree, period=0.0):
    """The maps OpenCASCADE's conversions give a direction with the file's range ``(a, b)``, likeliest first.

    ``knots`` and ``degree`` are the NURBS's in that direction; ``period`` is given when the NURBS covers a
    whole period of a periodic direction (then the angles wrap into it, see :class:`ParameterMap`).
    Identity (lines, B-spline and Bézier faces, parabolas); circle arcs from the first knot with
    ``Convert_TgtThetaOver2``'s equal spans, or a periodic circle's three spans from angle 0
    (``CheckAndSegment`` may start the NURBS inside one of them), in both cases a whole number of periods
    after the file's angle; an affine map (a Bézier curve cut to the range); a hyperbola's one span.
    """
    a, b = file_range
    s0, s1 = _bs_domain(knots, degree)
    scale = max(1.0, abs(a), abs(b))
    same = abs(s0 - a) <= 1e-12 * scale and abs(s1 - b) <= 1e-12 * scale
    out = [ParameterMap.identity()] if same and not period else []
    turns = round((s0 - a) / (2 * np.pi))
    if period or abs(s0 - a - 2 * np.pi * turns) <= 1e-9 * scale:
        _, h = circle_spans(s1 - s0)
        for origin, half in ((s0, h), (0.0, np.pi / 3)):
            if 0 < half < np.pi / 2:
                out.append(ParameterMap.circle(origin, half, 2 * np.pi * turns, knots, degree, period))
    if not period:
        out.append(ParameterMap.affine(s0 - a * (s1 - s0) / (b - a), (s1 - s0) / (b - a)))
        if same:
            out.append(ParameterMap.hyperbola(a, b))
    return out


def _bs_domain(knots, degree):
    n = len(knots) - degree - 1
    return float(knots[degree]), float(knots[n])


def _find_maps(surface, nurbs, domain, periods=(0.0, 0.0), candidates=None):
    """The first pair of candidate maps under which ``nurbs`` reproduces the file's ``surface`` (a Geom_Surface).

    Checked at 5 x 5 parameters of the file's domain (ends included); returns ``(map_u, map_v, deviation)``
    with the largest distance found, or the best pair with its (too large) deviation.  ``candidates``: the
    maps to try in u and in v (default :func:`_map_candidates`).
    """
    (u0, u1), (v0, v1) = domain
    f = np.array([0.0, 0.173, 0.5, 0.757, 1.0])
    u, v = np.meshgrid(u0 + (u1 - u0) * f, v0 + (v1 - v0) * f, indexing="ij")
    u, v = u.ravel(), v.ravel()
    ref = np.array([[p.X(), p.Y(), p.Z()] for p in (surface.Value(float(a), float(b)) for a, b in zip(u, v))])
    (s_lo, s_hi), (t_lo, t_hi) = nurbs.domain
    tol = MAP_RTOL * _size(nurbs)
    if candidates is None:
        candidates = (_map_candidates((u0, u1), nurbs.knots_u, nurbs.degree[0], periods[0]),
                      _map_candidates((v0, v1), nurbs.knots_v, nurbs.degree[1], periods[1]))

    def deviation(mu, mv, rows=slice(None)):
        s = np.clip(mu(u[rows])[0], s_lo, s_hi) if mu is not None else np.full(u[rows].shape, s_lo)
        t = np.clip(mv(v[rows])[0], t_lo, t_hi) if mv is not None else np.full(v[rows].shape, t_lo)
        return float(np.linalg.norm(nurbs._derivatives(s, t).b - ref[rows], axis=1).max())

    # every candidate takes the file's first parameter to the NURBS's first (usually): each direction's map
    # chosen along the other's first line, then the pair checked on the whole grid; else every pair
    guess = [next((m for m in candidates[0] if deviation(m, None, slice(0, None, 5)) <= tol), None),
             next((m for m in candidates[1] if deviation(None, m, slice(0, 5)) <= tol), None)]
    if None not in guess:
        err = deviation(*guess)
        if err <= tol:
            return guess[0], guess[1], err
    best = (None, None, np.inf)
    for mu in candidates[0]:
        for mv in candidates[1]:
            err = deviation(mu, mv)
            if err < best[2]:
                best = (mu, mv, err)
            if err <= tol:
                return best
    return best


def _size(surface):
    P = surface.control_points.reshape(-1, 3)
    return float(np.linalg.norm(np.ptp(P, axis=0))) or 1.0


def _nurbs(face, kind):
    """The face's surface as a NURBS, the maps from the file's (u, v) to its parameters and the file's domain.

    Returns ``(nurbs, maps, domain, exact, deviation)``: ``maps`` is None for a B-spline face (its NURBS
    is the file's surface, parameters and all).
    """
    from OCP.BRep import BRep_Tool
    from OCP.Geom import Geom_RectangularTrimmedSurface
    from OCP.GeomAdaptor import GeomAdaptor_Surface
    from OCP.GeomConvert import GeomConvert

    surface = BRep_Tool.Surface_s(face)  # with the face's location applied
    adaptor = GeomAdaptor_Surface(surface)
    if kind == "BSplineSurface":
        nurbs = lab_surface(_clamped(adaptor.BSpline()))
        return nurbs, None, nurbs.domain, True, 0.0
    if kind == "BezierSurface":  # the whole patch: knots 0 and 1, the Bézier parameters
        nurbs = lab_surface(GeomConvert.SurfaceToBSplineSurface_s(adaptor.Bezier()))
        return nurbs, None, nurbs.domain, True, 0.0
    domain, ((u0, u1), (v0, v1)) = _conversion_bounds(face, surface)
    trimmed_surface = Geom_RectangularTrimmedSurface(surface, u0, u1, v0, v1)
    nurbs = lab_surface(_clamped(GeomConvert.SurfaceToBSplineSurface_s(trimmed_surface)))
    # a whole period converted (a closed face, or a thread's that winds round more than once): angles wrap
    periods = tuple(p() if periodic() and hi - lo >= p() - 1e-9 else 0.0
                    for p, periodic, (lo, hi) in ((surface.UPeriod, surface.IsUPeriodic, (u0, u1)),
                                                  (surface.VPeriod, surface.IsVPeriodic, (v0, v1))))
    map_u, map_v, deviation = _find_maps(surface, nurbs, domain, periods)
    size = _size(nurbs)
    if deviation <= MAP_RTOL * size:
        return nurbs, (map_u, map_v), domain, True, deviation
    if kind in ("OffsetSurface", "OtherSurface"):
        # no exact NURBS form (an offset of a B-spline surface): GeomConvert approximates it to 1e-4 in the
        # file's unit; approximated here over the same parameters to APPROX_RTOL of the face's size instead
        nurbs, deviation = _approximation(trimmed_surface, surface, domain, size)
        return nurbs, (ParameterMap.identity(), ParameterMap.identity()), domain, False, deviation
    raise ValueError(f"no parameter map makes OpenCASCADE's NURBS form of this {kind} reproduce the file's "
                     f"surface: the best deviates by {deviation:.3g} (face size {size:.3g})")


def _approximation(trimmed_surface, surface, domain, size):
    """A NURBS approximation over the file's parameters (``GeomConvert_ApproxSurface``) and its deviation.

    Degrees up to 14 and 200 spans, C2, to :data:`APPROX_RTOL` of the face's size (an offset of a bicubic
    B-spline surface of size 10: 0.01 s, 12 x 39 poles, points within 5e-12 and K, H within 3e-10 of
    OpenCASCADE's); the deviation is measured at the 25 points that check a parameter map.
    """
    from OCP.GeomAbs import GeomAbs_Shape
    from OCP.GeomConvert import GeomConvert_ApproxSurface

    approx = GeomConvert_ApproxSurface(trimmed_surface, APPROX_RTOL * size, GeomAbs_Shape.GeomAbs_C2,
                                       GeomAbs_Shape.GeomAbs_C2, 14, 14, 200, 1)
    if not approx.HasResult():
        raise ValueError("GeomConvert_ApproxSurface found no NURBS approximation of the face's surface")
    nurbs = lab_surface(_clamped(approx.Surface()))
    identity = [ParameterMap.identity()]
    _, _, deviation = _find_maps(surface, nurbs, domain, candidates=(identity, identity))
    return nurbs, deviation


def _file_surface(nurbs, maps, domain, kind):
    """The NURBS itself (B-spline faces) or a :class:`ReparametrizedSurface` in the file's parameters."""
    if maps is None:
        return nurbs
    return ReparametrizedSurface(nurbs, maps[0], maps[1], domain, name=f"{kind} in the file's parameters")


# -- trimming loops ------------------------------------------------------------------------------------


def _loops(face, box):
    """The face's wires as (u, v) polylines in the file's parameters, outer first, each closed implicitly.

    Each pcurve within :data:`PCURVE_RTOL` of the smaller side of the face's (u, v) box ``box``, in the
    wire's order and sense (an edge reversed in its wire runs its pcurve backwards).
    """
    from OCP.BRepAdaptor import BRepAdaptor_Curve2d
    from OCP.BRepTools import BRepTools, BRepTools_WireExplorer
    from OCP.TopAbs import TopAbs_REVERSED, TopAbs_WIRE
    from OCP.TopExp import TopExp_Explorer

    (u0, u1), (v0, v1) = box
    deflection = PCURVE_RTOL * min(u1 - u0, v1 - v0)
    outer = BRepTools.OuterWire_s(face)
    wires = []
    explorer = TopExp_Explorer(face, TopAbs_WIRE)
    while explorer.More():
        wires.append(_cast("Wire")(explorer.Current()))
        explorer.Next()
    wires.sort(key=lambda w: not w.IsSame(outer))
    loops = []
    for wire in wires:
        parts = []
        walk = BRepTools_WireExplorer(wire, face)
        while walk.More():
            edge = walk.Current()
            points = pcurve_points(BRepAdaptor_Curve2d(edge, face), deflection, edge.Orientation() == TopAbs_REVERSED)
            parts.append(points[:-1])  # its last point is the next pcurve's first
            walk.Next()
        if parts:
            loops.append(np.concatenate(parts))
    return loops


def _oriented(loops, domain):
    """Loops clipped to the domain, the outer counter-clockwise and the holes clockwise."""
    out = []
    for n, L in enumerate(loops):
        L = _clip(L, domain)
        a = signed_area(L)
        if (n == 0 and a < 0) or (n > 0 and a > 0):
            L = L[::-1]
        out.append(L)
    return out


def _is_full_domain(loop, domain, rtol=1e-9):
    """Whether an outer loop is the boundary of the domain (an untrimmed patch)."""
    (u0, u1), (v0, v1) = domain
    area = (u1 - u0) * (v1 - v0)
    return abs(signed_area(loop) - area) <= rtol * area


def _face(index, face):
    """A :class:`Face` in the file's parameters (or raises ValueError with the reason)."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepTools import BRepTools
    from OCP.TopAbs import TopAbs_REVERSED

    kind = _kind(BRep_Tool.Surface_s(face))
    nurbs, maps, domain, exact, deviation = _nurbs(face, kind)
    surface = _file_surface(nurbs, maps, domain, kind)
    box = domain
    if maps is None:  # the pcurves' box within the surface's domain (a B-spline face may use part of it)
        u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
        (a0, a1), (b0, b1) = domain
        inner = ((max(u0, a0), min(u1, a1)), (max(v0, b0), min(v1, b1)))
        if inner[0][1] > inner[0][0] and inner[1][1] > inner[1][0]:
            box = inner
    loops = _oriented(_loops(face, box), domain)
    trim = None
    if loops and not (len(loops) == 1 and _is_full_domain(loops[0], domain)):
        trim = trimmed(surface, loops[0], loops[1:])
    return Face(index, kind, nurbs, trim, face.Orientation() == TopAbs_REVERSED, file_surface=surface, domain=box,
                maps=maps, exact=exact, deviation=deviation)


_STEP_FACE = re.compile(rb"=\s*(?:ADVANCED_FACE|FACE_SURFACE)\s*\(")


def step_face_count(path):
    """How many faces a STEP file names (its ``ADVANCED_FACE`` and ``FACE_SURFACE`` entities), or None for
    another format: a reader that skips a damaged entity transfers fewer, and says so only in its log."""
    if EXTENSIONS.get(os.path.splitext(os.fspath(path))[1].lower()) != "STEP":
        return None
    with open(path, "rb") as fh:
        return len(_STEP_FACE.findall(fh.read()))


def _faces_of(shape):
    """The shape's faces in the explorer's order (each once) and the map that numbers them."""
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp

    face_map = _shape_map()
    TopExp.MapShapes_s(shape, TopAbs_FACE, face_map)
    return [_cast("Face")(face_map.FindKey(i + 1)) for i in range(face_map.Extent())], face_map


def _sewn(path, shape, shapes, face_map, sew):
    """``(shape, owner, sewing tolerance or None)``: the file's faces sewn if ``sew`` says so (None: when they
    have free edges), else the file's shape; ``owner(face)`` is a face's file index (-1: none)."""
    from .sewing import _ancestors, _free_edges, sew_faces

    sewing = sew
    if sewing is None:
        sewing = len(shapes) > 1 and _free_edges(_ancestors(shape)) > 0
    if sewing and len(shapes) > 1:
        try:
            return sew_faces(shape, shapes)
        except Exception as exc:  # noqa: BLE001 - OCCT raises Standard_Failure subclasses: say so, keep the file's edges
            warnings.warn(f"{os.fspath(path)}: sewing the faces failed ({type(exc).__name__}: {exc}); "
                          "model.edges holds only the edges the file itself shares", UserWarning, stacklevel=4)
    return shape, lambda f: face_map.FindIndex(f) - 1, None


def oriented_shape(path, model):
    """The shape of a model read with ``orient=True`` from ``path``, as it was oriented (for :func:`lab.write`)."""
    from .sewing import orient_shells

    shape = occ_shape(path)
    shapes, face_map = _faces_of(shape)
    sewn, owner, _ = _sewn(path, shape, shapes, face_map, None)
    return orient_shells(sewn, owner, {f.index: f.reversed for f in model.faces})[0]


def read_occ(path, name=None, sew=None, orient=False):
    """A :class:`Model` of a STEP, IGES or BREP file (see :func:`lab.read`).

    Parameters
    ----------
    path : str or os.PathLike
    name : str, optional
    sew : bool or None
        Find the edges that faces share by sewing (``BRepBuilderAPI_Sewing``, see :func:`sew_faces`): ``True``
        always, ``False`` never (only the edges the file itself shares), ``None`` (default) when the file
        has free edges (edges of one face only, e.g. an IGES file's unsewn faces).  Sewing never changes
        the model's faces: they keep the file's order, surfaces, parameters, loops and orientation.  The
        edges are found (and the faces sewn) when ``model.edges`` is first used, not by the read.
    orient : bool
        Orient the faces as a CAD system orients a joined part (:func:`orient_shells`): the faces of each
        shell consistently, closed shells outwards, so that H has one sign convention over the part.  For
        IGES files, whose faces carry no orientation.  Sews (as ``sew`` says) during the read and sets each
        ``Face.reversed`` from the oriented shells; ``model.turned`` says how many faces it turned.
    """
    require_ocp()
    from OCP.BRep import BRep_Tool

    from .sewing import _shared_edges, orient_shells

    if sew not in (None, True, False):
        raise TypeError(f"sew must be True, False or None (sew when the file's faces are not sewn); got {sew!r}")
    if orient not in (True, False):
        raise TypeError(f"orient must be True or False; got {orient!r}")
    shape = occ_shape(path)
    shapes, face_map = _faces_of(shape)  # the explorer's order, each face once
    if not shapes:
        raise ValueError(f"{os.fspath(path)}: the file holds no faces (only points, curves or an empty shape)")
    named = step_face_count(path)
    if named is not None and named > len(shapes):
        warnings.warn(f"{os.fspath(path)}: the file names {named} faces (ADVANCED_FACE, FACE_SURFACE), OpenCASCADE "
                      f"transferred {len(shapes)}: {named - len(shapes)} lost to damaged or unsupported entities "
                      "(the model has the others)", UserWarning, stacklevel=3)
    faces, problems = [], []
    for index, f in enumerate(shapes):
        try:
            faces.append(_face(index, f))
        except Exception as exc:  # noqa: BLE001 - OCCT raises Standard_Failure subclasses; every failure is reported by face
            try:
                kind = _kind(BRep_Tool.Surface_s(f))
            except Exception:  # noqa: BLE001 - the kind is only for the report
                kind = "unknown"
            problems.append(Problem(index, kind, f"{type(exc).__name__}: {exc}"))
    domains = {f.index: f.file_surface.domain for f in faces}

    def find_edges():
        """``(edges, sewing tolerance or None)``, run once when ``model.edges`` is first used."""
        sewn, owner, tolerance = _sewn(path, shape, shapes, face_map, sew)
        return _shared_edges(sewn, owner, domains), tolerance

    if orient:
        sewn, owner, tolerance = _sewn(path, shape, shapes, face_map, sew)
        oriented, senses = orient_shells(sewn, owner, {f.index: f.reversed for f in faces})
        turned = 0
        for f in faces:
            if f.index in senses and senses[f.index] != f.reversed:
                f.reversed, turned = senses[f.index], turned + 1
        # the shared edges of the oriented shells, found when first used as the file's are
        model = Model(faces, lambda: (_shared_edges(oriented, owner, domains), tolerance), problems,
                      path=os.fspath(path), name=name)
        model.turned = turned
        return model

    return Model(faces, find_edges, problems, path=os.fspath(path), name=name)
