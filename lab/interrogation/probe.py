r"""A point probe: K, H, κ1, κ2, the principal directions and the Dupin indicatrix at one (u, v).

The Dupin indicatrix is the conic :math:`\kappa_1 x^2 + \kappa_2 y^2 = \pm 1` in the tangent plane, with
:math:`x, y` along :math:`\mathbf d_1, \mathbf d_2`: in the direction at angle θ from
:math:`\mathbf d_1` its radius is :math:`1/\sqrt{|\kappa_n(\theta)|}`,
:math:`\kappa_n = \kappa_1\cos^2\theta + \kappa_2\sin^2\theta` (Euler).  An
ellipse at an elliptic point, two pairs of conjugate hyperbolas at a hyperbolic
one (separated by the asymptotic directions, where :math:`\kappa_n = 0`), two
parallel lines at a parabolic one.  Drawn to scale ``size``: the shortest radius
(that of the largest :math:`|\kappa|`) is ``size``.
"""

from typing import NamedTuple

import numpy as np

from ..geometry import validation as _v
from . import export
from .faces import as_surface, check_inside, check_surface, is_face

__all__ = ["Probe", "probe", "probe_lines"]


class Probe(NamedTuple):
    """Curvature at one point: ``uv``, ``point``, ``normal``, ``K``, ``H``, ``k1``, ``k2``, ``d1``, ``d2`` (NaN at an
    umbilic), ``umbilic``, ``degenerate``, and ``indicatrix``: polylines (each (k, 3)) of the Dupin indicatrix
    (empty at an umbilic of a plane, a circle at any other umbilic)."""

    uv: tuple
    point: np.ndarray
    normal: np.ndarray
    K: float
    H: float
    k1: float
    k2: float
    d1: np.ndarray
    d2: np.ndarray
    umbilic: bool
    degenerate: bool
    indicatrix: list

    def _table(self):
        """The readout as one row: (u, v), the point, the normal, K, H, κ1, κ2, d1, d2, the flags."""
        from ..i18n import _

        columns = {"u": [float(self.uv[0])], "v": [float(self.uv[1])]}
        for name, vec in (("", self.point), ("n", self.normal), ("d1", self.d1), ("d2", self.d2)):
            columns.update({f"{name}{'_' if name else ''}{c}": [float(vec[k])] for k, c in enumerate("xyz")})
        columns.update({"K": [float(self.K)], "H": [float(self.H)], "k1": [float(self.k1)], "k2": [float(self.k2)],
                        "umbilic": [bool(self.umbilic)], "degenerate": [bool(self.degenerate)]})
        length = _("length")
        units = {"u": _("parameter"), "v": _("parameter"), "x": length, "y": length, "z": length,
                 "K": f"1/{length}²", "H": f"1/{length}", "k1": f"1/{length}", "k2": f"1/{length}"}
        units.update({f"{n}_{c}": _("unit vector") for n in ("n", "d1", "d2") for c in "xyz"})
        return export.Table(_("curvature at a point (probe)"), columns, units,
                            {"directions": _("d1, d2 NaN at an umbilic")})

    to_csv = export.to_csv
    to_pandas = export.to_pandas


def _indicatrix(point, e1, e2, k1, k2, size, n=181, reach=3.0):
    """Polylines of κ1 x² + κ2 y² = ±1 scaled so the shortest radius is ``size``; hyperbolas cut at ``reach``·size,
    ellipses at 10·size (only the very long ones of a nearly parabolic point)."""
    big = max(abs(k1), abs(k2))
    if not big > 0:
        return []
    lines = []
    theta = np.linspace(0.0, 2 * np.pi, n)
    kn = k1 * np.cos(theta) ** 2 + k2 * np.sin(theta) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        r = size * np.sqrt(big / np.abs(kn))
    if k1 * k2 > 0:  # an ellipse: drawn whole unless it is very long (near a parabolic point)
        reach = max(reach, 10.0)
    for sign in (1.0, -1.0):
        inside = (np.sign(kn) == sign) & (r <= reach * size)
        # the runs of directions on this side of the asymptotes, each one branch
        idx = np.nonzero(inside)[0]
        if not len(idx):
            continue
        runs = np.split(idx, np.nonzero(np.diff(idx) > 1)[0] + 1)
        if len(runs) > 1 and runs[0][0] == 0 and runs[-1][-1] == n - 1:  # θ = 0 and 2π are one direction
            runs = [np.concatenate([runs[-1], runs[0][1:]]), *runs[1:-1]]
        for run in runs:
            if len(run) < 2:
                continue
            t, rr = theta[run], r[run]
            lines.append(point + rr[:, None] * (np.cos(t)[:, None] * e1 + np.sin(t)[:, None] * e2))
    return lines


def probe(surface, u, v, *, size=None):
    """The curvature at ``(u, v)`` of ``surface`` with its principal directions and Dupin indicatrix.

    Parameters
    ----------
    surface : lab.Surface or lab.Face
        A surface, or a face of a model (:func:`lab.read`): then ``(u, v)`` must lie in the face's trimmed
        region, and the curvature and normal are the face's (H, κ1, κ2 change sign on a reversed face, κ1 and κ2
        and their directions swap).
    u, v : float
        A point of the domain.
    size : float, optional
        The indicatrix's shortest radius (default: 5 % of the surface's bounding-box diagonal).
    """
    reverse = bool(getattr(surface, "reversed", False)) if is_face(surface) else False
    surface, trim = as_surface(surface)
    check_surface(surface)
    (u0, u1), (v0, v1) = surface.domain
    u, v = _v.as_number(u, "u"), _v.as_number(v, "v")
    if not (u0 <= u <= u1 and v0 <= v <= v1):
        raise ValueError(f"(u, v) must lie in the domain [{u0:g}, {u1:g}] x [{v0:g}, {v1:g}]; got ({u:g}, {v:g})")
    check_inside(trim, (u, v), "the probe's point")
    if size is None:
        g = np.asarray(surface.evaluate(*np.meshgrid(np.linspace(u0, u1, 9), np.linspace(v0, v1, 9))))
        size = 0.05 * float(np.linalg.norm(np.ptp(g.reshape(-1, 3), axis=0)))
    size = _v.as_number(size, "size", positive=True, maximum=_v.COORDINATE_MAX)  # drawn as coordinates: bounded as they are
    c = surface.curvature(np.array([u]), np.array([v]), directions=True)
    point = np.asarray(surface.evaluate(np.array([u]), np.array([v])), dtype=float).reshape(3)
    d = surface.derivatives(np.array([u]), np.array([v]))
    n = np.cross(np.asarray(d.bu, dtype=float).reshape(3), np.asarray(d.bv, dtype=float).reshape(3))
    normal = n / np.linalg.norm(n) if np.linalg.norm(n) > 0 else np.full(3, np.nan)
    k1, k2 = float(c.k1[0]), float(c.k2[0])
    d1, d2 = np.asarray(c.d1, dtype=float).reshape(3), np.asarray(c.d2, dtype=float).reshape(3)
    umbilic, degenerate = bool(c.umbilic[0]), bool(c.degenerate[0])
    if umbilic and not degenerate:  # every direction is principal: draw the circle in any frame of the plane
        e1 = np.asarray(d.bu, dtype=float).reshape(3)
        e1 = e1 / np.linalg.norm(e1)
        e2 = np.cross(normal, e1)
        lines = _indicatrix(point, e1, e2, k1, k2, size)
    elif degenerate:
        lines = []
    else:
        lines = _indicatrix(point, d1, d2, k1, k2, size)
    H = float(c.H[0])
    if reverse:  # the opposite normal: (d1, d2, N) stays right-handed with d1 and d2 swapped
        normal, H, k1, k2, d1, d2 = -normal, -H, -k2, -k1, d2, d1
    return Probe((u, v), point, normal, float(c.K[0]), H, k1, k2, d1, d2, umbilic, degenerate, lines)


def probe_lines(p, *, size=None):
    """The probe as one pyvista.PolyData of lines: the directions d1, d2 as segments of length 2·``size`` through
    the point (cell data ``part`` 0 and 1) and the indicatrix (part 2)."""
    import pyvista as pv

    if size is None:
        size = max((float(np.max(np.linalg.norm(x - p.point, axis=1))) for x in p.indicatrix), default=1.0)
    points, cells, part = [], [], []
    for k, d in enumerate((p.d1, p.d2)):
        if np.all(np.isfinite(d)):
            points += [p.point - size * d, p.point + size * d]
            cells += [2, len(points) - 2, len(points) - 1]
            part.append(k)
    for line in p.indicatrix:
        start = len(points)
        points += list(line)
        cells += [len(line), *range(start, start + len(line))]
        part.append(2)
    mesh = pv.PolyData(np.array(points, dtype=float).reshape(-1, 3), lines=np.array(cells, dtype=np.int64))
    mesh.cell_data["part"] = np.array(part, dtype=np.int64)
    return mesh
