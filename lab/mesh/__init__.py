"""Meshes (PyVista) from the geometry: surfaces, patch collections and triangle meshes with exact curvature as point
data, welding, level lines on triangle meshes, trimmed-surface meshes and geomview files (CBEZ, coloured OFF).
May import numpy, scipy, pyvista and lab.geometry; surfaces and patches arrive as arguments (duck-typed).
"""

from .build import WELD_RTOL, color_cells, color_curvature, grid_mesh, patches_mesh, polyline_mesh, surface_mesh, weld
from .geomview import read_cbez, read_geomview, read_off, write_cbez, write_off
from .triangles import mesh_arrays, triangle_mesh
from .trimmed import trimmed_mesh

__all__ = [
    "WELD_RTOL",
    "color_cells",
    "color_curvature",
    "grid_mesh",
    "mesh_arrays",
    "patches_mesh",
    "polyline_mesh",
    "read_cbez",
    "read_geomview",
    "read_off",
    "surface_mesh",
    "triangle_mesh",
    "trimmed_mesh",
    "weld",
    "write_cbez",
    "write_off",
]
