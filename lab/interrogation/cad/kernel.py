"""The same numbers from a CAD kernel: OpenCASCADE's curvature of a model's face, for comparison with the lab's.

``occ_curvature(model, index, u, v)`` re-reads the model's file with OpenCASCADE and asks
``BRepLProp_SLProps`` (the analysis behind OCCT's and FreeCAD's curvature tools) at the file's (u, v) of face
``index``.  ``BRepLProp_SLProps`` gives the curvature of the underlying surface with the normal ``d/du × d/dv``
whatever the face's orientation (measured: ``face.Reversed()`` gives the same H and normal), so on a reversed
face H, k1 and k2 are turned to the face's normal here, as :meth:`lab.interrogation.cad.Face.curvature` does.
"""

import functools
import os

import numpy as np

from ...geometry.curvature import Curvature

__all__ = ["occ_curvature", "occ_projection"]


@functools.lru_cache(maxsize=4)
def _faces(path, mtime):
    """The faces of a file in the explorer's order (as :func:`lab.read` numbers them)."""
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp

    from .occ import _cast, _shape_map, occ_shape

    shape = occ_shape(path)
    faces = _shape_map()
    TopExp.MapShapes_s(shape, TopAbs_FACE, faces)
    return [_cast("Face")(faces.FindKey(k + 1)) for k in range(faces.Extent())]


def occ_curvature(model, index, u, v, *, tol=1e-9):
    """OpenCASCADE's K, H, k1 ≥ k2 of face ``index`` (its file index) at the file's ``(u, v)``.

    Parameters
    ----------
    model : lab.Model
        Read by :func:`lab.read` from a STEP, IGES or BREP file (``model.path``).
    index : int
        The face's index in the file (``face.index``).
    u, v : array_like
        Parameters of the face's surface in the file, broadcast against each other.
    tol : float
        ``BRepLProp_SLProps``'s linear tolerance (below it a derivative counts as zero).

    Returns
    -------
    Curvature
        Fields ``K, H, k1, k2, degenerate`` of shape ``broadcast(u, v).shape``, with the face's normal;
        ``degenerate`` where OpenCASCADE says the curvature is not defined (the values are NaN there).
    """
    from .occ import EXTENSIONS, require_ocp

    path = getattr(model, "path", None)
    if path is None or os.path.splitext(path)[1].lower() not in EXTENSIONS:
        raise ValueError(f"occ_curvature needs a model read from a STEP, IGES or BREP file; got {model!r}")
    require_ocp()
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepLProp import BRepLProp_SLProps
    from OCP.TopAbs import TopAbs_REVERSED

    faces = _faces(path, os.path.getmtime(path))
    if not 0 <= int(index) < len(faces):
        raise ValueError(f"face index must be in 0 … {len(faces) - 1} (the file's faces); got {index}")
    face = faces[int(index)]
    u, v = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(v, dtype=float))
    props = BRepLProp_SLProps(BRepAdaptor_Surface(face), 2, float(tol))
    out = np.full(u.shape + (4,), np.nan)
    defined = np.zeros(u.shape, dtype=bool)
    for k in np.ndindex(u.shape):
        props.SetParameters(float(u[k]), float(v[k]))
        if props.IsCurvatureDefined():  # computes the curvatures too: ask it before reading them
            out[k] = props.GaussianCurvature(), props.MeanCurvature(), props.MaxCurvature(), props.MinCurvature()
            defined[k] = True
    K, H, k1, k2 = np.moveaxis(out, -1, 0)
    if face.Orientation() == TopAbs_REVERSED:
        H, k1, k2 = -H, -k2, -k1
    return Curvature(K, H, k1, k2, ~defined)


def occ_projection(model, points, faces=None):
    """OpenCASCADE's nearest points of a model's part (read again from ``model.path``) to ``points``, one by one.

    With ``faces`` (the file index of a face per point) each point is projected onto that face's surface by
    ``GeomAPI_ProjectPointOnSurf`` (its nearest solution, the untrimmed surface: what a script does that knows
    the face); without, onto the whole part by ``BRepExtrema_DistShapeShape`` (a vertex against the shape:
    trims respected, every face searched).  ``lab.deviation`` is compared with both (tests, ``benchmarks/deviation.py``).

    Returns
    -------
    distance : (n,) ndarray
        Unsigned distances.
    feet : (n, 3) ndarray
    uv : (n, 2) ndarray
        The foot's parameters on its face (NaN where OpenCASCADE found no solution).
    """
    from .occ import EXTENSIONS, require_ocp

    path = getattr(model, "path", None)
    if path is None or os.path.splitext(path)[1].lower() not in EXTENSIONS:
        raise ValueError(f"occ_projection needs a model read from a STEP, IGES or BREP file; got {model!r}")
    require_ocp()
    from OCP.BRep import BRep_Tool
    from OCP.gp import gp_Pnt

    P = np.asarray(points, dtype=float).reshape(-1, 3)
    distance, feet, uv = np.full(len(P), np.nan), np.full((len(P), 3), np.nan), np.full((len(P), 2), np.nan)
    if faces is not None:
        from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf

        all_faces = _faces(path, os.path.getmtime(path))
        surfaces = {}
        for i, (p, f) in enumerate(zip(P, np.asarray(faces, dtype=int).ravel())):
            if f not in surfaces:
                surfaces[f] = BRep_Tool.Surface_s(all_faces[f])
            projector = GeomAPI_ProjectPointOnSurf(gp_Pnt(*p), surfaces[f])
            if projector.NbPoints():
                q, (u, v) = projector.NearestPoint(), projector.LowerDistanceParameters()
                distance[i], feet[i], uv[i] = projector.LowerDistance(), (q.X(), q.Y(), q.Z()), (u, v)
        return distance, feet, uv
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.TopoDS import TopoDS_Compound

    faces, shape, builder = _faces(path, os.path.getmtime(path)), TopoDS_Compound(), BRep_Builder()
    builder.MakeCompound(shape)
    for face in faces:  # the faces, not the solid: a point inside a solid is at distance 0 from it
        builder.Add(shape, face)
    for i, p in enumerate(P):
        extrema = BRepExtrema_DistShapeShape(BRepBuilderAPI_MakeVertex(gp_Pnt(*p)).Vertex(), shape)
        if extrema.IsDone() and extrema.NbSolution():
            q = extrema.PointOnShape2(1)
            distance[i], feet[i] = extrema.Value(), (q.X(), q.Y(), q.Z())
    return distance, feet, uv
