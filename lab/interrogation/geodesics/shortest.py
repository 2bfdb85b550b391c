"""The shortest geodesic between two points: a polyhedral shortest path, then shooting on the start angle and the length."""

import numpy as np

from ...geometry import validation as _v
from ...geometry.curvature import unit_normal
from .integrator import _integrate_fan
from .paths import _make_paths
from .polyhedral import polyhedral_mesh
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
    _problem,
    _regular_derivatives,
)

__all__ = ["geodesic_between"]

#: Tolerances of the solver while the shooting is still far from B (it switches to the requested ones near B).
COARSE_RTOL, COARSE_ATOL = 1e-5, 1e-7
#: Step in α of the forward difference for the derivative of the end point.
ANGLE_STEP = 1e-7
#: Largest change of α in one Gauss–Newton step (radians).
MAX_ANGLE_STEP = 0.25
#: A geodesic counts as the polyhedral path's when it is at most this much longer (relatively).
LENGTH_SLACK = 0.05


def geodesic_between(surface, uv_a, uv_b, *, tol=1e-9, n_candidates=4, rtol=RTOL, atol=ATOL, n_samples=201):
    r"""The shortest geodesic from ``A = x(uv_a)`` to ``B = x(uv_b)``: polyhedral path, then shooting on (α, L).

    1. A polyhedral shortest path between the mesh vertices nearest to A and B
       (potpourri3d's edge-flip geodesic on a mesh of the surface of about
       5000 vertices, built once per surface: :mod:`.polyhedral`) gives the
       first guess: the start angle α towards the path in the tangent plane at
       A, and its length L.
    2. The exact geodesic ODE (eq. 11) is shot from A and the unknowns
       ``(α, L)`` solve :math:`\mathbf x(u(L), v(L)) = \mathbf B`, three
       equations in the least-squares sense, by damped Gauss–Newton steps.
       The derivative in L is the unit tangent at the end point; the one in α a
       forward difference from a second geodesic integrated together with the
       first (:func:`geodesic_fan`'s vectorised integrator).  The solver runs
       with coarse tolerances while the end point is far from B and with
       ``rtol``, ``atol`` for the last steps.
    3. Only if that does not converge (a guess that leaves the domain), up to
       ``n_candidates`` further guesses are tried as before: the straight line
       to B in the tangent plane, and the closest approaches to B of a coarse
       fan of geodesics; the shortest converged geodesic is returned.

    The result is the geodesic in the homotopy class of the polyhedral
    shortest path, i.e. the globally shortest one unless the mesh (edges about
    1/70 of the surface's extent) misses a shorter class.

    Parameters
    ----------
    surface : Surface
    uv_a, uv_b : (float, float)
        Parameters of A (a regular point) and of B, two different points.
    tol : float
        Required distance of the end point from B, relative to max(1, |AB|).
    n_candidates : int
        Number of fallback guesses (the first is the tangent-plane guess).
    rtol, atol, n_samples
        As :func:`geodesic`.

    Returns
    -------
    Path
        Ends at B within ``tol``; its ``angle`` is the start angle α at A.

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
    n_samples = _v.as_positive_int(n_samples, "n_samples", minimum=2)
    d = _regular_derivatives(surface, *a, "point A")
    xa = d.b[0]
    xb = surface.evaluate(b[0], b[1])
    chord = float(np.linalg.norm(xb - xa))
    scale = max(1.0, chord)
    if chord <= 1e-12 * scale:
        raise ValueError(f"points A and B must be different points of the surface; got {a} and {b}")
    shooter = _Shooter(surface, _problem(surface, GEODESIC), d, a, xb, tol * scale, rtol, atol)
    guess = _polyhedral_guess(surface, d, xa, xb)
    found = None
    if guess is not None:
        found = shooter.solve(np.array([guess]), length_bound=(1 + LENGTH_SLACK) * guess[1])
    if found is None:
        found = shooter.solve(_fallback_guesses(shooter, d, xa, xb, chord, n_candidates))
    if found is None:
        why = "they leave the domain or do not converge"
        db = surface.derivatives(np.array([b[0]]), np.array([b[1]]))
        if unit_normal(db.bu, db.bv)[1][0]:
            why = ("B is a degenerate point (a pole: b_u x b_v = 0), where the geodesic equations in (u, v) are "
                   "singular and every geodesic towards it reaches the edge of the domain; aim at a point near it")
        raise ValueError(
            f"no geodesic from A = {a} to B = {b} found by shooting from the polyhedral shortest path "
            f"and {n_candidates} further initial guesses ({why})"
        )
    alpha, state, end, stop = found
    origin = (float(a[0]), float(a[1]))
    return _make_paths(shooter.problem, [state], [end], [stop], np.array([np.mod(alpha, 2 * np.pi)]), origin, None,
                       n_samples)[0]


class _Shooter:
    """Geodesics from A at angles α and lengths L, and the damped Gauss–Newton iteration on (α, L)."""

    def __init__(self, surface, problem, d, a, xb, goal, rtol, atol):
        self.surface, self.problem, self.d, self.a, self.xb = surface, problem, d, a, xb
        self.goal, self.rtol, self.atol = goal, rtol, atol

    def shoot(self, alphas, lengths, rtol, atol):
        """End points, unit end tangents, 'reached the length' flags, states and ends of geodesics from A."""
        alphas, lengths = np.asarray(alphas, dtype=float), np.asarray(lengths, dtype=float)
        _, duv = _direction(self.d, alphas)
        start = np.tile(self.a, (len(alphas), 1))
        problem = self.problem
        pieces, s_end, stops = _integrate_fan(problem, np.concatenate([start, duv], axis=1),
                                              problem.locate(start, duv), lengths, None, rtol, atol)
        Y = np.array([p(np.array([min(L, e)]))[0] for p, L, e in zip(pieces, lengths, s_end)])
        uvw = problem.wrap(Y[:, :2])
        dd = self.surface.derivatives(uvw[:, 0], uvw[:, 1])
        reached = s_end >= lengths * (1 - 1e-12)
        return dd.b, dd.bu * Y[:, 2:3] + dd.bv * Y[:, 3:4], reached, pieces, s_end, stops

    def residuals(self, x, fine):
        """Residuals x(α, L) - B (k, 3), Jacobians (k, 3, 2) and the solutions of the geodesics at ``x`` (k, 2)."""
        k = len(x)
        tols = (self.rtol, self.atol) if fine else (max(self.rtol, COARSE_RTOL), max(self.atol, COARSE_ATOL))
        pts, tangent, reached, pieces, s_end, stops = self.shoot(np.r_[x[:, 0], x[:, 0] + ANGLE_STEP],
                                                                 np.r_[x[:, 1], x[:, 1]], *tols)
        r = pts[:k] - self.xb
        J = np.stack([(pts[k:] - pts[:k]) / ANGLE_STEP, tangent[:k]], axis=-1)
        return r, J, (reached[:k], pieces[:k], s_end[:k], stops[:k])

    def solve(self, x, max_iterations=40, length_bound=None):
        """Damped Gauss–Newton from the guesses ``x`` (c, 2) together; the shortest converged one, or None.

        Each iteration evaluates its trial points with coarse tolerances while
        the end point is far from B and with the requested ones near it; a
        step changes α by at most :data:`MAX_ANGLE_STEP` and L by at most a
        quarter, so the iteration stays with the geodesic its guess is near.
        ``length_bound``: lengths above it are not accepted (a geodesic much
        longer than the polyhedral path belongs to another homotopy class).
        Returns ``(alpha, state, end, stop)`` of the geodesic that ends at B within the goal.
        """
        x = np.array(x, dtype=float)
        c = len(x)
        chord = float(np.linalg.norm(self.xb - self.d.b[0]))
        min_length, max_length = 1e-9 * max(1.0, chord), 4.0 * max(chord, np.max(x[:, 1]))
        if length_bound is not None:
            max_length = min(max_length, length_bound)
        switch = 1e3 * max(self.goal, COARSE_RTOL * chord)  # below this residual the coarse solution is not enough
        fine = np.zeros(c, dtype=bool)
        r, J, sol = self.residuals(x, fine=False)
        damping = np.ones(c)
        for _ in range(max_iterations):
            norm = np.linalg.norm(r, axis=1)
            done = fine & (norm <= self.goal) & sol[0]
            shortest = x[done, 1].min() if np.any(done) else np.inf
            live = ~done & (damping > 1e-4) & (x[:, 1] <= min(max_length, 1.5 * shortest))
            if not np.any(live):
                break
            lv = np.flatnonzero(live)
            step = np.array([np.linalg.lstsq(J[k], -r[k], rcond=None)[0] for k in lv])
            limit = np.maximum(np.abs(step[:, 0]) / MAX_ANGLE_STEP, np.abs(step[:, 1]) / (0.25 * x[lv, 1]))
            step /= np.maximum(limit, 1.0)[:, None]
            trial = x[lv] + damping[lv, None] * step
            trial[:, 1] = np.clip(trial[:, 1], min_length, 2 * max_length)
            trial_fine = norm[lv] <= switch
            for is_fine in (False, True):  # each trial at the tolerances its closeness to B calls for
                sel = trial_fine == is_fine
                if not np.any(sel):
                    continue
                ks = lv[sel]
                r_t, J_t, sol_t = self.residuals(trial[sel], fine=is_fine)
                # a first fine evaluation is taken as it is: the coarse residual it follows is only as good as
                # the coarse tolerances and may look smaller than the exact one
                better = (np.linalg.norm(r_t, axis=1) < norm[ks]) | (is_fine & ~fine[ks])
                kb = ks[better]
                x[kb], r[kb], J[kb], fine[kb] = trial[sel][better], r_t[better], J_t[better], is_fine
                sol = _merge(sol, tuple(_take(part, better) for part in sol_t), np.isin(np.arange(c), kb))
                damping[ks] = np.where(better, np.minimum(1.0, 2 * damping[ks]), damping[ks] / 4)
        done = fine & (np.linalg.norm(r, axis=1) <= self.goal) & sol[0] & (x[:, 1] <= max_length)
        if not np.any(done):
            return None
        k = np.flatnonzero(done)[np.argmin(x[done, 1])]
        return float(x[k, 0]), sol[1][k], float(sol[2][k]), int(sol[3][k])


def _take(part, mask):
    return [p for p, m in zip(part, mask) if m] if isinstance(part, list) else part[mask]


def _merge(sol, new, mask):
    """Replace the entries of the solution parts ``sol`` selected by ``mask`` by ``new`` (in order)."""
    reached, pieces, s_end, stops = (np.array(sol[0]), list(sol[1]), np.array(sol[2]), np.array(sol[3]))
    idx = np.flatnonzero(mask)
    reached[idx], s_end[idx], stops[idx] = new[0], new[2], new[3]
    for i, p in zip(idx, new[1]):
        pieces[i] = p
    return reached, pieces, s_end, stops


def _tangent_angle(d, w):
    """Angle α (eq. 10) of the projection of the vector ``w`` into the tangent plane at the start point."""
    e1, e2, _, _ = _frame(d)
    return float(np.arctan2(w @ e2[0], w @ e1[0]))


def _polyhedral_guess(surface, d, xa, xb):
    """(α, L) from the edge-flip shortest path between the mesh vertices nearest to A and B, or None."""
    try:
        mesh = polyhedral_mesh(surface)
    except Exception:  # noqa: BLE001 - no mesh (e.g. a non-manifold grid): the shooting falls back to other guesses
        return None
    ia, ib = mesh.nearest_vertex(xa), mesh.nearest_vertex(xb)
    if ia == ib:
        return _tangent_angle(d, xb - xa), float(np.linalg.norm(xb - xa))
    poly = mesh.path(ia, ib)
    poly[0], poly[-1] = xa, xb  # the path between the vertices, moved to start at A and end at B
    seg = np.linalg.norm(np.diff(poly, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(seg)])
    length = float(arc[-1])
    # aim at the path a fifth along it: far enough to see past the offset of A from its vertex (the angle
    # error ~ offset / distance), near enough that the path's bending in the tangent plane stays small
    s_aim = 0.2 * length
    aim = np.array([np.interp(s_aim, arc, poly[:, i]) for i in range(3)])
    return _tangent_angle(d, aim - xa), length


def _fallback_guesses(shooter, d, xa, xb, chord, n_candidates):
    """The tangent-plane guess and the closest approaches to B of a coarse fan of geodesics from A."""
    guesses = [(_tangent_angle(d, xb - xa), chord)]
    if n_candidates > 1:
        n_fan = 36
        fan_alpha = 2 * np.pi * np.arange(n_fan) / n_fan
        *_, pieces, s_end, _ = shooter.shoot(fan_alpha, np.full(n_fan, 3.0 * chord), 1e-6, 1e-8)
        problem, best = shooter.problem, []
        for k, (p, e) in enumerate(zip(pieces, s_end)):
            s = np.linspace(0, e, 200)
            uvw = problem.wrap(p(s)[:, :2])
            dist = np.linalg.norm(shooter.surface.evaluate(uvw[:, 0], uvw[:, 1]) - xb, axis=1)
            i = int(np.argmin(dist))
            best.append((dist[i], fan_alpha[k], max(s[i], 1e-3 * chord)))
        for _, alpha_k, s_k in sorted(best):
            if len(guesses) >= n_candidates:
                break
            if all(abs(np.angle(np.exp(1j * (alpha_k - g[0])))) > 3 * np.pi / n_fan for g in guesses):
                guesses.append((float(alpha_k), float(s_k)))
    return np.array(guesses)
