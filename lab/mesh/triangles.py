"""Triangle meshes of the lab's surfaces whose vertices carry the exact curvature: what discrete estimators are
measured against (notebook 13).

:func:`triangle_mesh` samples a surface on an ``nu × nv`` parameter grid (:func:`lab.mesh.surface_mesh`, welded where
the surface closes on itself or collapses) and splits every quad into two triangles along a chosen diagonal: all the
same way (``"regular"``: six triangles at an inner vertex), alternating like a chessboard (``"alternating"``: four and
eight) or at random.  ``noise`` moves every vertex along its normal by a normally distributed distance, as a scanner's
measurement error; the exact values stay those of the vertex's (u, v).
"""

import numpy as np
import pyvista as pv

from ..geometry import validation as _v
from ..geometry.discrete import boundary_vertices
from ..geometry.grids import weld_labels
from .build import surface_mesh

__all__ = ["DIAGONALS", "mesh_arrays", "triangle_mesh"]

#: How the quads of the parameter grid are split.
DIAGONALS = ("regular", "alternating", "random")


def _grid_triangles(labels, nu, nv, diagonals, rng):
    """Two triangles per quad of the ``nu × nv`` grid whose node (i, j) is the vertex ``labels[i * nv + j]``,
    counter-clockwise in (u, v); triangles with two equal vertices (a collapsed edge) are dropped."""
    node = labels.reshape(nu, nv)
    a, b, c, d = node[:-1, :-1], node[1:, :-1], node[1:, 1:], node[:-1, 1:]  # (i, j), (i+1, j), (i+1, j+1), (i, j+1)
    if diagonals == "regular":
        flip = np.zeros(a.shape, dtype=bool)
    elif diagonals == "alternating":
        flip = (np.add.outer(np.arange(nu - 1), np.arange(nv - 1)) % 2).astype(bool)
    else:
        flip = rng.random(a.shape) < 0.5
    # along the diagonal a-c: (a, b, c), (a, c, d); along b-d: (a, b, d), (b, c, d)
    first = np.where(flip[..., None], np.stack([a, b, d], -1), np.stack([a, b, c], -1)).reshape(-1, 3)
    second = np.where(flip[..., None], np.stack([b, c, d], -1), np.stack([a, c, d], -1)).reshape(-1, 3)
    faces = np.concatenate([first, second])
    keep = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])
    return faces[keep]


def triangle_mesh(surface, nu=33, nv=None, *, diagonals="regular", noise=0.0, seed=0, memory_limit=None):
    """A triangle mesh of a :class:`lab.Surface` on an ``nu × nv`` parameter grid, with the exact curvature at every
    vertex.

    Parameters
    ----------
    surface : lab.Surface
    nu, nv : int
        Grid nodes along u and v (``nv`` defaults to ``nu``); very different numbers give long thin triangles.
    diagonals : {"regular", "alternating", "random"}
        How each quad is split (module docstring).
    noise : float
        Standard deviation of a displacement along the exact normal, a length in the surface's units, as a scanner's
        measurement error (0: the vertices lie on the surface).
    seed : int
        Of the random diagonals and the noise.

    Returns
    -------
    pyvista.PolyData
        Triangles, oriented like ``b_u × b_v``; point data ``K``, ``H``, ``k1``, ``k2``, ``N``, ``degenerate`` (exact,
        at the vertex's parameters), ``uv``, ``boundary`` (a vertex on an edge of only one triangle) and
        ``border_distance``: the distance in parameters to the nearest boundary edge of the domain, as a share of the
        domain's side (0 on the boundary, 0.5 in the middle; a periodic or collapsed edge is no boundary).
    """
    diagonals = _v.as_choice(diagonals, DIAGONALS, "diagonals")
    nu = _v.as_positive_int(nu, "nu", minimum=2)
    nv = nu if nv is None else _v.as_positive_int(nv, "nv", minimum=2)
    noise = _v.as_number(noise, "noise", minimum=0.0)
    seed = _v.as_positive_int(seed, "seed")
    quads = surface_mesh(surface, nu, nv, memory_limit=memory_limit)
    labels, n = weld_labels((nu, nv), surface.seams)
    if n != quads.n_points:  # pragma: no cover - surface_mesh welds by the same labels
        raise RuntimeError(f"the grid's {n} welded nodes are not the mesh's {quads.n_points} vertices")
    rng = np.random.default_rng(seed)
    faces = _grid_triangles(labels, nu, nv, diagonals, rng)
    points = np.asarray(quads.points, dtype=float).copy()
    if noise > 0:
        points += (noise * rng.standard_normal(len(points)))[:, None] * np.asarray(quads.point_data["N"])
    mesh = pv.PolyData(points, np.hstack([np.full((len(faces), 1), 3), faces]).ravel())
    for name in ("K", "H", "k1", "k2", "N", "degenerate", "uv"):
        mesh.point_data[name] = np.asarray(quads.point_data[name])
    mesh.point_data["boundary"] = boundary_vertices(faces, len(points))
    mesh.point_data["border_distance"] = _border_distance(np.asarray(quads.point_data["uv"]), surface)
    return mesh


def _border_distance(uv, surface):
    """Parameter distance of each (u, v) to the nearest boundary edge of the domain, as a share of that side."""
    out = np.full(len(uv), 0.5)
    (periodic_u, periodic_v), collapsed = surface.seams
    for axis, ((lo, hi), periodic) in enumerate(zip(surface.domain, (periodic_u, periodic_v))):
        if periodic:
            continue
        t = (uv[:, axis] - lo) / (hi - lo)
        for end, gone in zip((t, 1 - t), collapsed[axis]):
            if not gone:
                out = np.minimum(out, np.clip(end, 0.0, 0.5))
    return out


def mesh_arrays(mesh):
    """``(points, faces)`` of a triangle mesh (a :class:`pyvista.PolyData`): ``(n, 3)`` floats, ``(f, 3)`` ints."""
    if not isinstance(mesh, pv.PolyData):
        raise TypeError(f"mesh must be a pyvista.PolyData of triangles; got {type(mesh).__name__}")
    if mesh.n_cells and not mesh.is_all_triangles:
        raise ValueError("mesh must consist of triangles only; triangulate it first (mesh.triangulate())")
    faces = np.asarray(mesh.faces, dtype=np.intp).reshape(-1, 4)[:, 1:] if mesh.n_cells else np.zeros((0, 3), np.intp)
    return np.asarray(mesh.points, dtype=float), faces
