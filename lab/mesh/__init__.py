"""Meshes (PyVista) from the geometry: surfaces and patch collections with exact curvature as point data, welding,
level lines on triangle meshes, trimmed-surface meshes and geomview files (CBEZ, coloured OFF).
May import numpy, scipy, pyvista and lab.geometry; surfaces and patches arrive as arguments (duck-typed).
"""

from .build import WELD_RTOL, color_cells, color_curvature, grid_mesh, patches_mesh, surface_mesh, weld
from .geomview import read_cbez, read_off, write_cbez, write_off
from .trimmed import trimmed_mesh

__all__ = [
    "weld",
    "grid_mesh",
    "patches_mesh",
    "surface_mesh",
    "color_curvature",
    "color_cells",
    "trimmed_mesh",
    "write_off",
    "read_off",
    "write_cbez",
    "read_cbez",
    "WELD_RTOL",
]
