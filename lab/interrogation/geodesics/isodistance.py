"""Polar isodistance curves: the points at arc length s_L along a fan of paths (Puig-Pey et al., §3, 5)."""

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from ...geometry import validation as _v
from .paths import Fan, Path

__all__ = ["Isodistance", "polar_isodistance"]


@dataclass(frozen=True, eq=False)
class Isodistance:
    """One piece of a polar isodistance curve (Puig-Pey et al., §3).

    Attributes
    ----------
    distance : float
        The arc length s_L from the origin along the paths.
    uv : (k, 2) ndarray
        Parameters of the samples (wrapped into the domain in periodic directions).
    points : (k, 3) ndarray
        Surface points; for a closed curve the last sample repeats the first.
    angles : (k,) ndarray
        Start angle α of each sample (increasing; may exceed 2π on a piece that runs over α = 0).
    closed : bool
        True when every path of the fan reached the distance.
    """

    distance: float
    uv: np.ndarray
    points: np.ndarray
    angles: np.ndarray
    closed: bool

    def __repr__(self):
        kind = "closed" if self.closed else "open"
        return f"Isodistance({kind}, distance={self.distance:g}, {len(self.points)} points)"


# --------------------------------------------------------------------------- polar isodistance curves


def _as_paths(fan):
    paths = list(fan.paths) if isinstance(fan, Fan) else list(fan) if isinstance(fan, (list, tuple)) else None
    if not paths or not all(isinstance(p, Path) for p in paths):
        raise TypeError(f"fan must be a Fan or a non-empty list of Path objects; got {type(fan).__name__}")
    first = paths[0]
    for p in paths[1:]:
        if p.surface is not first.surface or not np.allclose(p.origin, first.origin, rtol=0, atol=1e-12):
            raise ValueError("all paths of a fan must start at the same point of the same surface")
    return sorted(paths, key=lambda p: np.mod(p.angle, 2 * np.pi))


#: A curve's sample: its (u, v) and point, kept, and the spline's and the surface evaluation's temporaries.
ISODISTANCE_BYTES_PER_SAMPLE = 300


def polar_isodistance(fan, distances, *, samples_per_angle=8):
    r"""Polar isodistance curves: the points at arc length s_L along every path of a fan (Puig-Pey et al., §3, 5).

    For each distance the point of every path that reaches it is taken from
    the solver's dense output.  If all paths reach it, the curve is closed and
    interpolated in α by a periodic cubic spline through the parameters
    ``(u, v)`` (the paper's "closed cyclic cubic spline"); otherwise each run of
    consecutive angles whose paths reach it (cyclically) becomes an open piece:
    a not-a-knot cubic spline in α with at least four points, linear
    interpolation in ``(u, v)`` with two or three, a single point with one.
    The splines live in the parameter domain (unwrapped across periodic seams)
    and are mapped onto the surface.

    Parameters
    ----------
    fan : Fan or list of Path
        Paths from one point (from :func:`geodesic_fan` or :func:`normal_section_fan`).
    distances : float or (d,) array_like
        Positive arc lengths s_L.
    samples_per_angle : int
        Samples per angle interval of the fan.

    Returns
    -------
    list of list of Isodistance
        One list per distance: a single closed curve, or the open pieces
        (empty when no path reaches the distance).  The spline passes exactly
        through the paths' points; between them it interpolates.
    """
    paths = _as_paths(fan)
    surface = paths[0].surface
    if isinstance(fan, Fan):
        full_circle = fan.full_circle
    else:  # a list of paths: cyclic when its angles are equally spaced around the circle
        a = np.sort(np.mod([p.angle for p in paths], 2 * np.pi))
        full_circle = len(a) >= 2 and np.allclose(np.diff(np.append(a, a[0] + 2 * np.pi)), 2 * np.pi / len(a))
    dist = np.atleast_1d(_v.as_array(distances, "distances", finite=False))
    if dist.ndim != 1 or not np.all(np.isfinite(dist)) or np.any(dist <= 0):
        raise ValueError(f"distances must be positive finite numbers; got {distances}")
    per = _v.as_positive_int(samples_per_angle, "samples_per_angle", minimum=1)
    n = len(paths)
    _v.check_memory(ISODISTANCE_BYTES_PER_SAMPLE * dist.size * (n * per + 1),
                    f"{dist.size} polar isodistance curve(s) of {n} x {per} samples")
    alpha = np.array([np.mod(p.angle, 2 * np.pi) for p in paths])
    wrap = paths[0]._wrap
    out = []
    for sL in dist:
        reached = np.array([p.length >= sL * (1 - 1e-13) for p in paths])
        nodes = np.full((n, 2), np.nan)
        for k in np.flatnonzero(reached):
            nodes[k] = paths[k]._state(np.array([min(sL, paths[k].length)]))[0, :2]
        pieces = []
        if reached.all() and n >= 3 and full_circle:
            a = np.append(alpha, alpha[0] + 2 * np.pi)
            spline = CubicSpline(a, np.vstack([nodes, nodes[:1]]), bc_type="periodic")
            fine = np.linspace(a[0], a[-1], n * per + 1)
            pieces.append(_piece(surface, wrap, sL, fine, spline(fine), closed=True))
        elif reached.all() and full_circle:
            a = np.append(alpha, alpha[0] + 2 * np.pi)
            pieces.append(_linear_piece(surface, wrap, sL, a, np.vstack([nodes, nodes[:1]]), per, closed=True))
        else:
            for run in (_runs(reached) if full_circle else _linear_runs(reached)):
                a = alpha[run] + 2 * np.pi * np.cumsum(np.r_[0, np.diff(alpha[run]) < 0])  # increasing across α = 0
                pts = nodes[run]
                if len(run) >= 4:
                    spline = CubicSpline(a, pts)
                    fine = np.linspace(a[0], a[-1], (len(run) - 1) * per + 1)
                    pieces.append(_piece(surface, wrap, sL, fine, spline(fine), closed=False))
                else:
                    pieces.append(_linear_piece(surface, wrap, sL, a, pts, per, closed=False))
        out.append(pieces)
    return out


def _linear_runs(mask):
    """Maximal runs of consecutive True entries of a (non-cyclic) boolean mask, as index arrays."""
    runs, current = [], []
    for k, m in enumerate(mask):
        if m:
            current.append(k)
        elif current:
            runs.append(np.array(current))
            current = []
    if current:
        runs.append(np.array(current))
    return runs


def _runs(mask):
    """Maximal runs of consecutive True entries of a cyclic boolean mask, as index arrays (not all True)."""
    n = len(mask)
    start = int(np.flatnonzero(~mask)[0])
    order = (np.arange(n) + start) % n  # begins at a False entry, so no run is split
    return [order[run] for run in _linear_runs(np.asarray(mask)[order])]


def _piece(surface, wrap, sL, angles, uv, closed):
    uvw = wrap(uv)
    return Isodistance(float(sL), uvw, surface.evaluate(uvw[:, 0], uvw[:, 1]), angles, closed)


def _linear_piece(surface, wrap, sL, a, pts, per, closed):
    if len(pts) == 1:
        return _piece(surface, wrap, sL, a, pts, closed)
    fine = np.linspace(a[0], a[-1], (len(a) - 1) * per + 1)
    uv = np.stack([np.interp(fine, a, pts[:, 0]), np.interp(fine, a, pts[:, 1])], axis=1)
    return _piece(surface, wrap, sL, fine, uv, closed)


