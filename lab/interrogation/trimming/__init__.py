"""Trimmed surfaces (Choi & Lee, ``seeds/002`` section 2): trimming loops in the parameter domain, their
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
    "BSplineLoop",
    "TrimmedSurface",
    "Triangulation",
    "trimmed",
    "circle",
    "circle_curve",
    "rectangle",
    "signed_area",
    "loop_intersections",
    "loops_intersections",
    "point_in_loop",
    "distance_to_loop",
    "validate_loops",
    "triangulate",
    "boundary_edges",
    "TRIM_RTOL",
    "MAX_MIN_ANGLE",
]
