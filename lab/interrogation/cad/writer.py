"""Write lab surfaces, trimmed surfaces and models as BREP or STEP through OpenCASCADE (FreeCAD, Rhino and
every STEP reader open them), or as Rhino ``.3dm`` through rhino3dm.

A face is written as its NURBS surface (``Geom_BSplineSurface``: control points, weights, knots as they
are) bounded by its trimming loops: each loop a wire of straight pcurve segments between its (u, v)
points in the NURBS's parameters (a face read in the file's parameters has its loops mapped there by
``face.maps``), outer loop counter-clockwise and holes clockwise, the 3-D edge curves built on the surface
(``BRepLib.BuildCurves3d``) and a reversed face written reversed.  :func:`lab.read` then gives back the
same surfaces, the same loops (their points; the pcurves between them are the straight segments the lab's
loops are) and the same curvature.  An analytic face (cylinder, torus, ...) is written as its exact NURBS,
so it comes back as a B-spline face in the NURBS's parameters (``face.maps`` takes its loops there).
"""

import os
import warnings

import numpy as np

from ...geometry import validation as _v
from ...model.surface import BezierSurface
from .model import Model
from .occ import _cast, require_ocp

__all__ = ["WRITE_EXTENSIONS", "occ_bspline", "occ_face", "write"]

WRITE_EXTENSIONS = (".brep", ".step", ".stp", ".3dm")

#: Tolerance of the written edges (3-D curves built on the surface) and vertices, relative to the part's size.
WRITE_RTOL = 1e-7

#: Sewing tolerance of a model's written faces, relative to the part's size: the faces' loops are the lab's
#: polylines (chordal error 1e-3 of a face's (u, v) box, up to 3e-5 of linkrods' size), so neighbouring faces'
#: written edges lie that far apart, and sewing joins them into shared edges again.
SEW_RTOL = 1e-4


def occ_bspline(surface):
    """A ``Geom_BSplineSurface`` with the control points, weights, knots and degrees of a lab spline surface."""
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Pnt
    from OCP.OCP.collections import Array1_double, Array1_int, Array2_double, Array2_gp_Pnt

    P, knots_u, knots_v, p, q, w = surface._spline_args()
    nu, nv = P.shape[:2]
    poles = Array2_gp_Pnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*map(float, P[i, j])))

    def knots(t):
        values, mult = np.unique(t, return_counts=True)
        K, M = Array1_double(1, len(values)), Array1_int(1, len(values))
        for k, (x, m) in enumerate(zip(values, mult)):
            K.SetValue(k + 1, float(x))
            M.SetValue(k + 1, int(m))
        return K, M

    (ku, mu), (kv, mv) = knots(knots_u), knots(knots_v)
    if w is None:
        return Geom_BSplineSurface(poles, ku, kv, mu, mv, int(p), int(q), False, False)
    W = Array2_double(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            W.SetValue(i + 1, j + 1, float(w[i, j]))
    return Geom_BSplineSurface(poles, W, ku, kv, mu, mv, int(p), int(q), False, False)


class _Piece:
    """One face to write: a lab spline surface, its loops in the surface's parameters (None: untrimmed), its
    orientation and where it comes from (for messages)."""

    def __init__(self, surface, loops=None, reversed_=False, label="surface"):
        if not hasattr(surface, "_spline_args"):
            raise TypeError(f"{label}: only Bézier and B-spline/NURBS surfaces can be written; got "
                            f"{type(surface).__name__}")
        self.surface, self.loops, self.reversed, self.label = surface, loops, bool(reversed_), label


def _mapped(loops, maps):
    """Loops in the file's (u, v) taken to the NURBS's parameters (the maps increase: orientations stay).

    Angles are not wrapped into the turn the NURBS covers (a thread's loop runs over two turns and would
    cross itself): :func:`_covering` extends the surface over the turns the loops need.
    """
    if maps is None:
        return [np.asarray(L, dtype=float) for L in loops]
    maps = [m._replace(period=0.0) if getattr(m, "period", 0.0) else m for m in maps]
    return [np.column_stack([maps[0](L[:, 0])[0], maps[1](L[:, 1])[0]]) for L in loops]


def _covering(surface, loops, rtol=1e-12):
    """The surface repeated over as many periods as the loops' parameters need (a closed direction only).

    A NURBS closed in a direction (first and last rows of control points equal, clamped knots) continues
    periodically: its rows again after the last one, its knots shifted by the period, the knot at the
    joint of multiplicity ``degree`` (the rows meet there as at the surface's own closing).
    """
    from ...model.surface import BSplineSurface

    X = np.concatenate(loops)
    for axis in (0, 1):
        (lo, hi) = surface.domain[axis]
        period = hi - lo
        before = int(np.ceil((lo - X[:, axis].min()) / period - rtol)) if X[:, axis].min() < lo else 0
        after = int(np.ceil((X[:, axis].max() - hi) / period - rtol)) if X[:, axis].max() > hi else 0
        if not (before or after):
            continue
        P, ku, kv, p_u, p_v, w = surface._spline_args()
        P, w = np.moveaxis(P, axis, 0), None if w is None else np.moveaxis(w, axis, 0)
        knots, p = (ku, p_u) if axis == 0 else (kv, p_v)
        if not np.allclose(P[0], P[-1], rtol=0, atol=1e-9 * np.ptp(P)) or np.any(knots[: p + 1] != lo) \
                or np.any(knots[-p - 1 :] != hi):
            raise ValueError(f"the face's loops leave its surface's domain in {'uv'[axis]} and the surface "
                             "does not close there")
        inner = knots[p + 1 : -p - 1]
        turns = range(-before, after + 1)
        rows = np.concatenate([P[:1]] + [P[1:]] * len(turns))
        weights = None if w is None else np.concatenate([w[:1]] + [w[1:]] * len(turns))
        new = [np.full(p + 1, lo - before * period)]
        for k, t in enumerate(turns):
            new += [inner + t * period] + ([np.full(p, hi + t * period)] if k < len(turns) - 1 else [])
        new.append(np.full(p + 1, hi + after * period))
        new = np.concatenate(new)
        rows, weights = np.moveaxis(rows, 0, axis), None if weights is None else np.moveaxis(weights, 0, axis)
        ku, kv = (new, kv) if axis == 0 else (ku, new)
        surface = BSplineSurface(rows, ku, kv, p_u, p_v, weights=weights)
    return surface


def _pieces(obj):
    """The faces to write, as :class:`_Piece`."""
    _v.refuse_class(obj, "a lab.Model, a lab.TrimmedSurface, a lab.BezierSurface or a lab.BSplineSurface")
    if isinstance(obj, Model):
        out = []
        for f in obj.faces:
            loops = None if f.trim is None else _mapped(f.trim.loops, f.maps)
            out.append(_Piece(f.surface, loops, f.reversed, f"face {f.index} ({f.kind})"))
        return out
    if hasattr(obj, "outer") and hasattr(obj, "holes") and hasattr(obj, "surface"):  # lab.TrimmedSurface
        return [_Piece(obj.surface, [obj.outer] + list(obj.holes), False, "the trimmed surface's base surface")]
    if hasattr(obj, "_spline_args"):
        return [_Piece(obj)]
    if hasattr(obj, "control_points") and hasattr(obj, "__iter__"):  # BezierPatches
        return [_Piece(BezierSurface(patch.control_points, patch.weights), label=f"patch {k}")
                for k, patch in enumerate(obj)]
    raise TypeError(f"write needs a lab.Model, a lab.TrimmedSurface, a lab.BezierSurface or a lab.BSplineSurface; "
                    f"got {type(obj).__name__}")


def _size(pieces):
    P = np.concatenate([p.surface.control_points.reshape(-1, 3) for p in pieces])
    return float(np.linalg.norm(np.ptp(P, axis=0))) or 1.0


def _wire(loop, surface, tol):
    """A closed wire of straight pcurve segments through the loop's (u, v) points on ``surface``.

    Consecutive edges share their vertex, and so do loop points at one point in space; a segment that is one point in space (along a collapsed border of
    the surface, a pole; its ends and three points between them coincide) becomes a degenerated edge, as
    OpenCASCADE's own faces have there.
    """
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeVertex
    from OCP.Geom2d import Geom2d_Line
    from OCP.gp import gp_Dir2d, gp_Pnt2d
    from OCP.TopAbs import TopAbs_FORWARD, TopAbs_REVERSED
    from OCP.TopoDS import TopoDS_Edge, TopoDS_Wire

    builder = BRep_Builder()
    wire = TopoDS_Wire()
    builder.MakeWire(wire)
    X = np.asarray(loop, dtype=float)
    points = [surface.Value(float(u), float(v)) for u, v in X]
    xyz = np.array([[p.X(), p.Y(), p.Z()] for p in points])
    vertices = []  # one vertex per point in space: a loop that meets itself there (a seam, a pole) shares it
    for i in range(len(X)):
        near = np.flatnonzero(np.linalg.norm(xyz[:i] - xyz[i], axis=1) <= tol) if i else []
        vertices.append(vertices[near[0]] if len(near) else BRepBuilderAPI_MakeVertex(points[i]).Vertex())
    k = len(X)
    for i in range(k):
        j = (i + 1) % k
        a, b = gp_Pnt2d(*map(float, X[i])), gp_Pnt2d(*map(float, X[j]))
        length = a.Distance(b)
        segment = Geom2d_Line(a, gp_Dir2d(b.X() - a.X(), b.Y() - a.Y()))  # parameter: length along it
        inner = [surface.Value(*map(float, X[i] + f * (X[j] - X[i]))) for f in (0.25, 0.5, 0.75)]
        if max(p.Distance(points[i]) for p in [*inner, points[j]]) > tol:  # not a collapsed border
            edge = BRepBuilderAPI_MakeEdge(segment, surface, vertices[i], vertices[j], 0.0, length).Edge()
        else:  # a collapsed border: no 3-D curve, one vertex
            edge = TopoDS_Edge()
            builder.MakeEdge(edge)
            builder.UpdateEdge(edge, segment, surface, _identity(), tol)
            builder.Range(edge, 0.0, length)
            builder.Degenerated(edge, True)
            builder.Add(edge, vertices[i].Oriented(TopAbs_FORWARD))
            builder.Add(edge, vertices[j].Oriented(TopAbs_REVERSED))
        builder.Add(wire, edge)
    return wire


def _identity():
    from OCP.TopLoc import TopLoc_Location

    return TopLoc_Location()


def occ_face(surface, loops=None, reversed_=False, tol=1e-7):
    """A ``TopoDS_Face`` of a lab spline surface bounded by loops in its parameters (see the module docstring).

    Parameters
    ----------
    surface : lab.BSplineSurface or lab.BezierSurface
    loops : list of (k, 2) ndarray or None
        The outer loop (counter-clockwise) and the holes (clockwise) in the surface's parameters; None:
        the surface's natural bounds.
    reversed_ : bool
        Write the face reversed (its normal ``-(b_u x b_v)``).
    tol : float
        Tolerance of the edges and vertices.
    """
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepLib import BRepLib
    from OCP.TopoDS import TopoDS_Face

    if loops is not None:
        surface = _covering(surface, loops)
    geom = occ_bspline(surface)
    if loops is None:
        face = BRepBuilderAPI_MakeFace(geom, tol).Face()
    else:
        builder = BRep_Builder()
        face = TopoDS_Face()
        builder.MakeFace(face, geom, tol)
        for loop in loops:
            builder.Add(face, _wire(loop, geom, tol))
        if not BRepLib.BuildCurves3d_s(face, tol):
            raise ValueError("OpenCASCADE could not build the 3-D curves of the face's trimming edges")
        BRepLib.UpdateTolerances_s(face, True)
    return _cast("Face")(face.Reversed()) if reversed_ else face


def _sewn(faces, tolerance):
    """The faces sewn (``BRepBuilderAPI_Sewing``) into one shell, in their order and with their orientation, so
    that a reader sees the part's shared edges, not loose faces (sewing alone would reorder them, and making a
    solid could turn them round)."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing
    from OCP.TopoDS import TopoDS_Shell

    sewing = BRepBuilderAPI_Sewing(float(tolerance))
    for f in faces:
        sewing.Add(f)
    sewing.Perform()
    builder, shell = BRep_Builder(), TopoDS_Shell()
    builder.MakeShell(shell)
    for f in faces:
        g = _cast("Face")(sewing.Modified(f)) if sewing.IsModified(f) else f
        builder.Add(shell, g if g.Orientation() == f.Orientation() else _cast("Face")(g.Reversed()))
    return shell


def write(obj, path, *, drop_trims=False, sew=True):
    """Write a :class:`Model`, a :class:`lab.TrimmedSurface`, a :class:`lab.BezierSurface` or a
    :class:`lab.BSplineSurface` (or a :class:`lab.BezierPatches`).

    Parameters
    ----------
    obj : Model, TrimmedSurface, BezierSurface, BSplineSurface or BezierPatches
    path : str or os.PathLike
        ``.brep`` (OpenCASCADE's own format) or ``.step``/``.stp`` (AP214): one face per surface, trimmed
        faces with their loops (see the module docstring), in a compound; ``.3dm`` (Rhino, through
        rhino3dm): NURBS surfaces, without orientation and without trims (rhino3dm's Brep offers no way to
        add trimming curves to a face).  Control points, weights, knots and parameters are written as they
        are, so :func:`lab.read` gives the same surfaces back.
    drop_trims : bool
        ``.3dm`` only: write trimmed faces as their untrimmed surfaces (with a warning naming them) instead
        of refusing them.
    sew : bool
        ``.brep``/``.step`` with several faces built by the lab: sew them (at :data:`SEW_RTOL` of the part's
        size) into one shell, in their order and orientation, so that the part keeps shared edges; ``False``:
        loose faces in a compound.  A model read from a STEP, IGES or BREP file is written from the file's own shape
        (its exact edges, shells and solids: a conversion, e.g. IGES to STEP), not face by face; read with
        ``orient=True``, as its sewn and oriented shells and solids.

    Returns
    -------
    str
        The path written.

    Raises
    ------
    ValueError
        An unknown file type; trimmed faces for ``.3dm`` without ``drop_trims``; OpenCASCADE or rhino3dm
        failing to write.
    TypeError
        Something that is not a lab spline surface, model or trimmed surface.
    """
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext not in WRITE_EXTENSIONS:
        raise ValueError(f"{path}: cannot write {ext or '(no extension)'!r}; expected one of {', '.join(WRITE_EXTENSIONS)}")
    pieces = _pieces(obj)
    if ext == ".3dm":
        from .rhino import write_3dm

        trimmed = [p.label for p in pieces if p.loops is not None]
        if trimmed and not drop_trims:
            raise ValueError(f"{path}: rhino3dm cannot write trimming loops (its Brep offers no way to add trims "
                             f"to a face), and {len(trimmed)} faces have them ({', '.join(trimmed[:4])}"
                             f"{' ...' if len(trimmed) > 4 else ''}); write .brep or .step, or pass "
                             "drop_trims=True to write their untrimmed surfaces")
        if trimmed:
            warnings.warn(f"{path}: {len(trimmed)} trimmed faces written untrimmed ({', '.join(trimmed[:4])}"
                          f"{' ...' if len(trimmed) > 4 else ''}): rhino3dm cannot write trimming loops",
                          UserWarning, stacklevel=2)
        return write_3dm([(p.surface, p.reversed) for p in pieces], path)
    require_ocp()
    from OCP.BRep import BRep_Builder
    from OCP.TopoDS import TopoDS_Compound

    original = _file_shape(obj)
    if original is not None:  # a part read from a CAD file: its own shape, exact edges and topology
        return _write_shape(original, path, ext)
    tol = WRITE_RTOL * _size(pieces)
    builder = BRep_Builder()
    compound = TopoDS_Compound()
    builder.MakeCompound(compound)
    faces = []
    for piece in pieces:
        try:
            faces.append(occ_face(piece.surface, piece.loops, piece.reversed, tol))
        except Exception as exc:
            raise ValueError(f"{path}: {piece.label} could not be written: {type(exc).__name__}: {exc}") from exc
        builder.Add(compound, faces[-1])
    shape = _sewn(faces, SEW_RTOL * _size(pieces)) if sew and len(faces) > 1 else compound
    return _write_shape(shape, path, ext)


def _file_shape(obj):
    """The OpenCASCADE shape of a model read from a STEP, IGES or BREP file that is still there, else None."""
    from .occ import EXTENSIONS, occ_shape, oriented_shape

    path = getattr(obj, "path", None) if isinstance(obj, Model) else None
    if path is None or os.path.splitext(path)[1].lower() not in EXTENSIONS or not os.path.isfile(path):
        return None
    return occ_shape(path) if obj.turned is None else oriented_shape(path, obj)


def _write_shape(shape, path, ext):
    from OCP.BRepTools import BRepTools

    from .occ import _quiet

    _quiet()  # the STEP writer prints its statistics to stdout otherwise

    if ext == ".brep":
        if not BRepTools.Write_s(shape, path):
            raise ValueError(f"{path}: OpenCASCADE could not write the BREP file")
        return path
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    writer = STEPControl_Writer()
    if writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone or writer.Write(path) != IFSelect_RetDone:
        raise ValueError(f"{path}: OpenCASCADE could not write the STEP file")
    return path
