"""Geodesics, normal sections and polar isodistance curves on a surface (Puig-Pey, Gálvez, Iglesias 2002).

``problem`` (the ODEs and the patch-wise surface) → ``integrator`` (solve_ivp, vectorised DOP853) → ``paths``
(paths and fans) → ``isodistance``, ``shortest``; ``lines`` (lines of curvature) on the same integrator.  May import numpy, scipy, lab.geometry and lab.model.
"""

from .isodistance import Isodistance, polar_isodistance
from .lines import UmbilicWarning, line_of_curvature, lines_of_curvature
from .paths import Fan, Path, geodesic, geodesic_fan, normal_section, normal_section_fan
from .problem import ATOL, RTOL, christoffel, start_direction
from .shortest import geodesic_between

__all__ = [
    "ATOL",
    "RTOL",
    "Fan",
    "Isodistance",
    "Path",
    "UmbilicWarning",
    "christoffel",
    "geodesic",
    "geodesic_between",
    "geodesic_fan",
    "line_of_curvature",
    "lines_of_curvature",
    "normal_section",
    "normal_section_fan",
    "polar_isodistance",
    "start_direction",
]
