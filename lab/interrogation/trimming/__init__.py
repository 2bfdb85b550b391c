"""Trimmed surfaces (Choi & Lee, §2): trimming loops in the parameter domain, their
validation and constrained Delaunay triangulation, and the trimmed surface with exact curvature.
``loops`` → ``triangulation`` → ``surface``; may import numpy, scipy, triangle, lab.geometry and lab.mesh.
"""

from .loops import (
    TRIM_RTOL,
    BSplineLoop,
    circle,
    circle_curve,
    distance_to_loop,
    loop_intersections,
    loops_intersections,
    point_in_loop,
    rectangle,
    signed_area,
)
from .surface import TrimmedSurface, trimmed
from .triangulation import MAX_MIN_ANGLE, Triangulation, boundary_edges, triangulate, validate_loops

__all__ = [
    "MAX_MIN_ANGLE",
    "TRIM_RTOL",
    "BSplineLoop",
    "Triangulation",
    "TrimmedSurface",
    "boundary_edges",
    "circle",
    "circle_curve",
    "distance_to_loop",
    "loop_intersections",
    "loops_intersections",
    "point_in_loop",
    "rectangle",
    "signed_area",
    "triangulate",
    "trimmed",
    "validate_loops",
]
