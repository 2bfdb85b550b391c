r"""Discrete curvature of a triangle mesh: the angle deficit and the cotangent Laplacian (Meyer et al. 2003).

A mesh is given by ``points`` (n, 3) and ``faces`` (f, 3) of vertex indices, every face counter-clockwise seen from
the side its normal points to (the lab's meshes are oriented like ``b_u × b_v``).  What is computed per vertex i:

* the **angle deficit** :math:`2\pi - \sum_j \theta_j` over the corner angles :math:`\theta_j` of the faces at i, and
  :math:`\pi - \sum_j \theta_j` at a boundary vertex (a vertex on an edge that only one face has).  By Gauss–Bonnet
  it is the integral of K over a small region around i (Meyer et al. 2003, §4); at a boundary vertex it also holds
  the turning of the boundary curve (its geodesic curvature), so there it is not K times an area;
* the **mixed area** :math:`A_\mathrm{mixed}` of the region, the share of each face at i (Meyer et al. 2003, §3.3,
  figure 4): the Voronoi share :math:`\tfrac18(|PQ|^2\cot R + |PR|^2\cot Q)` in a face PQR with no obtuse angle,
  else half the face's area at its obtuse corner and a quarter at the other two;
* the **Gaussian curvature** :math:`K_i = (2\pi - \sum_j\theta_j)/A_\mathrm{mixed}` (π at a boundary vertex);
* the **mean curvature normal** by the cotangent Laplacian,
  :math:`\Delta\mathbf x_i = \frac{1}{2A_\mathrm{mixed}}\sum_j(\cot\alpha_{ij} + \cot\beta_{ij})(\mathbf x_j -
  \mathbf x_i) = 2H\mathbf N` (Meyer et al. 2003, §3.5, with their sign turned: the lab's H is
  ½(eG − 2fF + gE)/(EG − F²) with e = N·b_uu, so a sphere with outward normals has H = −1/r), and the mean
  curvature :math:`H_i = \tfrac12\,\Delta\mathbf x_i\cdot\mathbf N_i` with the area-weighted vertex normal.

Corner angles are ``atan2(|a × b|, a · b)``: accurate near 0 and π, where ``arccos`` of the cosine loses half the
digits.  Pure functions on arrays; the meshes of the lab's surfaces with their exact K and H are
:func:`lab.mesh.triangle_mesh`, the comparison with VTK, libigl and trimesh :mod:`lab.interrogation.estimators`.
"""

import numpy as np

from . import validation as _v

__all__ = ["angle_deficit", "boundary_vertices", "corner_angles", "cotangent_laplacian", "face_areas",
           "gaussian_curvature", "mean_curvature", "mixed_areas", "vertex_normals"]


def _mesh(points, faces):
    """``points`` (n, 3) float and ``faces`` (f, 3) int, checked."""
    points = _v._as_float_array(points, "points")
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points must be an (n, 3) array of vertex coordinates; got shape {points.shape}")
    faces = np.asarray(faces)
    if faces.ndim != 2 or faces.shape[1] != 3 or faces.dtype.kind not in "iu":
        raise TypeError(f"faces must be an (f, 3) array of integer vertex indices; got {faces.dtype} of shape "
                        f"{faces.shape}")
    if faces.size and (faces.min() < 0 or faces.max() >= len(points)):
        raise ValueError(f"faces must index the {len(points)} points (0 … {len(points) - 1}); got indices from "
                         f"{faces.min()} to {faces.max()}")
    return points, faces.astype(np.intp)


def _per_vertex(faces, values, n):
    """Sum of per-corner ``values`` (f, 3) at each of the ``n`` vertices."""
    return np.bincount(faces.ravel(), weights=np.asarray(values, dtype=float).ravel(), minlength=n)


def corner_angles(points, faces):
    """The interior angle (radians) at each corner of each face: ``(f, 3)``, column k at vertex ``faces[:, k]``."""
    points, faces = _mesh(points, faces)
    P = points[faces]
    a = np.roll(P, -1, axis=1) - P
    b = np.roll(P, 1, axis=1) - P
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("fki,fki->fk", a, b))


def face_areas(points, faces):
    """The area of each face: ``(f,)``."""
    points, faces = _mesh(points, faces)
    P = points[faces]
    return 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=-1)


def boundary_vertices(faces, n_points):
    """Which of the ``n_points`` vertices lie on the boundary (on an edge of only one face): a bool array ``(n,)``."""
    n_points = _v.as_positive_int(n_points, "n_points", minimum=1)
    faces = np.asarray(faces)
    if faces.ndim != 2 or faces.shape[1] != 3 or faces.dtype.kind not in "iu":
        raise TypeError(f"faces must be an (f, 3) array of integer vertex indices; got {faces.dtype} of shape "
                        f"{faces.shape}")
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    out = np.zeros(n_points, dtype=bool)
    out[unique[count == 1].ravel()] = True
    return out


def angle_deficit(points, faces):
    """The angle deficit at each vertex: 2π minus the sum of its corner angles, π minus it at a boundary vertex."""
    points, faces = _mesh(points, faces)
    total = _per_vertex(faces, corner_angles(points, faces), len(points))
    return np.where(boundary_vertices(faces, len(points)), np.pi, 2 * np.pi) - total


def mixed_areas(points, faces):
    """The mixed Voronoi area of each vertex (Meyer et al. 2003, §3.3, figure 4): ``(n,)``, summing to the mesh's area.

    In a face with no obtuse angle the Voronoi share of corner P is ⅛(|PQ|² cot R + |PR|² cot Q); in a face with an
    obtuse angle the obtuse corner gets half the face's area and the two others a quarter each.
    """
    points, faces = _mesh(points, faces)
    P = points[faces]
    theta = corner_angles(points, faces)
    area = face_areas(points, faces)
    # the squared length of the edge opposite each corner k (from corner k + 1 to corner k + 2)
    opposite = np.roll(P, -2, axis=1) - np.roll(P, -1, axis=1)
    l2 = np.einsum("fki,fki->fk", opposite, opposite)
    with np.errstate(divide="ignore", invalid="ignore"):
        cot = np.cos(theta) / np.sin(theta)
    # corner k: the edge to k + 1 is opposite corner k + 2, the edge to k + 2 opposite corner k + 1
    voronoi = (np.roll(l2, -2, axis=1) * np.roll(cot, -2, axis=1) + np.roll(l2, -1, axis=1) * np.roll(cot, -1, axis=1)) / 8
    obtuse = theta > np.pi / 2
    share = np.where(obtuse.any(axis=1)[:, None], np.where(obtuse, 0.5, 0.25) * area[:, None], voronoi)
    return _per_vertex(faces, share, len(points))


def gaussian_curvature(points, faces):
    """The discrete Gaussian curvature of each vertex: its angle deficit divided by its mixed area (Meyer et al. 2003,
    §4); at a boundary vertex the deficit π − Σθ also holds the boundary's turning, so the value there is no estimate of
    K."""
    points, faces = _mesh(points, faces)
    return angle_deficit(points, faces) / mixed_areas(points, faces)


def vertex_normals(points, faces):
    """Unit normals at the vertices: the sum of the adjacent faces' normals weighted by their areas, ``(n, 3)``."""
    points, faces = _mesh(points, faces)
    P = points[faces]
    cross = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    out = np.stack([_per_vertex(faces, np.repeat(cross[:, c : c + 1], 3, axis=1), len(points)) for c in range(3)],
                   axis=-1)
    norm = np.linalg.norm(out, axis=1, keepdims=True)
    return np.divide(out, norm, out=np.full_like(out, np.nan), where=norm > 0)


def cotangent_laplacian(points, faces):
    """The mean curvature normal Δx = 2HN at each vertex by the cotangent formula over the mixed area (Meyer et al.
    2003, §3.5), ``(n, 3)``; at a boundary vertex the sum misses the faces beyond the boundary and is no estimate."""
    points, faces = _mesh(points, faces)
    with np.errstate(divide="ignore", invalid="ignore"):
        theta = corner_angles(points, faces)
        cot = np.cos(theta) / np.sin(theta)
    out = np.zeros_like(points)
    for k in range(3):  # corner k is opposite the edge (i, j)
        i, j = faces[:, (k + 1) % 3], faces[:, (k + 2) % 3]
        w = cot[:, k : k + 1] * (points[j] - points[i])
        for c in range(3):
            out[:, c] += np.bincount(i, weights=w[:, c], minlength=len(points))
            out[:, c] -= np.bincount(j, weights=w[:, c], minlength=len(points))
    return out / (2 * mixed_areas(points, faces)[:, None])


def mean_curvature(points, faces, normals=None):
    """The discrete mean curvature of each vertex, H = ½ Δx · N with the cotangent Laplacian Δx and the unit vertex
    normal N (default: :func:`vertex_normals`, which follow the faces' orientation); the lab's sign (H < 0 on a sphere
    with outward normals)."""
    points, faces = _mesh(points, faces)
    N = vertex_normals(points, faces) if normals is None else _v._as_float_array(normals, "normals")
    if N.shape != points.shape:
        raise ValueError(f"normals must have the shape of points {points.shape}; got {N.shape}")
    return 0.5 * np.einsum("ij,ij->i", cotangent_laplacian(points, faces), N)
