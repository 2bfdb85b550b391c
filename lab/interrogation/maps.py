r"""Maps CAD users read off a part: the draft angle against a pull direction with its parting line, and the
minimum radius of curvature against a threshold.

*Draft angle.*  A mould opens along a pull direction :math:`\mathbf p`; a face
releases when its normal leans towards :math:`\mathbf p`.  The draft angle is
the angle between the normal and the plane perpendicular to :math:`\mathbf p`,

.. math::  \delta = \arcsin(\mathbf N\cdot\hat{\mathbf p}) \in [-90°, 90°],

positive where :math:`\mathbf N` has a component along :math:`\mathbf p` (with
the practical's normal :math:`\mathbf N = \mathbf b_u\times\mathbf b_v/|\cdot|`,
so the sign follows the orientation).  On the sphere with its outward normal
and :math:`\mathbf p = \mathbf e_z`, :math:`\delta` is the latitude.  The
*parting line* is the level line :math:`\delta = 0` (the silhouette seen along
:math:`\mathbf p`).

*Minimum radius.*  The smallest radius of curvature at a point is
:math:`\rho_{\min} = 1/\max(|\kappa_1|, |\kappa_2|)` (infinite at a flat point);
a tool of radius ``r`` cannot follow the surface where :math:`\rho_{\min} < r`.
"""

import numpy as np

from ..geometry import validation as _v
from ..mesh.levels import level_lines

__all__ = ["below_radius", "draft_angle", "draft_colors", "draft_map", "min_radius", "parting_line", "radius_colors",
           "radius_map"]

#: colours of the maps (RGB in 0 … 1): draft < 0 (undercut) blue, > 0 red, the threshold map's flagged points
NEGATIVE, POSITIVE, ZERO = (0.15, 0.3, 0.9), (0.9, 0.2, 0.15), (0.93, 0.93, 0.93)
FLAGGED, CLEAR = (0.9, 0.15, 0.1), (0.8, 0.8, 0.8)


def draft_angle(normals, pull):
    r"""Draft angle in degrees, :math:`\arcsin(\mathbf N\cdot\hat{\mathbf p})`, of unit ``normals`` (..., 3).

    NaN normals (degenerate points) give NaN; the caller flags them (their ``degenerate`` mask).
    """
    N = _v.as_array(normals, "normals", finite=False)
    if N.ndim < 1 or N.shape[-1] != 3:
        raise ValueError(f"normals must have shape (..., 3); got {N.shape}")
    p = _v.as_direction(pull, "pull")
    return np.degrees(np.arcsin(np.clip(N @ p, -1.0, 1.0)))


def min_radius(k1, k2):
    r""":math:`1/\max(|\kappa_1|, |\kappa_2|)`: the smallest radius of curvature (``inf`` at flat points)."""
    k1, k2 = _v.as_broadcast_arrays(k1=k1, k2=k2)
    m = np.maximum(np.abs(k1), np.abs(k2))
    with np.errstate(divide="ignore", over="ignore"):  # flat (or flatter than 1/1.8e308): inf
        return 1.0 / m


def below_radius(k1, k2, r):
    """True where the smallest radius of curvature is below ``r`` (i.e. ``max(|k1|, |k2|) > 1/r``)."""
    r = _v.as_number(r, "r", positive=True)
    k1, k2 = _v.as_broadcast_arrays(k1=k1, k2=k2)
    m = np.maximum(np.abs(k1), np.abs(k2))
    return m * r > 1.0


def _mesh(surface, resolution):
    from .meshes import as_curvature_mesh

    return as_curvature_mesh(surface, resolution).copy()


def draft_map(surface, pull=(0.0, 0.0, 1.0), *, limit=None, resolution=None):
    """A mesh of ``surface`` coloured by the draft angle against ``pull``: point data ``draft`` (degrees) and ``RGB``.

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches or pyvista.PolyData (with point data ``N``)
    pull : (3,) array_like
        The pull direction of the mould (default +z).
    limit : float, optional
        Angle in degrees at which the colours saturate (default 90): blue below 0 (undercut), red above,
        white at 0.
    resolution : int, optional
    """
    limit = 90.0 if limit is None else _v.as_number(limit, "limit", positive=True)
    mesh = _mesh(surface, resolution)
    delta = draft_angle(np.asarray(mesh.point_data["N"]), pull)
    mesh.point_data["draft"] = delta
    mesh.point_data["RGB"] = draft_colors(delta, limit)
    return mesh


def draft_colors(delta, limit=90.0):
    """RGB bytes (k, 3) of draft angles ``delta`` (degrees): white at 0, blue at −``limit``, red at +``limit``."""
    t = np.clip(np.nan_to_num(np.asarray(delta, dtype=float)) / limit, -1.0, 1.0)[:, None]
    rgb = np.where(t < 0, np.asarray(ZERO) + (-t) * (np.asarray(NEGATIVE) - ZERO),
                   np.asarray(ZERO) + t * (np.asarray(POSITIVE) - ZERO))
    return np.round(255 * rgb).astype(np.uint8)


def radius_colors(below):
    """RGB bytes (k, 3): red where ``below``, grey elsewhere."""
    return np.round(255 * np.where(np.asarray(below)[:, None], FLAGGED, CLEAR)).astype(np.uint8)


def parting_line(surface, pull=(0.0, 0.0, 1.0), *, resolution=None):
    """The parting line: where the draft angle against ``pull`` is 0, as polylines (pyvista.PolyData, cell data ``line``)."""
    from .meshes import _lines_mesh, _triangles

    mesh = surface if "draft" in getattr(surface, "point_data", {}) else draft_map(surface, pull, resolution=resolution)
    lines = level_lines(np.asarray(mesh.points, dtype=float), _triangles(mesh), np.asarray(mesh.point_data["draft"]))
    return _lines_mesh([((i,), [line]) for i, line in enumerate(lines)], ("line",))


def radius_map(surface, r, *, resolution=None):
    """A mesh of ``surface`` with point data ``min_radius`` (``inf`` where ``flat``, a mask), ``below`` (min radius <
    ``r``) and ``RGB`` (red where below)."""
    r = _v.as_number(r, "r", positive=True)
    mesh = _mesh(surface, resolution)
    k1, k2 = np.asarray(mesh.point_data["k1"]), np.asarray(mesh.point_data["k2"])
    mesh.point_data["min_radius"] = min_radius(k1, k2)
    mesh.point_data["flat"] = np.isinf(mesh.point_data["min_radius"])
    below = below_radius(k1, k2, r)
    mesh.point_data["below"] = below
    mesh.point_data["RGB"] = radius_colors(below)
    return mesh
