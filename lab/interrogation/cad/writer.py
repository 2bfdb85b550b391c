"""Write lab surfaces and models as BREP or STEP through OpenCASCADE, so that FreeCAD or Rhino can open them."""

import os

import numpy as np

from .model import Model
from .occ import _cast, require_ocp

__all__ = ["WRITE_EXTENSIONS", "occ_bspline", "write"]

WRITE_EXTENSIONS = (".brep", ".step", ".stp", ".3dm")


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


def _surfaces(obj):
    """The (surface, reversed) pairs to write; trimmed faces are refused (their loops are not written yet)."""
    if isinstance(obj, Model):
        trimmed = [f.index for f in obj.faces if f.trim is not None]
        if trimmed:
            raise ValueError(f"writing trimmed faces is not supported yet: faces {trimmed[:8]}"
                             f"{' ...' if len(trimmed) > 8 else ''} of the model have trimming loops")
        return [(f.surface, f.reversed) for f in obj.faces]
    if hasattr(obj, "_spline_args"):
        return [(obj, False)]
    if hasattr(obj, "control_points") and hasattr(obj, "__iter__"):  # BezierPatches
        return [(patch.surface if hasattr(patch, "surface") else patch, False) for patch in obj]
    raise TypeError(f"write needs a lab.Model, a lab.BezierSurface or a lab.BSplineSurface; got {type(obj).__name__}")


def write(obj, path):
    """Write a :class:`Model` (untrimmed faces), a :class:`lab.BezierSurface` or a :class:`lab.BSplineSurface`.

    Parameters
    ----------
    obj : Model, BezierSurface or BSplineSurface
    path : str or os.PathLike
        ``.brep`` (OpenCASCADE's own format), ``.step``/``.stp`` (AP214), one face per surface in a compound,
        or ``.3dm`` (Rhino, through rhino3dm: NURBS surfaces; the orientation is not written there);
        a reversed face is written reversed.  Control points, weights, knots and parameters are written as
        they are, so :func:`lab.read` gives the same surfaces back.
    """
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext not in WRITE_EXTENSIONS:
        raise ValueError(f"{path}: cannot write {ext or '(no extension)'!r}; expected one of {', '.join(WRITE_EXTENSIONS)}")
    pairs = _surfaces(obj)
    if ext == ".3dm":
        from .rhino import write_3dm

        return write_3dm(pairs, path)
    require_ocp()
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.BRepTools import BRepTools
    from OCP.TopoDS import TopoDS_Compound

    builder = BRep_Builder()
    compound = TopoDS_Compound()
    builder.MakeCompound(compound)
    for surface, reversed_ in pairs:
        face = BRepBuilderAPI_MakeFace(occ_bspline(surface), 1e-7).Face()
        builder.Add(compound, _cast("Face")(face.Reversed()) if reversed_ else face)
    if ext == ".brep":
        if not BRepTools.Write_s(compound, path):
            raise ValueError(f"{path}: OpenCASCADE could not write the BREP file")
        return path
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer

    writer = STEPControl_Writer()
    if writer.Transfer(compound, STEPControl_AsIs) != IFSelect_RetDone or writer.Write(path) != IFSelect_RetDone:
        raise ValueError(f"{path}: OpenCASCADE could not write the STEP file")
    return path
