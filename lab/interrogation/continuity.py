r"""How smooth is it?  G0, G1 and G2 across knot lines, patch borders and face edges (``lab.continuity``).

The practical's purpose (``seeds/001``): "Die Krümmungsvisualisierung erlaubt eine erste grobe Beurteilung
der Stetigkeit der zweiten Ableitung von B."  Here that judgement is a number per edge, as CAD systems
report it (OpenCASCADE's ``LocalAnalysis_SurfaceContinuity``, Rhino's EdgeContinuity/GCon):

* **G0** – ``g0``: the largest gap :math:`|\mathbf b_A - \mathbf b_B|` between the two sides (length);
* **G1** – ``g1``: the largest angle between the two sides' unit normals, in degrees (folded to at most
  90°, as OpenCASCADE does, so two sides with opposite orientations are compared as one surface);
* **G2** – ``g2``: the largest jump of the normal curvature in the cross-boundary direction
  :math:`\mathbf c = \mathbf N\times\mathbf t` (t the edge's tangent) on each side,
  :math:`|\kappa_n^A(\mathbf c_A) - \kappa_n^B(\mathbf c_B)|` (1/length), with
  :math:`\kappa_n(\mathbf c) = \mathrm{II}(\mathbf c)/\mathrm I(\mathbf c)`.

Every value comes from exact one-sided limits: each side is a Bézier patch (a B-spline surface's knot
spans, the patches of a collection) evaluated on its own border, so nothing is estimated by differences.

An edge *achieves* G0 when ``g0 <= tol_g0``, G1 when also ``g1 <= tol_g1`` and G2 when also
``g2 <= tol_g2 * (max |κn| on the edge + 1/size)``; otherwise ``"none"``.  The default tolerances
(:data:`TOLERANCES`): ``tol_g0 = 1e-6`` of the model's size (bounding-box diagonal), ``tol_g1 = 0.05``
degrees, ``tol_g2 = 0.01`` (1 %, OpenCASCADE's default ``Percent``).
"""

from dataclasses import dataclass, field

import numpy as np

from ..geometry import bezier
from ..geometry import validation as _v
from ..model.patches import BezierPatches
from ..model.surface import BSplineSurface

__all__ = ["LEVELS", "TOLERANCES", "Continuity", "Edge", "continuity", "measures"]

#: What an edge can achieve, worst first.
LEVELS = ("none", "G0", "G1", "G2")
#: Default tolerances: g0 relative to the model's size, g1 in degrees, g2 relative (see the module docstring).
TOLERANCES = {"g0": 1e-6, "g1": 0.05, "g2": 0.01}


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
        ``"G2"``, ``"G1"``, ``"G0"`` or ``"none"``.
    worst : (3,) ndarray
        Where the measure that decides :attr:`achieved` is largest (for ``"G2"``: where g2 is).
    points : (k, 3) ndarray
        The samples along the edge (side A), with ``gap``, ``angle`` and ``jump`` (k,) at each.
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

    def __repr__(self):
        where = f"{self.direction} = {self.value:g}" if self.value is not None else f"faces {self.faces}"
        return (f"Edge({self.kind} {where}: {self.achieved}, g0={self.g0:.3g}, g1={self.g1:.3g} deg, "
                f"g2={self.g2:.3g})")


@dataclass(frozen=True, eq=False)
class Continuity:
    """The continuity report of a surface: its :attr:`edges`, the :attr:`tolerances` used, and summaries."""

    edges: list
    tolerances: dict
    size: float

    @property
    def achieved(self):
        """The least any edge achieves (``"G2"`` when there are no edges)."""
        return min((e.achieved for e in self.edges), key=LEVELS.index, default="G2")

    @property
    def worst(self):
        """The edge that achieves least (the largest relevant measure among those), or None."""
        if not self.edges:
            return None
        return min(self.edges, key=lambda e: (LEVELS.index(e.achieved), -_deciding(e, self.tolerances, self.size)))

    def counts(self):
        """``{level: number of edges}`` for the four levels."""
        return {level: sum(e.achieved == level for e in self.edges) for level in LEVELS[::-1]}

    def table(self, max_rows=20):
        """A plain-text table: one row per edge (the ``max_rows`` worst when there are more), the tolerances."""
        tol = self.tolerances
        rows = sorted(self.edges, key=lambda e: (LEVELS.index(e.achieved), -_deciding(e, tol, self.size)))
        header = f"{'edge':<26} {'G0 gap':>10} {'G1 angle [deg]':>15} {'G2 jump [1/L]':>14} {'achieved':>9}"
        lines = [header, "-" * len(header)]
        for e in rows[:max_rows]:
            if e.value is not None:
                name = f"{e.kind} {e.direction} = {e.value:.6g}"
            else:
                name = f"{e.kind} {e.faces[0]}|{e.faces[1]}"
            lines.append(f"{name:<26} {e.g0:10.3g} {e.g1:15.3g} {e.g2:14.3g} {e.achieved:>9}")
        if len(rows) > max_rows:
            lines.append(f"… {len(rows) - max_rows} more edges")
        counts = ", ".join(f"{k}: {n}" for k, n in self.counts().items())
        lines.append(f"{len(self.edges)} edges ({counts}); overall {self.achieved}")
        lines.append(f"tolerances: G0 gap <= {tol['g0'] * self.size:.3g} ({tol['g0']:g} x size {self.size:.4g}), "
                     f"G1 angle <= {tol['g1']:g} deg, G2 jump <= {tol['g2']:g} x (max |kn| + 1/size)")
        return "\n".join(lines)

    def __repr__(self):
        return f"Continuity({len(self.edges)} edges, achieved {self.achieved}: {self.counts()})"


def _deciding(edge, tol, size):
    """The measure that decides an edge's level, relative to its tolerance (for sorting)."""
    if edge.achieved == "none":
        return edge.g0 / (tol["g0"] * size)
    if edge.achieved == "G0":
        return edge.g1 / tol["g1"]
    return edge.g2


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


def measures(dA, dB, tA, tB):
    """Gap, normal angle (degrees) and cross-boundary normal curvature jump at paired samples of two sides.

    Parameters
    ----------
    dA, dB : Derivatives
        One-sided derivatives of the two sides at the same points of the edge, fields ``(k, 3)``.
    tA, tB : (k, 3) ndarray
        The edge's tangent on each side (any length, the same sense or not).

    Returns
    -------
    gap, angle, jump, kn : (k,) ndarrays
        ``kn`` is the larger |κn| of the two sides (for the relative G2 tolerance).  NaN where a side has
        no normal (a degenerate sample).
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        gap = np.linalg.norm(dA.b - dB.b, axis=-1)
        NA, NB = np.cross(dA.bu, dA.bv), np.cross(dB.bu, dB.bv)
        NA = NA / np.linalg.norm(NA, axis=-1, keepdims=True)
        NB = NB / np.linalg.norm(NB, axis=-1, keepdims=True)
        cos = _dot(NA, NB)
        angle = np.degrees(np.arctan2(np.linalg.norm(np.cross(NA, NB), axis=-1), np.abs(cos)))
        flip = np.where(cos < 0, -1.0, 1.0)  # opposite orientations: compare as one surface
        cA, cB = np.cross(NA, tA), np.cross(NB, tB)
        kA = _normal_curvature(dA, NA, cA)
        kB = flip * _normal_curvature(dB, NB, cB)
        jump = np.abs(kA - kB)
        kn = np.maximum(np.abs(kA), np.abs(kB))
    return gap, angle, jump, kn


def _level(g0, g1, g2, kn, tol, size):
    if not g0 <= tol["g0"] * size:
        return "none"
    if not g1 <= tol["g1"]:
        return "G0"
    if not g2 <= tol["g2"] * (kn + 1 / size):
        return "G1"
    return "G2"


def _edge(kind, direction, value, faces, multiplicity, dA, dB, tA, tB, tol, size):
    gap, angle, jump, kn = measures(dA, dB, tA, tB)
    ok = np.isfinite(angle) & np.isfinite(jump)
    g0 = float(np.max(gap)) if gap.size else 0.0
    g1 = float(np.max(angle[ok])) if np.any(ok) else 0.0
    g2 = float(np.max(jump[ok])) if np.any(ok) else 0.0
    knmax = float(np.max(kn[ok])) if np.any(ok) else 0.0
    achieved = _level(g0, g1, g2, knmax, tol, size)
    deciding = {"none": gap, "G0": angle}.get(achieved, jump)
    i = int(np.nanargmax(np.where(ok | (achieved == "none"), deciding, -np.inf))) if deciding.size else 0
    return Edge(kind, direction, value, faces, multiplicity, g0, g1, g2, achieved, dA.b[i].copy(), dA.b.copy(),
                gap, angle, jump)


def _tolerances(tol_g0, tol_g1, tol_g2):
    tol = dict(TOLERANCES)
    for name, x in (("g0", tol_g0), ("g1", tol_g1), ("g2", tol_g2)):
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


def _border(nets, w, axis, end, t):
    """Derivatives of patches ``nets`` (k, ...) on their border ``axis`` (0: u = end, 1: v = end) at ``t``."""
    u, v = (np.full_like(t, end), t) if axis == 0 else (t, np.full_like(t, end))
    return bezier.derivatives(nets, u, v, w)


def _grid_edges(nets, w, seams, tol, size, samples, kind, knot_lines=None):
    """Edges of a grid of patches ``nets`` (R, C, ...): between rows (direction u) and columns (v)."""
    R, C = nets.shape[:2]
    t = np.linspace(0.0, 1.0, samples)
    edges = []
    for axis in (0, 1):
        n_lines = R if axis == 0 else C
        periodic = bool(seams.periodic[axis]) if seams is not None else False
        pairs = [(i, i + 1) for i in range(n_lines - 1)] + ([(n_lines - 1, 0)] if periodic and n_lines > 0 else [])
        for a, b in pairs:
            if axis == 0:
                A, B = nets[a], nets[b]
                wA, wB = (None, None) if w is None else (w[a], w[b])
            else:
                A, B = nets[:, a], nets[:, b]
                wA, wB = (None, None) if w is None else (w[:, a], w[:, b])
            dA = _border(A, wA, axis, 1.0, t).map(lambda x: x.reshape(-1, 3))
            dB = _border(B, wB, axis, 0.0, t).map(lambda x: x.reshape(-1, 3))
            tA, tB = (dA.bv, dB.bv) if axis == 0 else (dA.bu, dB.bu)
            direction = "uv"[axis]
            seam = b < a
            if knot_lines is not None:  # a B-spline surface: one edge per knot line
                value, mult = knot_lines[axis][len(knot_lines[axis]) - 1 if seam else a]
                edges.append(_edge("seam" if seam else kind, direction, value, None, mult, dA, dB, tA, tB, tol, size))
            else:  # a grid of patches: one edge per pair of neighbouring patches
                k = len(t)
                for j in range(A.shape[0]):
                    sl = slice(j * k, (j + 1) * k)
                    ia, ib = (a * C + j, b * C + j) if axis == 0 else (j * C + a, j * C + b)
                    edges.append(_edge("seam" if seam else kind, direction, None, (ia, ib), None,
                                       dA.map(lambda x: x[sl]), dB.map(lambda x: x[sl]), tA[sl], tB[sl], tol, size))
    return edges


def _knot_lines(knots, degree, intervals):
    """``(value, multiplicity)`` of the interior knot lines between consecutive spans, and the seam's (the end)."""
    out = []
    for (_, hi) in intervals[:-1]:
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
    edges = []
    for found in borders.values():
        if len(found) != 2 or found[0][0] == found[1][0]:
            continue
        (ka, axa, ea, oa), (kb, axb, eb, ob) = found
        tb = t if oa == ob else 1.0 - t
        dA = _border(P[ka], None if w is None else w[ka], axa, ea, t)
        dB = _border(P[kb], None if w is None else w[kb], axb, eb, tb)
        tA = dA.bv if axa == 0 else dA.bu
        tB = dB.bv if axb == 0 else dB.bu
        edges.append(_edge("patch border", None, None, (ka, kb), None, dA, dB, tA, tB, tol, size))
    return edges


def continuity(obj, *, samples=17, tol_g0=None, tol_g1=None, tol_g2=None):
    """G0/G1/G2 across the interior knot lines of a B-spline surface or the shared borders of Bézier patches.

    Parameters
    ----------
    obj : BSplineSurface or BezierPatches
        A B-spline/NURBS surface (its knot lines, and the seam of a periodic direction), or a collection
        of patches (borders of neighbours in its grid, or, without a grid, borders whose ends coincide).
    samples : int
        Samples per knot span (or per border) along each edge.
    tol_g0, tol_g1, tol_g2 : float, optional
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
    """
    samples = _v.as_positive_int(samples, "samples", minimum=2)
    tol = _tolerances(tol_g0, tol_g1, tol_g2)
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
    else:
        model = _as_model(obj)
        if model is None:
            raise TypeError(f"continuity needs a lab.BSplineSurface, a lab.BezierPatches or a lab.Model; "
                            f"got {type(obj).__name__}")
        raise TypeError("continuity of a lab.Model (face edges) is not available yet; pass a face's surface")
    return Continuity(edges, tol, size)


def _as_model(obj):
    """``obj`` if it is a lab.Model (a model with faces), else None."""
    return obj if hasattr(obj, "faces") and type(obj).__name__ == "Model" else None
