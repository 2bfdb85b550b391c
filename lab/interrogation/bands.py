"""Level lines at the borders of a picture's colour bands: information not by colour alone (WCAG 2.1, SC 1.4.1).

A colour map divides the values into bands: the classification at 0 (the parabolic lines, :func:`lab.parabolic_lines`
is the case ``levels = (0,)`` on K), Dill's five bands at their four inner edges, a colour bar at its labelled
ticks (:func:`lab.view.legend.legend` gives the ``levels`` of each).  Drawn on the surface, these lines say where
a band ends for a student who cannot tell its colour from the next one, and the legend says what lies between them.
The lines are the zero sets of the piecewise-linear values minus each level (marching triangles,
:func:`lab.mesh.levels.level_lines`), joined across a model's face borders (:mod:`lab.interrogation.faces`).
"""

import numpy as np
import pyvista as pv

from ..geometry import validation as _v
from ..mesh.levels import level_lines
from . import faces as _models
from .meshes import _lines_mesh, _triangles, as_curvature_mesh

__all__ = ["band_lines"]

#: Point data of a curvature mesh for each measure (the classification is K's sign).
FIELDS = {"gaussian": "K", "classification": "K", "mean": "H", "k1": "k1", "k2": "k2"}


def band_lines(surface, values, levels, *, tol=0.0, resolution=None):
    """The level lines of ``values`` at each of ``levels`` on ``surface``, as one PolyData of polylines.

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches, lab.Model or pyvista.PolyData
        As :func:`lab.parabolic_lines` takes it (a surface is tessellated on a ``resolution`` grid); a mesh
        needs only the point data named by ``values``.
    values : str or array_like
        A point data name of the mesh (``"values"``: the colours' values, ``"K"``, ``"H"`` …), a measure
        (``"gaussian"``, ``"mean"``, ``"k1"``, ``"k2"``, ``"classification"``), or one value per point.
    levels : sequence of float
        The band borders, in the units of the values.
    tol : float
        Values within ``tol`` of a level count as on it (the classification's zero tolerance): a line runs
        only between values strictly above and strictly below.

    Returns
    -------
    pyvista.PolyData
        Polylines with cell data ``level`` (index into ``levels``) and ``value`` (the level).
    """
    mesh = surface if isinstance(surface, pv.PolyData) and resolution is None else as_curvature_mesh(surface, resolution)
    if isinstance(values, str):
        name = FIELDS.get(values, values)
        if name not in mesh.point_data:
            raise ValueError(f"values must name point data of the mesh or a measure ({', '.join(FIELDS)}); got "
                             f"{values!r}, the mesh has {', '.join(mesh.point_data.keys())}")
        f = np.asarray(mesh.point_data[name], dtype=float)
    else:
        f = _v.as_array(values, "values", finite=False)
        if f.shape != (mesh.n_points,):
            raise ValueError(f"values must give one number per point of the mesh ({mesh.n_points}); got shape {f.shape}")
    if isinstance(levels, (str, bytes)) or not hasattr(levels, "__len__") or any(np.ndim(x) for x in levels):
        raise TypeError(f"levels must be a sequence of numbers (the band borders); got {_v._short(levels)}")
    levels = [_v.as_number(x, "level") for x in levels]
    tol = _v.as_number(tol, "tol", minimum=0)
    X = np.asarray(mesh.points, dtype=float)
    T = _triangles(mesh) if mesh.n_cells else np.zeros((0, 3), dtype=np.int64)
    join = _models.join_tol(mesh)
    found = [((k, level), _models.joined(level_lines(X, T, f, level, tol=tol), join)) for k, level in enumerate(levels)]
    return _lines_mesh(found, ("level", "value"))
