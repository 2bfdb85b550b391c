r"""Lines of curvature: curves whose tangent is a principal direction everywhere, through the path integrator.

A line of curvature of :math:`\kappa_i` solves :math:`(u', v') = \pm w_i/|w_i|`
with :math:`w_i` the eigenvector of the Weingarten map (see
:mod:`lab.geometry.directions`), by arc length.  The direction field has no
sign of its own, so the state carries a direction :math:`(p, q)` that picks
it and relaxes towards it (:func:`.problem._line_rhs`).  The integration is
the one of the geodesics (:mod:`.integrator`): patch by patch, restarted at
knot lines, stopped at the domain boundary, at degenerate points and just
before an umbilic (where κ1 − κ2 vanishes and the field is undefined; the
path's ``end`` is then ``"umbilic"``).
"""

import dataclasses
import warnings

import numpy as np

from ...geometry import validation as _v
from ...geometry.curvature import DegeneratePointWarning
from ...geometry.directions import eigen
from ...i18n import _
from .integrator import _integrate_fan, _solve_one
from .paths import PATH_BYTES, PATH_BYTES_PER_SAMPLE, _check_length_cap, _make_paths
from .problem import (
    _DEGENERATE,
    _UMBILIC_STOP,
    ATOL,
    LINES,
    RTOL,
    _check_length,
    _check_point,
    _check_surface,
    _check_tolerances,
    _line_direction,
    _problem,
    _regular_derivatives,
)

__all__ = ["UmbilicWarning", "line_of_curvature", "lines_of_curvature"]

#: The carried direction relaxes towards the principal direction at this rate times 1/length.
RELAXATION = 50.0


class UmbilicWarning(RuntimeWarning):
    """A line of curvature stopped just before an umbilic, where the principal directions are undefined."""


def _which(which):
    key = {1: "k1", 2: "k2", "1": "k1", "2": "k2", "k1": "k1", "k2": "k2"}.get(
        which if isinstance(which, (int, str)) and not isinstance(which, bool) else None)
    if key is None:
        raise ValueError(f"which must be 'k1' or 'k2' (the principal curvature whose direction the line follows); "
                         f"got {which!r}")
    return key


def _starts(surface, starts, key, backward):
    """Initial states ``(k, 4)`` and cells for lines from the points ``starts`` (k, 2), along ±d."""
    d = surface.derivatives(starts[:, 0], starts[:, 1])
    _, _, _, _, degenerate, _, _, gap = eigen(d)
    for (u, v), bad, g in zip(starts, degenerate, gap):
        if bad:
            _regular_derivatives(surface, u, v, "start point")  # raises, naming the point
        if not g > _UMBILIC_STOP:
            raise ValueError(f"start point (u, v) = ({u:g}, {v:g}) is an umbilic (κ1 = κ2): the principal "
                             "directions are undefined there; start a little away from it")
    w, _ = _line_direction(d, key == "k1")
    # orient as curvature(..., directions=True) does: d1 . b_u >= 0, d2 so that (d1, d2, N) is right-handed
    c = surface.curvature(starts[:, 0], starts[:, 1], directions=True)
    ref = c.d1 if key == "k1" else c.d2
    x = w[:, :1] * d.bu + w[:, 1:] * d.bv
    sign = np.where(np.einsum("ij,ij->i", x, ref) < 0, -1.0, 1.0)
    sign = -sign if backward else sign
    w = w * sign[:, None]
    return np.concatenate([starts, w], axis=1), w


def _finish(problem, paths, surface):
    """Name the paths that stopped before an umbilic (not at a degenerate point) and warn once."""
    out, n_umbilic = [], 0
    for p in paths:
        if p.end == "degenerate":
            d = surface.derivatives(p.uv[-1:, 0], p.uv[-1:, 1])
            if eigen(d)[7][0] <= 10 * _UMBILIC_STOP:
                p = dataclasses.replace(p, end="umbilic")
                n_umbilic += 1
        out.append(p)
    if n_umbilic:
        warnings.warn(_("{n} line(s) of curvature stopped just before an umbilic (κ1 = κ2), where the principal "
                        "directions are undefined").format(n=n_umbilic), UmbilicWarning, stacklevel=3)
    return out


def _run(surface, starts, which, length, backward, rtol, atol, n_samples):
    surface = _check_surface(surface)
    key = _which(which)
    L = _check_length(length)
    _check_length_cap(surface, L, "line of curvature")
    rtol, atol = _check_tolerances(rtol, atol)
    n_samples = _v.as_positive_int(n_samples, "n_samples", minimum=2)
    starts = np.array([_check_point(surface, s, "start point") for s in starts], dtype=float).reshape(-1, 2)
    _v.check_memory(len(starts) * (PATH_BYTES_PER_SAMPLE * n_samples + PATH_BYTES),
                    f"{len(starts)} line(s) of curvature of {n_samples} samples each")
    problem = _problem(surface, LINES[key])
    y0, w = _starts(surface, starts, key, backward)
    cell0 = problem.locate(starts, w)
    rate = np.full((len(starts), 1), RELAXATION / L)
    if len(starts) == 1:
        state, end, stop = _solve_one(problem, y0[0], cell0[0], L, rate[0], rtol, atol, "DOP853")
        states, ends, stops = [state], [end], [stop]
    else:
        states, ends, stops = _integrate_fan(problem, y0, cell0, L, rate, rtol, atol)
    angles = np.zeros(len(starts))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DegeneratePointWarning)  # said again below, with the right reason
        paths = _make_paths(problem, states, ends, stops, angles, None, rate, n_samples)
    paths = [dataclasses.replace(p, origin=(float(u), float(v)), angle=float("nan"))
             for p, (u, v) in zip(paths, starts)]
    if np.any(np.asarray(stops) == _DEGENERATE):
        paths = _finish(problem, paths, surface)
    return paths


def line_of_curvature(surface, start, which, length, *, backward=False, rtol=RTOL, atol=ATOL, n_samples=201):
    """The line of curvature through ``start`` along the principal direction of ``which``, by arc length.

    Parameters
    ----------
    surface : lab.Surface
    start : (float, float)
        ``(u0, v0)``; not an umbilic or a degenerate point.
    which : 'k1' or 'k2'
        Follow the direction of κ1 (``d1``) or of κ2 (``d2``).
    length : float
        Arc length, > 0.
    backward : bool
        Start along ``-d`` instead of ``+d`` (the orientation of ``curvature(..., directions=True)``).
    rtol, atol : float
        Tolerances of the solver.
    n_samples : int

    Returns
    -------
    Path
        As :func:`lab.geodesic` (``kind`` is ``"line of curvature (k1)"`` or ``"(k2)"``, ``angle`` NaN);
        ``end`` may also be ``"umbilic"`` (with an :class:`UmbilicWarning`).
    """
    return _run(surface, [start], which, length, backward, rtol, atol, n_samples)[0]


def lines_of_curvature(surface, starts, which, length, *, rtol=RTOL, atol=ATOL, n_samples=101):
    """A net of lines of curvature: through every start point both ways (``+d`` and ``-d``), integrated together.

    Returns a list of ``(forward, backward)`` pairs of :class:`Path`, one pair per start point.
    """
    starts = np.asarray(starts, dtype=float).reshape(-1, 2)
    if len(starts) == 0:
        raise ValueError("starts must hold at least one (u, v) pair; got none")
    fwd = _run(surface, starts, which, length, False, rtol, atol, n_samples)
    back = _run(surface, starts, which, length, True, rtol, atol, n_samples)
    return list(zip(fwd, back))
