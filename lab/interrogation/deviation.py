"""How far is a scanned part from its CAD model?  ``lab.deviation(points, part, tolerance=…)``.

For each scanned point the signed distance to the nearest point of the part: the foot point is found exactly
on the faces (Newton's iteration on the exact surface from the nearest vertex of a fine mesh, trims respected:
:mod:`lab.interrogation.projection`), and the face's normal at the foot gives the sign (+ above the surface,
on the side its normal points to; − below, inside a solid whose faces point outwards).  The statistics are
those a CAD system's point deviation reports (Rhino's PointDeviation): mean, median and standard deviation of
the signed distances, the largest distance above and below, and the share of points within the tolerance.

The colours (:func:`deviation_colors`) keep to Crameri's vik (:mod:`lab.geometry.palettes`), readable with a
colour-vision deficiency: points within the tolerance near-white, above it burnt orange, below it navy
(``"bands"``, vik's classification colours), or graded by how far they lie beyond it (``"graded"``).
"""

from dataclasses import dataclass, field

import numpy as np

from ..geometry import palettes
from ..geometry import validation as _v
from ..i18n import N_, _, decimal
from . import export
from .projection import closest_points

__all__ = ["DEVIATION_MAPS", "NO_SCAN", "Deviation", "DeviationStats", "deviation", "deviation_colors", "tolerance_band"]

#: The colour maps of a deviation: three bands, or graded beyond the tolerance.
DEVIATION_MAPS = ("bands", "graded")
#: Where the bands' colours sit on vik: below (navy), within (near-white), above (burnt orange), as the
#: curvature classification's (:data:`lab.geometry.palettes.CLASS_POSITIONS`).
BAND_POSITIONS = palettes.CLASS_POSITIONS
#: The graded map: vik from these positions at the tolerance to its ends at the range's ends.
GRADED_START = (0.36, 0.64)
#: The colour of a place no scanned point is near (:meth:`Deviation.on_points`): a neutral grey.
NO_SCAN = (0.62, 0.62, 0.62)
#: A place of the part counts as scanned when a foot point lies within this many times the scan's typical
#: spacing (the median distance between neighbouring feet).
REACH_SPACINGS = 6.0
#: Default tolerance, relative to the part's size (its bounding-box diagonal), when none is given.
DEFAULT_TOLERANCE_RTOL = 1e-3
#: The statistics with their names as tables and the CSV show them (marked for translation) and their units.
STATISTICS = (
    ("count", N_("points"), ""),
    ("mean", N_("mean distance"), "length"),
    ("median", N_("median distance"), "length"),
    ("std", N_("standard deviation"), "length"),
    ("mean_abs", N_("mean |distance|"), "length"),
    ("rms", N_("root mean square"), "length"),
    ("max_above", N_("largest above"), "length"),
    ("max_below", N_("largest below"), "length"),
    ("within", N_("share within tolerance"), "1"),
    ("above", N_("share above"), "1"),
    ("below", N_("share below"), "1"),
)


def tolerance_band(tolerance):
    """``tolerance`` as ``(lower, upper)``: a number t > 0 is ``(-t, t)``, a pair ``(lower <= 0 <= upper)`` itself."""
    if np.ndim(tolerance) == 0:
        t = _v.as_number(tolerance, "tolerance", positive=True)
        return (-t, t)
    if np.ndim(tolerance) != 1 or len(tolerance) != 2:
        raise ValueError(f"tolerance must be a number > 0 or a pair (lower, upper); got {tolerance!r}")
    lo, hi = (_v.as_number(x, "tolerance") for x in tolerance)
    if not lo <= 0 <= hi or lo == hi:
        raise ValueError(f"a tolerance pair must have lower <= 0 <= upper and lower < upper; got ({lo:g}, {hi:g})")
    return (lo, hi)


@dataclass(frozen=True)
class DeviationStats:
    """The statistics of a deviation (lengths in the part's unit; shares 0 … 1), as Rhino's PointDeviation gives
    them; ``std`` is the population standard deviation of the signed distances."""

    count: int
    mean: float
    median: float
    std: float
    mean_abs: float
    rms: float
    max_above: float
    max_below: float
    within: float
    above: float
    below: float
    tolerance: tuple

    def table(self):
        """The statistics as plain text in the current language (German with decimal commas)."""
        lines = []
        width = max(len(_(name)) for _key, name, _unit in STATISTICS)  # the names' column fits the language's longest
        for key, name, unit in STATISTICS:
            value = getattr(self, key)
            text = f"{value:d}" if key == "count" else f"{100 * value:.1f} %" if unit == "1" else f"{value:.6g}"
            lines.append(f"{_(name):<{width}} {decimal(text):>14}")
        lo, hi = self.tolerance
        lines.append(decimal(_("tolerance: {lo} … {hi}").format(lo=f"{lo:.6g}", hi=f"{hi:.6g}")))
        return "\n".join(lines)

    def _table(self):
        keys = [key for key, _name, _unit in STATISTICS]
        values = [float(getattr(self, key)) for key in keys]
        return export.Table(_("deviation statistics"), {"statistic": keys, "value": values},
                            {"value": _("length of the part; count in points; shares 0 … 1")},
                            {"tolerance": f"{self.tolerance[0]!r} … {self.tolerance[1]!r}"})

    to_csv = export.to_csv
    to_pandas = export.to_pandas

    def __str__(self):
        return self.table()


@dataclass(frozen=True, eq=False)
class Deviation:
    """A scan against its part: per point the signed ``distance``, the foot point's ``face`` and ``uv``.

    Attributes
    ----------
    points : (n, 3) ndarray
        The scanned points.
    distance : (n,) ndarray
        Signed distance to the nearest point of the part: + on the side the face's normal points to.
    face : (n,) ndarray of int
        The file index of the face the foot point lies on (0 for a single surface).
    uv : (n, 2) ndarray
        The foot point's parameters on that face (the file's parameters).
    foot : (n, 3) ndarray
        The foot points.
    normal : (n, 3) ndarray
        The face's unit normal at the foot.
    border : (n,) ndarray of bool
        Where the foot lies on a face's border (the point is beside the face, not above it).
    tolerance : (float, float)
        The band ``(lower, upper)`` counted as within.
    name : str
        What was scanned (the part's name), for tables and pictures.
    """

    points: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)
    face: np.ndarray = field(repr=False)
    uv: np.ndarray = field(repr=False)
    foot: np.ndarray = field(repr=False)
    normal: np.ndarray = field(repr=False)
    border: np.ndarray = field(repr=False)
    tolerance: tuple
    name: str = ""

    @property
    def band(self):
        """Per point: -1 below the tolerance, 0 within, +1 above (int8)."""
        lo, hi = self.tolerance
        return np.where(self.distance > hi, 1, np.where(self.distance < lo, -1, 0)).astype(np.int8)

    @property
    def stats(self):
        """The :class:`DeviationStats` of the signed distances."""
        d = self.distance
        n = len(d)
        if not n:
            nan = float("nan")
            return DeviationStats(0, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, self.tolerance)
        band = self.band
        return DeviationStats(n, float(d.mean()), float(np.median(d)), float(d.std()), float(np.abs(d).mean()),
                              float(np.sqrt(np.mean(d * d))), float(max(d.max(), 0.0)), float(min(d.min(), 0.0)),
                              float(np.mean(band == 0)), float(np.mean(band > 0)), float(np.mean(band < 0)),
                              self.tolerance)

    def colors(self, color_map="graded", vmax=None):
        """sRGB colours (n, 3) of the points under ``color_map`` (:func:`deviation_colors`)."""
        return deviation_colors(self.distance, self.tolerance, color_map, vmax=vmax)

    def on_points(self, X, reach=None):
        """The signed distance shown at places ``X`` (k, 3) of the part, e.g. the vertices of its mesh: that of
        the scanned point whose foot is nearest, or NaN where no foot lies within ``reach`` (default
        :data:`REACH_SPACINGS` times the median spacing of the feet) -- the part's unscanned places."""
        from scipy.spatial import cKDTree

        X = np.asarray(X, dtype=float).reshape(-1, 3)
        if not len(self.foot):
            return np.full(len(X), np.nan)
        tree = cKDTree(self.foot)
        if reach is None:
            if len(self.foot) > 1:
                spacing, _i = tree.query(self.foot, k=2)
                reach = REACH_SPACINGS * float(np.median(spacing[:, 1]))
            else:
                reach = np.inf
        gap, nearest = tree.query(X, distance_upper_bound=_v.as_number(reach, "reach", positive=True))
        out = np.full(len(X), np.nan)
        found = np.isfinite(gap)
        out[found] = self.distance[nearest[found]]
        return out

    def map(self, mesh, color_map="graded", *, vmax=None, reach=None):
        """A copy of ``mesh`` (a pyvista mesh of the part, e.g. ``model.to_mesh(n, n)``) coloured by the
        deviation: point data ``deviation`` (:meth:`on_points` at its vertices, NaN where not scanned) and
        ``RGB`` bytes (:func:`deviation_colors`; grey where not scanned)."""
        out = mesh.copy()
        values = self.on_points(np.asarray(out.points), reach=reach)
        out.point_data["deviation"] = values
        colors = deviation_colors(values, self.tolerance, color_map, vmax=vmax)
        out.point_data["RGB"] = np.round(255 * np.clip(colors, 0, 1)).astype(np.uint8)
        return out

    def outside(self):
        """Indices of the points beyond the tolerance, the farthest first."""
        lo, hi = self.tolerance
        excess = np.maximum(self.distance - hi, lo - self.distance)
        out = np.flatnonzero(excess > 0)
        return out[np.argsort(-excess[out], kind="stable")]

    def table(self):
        """The statistics as text (:meth:`DeviationStats.table`) under a line naming the scan and the part."""
        head = _("{n} points against {part}").format(n=len(self.distance), part=self.name or _("the part"))
        return head + "\n" + self.stats.table()

    def _table(self):
        lo, hi = self.tolerance
        unit = _("length of the part")
        columns = {"x": self.points[:, 0], "y": self.points[:, 1], "z": self.points[:, 2], "distance": self.distance,
                   "band": self.band.astype(int), "face": self.face.astype(int), "u": self.uv[:, 0],
                   "v": self.uv[:, 1], "foot_x": self.foot[:, 0], "foot_y": self.foot[:, 1],
                   "foot_z": self.foot[:, 2], "border": self.border.astype(bool)}
        units = {name: unit for name in ("x", "y", "z", "distance", "foot_x", "foot_y", "foot_z")}
        units.update({"u": _("parameter of the face"), "v": _("parameter of the face"),
                      "band": _("-1 below, 0 within, +1 above")})
        return export.Table(_("signed distance of each scanned point to the part"), columns, units,
                            {"part": self.name, "tolerance": f"{lo!r} … {hi!r}"})

    to_csv = export.to_csv
    to_pandas = export.to_pandas

    def __repr__(self):
        s = self.stats
        return decimal(_("Deviation({n} points, mean {mean:.3g}, largest above {above:.3g}, below {below:.3g}, "
                         "{within:.1f} % within {lo:.3g} … {hi:.3g})").format(
            n=s.count, mean=s.mean, above=s.max_above, below=s.max_below, within=100 * s.within,
            lo=self.tolerance[0], hi=self.tolerance[1]))


def deviation_colors(distance, tolerance, color_map="graded", *, vmax=None):
    """Colours (``distance.shape + (3,)``, sRGB 0 … 1) of signed distances against a tolerance band.

    ``"bands"``: navy below, near-white within, burnt orange above (vik's classification colours).
    ``"graded"``: near-white within; beyond the tolerance vik from a light tint at the band's border to its dark
    ends at ``±vmax`` (default: the largest |distance|), so that how far a point lies outside shows too.
    """
    d = np.asarray(distance, dtype=float)
    lo, hi = tolerance_band(tolerance)
    if color_map not in DEVIATION_MAPS:
        raise ValueError(f"color_map must be one of {', '.join(DEVIATION_MAPS)}; got {color_map!r}")
    out = _colors(d, lo, hi, color_map, vmax)
    out[np.isnan(d)] = NO_SCAN  # a place no scanned point is near
    return out


def _colors(d, lo, hi, color_map, vmax):
    below, within, above = palettes.ramp("vik", np.array(BAND_POSITIONS))
    if color_map == "bands":
        return np.where((d < lo)[..., None], below, np.where((d > hi)[..., None], above, within))
    top = float(vmax) if vmax is not None else float(np.nanmax(np.abs(d))) if np.any(np.isfinite(d)) else 1.0
    top = max(top, hi, -lo) * (1 + 1e-12) + 1e-300
    pos = np.full(d.shape, 0.5)
    up, down = d > hi, d < lo
    with np.errstate(invalid="ignore", divide="ignore"):
        pos[up] = GRADED_START[1] + (1 - GRADED_START[1]) * np.clip((d[up] - hi) / max(top - hi, 1e-300), 0, 1)
        pos[down] = GRADED_START[0] * (1 - np.clip((lo - d[down]) / max(top + lo, 1e-300), 0, 1))
    out = palettes.ramp("vik", pos)
    out[~(up | down)] = within
    return out


def deviation(points, part, tolerance=None, *, name=None, lines=None):
    """The signed distance of every scanned point to ``part``, with foot points, faces and statistics.

    Parameters
    ----------
    points : (n, 3) array_like, path or pyvista mesh
        The scan: an array, a file :func:`lab.interrogation.scans.read_scan` reads (PLY, STL, OBJ, XYZ …) or
        a mesh whose vertices are the points.
    part : lab.Model, face, lab surface or lab.TrimmedSurface
        The CAD model (a part from :func:`lab.read` or :mod:`lab.models`) or a surface.
    tolerance : float or (float, float), optional
        The band counted as within: ``t`` means ``-t … t``, a pair ``(lower, upper)`` an unequal band.
        Default: 0.1 % of the part's size (its bounding-box diagonal).
    name : str, optional
        The part's name in tables and pictures (default: the model's name).
    lines : int, optional
        The spacing of the mesh that starts the search: this many steps across the part's size (default 160).

    Returns
    -------
    Deviation
        ``.distance``, ``.face``, ``.uv``, ``.foot``, ``.stats``, ``.colors()``, ``.to_csv(path)``.

    Examples
    --------
    >>> import lab
    >>> plane = lab.surfaces.plane()
    >>> d = lab.deviation([[0.5, 0.5, 0.02], [0.25, 0.5, -0.001]], plane, tolerance=0.01)
    >>> [round(float(x), 12) for x in d.distance], d.stats.within
    ([0.02, -0.001], 0.5)
    """
    P = _scan_points(points)
    options = {} if lines is None else {"lines": lines}
    feet = closest_points(P, part, **options)
    if tolerance is None:
        size = float(np.linalg.norm(np.ptp(np.concatenate([P, feet.points]), axis=0))) if len(P) else 1.0
        tolerance = DEFAULT_TOLERANCE_RTOL * (size or 1.0)
    band = tolerance_band(tolerance)
    label = name if name is not None else getattr(part, "name", None) or ""
    return Deviation(P, feet.distance, feet.face, feet.uv, feet.points, feet.normal, feet.border, band, str(label))


def _scan_points(points):
    """The scan's points as an (n, 3) array from an array, a file or a mesh."""
    import os

    if isinstance(points, (str, os.PathLike)):
        from .scans import read_scan

        return read_scan(points)
    if hasattr(points, "points") and not isinstance(points, np.ndarray):  # a pyvista or trimesh object
        points = np.asarray(points.points if not hasattr(points, "vertices") else points.vertices)
    P = _v._as_float_array(points, "points")
    if P.ndim == 1 and P.shape == (3,):
        P = P[None]
    if P.ndim != 2 or P.shape[1] != 3:
        raise ValueError(f"points must have shape (n, 3); got {P.shape}")
    return P
