"""Meshes with exact curvature as point data (PyVista), welded by grid index.

The practical shows every Bézier patch as a quadrilateral with its four
corner colours (Gouraud shading interpolates between them); that is
:func:`patches_mesh` with ``resolution=1``.  Finer ``resolution`` samples each
patch on a grid, with curvature computed exactly at every node.  Vertices
shared by neighbouring patches, and the seams and collapsed edges of the
surface (:class:`lab.grids.Seams`), are welded by their grid index, and their
point data averaged, so the mesh is one connected surface.  Only a collection
of unrelated patches (no ``grid_shape``) is welded by distance.
"""

import numpy as np
import pyvista as pv
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..geometry import validation as _v
from ..geometry.colormaps import colors_for
from ..geometry.curvature import Curvature, CurvatureMode, curvature_values, unit_normal, zero_tolerance
from ..geometry.grids import NO_SEAMS, weld_labels

__all__ = [
    "MESH_BYTES_PER_POINT",
    "WELD_RTOL",
    "color_cells",
    "color_curvature",
    "grid_mesh",
    "patches_mesh",
    "polyline_mesh",
    "surface_mesh",
    "weld",
]

#: Points closer than WELD_RTOL times the bounding-box diagonal are merged (unrelated patches only).
WELD_RTOL = 1e-9
#: Bytes per vertex a mesh plans for: the sampled fields, the welded copies and VTK's arrays.
MESH_BYTES_PER_POINT = 400


def weld(points, rtol=WELD_RTOL, extent=None):
    """Labels that merge coincident points.

    Parameters
    ----------
    points : (k, 3) ndarray
    rtol : float
        Merge distance relative to the bounding-box diagonal.
    extent : float, optional
        The length the tolerance is relative to (default: the points' bounding-box diagonal).

    Returns
    -------
    labels : (k,) int ndarray
        ``labels[i]`` is the index of point ``i`` in the welded point list; the
        groups are the connected components of the "closer than tol" graph.
    n : int
        Number of welded points.
    """
    points = np.asarray(points, dtype=float)
    if extent is None:
        extent = np.linalg.norm(points.max(axis=0) - points.min(axis=0)) if len(points) else 0.0
    tol = rtol * max(extent, 1e-300)
    pairs = cKDTree(points).query_pairs(tol, output_type="ndarray")
    k = len(points)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(k, k))
    n, labels = connected_components(graph, directed=False)
    return labels, n


def _average(labels, n, values):
    """Mean of ``values`` (k, ...) over each label group; NaN-aware (NaN only if every member is NaN)."""
    values = np.asarray(values, dtype=float)
    flat = values.reshape(len(values), -1)
    finite = np.isfinite(flat)
    out = np.empty((n, flat.shape[1]))
    for c in range(flat.shape[1]):  # bincount is much faster than np.add.at
        counts = np.bincount(labels, weights=finite[:, c], minlength=n)
        sums = np.bincount(labels, weights=np.where(finite[:, c], flat[:, c], 0.0), minlength=n)
        with np.errstate(invalid="ignore", divide="ignore"):
            out[:, c] = np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)
    return out.reshape((n,) + values.shape[1:])


def _index_labels(g, a, b, grid_shape):
    """Node of the tiled rectangle of every grid point: patch (I, J) point (s, t) -> (I(a-1)+s, J(b-1)+t).

    Returns the node index of every point (row-major over the rectangle) and the rectangle's shape.
    """
    rows, cols = grid_shape
    I, J = np.divmod(np.arange(g), cols)
    gi = I[:, None, None] * (a - 1) + np.arange(a)[None, :, None]
    gj = J[:, None, None] * (b - 1) + np.arange(b)[None, None, :]
    width = cols * (b - 1) + 1
    return (gi * width + gj).ravel(), (rows * (a - 1) + 1, width)


def grid_mesh(points, point_data=None, weld_points=True, first_data=None, grid_shape=None, seams=NO_SEAMS):
    """A quad mesh from grids of points, welded across grids.

    Parameters
    ----------
    points : (g, a, b, 3) ndarray
        ``g`` grids of ``a x b`` points (one per patch).
    point_data : dict of name -> (g, a, b, ...) ndarray
        Values per grid point; averaged over welded points (booleans: any).
        A field called ``N`` (unit normals) is renormalised after averaging,
        and where it is NaN (degenerate points) replaced by the mesh normal.
    weld_points : bool
    first_data : dict of name -> (g, a, b, ...) ndarray
        Values per grid point of which a welded point keeps the first (e.g.
        ``uv`` parameters, which differ across the seam of a closed surface).
    grid_shape : (rows, columns), optional
        The grids tile a rectangle in row-major order (one grid: ``(1, 1)``):
        points are welded by index, shared edges of neighbouring grids and the
        rectangle's ``seams`` (:func:`lab.grids.weld_labels`).  Without it the
        grids are unrelated patches and coincident points are welded by
        distance (:func:`weld`).
    seams : lab.grids.Seams
        Periodic and collapsed edges of the rectangle (with ``grid_shape``).

    Returns
    -------
    pyvista.PolyData
    """
    g, a, b, _ = points.shape
    idx = np.arange(g * a * b).reshape(g, a, b)
    quads = np.stack([idx[:, :-1, :-1], idx[:, 1:, :-1], idx[:, 1:, 1:], idx[:, :-1, 1:]], axis=-1).reshape(-1, 4)
    flat_points = points.reshape(-1, 3)

    def flat(v):
        return np.asarray(v).reshape((g * a * b,) + np.shape(v)[3:])

    data = {k: flat(v) for k, v in (point_data or {}).items()}
    first = {k: flat(v) for k, v in (first_data or {}).items()}
    if weld_points:
        if grid_shape is not None:
            node, shape = _index_labels(g, a, b, grid_shape)
            node_labels, n = weld_labels(shape, seams)
            labels = node_labels[node]
        else:
            labels, n = weld(flat_points)
        if n < len(labels) or np.any(labels != np.arange(len(labels))):
            quads = labels[quads]
            flat_points = _average(labels, n, flat_points)
            for k, v in data.items():
                if v.dtype == bool:
                    data[k] = np.bincount(labels, weights=v, minlength=n) > 0
                else:
                    data[k] = _average(labels, n, v)
            first = {k: v[_first_of(labels, n)] for k, v in first.items()}
    mesh = pv.PolyData(flat_points, _faces_without_collapsed_edges(quads))
    if len(flat_points) and not np.isfinite(flat_points).all(axis=1).any():  # a function undefined everywhere
        raise ValueError(f"nothing to draw: the surface is not finite at any of its {len(flat_points)} points (its "
                         "function is not defined there, or exceeds the float range)")
    if len(flat_points) and np.all(flat_points == flat_points[0]):  # every point the same: nothing has an area
        raise ValueError(f"nothing to draw: all points of the surface coincide at "
                         f"({', '.join(f'{x:.6g}' for x in flat_points[0])}) (a surface of zero size)")
    for k, v in {**data, **first}.items():
        mesh.point_data[k] = v
    if "N" in mesh.point_data:
        N = np.asarray(mesh.point_data["N"])
        with np.errstate(invalid="ignore", divide="ignore"):  # degenerate points: filled from VTK's normals below
            N = N / np.linalg.norm(N, axis=1, keepdims=True)
        missing = ~np.all(np.isfinite(N), axis=1)
        if np.any(missing):
            normals = mesh.compute_normals(point_normals=True, cell_normals=False, auto_orient_normals=False,
                                           consistent_normals=False, split_vertices=False)
            fill = np.asarray(normals.point_data["Normals"][missing], dtype=float)
            with np.errstate(invalid="ignore", divide="ignore"):  # a zero-size surface: no normal at all (NaN)
                N[missing] = fill / np.linalg.norm(fill, axis=1, keepdims=True)  # VTK's normals are float32
        mesh.point_data["N"] = N
    return mesh


def _faces_without_collapsed_edges(quads):
    """VTK face array of welded quads: a quad with a collapsed edge becomes a triangle, a collapsed quad is dropped.

    Where an edge of the parameter square collapses to one point (the centre
    of a surface of revolution, a sphere's pole) welding leaves quads such as
    ``(c, c, a, b)``.  Passed on as quads they break VTK's edge traversal:
    ``compute_normals`` (which PyVista runs for smooth shading) then "repairs"
    the orientation of all cells but a strip, and the vertex normals along the
    strip's borders average to about zero: dark streaks from the centre
    outwards (Dill's sine wave of revolution).
    """
    quads = np.asarray(quads)
    nxt = np.roll(quads, -1, axis=1)
    keep = quads != nxt  # drop a vertex equal to its cyclic successor
    counts = keep.sum(axis=1)
    faces = []
    whole = counts == 4
    faces.append(np.hstack([np.full((whole.sum(), 1), 4), quads[whole]]).ravel())
    tri = counts == 3
    if np.any(tri):
        t = quads[tri][keep[tri]].reshape(-1, 3)
        distinct = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 0] != t[:, 2])
        t = t[distinct]
        faces.append(np.hstack([np.full((len(t), 1), 3), t]).ravel())
    return np.concatenate(faces)


def _first_of(labels, n=None):
    """For labels 0..n-1: the index of the first element carrying each label."""
    n = int(labels.max()) + 1 if n is None else n
    order = np.arange(len(labels))[::-1]
    pick = np.empty(n, dtype=int)
    pick[labels[order]] = order  # reversed assignment leaves the smallest index
    return pick


def _bilinear(corner_values, s):
    """Bilinear interpolation of ``(..., 2, 2, c)`` corner values on the grid ``s x s`` (s from 0 to 1)."""
    a = np.stack([1 - s, s], axis=-1)  # (r, 2)
    return np.einsum("ia,jb,...abc->...ijc", a, a, corner_values)


def _curvature_data(D, curv):
    """Point data of a curvature mesh: K, H, k1, k2, degenerate and the unit normal N."""
    N, _ = unit_normal(D.bu, D.bv)
    return {"K": curv.K, "H": curv.H, "k1": curv.k1, "k2": curv.k2, "degenerate": curv.degenerate, "N": N}


def patches_mesh(patches, resolution=1, *, memory_limit=None):
    """A welded :class:`pyvista.PolyData` of a :class:`lab.BezierPatches` collection.

    Parameters
    ----------
    patches : BezierPatches
    resolution : int
        Quads per patch edge; 1 gives one quad per patch with the corners only,
        as the practical draws it.

    Returns
    -------
    pyvista.PolyData
        Point data ``K``, ``H``, ``k1``, ``k2`` (exact at every node),
        ``degenerate`` (bool), ``N`` (unit normal b_u x b_v / |b_u x b_v|); if
        the collection has been coloured (``visualize_curvature`` or
        ``set_colors``), also ``RGB`` (uint8, the corner colours interpolated
        bilinearly inside a patch, as Gouraud shading would) and ``values``
        (the stored corner values, interpolated).  Patches that tile a grid
        (:attr:`lab.BezierPatches.grid_shape`) are welded by index, also across the
        surface's seams (:attr:`lab.BezierPatches.seams`); unrelated patches by distance.
    """
    resolution = _v.as_positive_int(resolution, "resolution", minimum=1)
    _v.check_memory(MESH_BYTES_PER_POINT * len(patches) * (resolution + 1) ** 2,
                    f"a mesh of {len(patches)} patches at resolution {resolution}", memory_limit)
    s = np.linspace(0.0, 1.0, resolution + 1)
    if resolution == 1:
        D = patches.corner_derivatives()
        curv = patches.corner_curvature(D)
    else:
        U, V = np.meshgrid(s, s, indexing="ij")
        D = patches.derivatives(U, V)
        curv = patches.curvature_at(U, V)
    data = _curvature_data(D, curv)
    if np.all(np.isfinite(patches.colors)):
        data["colors"] = _bilinear(patches.colors, s)
        data["values"] = _bilinear(patches.curvature[..., None], s)[..., 0]
    mesh = grid_mesh(D.b, data, grid_shape=patches.grid_shape, seams=patches.seams)
    if "colors" in mesh.point_data:
        mesh.point_data["RGB"] = np.round(255 * np.clip(mesh.point_data.pop("colors"), 0, 1)).astype(np.uint8)
    return mesh


def surface_mesh(surface, nu=64, nv=64, curvature_mode=None, color_map=None, *, memory_limit=None, **map_options):
    """A welded mesh of any :class:`lab.Surface` on an ``nu x nv`` parameter grid, with exact curvature.

    The grid is sampled in one pass (:meth:`lab.Surface.sample_grid`: basis
    functions once per u and once per v); its nodes are the vertices, welded
    by index where the surface closes on itself or collapses
    (:attr:`lab.Surface.seams`: a torus's seams, a sphere's poles), never by
    distance.  Point data as :func:`patches_mesh`, plus ``uv``, the
    parameters of each vertex (the first node's on a seam).  With
    ``curvature_mode`` and ``color_map`` the point data also holds ``values``
    and ``RGB`` coloured like :meth:`lab.BezierPatches.visualize_curvature`.
    ``memory_limit``: see :func:`lab.memory_limit`; larger grids are refused before any work.
    """
    nu = _v.as_positive_int(nu, "nu", minimum=2)
    nv = _v.as_positive_int(nv, "nv", minimum=2)
    _v.check_memory(MESH_BYTES_PER_POINT * nu * nv, f"a surface mesh of {nu} x {nv} vertices", memory_limit)
    (u0, u1), (v0, v1) = surface.domain
    u, v = np.linspace(u0, u1, nu), np.linspace(v0, v1, nv)
    b, N, curv = surface.sample_grid(u, v, memory_limit=memory_limit)
    data = {"K": curv.K, "H": curv.H, "k1": curv.k1, "k2": curv.k2, "degenerate": curv.degenerate, "N": N}
    uv = np.empty((nu, nv, 2))
    uv[..., 0], uv[..., 1] = u[:, None], v[None, :]
    mesh = grid_mesh(b[None], {k: x[None] for k, x in data.items()}, first_data={"uv": uv[None]}, grid_shape=(1, 1),
                     seams=surface.seams)
    if curvature_mode is not None and color_map is not None:
        color_curvature(mesh, curvature_mode, color_map, **map_options)
    return mesh


def color_curvature(mesh, curvature_mode, color_map, **map_options):
    """Add ``values`` and ``RGB`` point data to a mesh with ``K, H, k1, k2`` point data (in place)."""
    curv = Curvature(*(mesh.point_data[k] for k in ("K", "H", "k1", "k2", "degenerate")))
    values = curvature_values(curv, curvature_mode)
    size = float(np.linalg.norm(np.ptp(mesh.points, axis=0)))
    name = color_map.value if hasattr(color_map, "value") else color_map
    rgb = colors_for(values, name, tol=zero_tolerance(CurvatureMode(curvature_mode), size), **map_options)
    mesh.point_data["values"] = values
    mesh.point_data["RGB"] = np.round(255 * rgb).astype(np.uint8)
    return mesh



def color_cells(mesh, curvature_mode=None, color_map=None, **map_options):
    """Dill's polygon colours: one colour per cell, from the mean of its vertices' values (returns a copy).

    Dill (1981, "Image generation"): "A set of values … is assigned to
    each polygon by averaging the values at the vertices", and the polygon is
    coloured by that value.  With ``curvature_mode`` and ``color_map`` the mean
    of the cell's vertex curvature is coloured by the map (with
    ``map_options``); without them (patches coloured by their own
    ``visualize_curvature``) a cell gets the mean of its vertices' ``RGB``.
    The result has cell data ``values`` (if coloured by a map) and ``RGB``
    (uint8) and no point colours.
    """
    offsets = np.asarray(mesh.face_offsets)
    conn = np.asarray(mesh.face_connectivity)
    counts = np.diff(offsets)

    def mean(values):
        values = np.asarray(values, dtype=float)
        return np.add.reduceat(values[conn], offsets[:-1], axis=0) / counts.reshape((-1,) + (1,) * (values.ndim - 1))

    out = mesh.copy()
    if curvature_mode is not None and color_map is not None:
        curv = Curvature(*(np.asarray(mesh.point_data[k]) for k in ("K", "H", "k1", "k2", "degenerate")))
        values = mean(curvature_values(curv, curvature_mode))
        size = float(np.linalg.norm(np.ptp(mesh.points, axis=0)))
        name = color_map.value if hasattr(color_map, "value") else color_map
        rgb = colors_for(values, name, tol=zero_tolerance(CurvatureMode(curvature_mode), size), **map_options)
        out.cell_data["values"] = values
    elif "RGB" in mesh.point_data:
        rgb = mean(mesh.point_data["RGB"]) / 255.0
    else:
        raise ValueError("color_cells needs a curvature mode and a colour map, or a mesh with RGB point colours")
    for name in ("RGB", "values"):
        if name in out.point_data:
            del out.point_data[name]
    out.cell_data["RGB"] = np.round(255 * np.clip(rgb, 0, 1)).astype(np.uint8)
    return out


def _faces(mesh):
    """Faces of a PolyData as a list of index arrays."""
    faces, out, i = mesh.faces, [], 0
    while i < len(faces):
        k = faces[i]
        out.append(faces[i + 1 : i + 1 + k])
        i += k + 1
    return out


def polyline_mesh(polylines):
    """A ``pyvista.PolyData`` of polylines from a list of ``(k, 3)`` point arrays (e.g. paths' ``points``),
    for ``render.show(..., lines=...)`` and the explorers' overlays."""
    pieces = [np.asarray(p, dtype=float).reshape(-1, 3) for p in polylines]
    pieces = [p for p in pieces if len(p) >= 2]
    if not pieces:
        return pv.PolyData()
    points = np.concatenate(pieces)
    cells, start = [], 0
    for p in pieces:
        cells.append(np.concatenate([[len(p)], np.arange(start, start + len(p))]))
        start += len(p)
    return pv.PolyData(points, lines=np.concatenate(cells).astype(np.int64))

