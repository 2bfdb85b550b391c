"""The explorers: ipywidgets controls beside a live PyVista (trame) view, one call in a notebook each.

``base`` (threads, view, lifecycle) → ``curvature``, ``interrogation`` (focal, reflection, geodesic); ``models``
(a model's meshes by lines per face), ``edges`` and ``tools`` beside them.
May import ipywidgets, pyvista, trame and every layer below lab.view.
"""

from .base import Explorer, callback_threads, in_jupyter_session, live_view_possible
from .curvature import CurvatureExplorer
from .interrogation import FocalExplorer, GeodesicExplorer, ReflectionExplorer

__all__ = [
           "CurvatureExplorer",
           "Explorer",
           "FocalExplorer",
           "GeodesicExplorer",
           "ReflectionExplorer",
           "callback_threads",
           "in_jupyter_session",
           "live_view_possible",
]
