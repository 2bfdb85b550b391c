"""Models and their faces (:class:`lab.Model`, :class:`lab.Face`) as the interrogation tools see them.

The probe, the combs and the paths (geodesics, normal sections) take a face where they take a surface; they
evaluate the surface that :func:`face_surface` names, keep to the face's trimmed region and follow its normal.
The tools on meshes take a model; its mesh has one vertex set per face, and level lines are joined across
face borders (:func:`joined`).  Nothing here imports :mod:`lab.interrogation.cad` (a model or a face is
recognised by what it has).
"""

import numpy as np

from ..mesh.levels import join_polylines

__all__ = ["JOIN_RTOL", "as_surface", "check_inside", "face_surface", "fill_normals", "is_face", "is_model", "join_tol",
           "joined"]

#: Level lines of neighbouring faces of a model are joined where their ends lie closer than this times the
#: mesh's median edge length.  Across a tangent-continuous border the ends differ only by the two faces'
#: different sampling of the edge; across a kink the lines jump.  Measured with 12 reflection lines on the
#: hammer and linkrods at 8 and 16 lines per face: ends at G1/G2 edges (and at linkrods' tangent edges whose
#: gap exceeds the default G0 tolerance) at most 0.062 of an edge apart, ends at G0 edges at least 0.33.
JOIN_RTOL = 0.15


def is_face(obj):
    """Whether ``obj`` is a face of a model (a surface with trimming loops and an orientation), not a surface."""
    from .cad.model import Face

    return isinstance(obj, Face)


def face_surface(face):
    """The surface a face's (u, v) refer to: ``face.file_surface``, the face's surface in the file's parameters
    (the NURBS ``face.surface`` itself for B-spline faces, a :class:`lab.ReparametrizedSurface` over it for the
    file's analytic faces).

    The one place that says which surface a face is evaluated on."""
    return getattr(face, "file_surface", None) or face.surface


def as_surface(obj):
    """``(surface, trim)`` for a surface (``trim`` None) or a face (its surface and its trimmed region or None)."""
    if is_face(obj):
        return face_surface(obj), obj.trim
    return obj, None


def check_inside(trim, uv, name="start point"):
    """Refuse a point outside a face's trimmed region (a ValueError naming it); ``trim`` None accepts any."""
    if trim is None:
        return
    u, v = (float(x) for x in uv)
    if not bool(trim.contains(u, v)):
        raise ValueError(f"{name} (u, v) = ({u:g}, {v:g}) lies outside the face's trimmed region; choose a point "
                         "inside its outer loop and outside its holes (face.trim.contains(u, v))")


def is_model(obj):
    """Whether ``obj`` is a :class:`lab.Model` (a part read by :func:`lab.read`: faces and the edges they share)."""
    return hasattr(obj, "faces") and hasattr(obj, "edges") and hasattr(obj, "to_mesh") and not hasattr(obj, "points")


def join_tol(mesh):
    """How far apart the ends of level lines on two faces of a model's mesh may be to be joined: :data:`JOIN_RTOL`
    times the median edge (None: not a model's mesh, or one face only)."""
    if "face" not in mesh.point_data:
        return None
    face = np.asarray(mesh.point_data["face"])
    if face.size == 0 or face.min() == face.max():
        return None
    tri = mesh if mesh.is_all_triangles else mesh.triangulate()
    T = np.asarray(tri.faces).reshape(-1, 4)[:, 1:]
    X = np.asarray(mesh.points, dtype=float)
    edges = np.linalg.norm(X[T] - X[np.roll(T, 1, axis=1)], axis=-1)
    return JOIN_RTOL * float(np.median(edges))


def joined(lines, tol):
    """Level lines joined across face borders within ``tol`` (:func:`join_tol`), or as they are (``tol`` None)."""
    return lines if tol is None or len(lines) < 2 else join_polylines(lines, tol)


def fill_normals(mesh):
    """``mesh`` with a unit normal ``N`` at every vertex of a model's mesh (changed in place, and returned).

    At a collapsed patch edge (the teapot's lid top) the corner vertex of a face's grid touches only
    triangles of zero area, so neither ``b_u x b_v`` nor the mesh gives it a normal.  It gets the mean normal of
    the vertices of the same face at the same position (the others on the collapsed edge), which have one.
    """
    if "N" not in mesh.point_data:
        return mesh
    N = np.asarray(mesh.point_data["N"], dtype=float)
    bad = ~np.all(np.isfinite(N), axis=1)
    if not bad.any():
        return mesh
    X = np.asarray(mesh.points, dtype=float)
    face = np.asarray(mesh.point_data["face"]) if "face" in mesh.point_data else np.zeros(len(X), int)
    for i in np.nonzero(bad)[0]:
        same = (face == face[i]) & np.all(X == X[i], axis=1) & ~bad
        if same.any():
            n = N[same].sum(axis=0)
            N[i] = n / np.linalg.norm(n) if np.linalg.norm(n) > 0 else N[same][0]
    mesh.point_data["N"] = N
    return mesh
