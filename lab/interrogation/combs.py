r"""Curvature combs (Rhino's CurvatureGraph) along curves on a surface: iso-parametric curves, borders, trim curves.

Along a curve :math:`t \mapsto (u(t), v(t))` in the parameter domain the
normal curvature in the curve's direction :math:`(\dot u, \dot v)` is

.. math::  \kappa_n = \frac{e\dot u^2 + 2f\dot u\dot v + g\dot v^2}{E\dot u^2 + 2F\dot u\dot v + G\dot v^2}

(practical, eq. 2.5's normal and forms).  The comb's tooth at a point
:math:`\mathbf b` is the segment from :math:`\mathbf b` to
:math:`\mathbf b + s\,\kappa_n\mathbf N` (``scale`` :math:`s`): its length is
:math:`s|\kappa_n|`, it stands on the side the normal points to where
:math:`\kappa_n > 0`.  On a circle of radius R on a cylinder every tooth has
length :math:`s/R`.  *Inflections* are where :math:`\kappa_n` changes sign
along the curve; they are located between samples by bisection on the exact
:math:`\kappa_n` (the curve is taken as linear in (u, v) between two samples,
exact for iso-parametric curves).
"""

from typing import NamedTuple

import numpy as np

from ..geometry import validation as _v
from ..geometry.curvature import fundamental_forms
from .faces import as_surface, check_surface

__all__ = ["Comb", "border_combs", "comb", "comb_lines", "iso_comb"]


class Comb(NamedTuple):
    """A curvature comb: ``uv`` (k, 2), ``points`` and ``tips`` (k, 3), ``kn`` (k,), ``normals`` (k, 3),
    ``degenerate`` (k,) mask (no normal there: no tooth, ``tips`` NaN), ``inflections`` (j, 2) parameters and
    ``inflection_points`` (j, 3) where ``kn`` changes sign with the surface's normals there
    (``inflection_normals``), and the ``scale``."""

    uv: np.ndarray
    points: np.ndarray
    tips: np.ndarray
    kn: np.ndarray
    normals: np.ndarray
    degenerate: np.ndarray
    inflections: np.ndarray
    inflection_points: np.ndarray
    inflection_normals: np.ndarray
    scale: float


def _kn(surface, uv, duv):
    d = surface.derivatives(uv[:, 0], uv[:, 1])
    forms = fundamental_forms(d)
    du, dv = duv[:, 0], duv[:, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        kn = (forms.e * du * du + 2 * forms.f * du * dv + forms.g * dv * dv) / (
            forms.E * du * du + 2 * forms.F * du * dv + forms.G * dv * dv)
    return np.asarray(d.b, dtype=float), np.asarray(forms.N, dtype=float), kn


def comb(surface, uv, *, scale=1.0, tangent=None, tol=1e-12):
    """The curvature comb of ``surface`` along the parameter polyline ``uv`` (k, 2).

    Parameters
    ----------
    surface : lab.Surface
    uv : (k, 2) array_like
        Points of the curve in the parameter domain, in order (k ≥ 2).
    scale : float
        Tooth length per unit of curvature (length²).
    tangent : (k, 2) array_like, optional
        The curve's direction (u', v') at each point; default: central differences of ``uv``.
    tol : float
        Inflection search: bisection down to ``tol`` of the segment.
    """
    check_surface(surface)
    uv = _v.as_array(uv, "uv", finite=False)
    if uv.ndim != 2 or uv.shape[1] != 2 or len(uv) < 2:
        raise ValueError(f"uv must have shape (k, 2) with k >= 2; got {uv.shape}")
    if not np.all(np.isfinite(uv)):
        raise ValueError("uv must be finite parameter values; got NaN or inf")
    scale = _v.as_number(scale, "scale")
    duv = np.gradient(uv, axis=0) if tangent is None else np.asarray(tangent, dtype=float)
    if duv.shape != uv.shape:
        raise ValueError(f"tangent must have the shape of uv {uv.shape}; got {duv.shape}")
    points, N, kn = _kn(surface, uv, duv)
    degenerate = ~np.isfinite(kn) | ~np.all(np.isfinite(N), axis=1)
    tips = points + scale * kn[:, None] * N
    tips[degenerate] = np.nan
    found = []
    s = np.sign(np.where(degenerate, 0.0, kn))
    for i in np.nonzero(s[:-1] * s[1:] < 0)[0]:
        a, b, ka = 0.0, 1.0, kn[i]
        d = 0.5 * (duv[i] + duv[i + 1])
        while b - a > tol:
            m = 0.5 * (a + b)
            km = _kn(surface, (uv[i] + m * (uv[i + 1] - uv[i]))[None], d[None])[2][0]
            if np.sign(km) == np.sign(ka):
                a, ka = m, km
            else:
                b = m
        found.append(uv[i] + 0.5 * (a + b) * (uv[i + 1] - uv[i]))
    inflections = np.array(found, dtype=float).reshape(-1, 2)
    if len(inflections):
        ip, inormals, _k = _kn(surface, inflections, np.ones_like(inflections))
    else:
        ip, inormals = np.zeros((0, 3)), np.zeros((0, 3))
    return Comb(uv, points, tips, kn, N, degenerate, inflections, ip, inormals, scale)


def iso_comb(surface, direction, value, *, density=64, scale=1.0):
    """The comb along the iso-parametric curve ``direction = value``: ``"u"`` holds u fixed (v runs), ``"v"`` holds v."""
    check_surface(surface)
    if not isinstance(direction, str) or direction not in ("u", "v"):
        raise ValueError(f"direction must be 'u' (u fixed, v runs) or 'v' (v fixed, u runs); got {direction!r}")
    density = int(_v.as_number(density, "density", minimum=2))
    _v.check_memory(COMB_BYTES_PER_TOOTH * density, f"a comb of {_v.format_count(density)} teeth")
    (u0, u1), (v0, v1) = surface.domain
    value = _v.as_number(value, "value")
    lo, hi = (u0, u1) if direction == "u" else (v0, v1)
    if not lo - 1e-12 <= value <= hi + 1e-12:
        raise ValueError(f"value must lie in the domain's {direction} range [{lo:g}, {hi:g}]; got {value:g}")
    t = np.linspace(*((v0, v1) if direction == "u" else (u0, u1)), density)
    fixed = np.full_like(t, value)
    uv = np.stack([fixed, t], 1) if direction == "u" else np.stack([t, fixed], 1)
    tangent = np.tile([0.0, 1.0] if direction == "u" else [1.0, 0.0], (density, 1))
    return comb(surface, uv, scale=scale, tangent=tangent)


#: Most interior iso-curves per direction of :func:`border_combs` (each is a comb of its own: about 5 ms).
MAX_COMB_COUNT = 1000
#: Memory of one tooth of a comb with its temporaries (points, normals, derivatives), in bytes.
COMB_BYTES_PER_TOOTH = 2048


def border_combs(surface, *, density=64, scale=1.0, count=0):
    """Combs along the four borders of the domain and ``count`` interior iso-curves in each direction.

    On a face of a model (:class:`lab.Face`) the borders are the face's trimming loops (the polylines
    ``face.trim.loops``, outer first), and the ``count`` iso-curves in each direction span the loops' bounding box
    and are cut to the trimmed region (one comb per piece inside).  The teeth stand on the side of the face's
    normal where the curve bends towards it; a reversed face flips N and κn together, so the teeth stay.
    """
    surface, trim = as_surface(surface)
    check_surface(surface)
    count = int(_v.as_number(count, "count", minimum=0, maximum=MAX_COMB_COUNT))
    density = int(_v.as_number(density, "density", minimum=2))
    teeth = 2 * (count + 2) * density
    _v.check_memory(COMB_BYTES_PER_TOOTH * teeth, f"{2 * (count + 2)} combs of {density} teeth each")
    if trim is not None:
        return _face_combs(surface, trim, density, scale, count)
    (u0, u1), (v0, v1) = surface.domain
    combs = []
    for direction, (lo, hi) in (("u", (u0, u1)), ("v", (v0, v1))):
        for value in np.linspace(lo, hi, count + 2):
            combs.append(iso_comb(surface, direction, value, density=density, scale=scale))
    return combs


def _resampled(surface, uv, density):
    """The parameter polyline ``uv`` with its segments split (linearly in (u, v)) so that no piece is longer in space
    than the polyline's 3-D extent over ``density``: a loop's straight pcurve (a cylinder's rim, two points in the
    file's angle) gets teeth along it, as a curved one does."""
    t = np.linspace(0.0, 1.0, 9)[:, None, None]  # 9 points a segment: a rim from u = 0 to 2π closes on itself
    W = uv[:-1] + t * (uv[1:] - uv[:-1])
    X = surface.evaluate(W[..., 0], W[..., 1])
    lengths = np.linalg.norm(np.diff(X, axis=0), axis=2).sum(axis=0)
    spacing = float(np.linalg.norm(np.ptp(X.reshape(-1, 3), axis=0))) / density
    if not spacing > 0:
        return uv
    pieces = np.maximum(1, np.ceil(lengths / spacing).astype(int))
    out = [a + np.linspace(0, 1, k, endpoint=False)[:, None] * (b - a) for a, b, k in zip(uv[:-1], uv[1:], pieces)]
    return np.vstack(out + [uv[-1:]])


def _face_combs(surface, trim, density, scale, count):
    """Combs along a face's loops and along its iso-curves, cut to the trimmed region."""
    density = int(_v.as_number(density, "density", minimum=2))
    combs = [comb(surface, _resampled(surface, np.vstack([loop, loop[:1]]), density), scale=scale)
             for loop in trim.loops]
    X = np.concatenate(trim.loops)
    lo, hi = X.min(axis=0), X.max(axis=0)
    for axis in (0, 1):  # axis 0: u fixed ("u" curves, v runs)
        for value in np.linspace(lo[axis], hi[axis], count + 2)[1:-1]:
            t = np.linspace(lo[1 - axis], hi[1 - axis], density)
            uv = np.empty((len(t), 2))
            uv[:, axis], uv[:, 1 - axis] = value, t
            inside = np.asarray(trim.contains(uv[:, 0], uv[:, 1]))
            runs = np.split(np.nonzero(inside)[0], np.nonzero(np.diff(np.nonzero(inside)[0]) > 1)[0] + 1)
            tangent = np.tile([0.0, 1.0] if axis == 0 else [1.0, 0.0], (len(t), 1))
            for run in runs:
                if len(run) >= 2:
                    combs.append(comb(surface, uv[run], scale=scale, tangent=tangent[run]))
    return combs


def comb_lines(combs):
    """The teeth and the envelope (the polyline through the tips) of ``combs`` as one pyvista.PolyData of lines.

    Cell data ``part``: 0 for teeth, 1 for envelopes, 2 for the inflection marks (a segment through the
    inflection point along the normal, as long as the comb's longest tooth on either side).  Inflection points are in ``field_data["inflections"]`` (absent when there are none).
    """
    import pyvista as pv

    if isinstance(combs, Comb):
        combs = [combs]
    points, cells, part = [], [], []
    n = 0
    for c in combs:
        ok = np.nonzero(~c.degenerate)[0]
        for i in ok:
            points += [c.points[i], c.tips[i]]
            cells += [2, n, n + 1]
            part.append(0)
            n += 2
        # the envelope, broken at degenerate points
        runs = np.split(ok, np.nonzero(np.diff(ok) > 1)[0] + 1) if len(ok) else []
        for run in runs:
            if len(run) < 2:
                continue
            points += list(c.tips[run])
            cells += [len(run), *range(n, n + len(run))]
            part.append(1)
            n += len(run)
    # inflections: a mark across the curve along the normal, as long as the comb's longest tooth on each side
    for c in combs:
        if not len(c.inflection_points):
            continue
        ok = ~c.degenerate
        half = float(np.max(np.abs(c.scale * c.kn[ok]))) if ok.any() else 0.0
        for p, nrm in zip(c.inflection_points, c.inflection_normals, strict=True):
            points += [p - half * nrm, p + half * nrm]
            cells += [2, n, n + 1]
            part.append(2)
            n += 2
    mesh = pv.PolyData(np.array(points, dtype=float).reshape(-1, 3), lines=np.array(cells, dtype=np.int64))
    mesh.cell_data["part"] = np.array(part, dtype=np.int64)
    flex = [c.inflection_points for c in combs if len(c.inflection_points)]
    if flex:  # PyVista refuses an empty array as field data: no inflections, no entry
        mesh.field_data["inflections"] = np.concatenate(flex)
    return mesh
