"""curvature-lab: exact curvature of free-form surfaces for teaching (Versuch 6: Krümmungsvisualisierung)."""

from . import bezier, bspline, colormaps, curvature, focal, geodesics, reflection, surfaces, trimming, widgets
from .curvature import Curvature, DegeneratePointWarning, PointClass
from .derivatives import Derivatives
from .patches import BezierPatch, BezierPatches, ColorMap, CurvatureMode
from .surface import BezierSurface, BSplineSurface, ParametricSurface, Surface
from .trimming import BSplineLoop, TrimmedSurface, trimmed
from .geodesics import (
    Fan,
    Isodistance,
    geodesic,
    geodesic_between,
    geodesic_fan,
    normal_section,
    normal_section_fan,
    polar_isodistance,
)
from .widgets import CurvatureExplorer, FocalExplorer, GeodesicExplorer, ReflectionExplorer
from .interrogation import (
    FocalSheetWarning,
    focal_sheets,
    focal_surface,
    isophotes,
    parabolic_lines,
    polylines,
    reflection_lines,
    stripe_mapping,
)

__version__ = "0.1.0"

__all__ = [
    "bezier",
    "bspline",
    "colormaps",
    "curvature",
    "surfaces",
    "Curvature",
    "DegeneratePointWarning",
    "PointClass",
    "Derivatives",
    "BezierPatch",
    "BezierPatches",
    "ColorMap",
    "CurvatureMode",
    "BezierSurface",
    "BSplineSurface",
    "ParametricSurface",
    "Surface",
    "trimming",
    "BSplineLoop",
    "TrimmedSurface",
    "trimmed",
    "focal",
    "reflection",
    "FocalSheetWarning",
    "focal_sheets",
    "focal_surface",
    "isophotes",
    "parabolic_lines",
    "polylines",
    "reflection_lines",
    "stripe_mapping",
    "geodesics",
    "Fan",
    "Isodistance",
    "geodesic",
    "geodesic_between",
    "geodesic_fan",
    "normal_section",
    "normal_section_fan",
    "polar_isodistance",
    "widgets",
    "CurvatureExplorer",
    "FocalExplorer",
    "GeodesicExplorer",
    "ReflectionExplorer",
]
