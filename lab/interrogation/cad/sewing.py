"""The edges two faces of a part share, found in the file or by sewing its faces (``BRepBuilderAPI_Sewing``).

Used by :func:`lab.interrogation.cad.occ.read_occ` when ``model.edges`` is first used; imports ``OCP`` only
inside its functions.
"""

import numpy as np

from .curves import _cast, _clip, _shape_map, curve2d_values, curve3d_values
from .model import Edge

__all__ = ["PCURVE_SAMPLES", "SEW_RTOL", "orient_shells", "sew_faces"]

#: Samples per shared edge (the 3-D curve and both pcurves at the same parameters).
PCURVE_SAMPLES = 24

#: Sewing tolerance, relative to the part's size (bounding-box diagonal), unless the shape's own tolerances
#: are larger (see :func:`sew_faces`).
SEW_RTOL = 1e-6


def _free_edges(ancestors):
    """How many edges (not degenerate) bound only one face: a part whose faces are not sewn has many."""
    from OCP.BRep import BRep_Tool

    free = 0
    for k in range(1, ancestors.Extent() + 1):
        if ancestors.FindFromIndex(k).Size() == 1 and not BRep_Tool.Degenerated_s(_cast("Edge")(ancestors.FindKey(k))):
            free += 1
    return free


def _ancestors(shape):
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp

    ancestors = _shape_map(data=True)
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, ancestors)
    return ancestors


def _bounding_size(shape):
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box, False)
    if box.IsVoid():
        return 1.0
    lo, hi = box.CornerMin(), box.CornerMax()
    return float(np.linalg.norm([hi.X() - lo.X(), hi.Y() - lo.Y(), hi.Z() - lo.Z()])) or 1.0


def sew_faces(shape, faces, tolerance=None):
    """The faces sewn with ``BRepBuilderAPI_Sewing`` and, per sewn face, the index of the file's face.

    Sewing merges edges of different faces that lie within ``tolerance`` of each other (default
    :data:`SEW_RTOL` of the part's size, or the shape's largest tolerance if that is larger) into one edge
    with a pcurve on each face; it keeps the faces' surfaces, may give a face new edges and pcurves
    (projected onto the same surface, so in the same parameters) and may reverse faces to orient a shell
    consistently.  The lab uses the sewn shape only for its shared edges.

    Parameters
    ----------
    shape : TopoDS_Shape
    faces : list of TopoDS_Face
        The file's faces, in the file's order.
    tolerance : float, optional

    Returns
    -------
    sewn : TopoDS_Shape
    owner : dict
        Sewn ``TopoDS_Face`` (hashed by OpenCASCADE's shape map) -> file index, as a function ``owner(face)``.
    tolerance : float
        The tolerance used.
    """
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Sewing
    from OCP.ShapeAnalysis import ShapeAnalysis_ShapeTolerance

    if tolerance is None:
        largest = ShapeAnalysis_ShapeTolerance().Tolerance(shape, 1)  # 1: the largest
        tolerance = max(SEW_RTOL * _bounding_size(shape), largest)
    sewing = BRepBuilderAPI_Sewing(float(tolerance))
    for f in faces:
        sewing.Add(f)
    sewing.Perform()
    sewn = sewing.SewedShape()
    index = _shape_map()
    owners = []
    for i, f in enumerate(faces):
        g = sewing.Modified(f) if sewing.IsModified(f) else f
        if index.FindIndex(g) == 0:
            index.Add(g)
            owners.append(i)

    def owner(face):
        k = index.FindIndex(face)
        return owners[k - 1] if k > 0 else -1

    return sewn, owner, float(tolerance)


def orient_shells(shape, owner, file_reversed):
    """The faces of a sewn part oriented as a CAD system orients a joined part.

    Within a shell the faces are consistent as sewing leaves them; a closed shell is made a solid and turned
    to face outwards (``BRepLib::OrientClosedSolid``, as a STEP or BREP solid is); an open shell, which has no
    outside, is turned so that most of its faces keep the file's orientation.  Faces in no shell keep theirs.

    Parameters
    ----------
    shape : TopoDS_Shape
        The sewn part (or the file's shape when its faces already share their edges).
    owner : callable
        ``owner(face)``: the file index of a face of ``shape`` (-1: none).
    file_reversed : dict
        File index -> the face's orientation in the file (``Face.reversed``).

    Returns
    -------
    oriented : TopoDS_Compound
        The solids, open shells and loose faces, oriented, each with its faces in the file's order (a part
        in one shell is written in the file's face order).
    reversed : dict
        File index -> its orientation in ``oriented``.
    """
    from OCP.BRep import BRep_Builder, BRep_Tool
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeSolid
    from OCP.BRepLib import BRepLib
    from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED, TopAbs_SHELL
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS_Compound, TopoDS_Shell, TopoDS_Solid

    def faces(piece):
        """``[(file index, face as oriented in piece), ...]`` in the file's order."""
        out = {}
        walk = TopExp_Explorer(piece, TopAbs_FACE)
        while walk.More():
            i = owner(walk.Current())
            if i >= 0:
                out.setdefault(i, walk.Current())
            walk.Next()
        return sorted(out.items(), key=lambda item: item[0])

    builder = BRep_Builder()
    pieces = []  # (first file index, shell or solid rebuilt with its faces in the file's order)
    loose = []
    shells = TopExp_Explorer(shape, TopAbs_SHELL)
    while shells.More():
        piece = shells.Current()
        closed = BRep_Tool.IsClosed_s(piece)
        if closed:
            solid = BRepBuilderAPI_MakeSolid(_cast("Shell")(piece)).Solid()
            closed = BRepLib.OrientClosedSolid_s(solid)  # False: not a valid solid; treated as an open shell
            if closed:
                piece = solid
        found = faces(piece)
        if not closed and 2 * sum((f.Orientation() == TopAbs_REVERSED) == file_reversed.get(i, False)
                                  for i, f in found) < len(found):
            found = [(i, f.Reversed()) for i, f in found]
        shell = TopoDS_Shell()
        builder.MakeShell(shell)
        for _i, f in found:
            builder.Add(shell, f)
        shell.Closed(closed)
        if closed:
            solid = TopoDS_Solid()
            builder.MakeSolid(solid)
            builder.Add(solid, shell)
            shell = solid
        if found:
            pieces.append((found[0][0], shell))
        shells.Next()
    walk = TopExp_Explorer(shape, TopAbs_FACE, TopAbs_SHELL)
    while walk.More():
        loose += faces(walk.Current())
        walk.Next()
    oriented = TopoDS_Compound()
    builder.MakeCompound(oriented)
    for _i, piece in sorted(pieces + loose, key=lambda item: item[0]):
        builder.Add(oriented, piece)
    reversed_ = {i: f.Orientation() == TopAbs_REVERSED for i, f in faces(oriented)}
    return oriented, reversed_


def _shared_edges(shape, owner, domains):
    """Edges between two faces, sampled at the same parameters of the 3-D curve, with both faces' (u, v).

    ``owner(face)`` is the file index of a face of ``shape`` (-1: none).  A face's (u, v) come from its
    pcurve at the edge curve's parameter (OpenCASCADE's edges are same-parameter), in the file's parameters.
    The pcurve is taken of the edge as the face holds it: where a periodic surface has two pcurves for an
    edge (u = 0 and u = 2 pi), the edge's orientation in the face chooses the one the face's loop uses.
    """
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Curve2d
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_REVERSED
    from OCP.TopExp import TopExp_Explorer

    ancestors = _ancestors(shape)
    held = {}  # (edge index, file index) -> [(face, edge as the face holds it), ...]
    faces = TopExp_Explorer(shape, TopAbs_FACE)
    while faces.More():
        face = _cast("Face")(faces.Current())
        i = owner(face)
        if i >= 0 and i in domains:
            walk = TopExp_Explorer(face, TopAbs_EDGE)
            while walk.More():
                held.setdefault((ancestors.FindIndex(walk.Current()), i), []).append((face, _cast("Edge")(walk.Current())))
                walk.Next()
        faces.Next()
    edges = []
    for k in range(1, ancestors.Extent() + 1):
        edge = _cast("Edge")(ancestors.FindKey(k))
        if ancestors.FindFromIndex(k).Size() < 2 or BRep_Tool.Degenerated_s(edge):
            continue
        owners = [(i, held[k, i][0]) for i in _owners_of(ancestors.FindFromIndex(k), owner, domains)]
        if len(owners) != 2 or any(len(held[k, i]) != 1 for i, _ in owners):
            continue  # a free edge, a seam of one face, or an edge twice in a face
        try:
            curve = BRepAdaptor_Curve(edge)
            t = np.linspace(curve.FirstParameter(), curve.LastParameter(), PCURVE_SAMPLES)
            points, tangents = curve3d_values(curve, t)
            uvs = [_clip(curve2d_values(BRepAdaptor_Curve2d(e, f), t), domains[i]) for i, (f, e) in owners]
        except Exception:  # noqa: BLE001, S112 - an edge OpenCASCADE cannot evaluate is not a shared edge of the model
            continue
        senses = tuple(f.Orientation() == TopAbs_REVERSED for _, (f, _e) in owners)
        edges.append(Edge(len(edges), tuple(i for i, _ in owners), points, tuple(uvs), t, tangents,
                          BRep_Tool.Tolerance_s(edge), senses))
    return edges


def _owners_of(around, owner, domains):
    """The distinct file indices of the faces in a list of faces, in its order."""
    out = []
    for f in around:
        i = owner(f)
        if i >= 0 and i in domains and i not in out:
            out.append(i)
    return out
