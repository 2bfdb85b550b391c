"""The shortest geodesic between two points, by shooting on the start angle and the length."""

import numpy as np

from ...geometry import validation as _v
from .integrator import _integrate_fan
from .paths import geodesic
from .problem import (
    ATOL,
    GEODESIC,
    RTOL,
    _check_length,
    _check_point,
    _check_surface,
    _check_tolerances,
    _direction,
    _frame,
    _Problem,
    _regular_derivatives,
)

__all__ = ["geodesic_between"]


# --------------------------------------------------------------------------- geodesic between two points


def geodesic_between(surface, uv_a, uv_b, *, tol=1e-9, n_candidates=4, rtol=RTOL, atol=ATOL, n_samples=201):
    r"""A geodesic from ``A = x(uv_a)`` to ``B = x(uv_b)``, by shooting on the start angle α and the length L.

    The unknowns ``(α, L)`` solve :math:`\mathbf x(u(L), v(L)) = \mathbf B`, three
    equations in the least-squares sense, by damped Gauss–Newton steps.  The
    derivative in L is the unit tangent at the end point; the one in α is a
    forward difference from a second geodesic integrated together with the
    first.  Initial guesses: the straight line from A to B projected into the
    tangent plane at A (length |AB|), and the closest approaches to B of a
    coarse fan of geodesics from A; all guesses are iterated together (one
    vectorised integration per step, see :func:`geodesic_fan`).  Of the
    converged geodesics the shortest is returned: a locally shortest path,
    and the shortest path from A to B unless all guesses missed a shorter geodesic.

    Parameters
    ----------
    surface : Surface
    uv_a, uv_b : (float, float)
        Parameters of A (a regular point) and of B, two different points.
    tol : float
        Required distance of the end point from B, relative to max(1, |AB|).
    n_candidates : int
        Number of initial guesses (the first is the tangent-plane guess).
    rtol, atol, n_samples
        As :func:`geodesic`.

    Returns
    -------
    Path
        Integrated by :func:`geodesic`; it ends at B within ``tol``, and its
        ``angle`` is the start angle α at A.

    Raises
    ------
    ValueError
        If no guess converges (e.g. every geodesic towards B leaves the domain).
    """
    surface = _check_surface(surface)
    a = _check_point(surface, uv_a, "point A")
    b = _check_point(surface, uv_b, "point B")
    n_candidates = _v.as_positive_int(n_candidates, "n_candidates", minimum=1)
    rtol, atol = _check_tolerances(rtol, atol)
    tol = _check_length(tol, "tol")
    d = _regular_derivatives(surface, *a, "point A")
    xa = d.b[0]
    xb = surface.evaluate(b[0], b[1])
    chord = float(np.linalg.norm(xb - xa))
    scale = max(1.0, chord)
    if chord <= 1e-12 * scale:
        raise ValueError(f"points A and B must be different points of the surface; got {a} and {b}")
    problem = _Problem(surface, GEODESIC)

    def shoot(alphas, lengths, rtol=rtol, atol=atol):
        """End points, unit end tangents and 'reached the length' flags of geodesics from A (one integration)."""
        alphas, lengths = np.asarray(alphas, dtype=float), np.asarray(lengths, dtype=float)
        _, duv = _direction(d, alphas)
        start = np.tile(a, (len(alphas), 1))
        pieces, s_end, _ = _integrate_fan(problem, np.concatenate([start, duv], axis=1), problem.locate(start, duv),
                                          lengths, None, rtol, atol)
        Y = np.array([p(np.array([min(L, e)]))[0] for p, L, e in zip(pieces, lengths, s_end)])
        uvw = problem.wrap(Y[:, :2])
        dd = surface.derivatives(uvw[:, 0], uvw[:, 1])
        return dd.b, dd.bu * Y[:, 2:3] + dd.bv * Y[:, 3:4], s_end >= lengths * (1 - 1e-12), pieces, s_end

    # initial guesses: the tangent plane, then the closest approaches of a coarse fan
    e1, e2, _, _ = _frame(d)
    w = xb - xa
    guesses = [(float(np.arctan2(w @ e2[0], w @ e1[0])), chord)]
    if n_candidates > 1:
        n_fan = 36
        fan_alpha = 2 * np.pi * np.arange(n_fan) / n_fan
        _, _, _, pieces, s_end = shoot(fan_alpha, np.full(n_fan, 3.0 * chord), rtol=max(rtol, 1e-6),
                                       atol=max(atol, 1e-8))
        best = []
        for k, (p, e) in enumerate(zip(pieces, s_end)):
            s = np.linspace(0, e, 200)
            uvw = problem.wrap(p(s)[:, :2])
            dist = np.linalg.norm(surface.evaluate(uvw[:, 0], uvw[:, 1]) - xb, axis=1)
            i = int(np.argmin(dist))
            best.append((dist[i], fan_alpha[k], max(s[i], 1e-3 * chord)))
        for _, alpha_k, s_k in sorted(best):
            if len(guesses) >= n_candidates:
                break
            if all(abs(np.angle(np.exp(1j * (alpha_k - g[0])))) > 3 * np.pi / n_fan for g in guesses):
                guesses.append((float(alpha_k), float(s_k)))

    x = np.array(guesses)  # (c, 2): alpha, L
    c = len(x)
    delta = 1e-6
    min_length, max_length = 1e-9 * scale, 4.0 * chord
    goal = 0.1 * tol * scale

    def residuals(x):
        k = len(x)
        pts, tangent, _, _, _ = shoot(np.r_[x[:, 0], x[:, 0] + delta], np.r_[x[:, 1], x[:, 1]])
        r = pts[:k] - xb
        J = np.stack([(pts[k:] - pts[:k]) / delta, tangent[:k]], axis=-1)  # (k, 3, 2)
        return r, J

    r, J = residuals(x)
    damping = np.ones(c)
    for _ in range(40):
        norm = np.linalg.norm(r, axis=1)
        converged = norm <= goal
        # a candidate much longer than a geodesic already found will not become the shortest
        shortest = x[converged, 1].min() if np.any(converged) else np.inf
        live = ~converged & (damping > 1e-4) & (x[:, 1] <= min(max_length, 1.5 * shortest))
        if not np.any(live):
            break
        lv = np.flatnonzero(live)
        step = np.array([np.linalg.lstsq(J[k], -r[k], rcond=None)[0] for k in lv])
        trial = x[lv] + damping[lv, None] * step
        trial[:, 1] = np.clip(trial[:, 1], min_length, 2 * max_length)
        r_t, J_t = residuals(trial)
        better = np.linalg.norm(r_t, axis=1) < norm[lv]
        kb = lv[better]
        x[kb], r[kb], J[kb] = trial[better], r_t[better], J_t[better]
        damping[lv] = np.where(better, np.minimum(1.0, 2 * damping[lv]), damping[lv] / 4)
    ok = np.linalg.norm(r, axis=1) <= tol * scale
    if np.any(ok):  # the end point must be reached, not a boundary stop that happens to lie near B
        _, _, reached, _, _ = shoot(x[ok, 0], x[ok, 1])
        ok[np.flatnonzero(ok)[~reached]] = False
    if not np.any(ok):
        raise ValueError(
            f"no geodesic from A = {a} to B = {b} found by shooting from {c} initial guesses "
            "(they leave the domain or do not converge)"
        )
    k = np.flatnonzero(ok)[np.argmin(x[ok, 1])]
    path = geodesic(surface, a, float(np.mod(x[k, 0], 2 * np.pi)), float(x[k, 1]), rtol=rtol, atol=atol,
                    n_samples=n_samples)
    miss = float(np.linalg.norm(path.points[-1] - xb))
    if path.hit_boundary or miss > tol * scale:  # pragma: no cover - the two integrators agree far below tol
        raise ValueError(f"the geodesic from A to B misses B by {miss:.3g}")
    return path

