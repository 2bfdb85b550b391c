"""A trimmed surface: a base surface restricted to the region between its trimming loops (Choi & Lee, §2)."""

import numpy as np

from ...geometry import validation as _v
from ...i18n import _
from ...mesh.trimmed import trimmed_mesh
from .loops import TRIM_RTOL, distance_to_loop, point_in_loop, signed_area
from .triangulation import _domain_scale, triangulate, validate_loops

__all__ = ["TrimmedSurface", "trimmed"]

# -- the trimmed surface -------------------------------------------------------------


class TrimmedSurface:
    """A base surface restricted to the region bounded by trimming loops in its domain (Choi & Lee, §2).

    Build it with :func:`trimmed`.  The loops are stored as validated
    polylines: :attr:`outer` (counter-clockwise) and :attr:`holes` (clockwise).

    Parameters
    ----------
    surface : lab.Surface
        The base surface (anything with ``domain``, ``derivatives`` and ``curvature``).
    outer : (k, 2) array_like or BSplineLoop or None
        Outer loop, counter-clockwise; ``None`` is the boundary of the domain.
    holes : sequence of ((k, 2) array_like or BSplineLoop)
        Holes, clockwise.
    tol : float, optional
        Chordal tolerance for sampling B-spline loops (default ``1e-4`` times
        the diagonal of the domain).
    """

    def __init__(self, surface, outer=None, holes=(), tol=None):
        for attr in ("domain", "derivatives", "curvature"):
            if not hasattr(surface, attr) or isinstance(surface, type):
                raise TypeError(f"surface must be a lab.Surface (with domain, derivatives, curvature); got {surface!r}")
        self.surface = surface
        self.domain = tuple(tuple(float(x) for x in pair) for pair in surface.domain)
        self.outer, self.holes = validate_loops(outer, holes, self.domain, tol)

    @property
    def loops(self):
        """The outer loop followed by the holes, as polylines."""
        return [self.outer] + self.holes

    @property
    def area_uv(self):
        """Area of the trimmed region in the parameter domain (outer minus holes, as polygons)."""
        return signed_area(self.outer) + sum(signed_area(h) for h in self.holes)

    def contains(self, u, v, atol=None):
        """Whether ``(u, v)`` lies in the trimmed region; points on a loop (within ``atol``) count as inside.

        Parameters
        ----------
        u, v : array_like
            Broadcast against each other (need not lie in the domain).
        atol : float, optional
            Default :data:`TRIM_RTOL` times the diagonal of the domain.

        Returns
        -------
        bool ndarray of shape ``broadcast(u, v).shape``
        """
        uu, vv = np.broadcast_arrays(_v._as_float_array(u, "u"), _v._as_float_array(v, "v"))
        X = np.column_stack([uu.ravel(), vv.ravel()])
        if atol is None:
            atol = TRIM_RTOL * _domain_scale(self.domain)
        inside = point_in_loop(X, self.outer)
        for h in self.holes:
            inside &= ~point_in_loop(X, h)
        near = np.zeros(len(X), dtype=bool)
        for L in self.loops:
            near |= distance_to_loop(X, L) <= atol
        return (inside | near).reshape(uu.shape)

    def _inside(self, u, v, what):
        u, v = _v.as_parameters(u, v, self.domain)
        ok = self.contains(u, v)
        if not np.all(ok):
            i = int(np.flatnonzero(~ok.ravel())[0])
            raise ValueError(
                f"{what}: {np.count_nonzero(~ok)} of {ok.size} (u, v) points lie outside the trimmed region, "
                f"e.g. ({u.ravel()[i]:g}, {v.ravel()[i]:g}); select points with contains(u, v)"
            )
        return u, v

    def derivatives(self, u, v):
        """Derivatives of the base surface at ``(u, v)`` inside the trimmed region (``ValueError`` outside)."""
        return self.surface.derivatives(*self._inside(u, v, "derivatives"))

    def evaluate(self, u, v):
        """Surface points at ``(u, v)`` inside the trimmed region (``ValueError`` outside)."""
        return self.derivatives(u, v).b

    def curvature(self, u, v, outside="raise"):
        """Curvature of the base surface (fields ``K, H, k1, k2, degenerate``) at ``(u, v)``.

        Trimming does not change the surface, so the values are the base
        surface's.  Points outside the trimmed region raise a ``ValueError``
        (``outside="raise"``) or get NaN values with ``degenerate`` False
        (``outside="nan"``).
        """
        outside = _v.as_choice(outside, ("raise", "nan"), "outside")
        if outside == "raise":
            return self.surface.curvature(*self._inside(u, v, "curvature"))
        u, v = _v.as_parameters(u, v, self.domain)
        c = self.surface.curvature(u, v)
        ok = self.contains(u, v)
        return type(c)(*(np.where(ok, f, np.nan) for f in c[:4]), np.where(ok, c.degenerate, False))

    def triangulate(self, n_u=32, n_v=32, max_area=None, min_angle=20.0, iso_nodes=True):
        """Triangulate the trimmed region in ``(u, v)``; see :func:`triangulate`."""
        return triangulate(self.outer, self.holes, self.domain, n_u, n_v, max_area, min_angle, iso_nodes)

    def to_mesh(self, n_u=32, n_v=32, max_area=None, min_angle=20.0, curvature_mode=None, color_map=None):
        """A :class:`pyvista.PolyData` with exact curvature point data; see :func:`lab.mesh.trimmed_mesh`."""
        return trimmed_mesh(self, n_u=n_u, n_v=n_v, max_area=max_area, min_angle=min_angle,
                            curvature_mode=curvature_mode, color_map=color_map)

    def __repr__(self):
        return _("TrimmedSurface({surface}, outer loop of {n} points, {holes} holes)").format(
            surface=repr(self.surface), n=len(self.outer), holes=len(self.holes))


def trimmed(surface, outer=None, holes=(), *, tol=None):
    """A trimmed surface: ``surface`` restricted to the region inside ``outer`` and outside the ``holes``.

    Parameters
    ----------
    surface : lab.Surface
    outer : (k, 2) array_like or BSplineLoop or None
        Counter-clockwise outer loop in the parameter domain; ``None`` is the domain's boundary.
    holes : sequence of ((k, 2) array_like or BSplineLoop)
        Clockwise holes strictly inside the outer loop.
    tol : float, optional
        Chordal tolerance for sampling B-spline loops (default ``1e-4`` times
        the diagonal of the domain).

    Returns
    -------
    TrimmedSurface

    Examples
    --------
    >>> import lab
    >>> from lab import trimming
    >>> s = trimming.trimmed(lab.surfaces.plane(), trimming.circle((0.5, 0.5), 0.4, n=128),
    ...                      holes=[trimming.circle((0.5, 0.5), 0.1, n=32, clockwise=True)])
    >>> bool(s.contains(0.5, 0.5)), bool(s.contains(0.5, 0.75))
    (False, True)
    """
    return TrimmedSurface(surface, outer, holes, tol=tol)

