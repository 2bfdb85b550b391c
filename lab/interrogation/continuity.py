r"""How smooth is it?  G0, G1, G2 and G3 across knot lines, patch borders and face edges (``lab.continuity``).

The practical's purpose (its sheet, §1): "Die Krümmungsvisualisierung erlaubt eine erste grobe Beurteilung
der Stetigkeit der zweiten Ableitung von B."  Here that judgement is a number per edge, as CAD systems
report it (OpenCASCADE's ``LocalAnalysis_SurfaceContinuity``, Rhino's EdgeContinuity/GCon):

* **G0** – ``g0``: the largest gap :math:`|\mathbf b_A - \mathbf b_B|` between the two sides (length);
* **G1** – ``g1``: the largest angle between the two sides' unit normals, in degrees (folded to at most
  90°, as OpenCASCADE does, so two sides with opposite orientations are compared as one surface);
* **G2** – ``g2``: the largest jump of the normal curvature in the cross-boundary direction
  :math:`\mathbf c = \mathbf N\times\mathbf t` (t the edge's tangent) on each side,
  :math:`|\kappa_n^A(\mathbf c_A) - \kappa_n^B(\mathbf c_B)|` (1/length), with
  :math:`\kappa_n(\mathbf c) = \mathrm{II}(\mathbf c)/\mathrm I(\mathbf c)`;
* **G3** – ``g3``: the largest jump :math:`|\kappa_n'^A - \kappa_n'^B|` (1/length²) of the derivative of κn along
  the geodesic leaving the edge in direction c (:mod:`.borders`: exact one-sided third derivatives).  A spline of
  degree p is C^(p-k) at a knot of multiplicity k: a simple knot of a quartic or quintic is G3, of a cubic G2.

Every value comes from exact one-sided limits: each side is a Bézier patch (a B-spline surface's knot
spans, the patches of a collection) evaluated on its own border, so nothing is estimated by differences.
A model's face edges (:func:`lab.read`) pair each face's surface at the edge's pcurve points, with the
faces' orientations (the angle then runs from 0° to 180°; a sewn file's faces as sewing oriented them,
``edge.reversed``) and the file's exact edge tangents.

An edge *achieves* G0 when ``g0 <= tol_g0``, G1 when also ``g1 <= tol_g1``, G2 when also
``g2 <= tol_g2 * (max |κn| on the edge + 1/size)`` and G3 when also ``g3 <= tol_g3 * (max |κn'| + 1/size²)``;
otherwise ``"none"``.  The default tolerances (:data:`TOLERANCES`): ``tol_g0 = 1e-6`` of the model's size
(bounding-box diagonal), ``tol_g1 = 0.05`` degrees, ``tol_g2 = 0.01`` (1 %, OpenCASCADE's default ``Percent``),
``tol_g3 = 0.01`` (1 %).  A model's face edges take each face's third derivatives at the pcurve points
(:meth:`lab.Surface.third_derivatives`: exact for its NURBS faces and, by the chain rule, for its cylinders,
cones, spheres, tori and surfaces of revolution); an edge of a face without them is measured up to G2 and its
``g3`` is NaN.
"""

from dataclasses import dataclass, field

import numpy as np

from ..geometry import validation as _v
from ..geometry.derivatives import Derivatives
from ..i18n import N_, _, decimal
from ..model.patches import BezierPatches
from ..model.surface import BSplineSurface
from . import export
from .borders import border as _border
from .borders import curvature_derivative
from .faces import collapsed_sides, on_collapsed_side

__all__ = ["LEVELS", "TOLERANCES", "Continuity", "Edge", "continuity", "measures"]

#: What an edge can achieve, worst first.
LEVELS = ("none", "G0", "G1", "G2", "G3")
#: How a level is written for people: "none" (not even closed) as "open" (German "offen"); the others as they are.
LEVEL_NAMES = {"none": N_("open")}


def level_name(level):
    """``level`` ("none", "G0", "G1", "G2") as the table and the legends write it, in the current language."""
    return _(LEVEL_NAMES[level]) if level in LEVEL_NAMES else level
#: the edge kinds as the table names them (marked for translation)
EDGE_KINDS = {"knot line": N_("knot line"), "seam": N_("seam"), "patch border": N_("patch border"),
              "face edge": N_("face edge")}
#: Default tolerances: g0 relative to the model's size, g1 in degrees, g2 relative (see the module docstring).
TOLERANCES = {"g0": 1e-6, "g1": 0.05, "g2": 0.01, "g3": 0.01}


@dataclass(frozen=True, eq=False)
class Edge:
    """One edge between two pieces and how continuous the surface is across it.

    Attributes
    ----------
    kind : str
        ``"knot line"``, ``"seam"`` (where a periodic surface closes), ``"patch border"`` or ``"face edge"``.
    direction : str or None
        ``"u"`` for a line u = value, ``"v"`` for v = value (knot lines, seams, borders of a grid of patches).
    value : float or None
        The knot (knot lines, seams).
    faces : tuple or None
        The two pieces it joins: patch indices (patch borders) or face indices (face edges).
    multiplicity : int or None
        The knot's multiplicity (knot lines): the spline is C^(degree - multiplicity) there.
    g0, g1, g2 : float
        Largest gap (length), normal angle (degrees) and cross-boundary normal curvature jump (1/length).
    achieved : str
        ``"G3"``, ``"G2"``, ``"G1"``, ``"G0"`` or ``"none"``.
    worst : (3,) ndarray
        Where the measure that decides :attr:`achieved` is largest (for ``"G2"``: where g2 is).
    points : (k, 3) ndarray
        The samples along the edge (side A), with ``gap``, ``angle`` and ``jump`` (k,) at each.
    g0_tol : float or None
        The edge's own G0 tolerance (a length) where it is larger than the report's: a model's face edge is
        closed within twice the file's tolerance of the edge (each face's pcurve lies within that tolerance of
        the edge's curve, ``BRep_Tool.Tolerance``), which CAD files need for the gaps they leave.
    g3 : float
        Largest jump of the cross-boundary derivative of κn (1/length²), ``jump3`` (k,) at the samples; NaN where
        not measured (a face without third derivatives: at most G2).
    degenerate : (k,) bool ndarray
        The samples where a side has no normal (a pole, a collapsed side): they count for the gap only.
    """

    kind: str
    direction: object
    value: object
    faces: object
    multiplicity: object
    g0: float
    g1: float
    g2: float
    achieved: str
    worst: np.ndarray
    points: np.ndarray = field(repr=False)
    gap: np.ndarray = field(repr=False)
    angle: np.ndarray = field(repr=False)
    jump: np.ndarray = field(repr=False)
    g0_tol: object = field(default=None, repr=False)
    g3: float = float("nan")
    jump3: object = field(default=None, repr=False)
    degenerate: object = field(default=None, repr=False)

    def __repr__(self):
        where = f"{self.direction} = {self.value:g}" if self.value is not None else f"faces {self.faces}"
        return (f"Edge({self.kind} {where}: {self.achieved}, g0={self.g0:.3g}, g1={self.g1:.3g} deg, "
                f"g2={self.g2:.3g}, g3={self.g3:.3g})")


@dataclass(frozen=True, eq=False)
class Continuity:
    """The continuity report of a surface: its :attr:`edges`, the :attr:`tolerances` used, and summaries."""

    edges: list
    tolerances: dict
    size: float

    @property
    def achieved(self):
        """The least any edge achieves (``"G3"`` when there are no edges)."""
        return min((e.achieved for e in self.edges), key=LEVELS.index, default="G3")

    @property
    def worst(self):
        """The edge that achieves least (the largest relevant measure among those), or None."""
        if not self.edges:
            return None
        return min(self.edges, key=lambda e: (LEVELS.index(e.achieved), -_deciding(e, self.tolerances, self.size)))

    @property
    def measured_g3(self):
        """Whether G3 was measured on any edge (not where a face has no third derivatives, see :attr:`Edge.g3`)."""
        return any(np.isfinite(e.g3) for e in self.edges)

    def counts(self):
        """``{level: number of edges}``, best level first; "G3" only where G3 was measured (:attr:`measured_g3`)."""
        levels = LEVELS[::-1] if self.measured_g3 else LEVELS[-2::-1]
        return {level: sum(e.achieved == level for e in self.edges) for level in levels}

    def summary(self):
        """One line: the number of edges, how many achieve each level, the level of the whole (current language)."""
        counts = ", ".join(f"{level_name(k)}: {n}" for k, n in self.counts().items())
        return _("{n} edges ({counts}); overall {level}").format(n=len(self.edges), counts=counts,
                                                                 level=level_name(self.achieved))

    def table(self, max_rows=20):
        """A plain-text table in the current language: one row per edge (the ``max_rows`` worst), the tolerances."""
        tol = self.tolerances
        rows = sorted(self.edges, key=lambda e: (LEVELS.index(e.achieved), -_deciding(e, tol, self.size)))
        edge, g0, g1, g2, achieved = (_("edge"), _("G0 gap"), _("G1 angle [deg]"), _("G2 jump [1/length]"),
                                      _("achieved"))
        has_g3 = self.measured_g3  # no edge with a G3 measure: no G3 column
        g3 = _("G3 jump [1/length²]")
        g3 = f" {g3:>20}" if has_g3 else ""
        header = f"{edge:<26} {g0:>10} {g1:>15} {g2:>19}{g3} {achieved:>9}"
        lines = [header, "-" * len(header)]
        for e in rows[:max_rows]:
            kind = _(EDGE_KINDS.get(e.kind, e.kind))
            if e.value is not None:
                name = f"{kind} {e.direction} = {decimal(f'{e.value:.6g}')}"
            else:
                name = f"{kind} {min(e.faces)}|{max(e.faces)}"
            g3_text = "" if not has_g3 else f" {e.g3:20.3g}" if np.isfinite(e.g3) else f" {'–':>20}"
            numbers = decimal(f"{e.g0:10.3g} {e.g1:15.3g} {e.g2:19.3g}{g3_text}")
            lines.append(f"{name:<26} {numbers} {level_name(e.achieved):>9}")
        if len(rows) > max_rows:
            lines.append(_("… {n} more edges").format(n=len(rows) - max_rows))
        lines.append(self.summary())
        lines.append(decimal(_("tolerances: G0 gap <= {g0} ({tol_g0} x size {size}), G1 angle <= {g1} deg, "
                               "G2 jump <= {g2} x (max |kn| + 1/size)").format(
            g0=f"{tol['g0'] * self.size:.3g}", tol_g0=f"{tol['g0']:g}", size=f"{self.size:.4g}", g1=f"{tol['g1']:g}",
            g2=f"{tol['g2']:g}")))
        if has_g3:
            lines.append(decimal(_("  G3 jump <= {g3} x (max |kn'| + 1/size^2), kn' along the cross-boundary geodesic")
                                 .format(g3=f"{tol['g3']:g}")))
        if any(e.g0_tol is not None for e in self.edges):
            lines.append(_("  face edges: G0 gap also <= twice the file's tolerance of the edge (up to {g0})").format(
                g0=decimal(f"{max(e.g0_tol or 0 for e in self.edges):.3g}")))
        return "\n".join(lines)

    def __repr__(self):
        return f"Continuity({len(self.edges)} edges, achieved {self.achieved}: {self.counts()})"

    def _table(self):
        """One row per edge (in :attr:`edges`' order): what it is, its four measures, the level and the worst point."""
        e = self.edges
        nan = float("nan")
        columns = {
            "kind": [x.kind for x in e], "direction": [x.direction or "" for x in e],
            "value": [nan if x.value is None else float(x.value) for x in e],
            "faces": ["" if x.faces is None else "|".join(str(int(f)) for f in x.faces) for x in e],
            "multiplicity": [nan if x.multiplicity is None else float(x.multiplicity) for x in e],
            "g0": [x.g0 for x in e], "g1": [x.g1 for x in e], "g2": [x.g2 for x in e], "g3": [x.g3 for x in e],
            "achieved": [x.achieved for x in e], "worst_x": [float(x.worst[0]) for x in e],
            "worst_y": [float(x.worst[1]) for x in e], "worst_z": [float(x.worst[2]) for x in e]}
        length = _("length")
        units = {"value": _("parameter"), "g0": length, "g1": _("deg"), "g2": f"1/{length}", "g3": f"1/{length}²",
                 "worst_x": length, "worst_y": length, "worst_z": length}
        tol = self.tolerances
        meta = {"tolerance": f"g0 <= {tol['g0']!r} x size; g1 <= {tol['g1']!r} deg; g2 <= {tol['g2']!r} x "
                             f"(max |kn| + 1/size); g3 <= {tol['g3']!r} x (max |kn'| + 1/size^2)",
                "size": repr(self.size), "achieved": self.achieved}
        return export.Table(_("continuity across edges"), columns, units, meta)

    to_csv = export.to_csv
    to_pandas = export.to_pandas


def _deciding(edge, tol, size):
    """The measure that decides an edge's level, relative to its tolerance (for sorting)."""
    if edge.achieved == "none":
        return edge.g0 / (edge.g0_tol or tol["g0"] * size)
    if edge.achieved == "G0":
        return edge.g1 / tol["g1"]
    if edge.achieved == "G1":
        return edge.g2
    return edge.g3 if np.isfinite(edge.g3) else 0.0


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def _normal_curvature(d, N, c):
    """κn in the tangent direction ``c`` (3-vectors) from derivatives ``d``: II(w)/I(w), w the coordinates of c."""
    E, F, G = _dot(d.bu, d.bu), _dot(d.bu, d.bv), _dot(d.bv, d.bv)
    e, f, g = _dot(N, d.buu), _dot(N, d.buv), _dot(N, d.bvv)
    a, b = _dot(c, d.bu), _dot(c, d.bv)
    det = E * G - F * F
    w1, w2 = (G * a - F * b) / det, (E * b - F * a) / det
    return (e * w1 * w1 + 2 * f * w1 * w2 + g * w2 * w2) / (E * w1 * w1 + 2 * F * w1 * w2 + G * w2 * w2)


def measures(dA, dB, tA, tB, signs=None):
    """Gap, normal angle (degrees) and cross-boundary normal curvature jump at paired samples of two sides.

    Parameters
    ----------
    dA, dB : Derivatives
        One-sided derivatives of the two sides at the same points of the edge, fields ``(k, 3)``.
    tA, tB : (k, 3) ndarray
        The edge's tangent on each side (any length, the same sense or not).
    signs : ((k,) ndarray, (k,) ndarray), optional
        The sides' orientations (+1: N = b_u x b_v, -1: the opposite, a reversed face).  Given, the angle is
        between the oriented normals (0° to 180°, a fold-back is not tangent) and each side's normal
        curvature is taken with its own normal; without, the angle is folded to at most 90° and side B is
        compared as if it had side A's orientation.

    Returns
    -------
    gap, angle, jump, kn : (k,) ndarrays
        ``kn`` is the larger |κn| of the two sides (for the relative G2 tolerance).  NaN where a side has
        no normal (a degenerate sample).
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        gap = np.linalg.norm(dA.b - dB.b, axis=-1)
        NA, NB, angle, flip = _normals(dA, dB, signs)  # flip: opposite orientations compared as one surface
        cA, cB = np.cross(NA, tA), np.cross(NB, tB)
        kA = _normal_curvature(dA, NA, cA)
        kB = flip * _normal_curvature(dB, NB, cB)
        jump = np.abs(kA - kB)
        kn = np.maximum(np.abs(kA), np.abs(kB))
    return gap, angle, jump, kn


def _normals(dA, dB, signs):
    """Unit normals of the two sides (oriented by ``signs``), their angle in degrees and the factor (+-1) that
    turns side B's curvatures to side A's orientation (see :func:`measures`)."""
    NA, NB = np.cross(dA.bu, dA.bv), np.cross(dB.bu, dB.bv)
    NA = NA / np.linalg.norm(NA, axis=-1, keepdims=True)
    NB = NB / np.linalg.norm(NB, axis=-1, keepdims=True)
    if signs is not None:
        NA, NB = NA * np.asarray(signs[0])[..., None], NB * np.asarray(signs[1])[..., None]
    cos = _dot(NA, NB)
    sine = np.linalg.norm(np.cross(NA, NB), axis=-1)
    if signs is None:
        return NA, NB, np.degrees(np.arctan2(sine, np.abs(cos))), np.where(cos < 0, -1.0, 1.0)
    return NA, NB, np.degrees(np.arctan2(sine, cos)), 1.0


def measures_g3(dA, dB, thirdA, thirdB, tA, signs=None):
    r"""The jump of :func:`.borders.curvature_derivative` across an edge in the cross-boundary direction
    :math:`\mathbf c = \mathbf N_A\times\mathbf t` (side B: c projected into B's tangent plane, its normal turned to
    A's orientation as in :func:`measures`).  Returns ``jump3, dkn``, each ``(k,)``: the jump and the larger |κn'| of the two sides (1/length²)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        NA, NB, _angle, flip = _normals(dA, dB, signs)
        NB = NB * np.asarray(flip)[..., None] if np.ndim(flip) else NB * flip
        c = np.cross(NA, tA)
        c = c / np.linalg.norm(c, axis=-1, keepdims=True)
        cB = c - _dot(c, NB)[..., None] * NB
        kA = curvature_derivative(dA, thirdA, NA, c)
        kB = curvature_derivative(dB, thirdB, NB, cB)
        return np.abs(kA - kB), np.maximum(np.abs(kA), np.abs(kB))


def _levels(g0, g1, g2, kn, tol, size, g0_tol=None, g3=None, dkn=None):
    """The level achieved for arrays of per-edge maxima (``g0_tol``: per-edge G0 tolerances where larger;
    without ``g3`` at most G2)."""
    out = np.full(np.shape(g0), "G2", dtype=object)
    if g3 is not None:
        out[g3 <= tol["g3"] * (dkn + 1 / size ** 2)] = "G3"
    out[~(g2 <= tol["g2"] * (kn + 1 / size))] = "G1"
    out[~(g1 <= tol["g1"])] = "G0"
    out[~(g0 <= (tol["g0"] * size if g0_tol is None else np.maximum(tol["g0"] * size, g0_tol)))] = "none"
    return out


def _edges(meta, dA, dB, tA, tB, tol, size, signs=None, g0_tol=None, third=None):
    """Edges from paired samples: fields of ``dA, dB`` and ``tA, tB`` have shape ``(edges, samples, 3)``;
    ``meta`` holds per edge ``(kind, direction, value, faces, multiplicity)``; ``signs`` as in :func:`measures`
    with shape ``(edges, samples)``; ``g0_tol`` per edge, its own G0 tolerance (a length) where larger;
    ``third`` the two sides' third derivatives (each a 4-tuple of such arrays) for G3."""
    flat = lambda x: x.reshape(-1, 3)
    if signs is not None:
        signs = tuple(np.asarray(x).ravel() for x in signs)
    gap, angle, jump, kn = measures(dA.map(flat), dB.map(flat), flat(tA), flat(tB), signs)
    shape = tA.shape[:2]
    gap, angle, jump, kn = (x.reshape(shape) for x in (gap, angle, jump, kn))
    jump3 = g3 = dknmax = None
    if third is not None:
        jump3, dkn = measures_g3(dA.map(flat), dB.map(flat), *(tuple(map(flat, x)) for x in third), flat(tA), signs)
        jump3, dkn = jump3.reshape(shape), dkn.reshape(shape)
    ok = np.isfinite(angle) & np.isfinite(jump)
    with np.errstate(invalid="ignore"):
        g0 = np.max(gap, axis=1)
        g1 = np.max(np.where(ok, angle, 0.0), axis=1)
        g2 = np.max(np.where(ok, jump, 0.0), axis=1)
        knmax = np.max(np.where(ok, kn, 0.0), axis=1)
        if third is not None:  # an edge without a finite sample of g3 (a face without third derivatives): NaN
            ok3 = ok & np.isfinite(jump3)
            g3 = np.where(np.any(ok3, axis=1), np.max(np.where(ok3, jump3, 0.0), axis=1), np.nan)
            dknmax = np.max(np.where(ok3, dkn, 0.0), axis=1)
    levels = _levels(g0, g1, g2, knmax, tol, size, g0_tol, g3, dknmax)
    deciding = np.where((levels == "none")[:, None], gap, np.where((levels == "G0")[:, None], angle, jump))
    if third is not None:
        deciding = np.where((levels == "G2")[:, None] & ok3, jump3, deciding)
    deciding = np.where(ok | (levels == "none")[:, None], deciding, -np.inf)
    worst = np.argmax(deciding, axis=1)
    points = dA.b
    own = [None] * len(meta) if g0_tol is None else [float(x) if x > tol["g0"] * size else None for x in g0_tol]
    return [Edge(*meta[i], float(g0[i]), float(g1[i]), float(g2[i]), levels[i], points[i, worst[i]].copy(),
                 points[i], gap[i], angle[i], jump[i], own[i], float("nan") if g3 is None else float(g3[i]),
                 None if jump3 is None else jump3[i], ~ok[i]) for i in range(len(meta))]


def _tolerances(tol_g0, tol_g1, tol_g2, tol_g3=None):
    tol = dict(TOLERANCES)
    for name, x in (("g0", tol_g0), ("g1", tol_g1), ("g2", tol_g2), ("g3", tol_g3)):
        if x is not None:
            try:
                x = float(x)
            except (TypeError, ValueError):
                raise TypeError(f"tol_{name} must be a number; got {type(x).__name__}") from None
            if not (np.isfinite(x) and x >= 0):
                raise ValueError(f"tol_{name} must be a finite number >= 0; got {x}")
            tol[name] = x
    return tol


def _size(points):
    p = np.asarray(points).reshape(-1, 3)
    return float(np.linalg.norm(p.max(axis=0) - p.min(axis=0))) or 1.0


def _grid_edges(nets, w, seams, tol, size, samples, kind, knot_lines=None):
    """Edges of a grid of patches ``nets`` (R, C, ...): between rows (direction u) and columns (v).

    All borders of a direction are evaluated together; a B-spline surface (``knot_lines`` given) gets one
    edge per knot line, a grid of patches one per pair of neighbours."""
    R, C = nets.shape[:2]
    t = np.linspace(0.0, 1.0, samples)
    edges = []
    for axis in (0, 1):
        n_lines = R if axis == 0 else C
        periodic = bool(seams.periodic[axis]) if seams is not None else False
        a = np.arange(n_lines - 1 + (periodic and n_lines > 1))
        b = (a + 1) % n_lines
        if len(a) == 0:
            continue
        take = (lambda x, i: x[i]) if axis == 0 else (lambda x, i: np.swapaxes(x[:, i], 0, 1))
        A, B = take(nets, a), take(nets, b)  # (lines, others, p+1, q+1, 3)
        wA, wB = (None, None) if w is None else (take(w, a), take(w, b))
        (dA, thA), (dB, thB) = (_border(A, wA, axis, 1.0, t, 3),
                                _border(B, wB, axis, 0.0, t, 3))  # (lines, others, samples, 3)
        tA, tB = (dA.bv, dB.bv) if axis == 0 else (dA.bu, dB.bu)
        direction = "uv"[axis]
        seam = b < a
        if knot_lines is not None:  # one edge per knot line: its samples over all the spans along it
            lines = knot_lines[axis]
            meta = [("seam" if seam[i] else kind, direction, *lines[-1 if seam[i] else i][:1], None,
                     lines[-1 if seam[i] else i][1]) for i in range(len(a))]
            merge = lambda x: x.reshape(x.shape[0], -1, 3)
        else:  # one edge per pair of neighbouring patches
            others = A.shape[1]
            flat = [(a[i] * C + j, b[i] * C + j) if axis == 0 else (j * C + a[i], j * C + b[i])
                    for i in range(len(a)) for j in range(others)]
            meta = [("seam" if seam[i] else kind, direction, None, flat[i * others + j], None)
                    for i in range(len(a)) for j in range(others)]
            merge = lambda x: x.reshape(-1, x.shape[-2], 3)
        third = (tuple(map(merge, thA)), tuple(map(merge, thB)))
        edges += _edges(meta, dA.map(merge), dB.map(merge), merge(tA), merge(tB), tol, size, third=third)
    return edges


def _knot_lines(knots, degree, intervals):
    """``(value, multiplicity)`` of the interior knot lines between consecutive spans, and the seam's (the end)."""
    out = []
    for (_lo, hi) in intervals[:-1]:
        out.append((float(hi), int(np.count_nonzero(knots == hi))))
    end = intervals[-1][1]
    out.append((float(end), int(np.count_nonzero(knots == end))))  # used by a periodic direction's seam
    return out


def _matched_edges(patches, tol, size, samples):
    """Shared borders of patches without a grid: borders whose end points coincide (within the G0 tolerance)."""
    P, w = patches.control_points, patches.weights
    t = np.linspace(0.0, 1.0, samples)
    eps = max(tol["g0"] * size, 1e-12 * size)
    borders = {}
    for k in range(len(P)):
        for axis in (0, 1):
            for end in (0.0, 1.0):
                net = P[k]
                if axis == 0:
                    row = net[-1] if end else net[0]
                else:
                    row = net[:, -1] if end else net[:, 0]
                a, b = (tuple(np.round(x / eps).astype(np.int64)) for x in (row[0], row[-1]))
                borders.setdefault(frozenset((a, b)), []).append((k, axis, end, a <= b))
    pairs = [found for found in borders.values() if len(found) == 2 and found[0][0] != found[1][0]]
    if not pairs:
        return []
    sides = []
    for side in (0, 1):
        derivs, thirds, tangents = [], [], []
        for found in pairs:
            k, axis, end, forward = found[side]
            tt = t if side == 0 or forward == found[0][3] else 1.0 - t
            d, th = _border(P[k], None if w is None else w[k], axis, end, tt, 3)
            derivs.append(d)
            thirds.append(th)
            tangents.append(d.bv if axis == 0 else d.bu)
        stacked = type(derivs[0])(*(np.stack([getattr(d, f) for d in derivs]) for f in derivs[0]._fields))
        sides.append((stacked, np.stack(tangents), tuple(np.stack(x) for x in zip(*thirds))))
    meta = [("patch border", None, None, (found[0][0], found[1][0]), None) for found in pairs]
    return _edges(meta, sides[0][0], sides[1][0], sides[0][1], sides[1][1], tol, size,
                  third=(sides[0][2], sides[1][2]))


def continuity(obj, *, samples=17, tol_g0=None, tol_g1=None, tol_g2=None, tol_g3=None):
    """G0/G1/G2/G3 across the knot lines of a B-spline surface, the shared borders of Bézier patches or a model's
    edges.

    Parameters
    ----------
    obj : BSplineSurface, BezierPatches or lab.Model
        A B-spline/NURBS surface (its knot lines, and the seam of a periodic direction), a collection
        of patches (borders of neighbours in its grid, or, without a grid, borders whose ends coincide), or
        a model read by :func:`lab.read` (the edges two faces share, ``model.edges``: each face evaluated at
        the edge's pcurve, with the faces' orientations, so the angle runs from 0° to 180°).
    samples : int
        Samples per knot span (or per border) along each edge; a model's edges keep the samples
        :func:`lab.read` took.
    tol_g0, tol_g1, tol_g2, tol_g3 : float, optional
        Tolerances (see the module docstring; defaults :data:`TOLERANCES`).

    Returns
    -------
    Continuity
        ``.edges`` (each an :class:`Edge`), ``.achieved``, ``.worst``, ``.table()``.

    Examples
    --------
    >>> import lab
    >>> lab.continuity(lab.surfaces.practical()).achieved      # a bicubic B-spline with simple knots is C2
    'G2'
    >>> lab.continuity(lab.surfaces.torus()).achieved           # rational, double knots: G3 all the same
    'G3'
    """
    samples = _v.as_positive_int(samples, "samples", minimum=2, maximum=100_000)
    tol = _tolerances(tol_g0, tol_g1, tol_g2, tol_g3)
    if isinstance(obj, BSplineSurface):
        nets, w, iu, iv = obj.bezier_nets()
        size = _size(obj.control_points)
        lines = (_knot_lines(obj.knots_u, obj.degree[0], iu), _knot_lines(obj.knots_v, obj.degree[1], iv))
        edges = _grid_edges(nets, w, obj.seams, tol, size, samples, "knot line", lines)
    elif isinstance(obj, BezierPatches):
        size = _size(obj.control_points)
        if obj.grid_shape is not None:
            R, C = obj.grid_shape
            P = obj.control_points.reshape((R, C) + obj.control_points.shape[1:])
            w = None if obj.weights is None else obj.weights.reshape((R, C) + obj.weights.shape[1:])
            edges = _grid_edges(P, w, obj.seams, tol, size, samples, "patch border")
        else:
            edges = _matched_edges(obj, tol, size, samples)
    elif hasattr(obj, "faces") and type(obj).__name__ == "Model":  # a lab.Model (not imported: OCP stays optional)
        lo, hi = obj.bounds()
        size = float(np.linalg.norm(hi - lo)) or 1.0
        edges = _model_edges(obj, tol, size)
    else:
        raise TypeError(f"continuity needs a lab.BSplineSurface, a lab.BezierPatches or a lab.Model; "
                        f"got {type(obj).__name__}")
    return Continuity(edges, tol, size)


def _model_edges(model, tol, size):
    """Edges of a model: at each edge's samples both faces evaluated at their pcurve's (u, v), with the faces'
    orientations; the edge's tangent from the file's 3-D curve (differences of its points where it has none).
    Samples on a side of a face that is collapsed within the file's accuracy (:func:`collapsed_sides`: its normal
    there is rounding noise) count for the gap only, not for the angle and the curvature jump.  The gap is the
    distance across the edge: where the two faces' pcurves give points shifted along the edge (a file's pcurves
    may slip by more than its tolerance), that shift is no gap.  An edge is closed within twice the file's
    tolerance of the edge as well (:attr:`Edge.g0_tol`).

    Each face is evaluated once (to the third derivatives, where it has them), at the samples of all its edges;
    edges with the same number of samples are measured together.  The derivatives are the surface's own:
    one-sided where the edge is the surface's border, not along an interior knot line of lower continuity."""
    edges = [e for e in model.edges if len(e.faces) == 2]
    if not edges:
        return []
    wanted = {}
    for n, e in enumerate(edges):
        for side, (index, uv) in enumerate(zip(e.faces, e.uv)):
            wanted.setdefault(index, []).append((n, side, np.asarray(uv, dtype=float)))
    derivs, thirds = {}, {}
    for index, items in wanted.items():
        face = model.face(index)
        uv = np.concatenate([uv for _n, _s, uv in items])
        surface = getattr(face, "file_surface", face.surface)  # edge uv: the file's
        d = surface.derivatives(uv[:, 0], uv[:, 1])
        try:
            third = surface.third_derivatives(uv[:, 0], uv[:, 1])
        except NotImplementedError:  # a face without third derivatives: its edges are measured up to G2
            third = (np.full_like(d.b, np.nan),) * 4
        collapsed = on_collapsed_side(surface, uv, collapsed_sides(surface))
        if np.any(collapsed):  # a side that is a point within the file's accuracy: no normal there, not measured
            d = d._replace(**{f: np.where(collapsed[:, None], np.nan, getattr(d, f))
                              for f in ("bu", "bv", "buu", "buv", "bvv")})
            third = tuple(np.where(collapsed[:, None], np.nan, x) for x in third)
        start = 0
        for n, side, part in items:
            stop = start + len(part)
            derivs[n, side] = d.map(lambda x, a=start, b=stop: x[a:b])
            thirds[n, side] = tuple(x[start:stop] for x in third)
            start = stop
    groups = {}
    for n, e in enumerate(edges):
        groups.setdefault(len(e.t), []).append(n)
    out = [None] * len(edges)
    for members in groups.values():
        sides, signs, third = [], [], []
        for side in (0, 1):
            ds = [derivs[n, side] for n in members]
            sides.append(Derivatives(*(np.stack([getattr(d, f) for d in ds]) for f in Derivatives._fields)))
            third.append(tuple(np.stack([thirds[n, side][k] for n in members]) for k in range(4)))
            signs.append(np.array([[-1.0 if _reversed(model, edges[n], side) else 1.0]
                                   * len(edges[n].t) for n in members]))
        t = np.stack([_edge_tangents(edges[n]) for n in members])
        # the gap across the edge: a pcurve may slip along the edge (linkrods' by 5e-5, where the faces meet to
        # 1e-13), which parts no faces; the part of the difference along the edge's tangent is not a gap
        unit = t / np.where(np.linalg.norm(t, axis=-1, keepdims=True) > 0, np.linalg.norm(t, axis=-1, keepdims=True), 1)
        slip = np.sum((sides[0].b - sides[1].b) * unit, axis=-1, keepdims=True) * unit
        sides[1] = sides[1]._replace(b=sides[1].b + np.nan_to_num(slip))
        meta = [("face edge", None, None, tuple(edges[n].faces), None) for n in members]
        own = np.array([2.0 * (getattr(edges[n], "tolerance", None) or 0.0) for n in members])
        for n, edge in zip(members, _edges(meta, sides[0], sides[1], t, t, tol, size, signs, own, tuple(third))):
            out[n] = edge
    return out


def _reversed(model, edge, side):
    """The orientation of an edge's face: as the shell the edge was found in has it (a sewn file's faces are
    oriented consistently by sewing), else the face's own."""
    senses = getattr(edge, "reversed", None)
    return bool(senses[side]) if senses is not None else model.face(edge.faces[side]).reversed


def _edge_tangents(edge):
    """The 3-D edge curve's tangents at its samples: the file's exact ones, else second-order differences."""
    if getattr(edge, "tangents", None) is not None:
        return np.asarray(edge.tangents, dtype=float)
    return np.gradient(np.asarray(edge.points, dtype=float), np.asarray(edge.t, dtype=float), axis=0)
