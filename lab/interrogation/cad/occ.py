"""STEP, IGES and BREP files through OpenCASCADE (``cadquery-ocp-novtk``, the lab's extra ``cad``).

Only :func:`read_occ` imports ``OCP``, and only when it is called, so ``import lab`` stays free of it.
A face's surface becomes a :class:`lab.BSplineSurface` with the file's poles,
weights and knots (periodic surfaces get their clamped, non-periodic form,
same parameters); analytic faces (plane, cylinder, cone, sphere, torus,
revolution, extrusion, offset) are converted by ``BRepBuilderAPI_NurbsConvert``,
which also rewrites their pcurves, so that loops and surface stay consistent.
"""

import os

import numpy as np

from ...model.surface import BSplineSurface
from ..trimming import trimmed
from ..trimming.loops import signed_area
from .model import Edge, Face, Model, Problem

__all__ = ["EXTENSIONS", "occ_shape", "read_occ", "require_ocp"]

#: File name endings read through OpenCASCADE.
EXTENSIONS = {".step": "STEP", ".stp": "STEP", ".iges": "IGES", ".igs": "IGES", ".brep": "BREP", ".brp": "BREP"}

#: Samples per pcurve that is not a straight line (a line gets its two ends).
PCURVE_SAMPLES = 24

_KINDS = ("Plane", "Cylinder", "Cone", "Sphere", "Torus", "BezierSurface", "BSplineSurface",
          "SurfaceOfRevolution", "SurfaceOfExtrusion", "OffsetSurface", "OtherSurface")


def require_ocp():
    """Import OCP or raise an ImportError that says how to install it."""
    try:
        import OCP  # noqa: F401
    except ImportError:
        raise ImportError(
            "reading STEP, IGES and BREP files needs OpenCASCADE: pip install -e '.[cad]' "
            "(the package cadquery-ocp-novtk); make setup installs it"
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


def _weights(bs):
    """The weights as an ``Array2_double`` and an ndarray, read one by one.

    ``Geom_BSplineSurface.Weights()`` must not be called from Python: OCP hands
    out the surface's own array as a pointer it then frees (a double free).
    """
    from OCP.OCP.collections import Array2_double

    nu, nv = bs.NbUPoles(), bs.NbVPoles()
    w = np.array([[bs.Weight(i + 1, j + 1) for j in range(nv)] for i in range(nu)])
    W = Array2_double(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            W.SetValue(i + 1, j + 1, float(w[i, j]))
    return W, w


def _bspline(face):
    """The face's ``Geom_BSplineSurface`` (a non-periodic copy if periodic: same parameters), or None."""
    from OCP.BRep import BRep_Tool
    from OCP.Geom import Geom_BSplineSurface
    from OCP.GeomAdaptor import GeomAdaptor_Surface

    adaptor = GeomAdaptor_Surface(BRep_Tool.Surface_s(face))
    if adaptor.GetType().name != "GeomAbs_BSplineSurface":
        return None
    bs = adaptor.BSpline()
    if bs.IsUPeriodic() or bs.IsVPeriodic():
        copy = Geom_BSplineSurface(bs.Poles(), _weights(bs)[0], bs.UKnots(), bs.VKnots(), bs.UMultiplicities(),
                                   bs.VMultiplicities(), bs.UDegree(), bs.VDegree(), bs.IsUPeriodic(),
                                   bs.IsVPeriodic())
        if copy.IsUPeriodic():
            copy.SetUNotPeriodic()
        if copy.IsVPeriodic():
            copy.SetVNotPeriodic()
        bs = copy
    return bs


def lab_surface(bs):
    """A :class:`lab.BSplineSurface` with the poles, weights, knots and degrees of a ``Geom_BSplineSurface``."""
    nu, nv = bs.NbUPoles(), bs.NbVPoles()
    poles = bs.Poles()
    P = np.empty((nu, nv, 3))
    for i in range(nu):
        for j in range(nv):
            p = poles.Value(i + 1, j + 1)
            P[i, j] = p.X(), p.Y(), p.Z()
    weights = _weights(bs)[1] if (bs.IsURational() or bs.IsVRational()) else None
    ku, kv = bs.UKnotSequence(), bs.VKnotSequence()
    knots_u = np.array([ku.Value(k) for k in range(ku.Lower(), ku.Upper() + 1)])
    knots_v = np.array([kv.Value(k) for k in range(kv.Lower(), kv.Upper() + 1)])
    return BSplineSurface(P, knots_u, knots_v, bs.UDegree(), bs.VDegree(), weights=weights)


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


def _pcurve(edge, face, n=PCURVE_SAMPLES):
    """``(t, uv (k, 2))`` of the edge's pcurve on the face, in the edge's direction within the face's wire."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve2d
    from OCP.TopAbs import TopAbs_REVERSED

    c2d = BRepAdaptor_Curve2d(edge, face)
    line = c2d.GetType().name == "GeomAbs_Line"
    t = np.linspace(c2d.FirstParameter(), c2d.LastParameter(), 2 if line else n)
    if edge.Orientation() == TopAbs_REVERSED:
        t = t[::-1]
    return t, _values2d(c2d, t)


def _values2d(c2d, t):
    uv = np.empty((len(t), 2))
    for k, x in enumerate(t):
        p = c2d.Value(float(x))
        uv[k] = p.X(), p.Y()
    return uv


def _loops(face):
    """The face's wires as (u, v) polylines, outer first, each closed implicitly."""
    from OCP.BRepTools import BRepTools, BRepTools_WireExplorer
    from OCP.TopAbs import TopAbs_WIRE
    from OCP.TopExp import TopExp_Explorer

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
            parts.append(_pcurve(walk.Current(), face)[1][:-1])
            walk.Next()
        if parts:
            loops.append(np.concatenate(parts))
    return loops


def _to_nurbs(face):
    """The face converted by ``BRepBuilderAPI_NurbsConvert`` (surface and pcurves rewritten together)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer

    converter = BRepBuilderAPI_NurbsConvert(face, True)
    explorer = TopExp_Explorer(converter.Shape(), TopAbs_FACE)
    if not explorer.More():
        raise ValueError("BRepBuilderAPI_NurbsConvert gave no face")
    return _cast("Face")(explorer.Current())


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
    """A :class:`Face` (or raises ValueError with the reason) and the face whose pcurves it uses."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_REVERSED

    kind = _kind(BRep_Tool.Surface_s(face))
    used = face
    bs = _bspline(face)
    if bs is None:
        used = _to_nurbs(face)
        bs = _bspline(used)
        if bs is None:
            got = _kind(BRep_Tool.Surface_s(used))
            raise ValueError(f"BRepBuilderAPI_NurbsConvert did not give a B-spline surface (got {got})")
    surface = lab_surface(bs)
    loops = _oriented(_loops(used), surface.domain)
    trim = None
    if loops and not (len(loops) == 1 and _is_full_domain(loops[0], surface.domain)):
        trim = trimmed(surface, loops[0], loops[1:])
    return Face(index, kind, surface, trim, face.Orientation() == TopAbs_REVERSED), (None if used is face else bs)


def _clip(uv, domain):
    """(u, v) points moved into the domain (pcurves and projections may stray by OpenCASCADE's tolerance)."""
    (u0, u1), (v0, v1) = domain
    return np.column_stack([np.clip(uv[:, 0], u0, u1), np.clip(uv[:, 1], v0, v1)])


def _shared_edges(shape, face_map, converted, domains):
    """Edges between two faces, sampled at the same parameters of the 3-D curve, with both faces' (u, v).

    A face's (u, v) come from its pcurve at the edge curve's parameter (OpenCASCADE's edges are same-parameter);
    on a face converted to NURBS they are found by projecting the edge's points (``ShapeAnalysis_Surface``).
    """
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Curve2d
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.ShapeAnalysis import ShapeAnalysis_Surface
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp

    ancestors = _shape_map(data=True)
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, ancestors)
    analysers = {}
    edges = []
    for k in range(1, ancestors.Extent() + 1):
        edge = _cast("Edge")(ancestors.FindKey(k))
        if BRep_Tool.Degenerated_s(edge):
            continue
        around = ancestors.FindFromIndex(k)
        if around.Size() < 2:
            continue  # a free edge (IGES faces are often not sewn)
        owners = []
        for f in around:
            i = face_map.FindIndex(f) - 1
            if i >= 0 and i in domains and i not in [o for o, _ in owners]:
                owners.append((i, _cast("Face")(f)))
        if len(owners) != 2:
            continue  # a free edge or a seam of one face
        try:
            curve = BRepAdaptor_Curve(edge)
            t = np.linspace(curve.FirstParameter(), curve.LastParameter(), PCURVE_SAMPLES)
            points, tangents = np.empty((len(t), 3)), np.empty((len(t), 3))
            p, d = gp_Pnt(), gp_Vec()
            for n, x in enumerate(t):
                curve.D1(float(x), p, d)
                points[n], tangents[n] = (p.X(), p.Y(), p.Z()), (d.X(), d.Y(), d.Z())
            uvs = []
            for i, f in owners:
                if i in converted:
                    if i not in analysers:
                        analysers[i] = ShapeAnalysis_Surface(converted[i])
                    sas = analysers[i]
                    uvs.append(np.array([[q.X(), q.Y()] for q in (sas.ValueOfUV(gp_Pnt(*p), 1e-9) for p in points)]))
                else:
                    uvs.append(_values2d(BRepAdaptor_Curve2d(edge, f), t))
        except Exception:  # noqa: BLE001, S112 - an edge OpenCASCADE cannot evaluate is not a shared edge of the model
            continue
        uvs = [_clip(uv, domains[i]) for uv, (i, _) in zip(uvs, owners)]
        edges.append(Edge(len(edges), tuple(i for i, _ in owners), points, tuple(uvs), t, tangents))
    return edges


def read_occ(path, name=None):
    """A :class:`Model` of a STEP, IGES or BREP file (see :func:`lab.read`)."""
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp

    shape = occ_shape(path)
    face_map = _shape_map()
    TopExp.MapShapes_s(shape, TopAbs_FACE, face_map)  # the explorer's order, each face once
    if face_map.Extent() == 0:
        raise ValueError(f"{os.fspath(path)}: the file holds no faces (only points, curves or an empty shape)")
    faces, problems, converted = [], [], {}
    for index in range(face_map.Extent()):
        f = _cast("Face")(face_map.FindKey(index + 1))
        try:
            face, bs = _face(index, f)
        except Exception as exc:  # noqa: BLE001 - OCCT raises Standard_Failure subclasses; every failure is reported by face
            try:
                kind = _kind(BRep_Tool.Surface_s(f))
            except Exception:  # noqa: BLE001 - the kind is only for the report
                kind = "unknown"
            problems.append(Problem(index, kind, f"{type(exc).__name__}: {exc}"))
            continue
        faces.append(face)
        if bs is not None:
            converted[index] = bs
    edges = _shared_edges(shape, face_map, converted, {f.index: f.domain for f in faces})
    return Model(faces, edges, problems, path=os.fspath(path), name=name)
