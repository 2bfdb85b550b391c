"""Rhino ``.3dm`` files through ``rhino3dm`` (the extra ``cad``): NURBS surfaces and the faces of Breps, and writing.

rhino3dm's control points are homogeneous (``Points[i, j]`` is ``(w x, w y, w z, w)``) and its knot lists omit
the two end knots of a clamped knot vector (OpenNURBS's convention); trims give no 2-D curves there, so a Brep
face is read as its untrimmed underlying surface and ``model.problems`` says so.
"""

import os

import numpy as np

from ...model.surface import BSplineSurface
from .model import Face, Model, Problem

__all__ = ["read_3dm", "write_3dm"]


def _rhino():
    try:
        import rhino3dm
    except ImportError:
        raise ImportError("Rhino .3dm files need rhino3dm: pip install -e '.[cad]' (make setup installs it)") from None
    return rhino3dm


def _lab_surface(ns):
    nu, nv = ns.Points.CountU, ns.Points.CountV
    Pw = np.array([[[c for c in (ns.Points[i, j].X, ns.Points[i, j].Y, ns.Points[i, j].Z, ns.Points[i, j].W)]
                    for j in range(nv)] for i in range(nu)])
    w = Pw[..., 3]
    P = Pw[..., :3] / w[..., None]
    ku = [ns.KnotsU[k] for k in range(len(ns.KnotsU))]
    kv = [ns.KnotsV[k] for k in range(len(ns.KnotsV))]
    return BSplineSurface(P, [ku[0]] + ku + [ku[-1]], [kv[0]] + kv + [kv[-1]], ns.OrderU - 1, ns.OrderV - 1,
                          weights=w if ns.IsRational else None)


def read_3dm(path, name=None):
    """A :class:`Model` of the surfaces in a ``.3dm`` file (NURBS and other surfaces, Brep faces untrimmed)."""
    rhino3dm = _rhino()
    path = os.fspath(path)
    if os.path.getsize(path) == 0:
        raise ValueError(f"{path}: the file is empty; expected a Rhino .3dm file")
    f = rhino3dm.File3dm.Read(path)
    if f is None:
        raise ValueError(f"{path}: rhino3dm could not read it as a .3dm file (corrupt or not 3dm)")
    faces, problems, index = [], [], 0
    for obj in f.Objects:
        geometry = obj.Geometry
        if isinstance(geometry, rhino3dm.Brep):
            parts = [(face.UnderlyingSurface(), "BrepFace") for face in geometry.Faces]
        elif isinstance(geometry, rhino3dm.Surface):
            parts = [(geometry, type(geometry).__name__)]
        else:
            continue
        for surface, kind in parts:
            try:
                ns = surface.ToNurbsSurface()
                faces.append(Face(index, kind, _lab_surface(ns)))
                if kind == "BrepFace":
                    problems.append(Problem(index, kind, "read untrimmed: rhino3dm gives no 2-D trimming curves"))
            except Exception as exc:  # noqa: BLE001 - rhino3dm raises plain RuntimeErrors; report the face, never drop it
                problems.append(Problem(index, kind, f"{type(exc).__name__}: {exc}"))
            index += 1
    if index == 0:
        raise ValueError(f"{path}: the file holds no surfaces")
    return Model(faces, (), problems, path=path, name=name)


def write_3dm(pairs, path):
    """Write ``(surface, reversed)`` pairs of lab spline surfaces as NURBS surfaces in a ``.3dm`` file."""
    rhino3dm = _rhino()
    out = rhino3dm.File3dm()
    for surface, _reversed in pairs:
        P, knots_u, knots_v, p, q, w = surface._spline_args()
        nu, nv = P.shape[:2]
        ns = rhino3dm.NurbsSurface.Create(3, w is not None, int(p) + 1, int(q) + 1, nu, nv)
        W = np.ones((nu, nv)) if w is None else w
        for i in range(nu):
            for j in range(nv):
                x, y, z = (float(c) * W[i, j] for c in P[i, j])
                ns.Points[i, j] = rhino3dm.Point4d(x, y, z, float(W[i, j]))
        for k, t in enumerate(knots_u[1:-1]):
            ns.KnotsU[k] = float(t)
        for k, t in enumerate(knots_v[1:-1]):
            ns.KnotsV[k] = float(t)
        out.Objects.AddSurface(ns)
    if not out.Write(os.fspath(path), 7):
        raise ValueError(f"{os.fspath(path)}: rhino3dm could not write the file")
    return os.fspath(path)
