"""Polyhedral shortest paths on a triangle mesh of a surface: the first guess for :func:`lab.geodesic_between`.

The surface is sampled on a grid of about :data:`MESH_VERTICES` nodes, welded by
index (:mod:`lab.grids`: seams and collapsed edges) and split into triangles;
potpourri3d's ``EdgeFlipGeodesicSolver`` (FlipOut, Sharp & Crane 2020) then
finds a locally shortest path along the mesh between two vertices, starting
from Dijkstra's shortest edge path, so in the homotopy class of the globally
shortest edge path.  Mesh and solver are built once per surface and kept
(:meth:`lab.Surface.cached`); one path costs about a millisecond.
"""

import numpy as np

from ...geometry.grids import weld_labels

__all__ = ["MESH_VERTICES", "PolyhedralMesh", "polyhedral_mesh"]

#: About this many vertices in the mesh a path is found on (edge length ~ 1/70 of the surface's extent).
MESH_VERTICES = 5000


class PolyhedralMesh:
    """A welded triangle mesh of a surface on a parameter grid, with its edge-flip geodesic solver.

    Attributes
    ----------
    vertices : (n, 3) ndarray
    faces : (f, 3) int ndarray
    uv : (n, 2) ndarray
        Parameters of each vertex (the first grid node's on a seam).
    """

    def __init__(self, surface, n_vertices=MESH_VERTICES):
        import potpourri3d

        nu, nv = _grid_size(surface, n_vertices)
        (u0, u1), (v0, v1) = surface.domain
        u, v = np.linspace(u0, u1, nu), np.linspace(v0, v1, nv)
        points = surface.evaluate(u[:, None], v[None, :]).reshape(-1, 3)
        labels, n = weld_labels((nu, nv), surface.seams)
        first = np.full(n, -1)
        first[labels[::-1]] = np.arange(nu * nv)[::-1]  # the first node of each vertex
        self.vertices = points[first]
        U, V = np.meshgrid(u, v, indexing="ij")
        self.uv = np.column_stack([U.ravel(), V.ravel()])[first]
        node = labels.reshape(nu, nv)
        a, b, c, d = node[:-1, :-1], node[1:, :-1], node[1:, 1:], node[:-1, 1:]
        faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
        keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])
        self.faces = faces[keep]  # a collapsed edge leaves triangles with a repeated vertex: dropped
        self._solver = potpourri3d.EdgeFlipGeodesicSolver(self.vertices, self.faces)

    def nearest_vertex(self, point):
        """Index of the mesh vertex nearest to a 3-D point."""
        return int(np.argmin(np.sum((self.vertices - point) ** 2, axis=1)))

    def path(self, start, end):
        """The edge-flip geodesic between vertices ``start`` and ``end``: a polyline (k, 3) on the mesh."""
        return np.asarray(self._solver.find_geodesic_path(start, end), dtype=float)


def polyhedral_mesh(surface):
    """The :class:`PolyhedralMesh` of ``surface``, built once per surface and kept."""
    return surface.cached("polyhedral mesh", lambda: PolyhedralMesh(surface))


def _grid_size(surface, n_vertices):
    """Grid nodes ``(nu, nv)`` with about ``n_vertices`` in all and edges of similar length in u and v."""
    (u0, u1), (v0, v1) = surface.domain
    t = np.linspace(0.0, 1.0, 9)
    U, V = np.meshgrid(u0 + t * (u1 - u0), v0 + t * (v1 - v0), indexing="ij")
    X = surface.evaluate(U, V)
    length_u = np.linalg.norm(np.diff(X, axis=0), axis=-1).sum(axis=0).mean()  # along u, averaged over v
    length_v = np.linalg.norm(np.diff(X, axis=1), axis=-1).sum(axis=1).mean()
    ratio = np.sqrt(max(length_u, 1e-12) / max(length_v, 1e-12))
    nu = int(np.clip(round(np.sqrt(n_vertices) * ratio), 8, n_vertices // 8))
    nv = int(np.clip(round(n_vertices / nu), 8, n_vertices // 8))
    return nu, nv
