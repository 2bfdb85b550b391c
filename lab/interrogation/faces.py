"""Models and their faces (:class:`lab.Model`, :class:`lab.Face`) as the interrogation tools see them.

The probe, the combs and the paths (geodesics, normal sections) take a face where they take a surface; they
evaluate the surface that :func:`face_surface` names, keep to the face's trimmed region and follow its normal.
The tools on meshes take a model; its mesh has one vertex set per face, and level lines are joined across
face borders (:func:`joined`).  Nothing here imports :mod:`lab.interrogation.cad` (a model or a face is
recognised by what it has).
"""

import numpy as np

from ..mesh.levels import join_polylines

__all__ = ["COLLAPSE_RTOL", "JOIN_RTOL", "as_surface", "check_inside", "check_surface", "collapsed_sides", "face_surface", "fill_normals",
           "is_face", "is_model", "join_tol", "joined", "on_collapsed_side"]

#: Level lines of neighbouring faces of a model are joined where their ends lie closer than this times the
#: mesh's median edge length.  Across a tangent-continuous border the ends differ only by the two faces'
#: different sampling of the edge; across a kink the lines jump.  Measured with 12 reflection lines on the
#: hammer and linkrods at 8 and 16 lines per face: ends at G1/G2 edges (and at linkrods' tangent edges whose
#: gap exceeds the default G0 tolerance) at most 0.062 of an edge apart, ends at G0 edges at least 0.33.
JOIN_RTOL = 0.15


#: A side of a face's parameter domain whose curve in space is shorter than this fraction of the face's size
#: (its control points' box) is a point within the file's accuracy: a CAD file's collapsed edge (shell1.brep's
#: are 2e-6 to 4e-6 long on faces of size 2 to 5, at most 1.1e-6 of them; 5e-8 of the part).
COLLAPSE_RTOL = 1e-5


def collapsed_sides(surface, rtol=COLLAPSE_RTOL):
    """Which sides ``"u0", "u1", "v0", "v1"`` of the surface's domain are collapsed within ``rtol`` of its size.

    The lab's exact test (:data:`lab.curvature.DEGENERATE_RTOL`, 1e-10) takes a side of 1e-6 of the size for a
    curve, and b_u × b_v nearly vanishes there: curvature evaluated on it is rounding noise (10⁷ where the face
    curves by 0.1).  Such a side is a degenerate point of the file, and its curvature is the limit from inside.
    """
    (u0, u1), (v0, v1) = surface.domain
    t = np.linspace(0.0, 1.0, 17)
    curves = {"u0": (np.full_like(t, u0), v0 + t * (v1 - v0)), "u1": (np.full_like(t, u1), v0 + t * (v1 - v0)),
              "v0": (u0 + t * (u1 - u0), np.full_like(t, v0)), "v1": (u0 + t * (u1 - u0), np.full_like(t, v1))}
    P = np.asarray(surface.control_points, dtype=float).reshape(-1, 3) if hasattr(surface, "control_points") else \
        np.concatenate([surface.evaluate(*uv) for uv in curves.values()])
    size = float(np.linalg.norm(np.ptp(P, axis=0)))
    out = set()
    for side, (u, v) in curves.items():
        X = surface.evaluate(u, v)
        if float(np.sum(np.linalg.norm(np.diff(X, axis=0), axis=1))) <= rtol * size:
            out.add(side)
    return out


def on_collapsed_side(surface, uv, sides):
    """Which parameter points ``uv`` (k, 2) lie on one of the collapsed ``sides`` (see :func:`collapsed_sides`)."""
    uv = np.asarray(uv, dtype=float).reshape(-1, 2)
    mask = np.zeros(len(uv), dtype=bool)
    if not sides:
        return mask
    (u0, u1), (v0, v1) = surface.domain
    eps_u, eps_v = 1e-9 * (u1 - u0), 1e-9 * (v1 - v0)
    near = {"u0": np.abs(uv[:, 0] - u0) <= eps_u, "u1": np.abs(uv[:, 0] - u1) <= eps_u,
            "v0": np.abs(uv[:, 1] - v0) <= eps_v, "v1": np.abs(uv[:, 1] - v1) <= eps_v}
    for side in sides:
        mask |= near[side]
    return mask


def is_face(obj):
    """Whether ``obj`` is a face of a model (a surface with trimming loops and an orientation), not a surface."""
    return all(hasattr(obj, name) for name in ("surface", "trim", "reversed", "index", "kind"))


def face_surface(face):
    """The surface a face's (u, v) refer to: ``face.file_surface``, the face's surface in the file's parameters
    (the NURBS ``face.surface`` itself for B-spline faces, a :class:`lab.ReparametrizedSurface` over it for the
    file's analytic faces).

    The one place that says which surface a face is evaluated on."""
    return getattr(face, "file_surface", None) or face.surface


def check_surface(surface, name="surface"):
    """Refuse anything but a lab surface (Bézier, B-spline, parametric, …) with a ``TypeError`` naming it."""
    from ..model.surface import Surface

    if not isinstance(surface, Surface):
        hint = " (patches: pass the surface they came from)" if type(surface).__name__ == "BezierPatches" else ""
        text = repr(surface) if isinstance(surface, (int, float, str, type(None))) else type(surface).__name__
        raise TypeError(f"{name} must be a lab surface (Bézier, B-spline, parametric){hint}; got {text[:60]}")
    return surface


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
