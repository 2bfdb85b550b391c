"""Meshes of trimmed surfaces (PyVista): the triangulated trimmed region mapped to 3-D with exact curvature.

The point data are those of :func:`lab.mesh.surface_mesh`, so every tool
that reads a curvature mesh works on a trimmed one too: ``K``, ``H``,
``k1``, ``k2`` and ``degenerate`` computed by the base surface at each
vertex's parameters, the unit normal ``N = b_u x b_v / |b_u x b_v|`` and the
parameters ``uv``.
"""

import numpy as np
import pyvista as pv

from ..geometry.grids import weld_parameters
from .build import _average, _curvature_data, color_curvature

__all__ = ["trimmed_mesh"]


def trimmed_mesh(trimmed, n_u=32, n_v=32, max_area=None, min_angle=20.0, curvature_mode=None, color_map=None,
                 weld_points=True):
    """A triangle mesh of a :class:`lab.trimming.TrimmedSurface` with exact curvature at every vertex.

    Parameters
    ----------
    trimmed : TrimmedSurface
    n_u, n_v, max_area, min_angle
        Triangulation density and quality, see :func:`lab.trimming.triangulate`.
    curvature_mode, color_map : optional
        With both, also ``values`` and ``RGB`` point data coloured like
        :meth:`lab.BezierPatches.visualize_curvature`.
    weld_points : bool
        Merge vertices that the base surface maps to the same point, by their
        parameters: on a seam of a closed surface or a collapsed edge
        (:attr:`lab.Surface.seams`, :func:`lab.grids.weld_parameters`); their data
        are averaged, ``uv`` keeps the first, and triangles that collapse are dropped.

    Returns
    -------
    pyvista.PolyData
        Triangles in the orientation of ``N``; point data ``K, H, k1, k2,
        degenerate, N, uv``.
    """
    uv, tri = trimmed.triangulate(n_u=n_u, n_v=n_v, max_area=max_area, min_angle=min_angle)
    u, v = uv[:, 0], uv[:, 1]
    surface = trimmed.surface
    D = surface.derivatives(u, v)
    data = _curvature_data(D, surface.curvature(u, v))
    points = D.b
    if weld_points and len(points) > 1:
        labels, n = weld_parameters(uv, surface.domain, surface.seams)
        if n < len(points):
            tri = labels[tri]
            tri = tri[(tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 2] != tri[:, 0])]
            points = _average(labels, n, points)
            for k, val in data.items():
                if val.dtype == bool:
                    merged = np.zeros(n, bool)
                    np.logical_or.at(merged, labels, val)
                    data[k] = merged
                else:
                    data[k] = _average(labels, n, val)
            pick = np.empty(n, dtype=int)
            order = np.arange(len(labels))[::-1]
            pick[labels[order]] = order  # the smallest index of each group
            uv = uv[pick]
    faces = np.hstack([np.full((len(tri), 1), 3), tri]).ravel()
    mesh = pv.PolyData(np.asarray(points, dtype=float), faces)
    for k, val in data.items():
        mesh.point_data[k] = val
    mesh.point_data["uv"] = uv
    N = np.asarray(mesh.point_data["N"])
    N = N / np.linalg.norm(N, axis=1, keepdims=True)
    missing = ~np.all(np.isfinite(N), axis=1)
    if np.any(missing):  # degenerate points have no b_u x b_v: use the mesh normal there
        normals = mesh.compute_normals(point_normals=True, cell_normals=False, auto_orient_normals=False,
                                       consistent_normals=False, split_vertices=False)
        N[missing] = normals.point_data["Normals"][missing]
    mesh.point_data["N"] = N
    if curvature_mode is not None and color_map is not None:
        color_curvature(mesh, curvature_mode, color_map)
    return mesh
