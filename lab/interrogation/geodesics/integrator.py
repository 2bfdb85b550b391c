"""Integrators for the path ODEs: one path with ``solve_ivp``, many with a vectorised DOP853 stepper.

:func:`_integrate_fan` advances all paths of a fan together, each with the
step decisions ``solve_ivp(method="DOP853")`` would make for it alone
(Hairer, Nørsett, Wanner II.4-II.6), restarting paths at patch edges.
"""

import warnings

import numpy as np
from scipy.integrate import DOP853, solve_ivp
from scipy.optimize import brentq

from .problem import _BOUNDARY, _CROSS_MARGIN, _DEGENERATE, _EPS, _fmt

# --------------------------------------------------------------------------- dense output


class _Pieces:
    """Continuous state of one path: DOP853 interpolants of its steps (same polynomial as scipy's ``Dop853DenseOutput``).

    ``dense`` holds the steps of all paths integrated together (:class:`_DenseOutput`), ``rows`` this path's.
    """

    def __init__(self, dense, rows):
        self._dense, self._rows = dense, rows
        self.t_old, self.t_hi, self.h, self.y_old = (x[rows] for x in (dense.t_old, dense.t_hi, dense.h, dense.y_old))

    @property
    def F(self):
        """Coefficients of the interpolants, (steps, 7, m)."""
        return self._dense.F[self._rows]

    def __call__(self, s):
        s = np.atleast_1d(np.asarray(s, dtype=float))
        i = np.clip(np.searchsorted(self.t_hi, s, side="left"), 0, len(self.t_hi) - 1)
        return _dop853_poly((s - self.t_old[i]) / self.h[i], self.y_old[i], self.F[i])


class _DenseOutput:
    """The accepted steps of the paths integrated together, and the coefficients of their interpolants.

    An interpolant costs three more stages per step (:func:`_dense_coefficients`).
    They are computed at once for the steps with an event (their roots are found
    on the interpolant) and, for all other steps of all paths together, only
    when a path is first evaluated between its steps: the Gauss–Newton
    iterations of :func:`lab.geodesic_between` look at the end points of most
    of their paths only.
    """

    def __init__(self, problem, D):
        self.problem, self.D = problem, D
        self._chunks = []
        self._F = None

    def add(self, paths, t_old, t_hi, h, y_old, y_new, K, cell, F, known):
        """Record accepted steps of ``paths``; ``F[known]`` are already computed coefficients."""
        self._chunks.append([paths, t_old, t_hi, h, y_old, y_new, K.swapaxes(0, 1), cell, F, known])

    def pieces(self, n):
        """The :class:`_Pieces` of paths ``0 … n-1`` (after the integration).

        The steps are put in the order of the paths (and of the steps), each recorded part freed once it is
        copied, so that at most one part is held twice.
        """
        chunks, self._chunks = self._chunks, None
        paths = np.concatenate([c[0] for c in chunks])
        order = np.argsort(paths, kind="stable")
        where = np.empty_like(order)
        where[order] = np.arange(len(order))  # the sorted position of every recorded step
        fields = []
        for k in range(1, len(chunks[0])):
            out = np.empty((len(paths),) + chunks[0][k].shape[1:], dtype=chunks[0][k].dtype)
            start = 0
            for c in chunks:
                out[where[start : start + len(c[k])]] = c[k]
                start += len(c[k])
                c[k] = None
            fields.append(out)
        self.t_old, self.t_hi, self.h, self.y_old, y_new, K, cell, F, known = fields
        self._pending = (F, y_new, K, cell, np.flatnonzero(~known))
        self._paths = paths[order]
        bounds = np.concatenate([[0], np.cumsum(np.bincount(paths, minlength=n))])
        return [_Pieces(self, slice(bounds[j], bounds[j + 1])) for j in range(n)]

    @property
    def F(self):
        """Coefficients of the interpolants of all steps, (steps, 7, m), computed on first use."""
        F, pending = self._F, self._pending  # one read each: paths may be evaluated from several threads
        if F is not None:
            return F
        F, y_new, K, cell, todo = pending  # (two threads at once would write the same values into F)
        for a in range(0, len(todo), _DENSE_CHUNK):  # in blocks: bounded temporaries
            rows = todo[a : a + _DENSE_CHUNK]
            D = None if self.D is None else self.D[self._paths[rows]]
            F[rows] = _dense_coefficients(self.problem, self.h[rows], self.y_old[rows], y_new[rows],
                                          K[rows].swapaxes(0, 1), cell[rows], D)
        self._F = F
        self._pending = None  # the stages are no longer needed
        return F


#: Steps per block when the interpolants of a fan's steps are computed together (the patch coefficients
#: gathered for a block take 2.3 KiB per step for bicubic patches).
_DENSE_CHUNK = 64


def _dense_coefficients(problem, h, y_old, y_new, K, cell, D):
    """Coefficients ``F`` (q, 7, m) of the DOP853 interpolants of q steps from their stages ``K`` (13, q, m).

    The three extra stages of the dense output (as scipy's ``DOP853._dense_output_impl``).
    """
    q, m = y_old.shape
    Kx = np.empty((_N_STAGES + 4, q, m))
    Kx[: _N_STAGES + 1] = K
    for s, arow in enumerate(_A_EXTRA, start=_N_STAGES + 1):
        dy = _combine(arow[:s], Kx) * h[:, None]
        Kx[s] = problem.rhs(y_old + dy, cell, D)
    delta = y_new - y_old
    F = np.empty((q, 7, m))
    F[:, 0] = delta
    F[:, 1] = h[:, None] * K[0] - delta
    F[:, 2] = 2 * delta - h[:, None] * (K[-1] + K[0])
    F[:, 3:] = h[:, None, None] * (_Dd @ Kx.reshape(len(Kx), -1)).reshape((len(_Dd),) + Kx.shape[1:]).swapaxes(0, 1)
    return F


def _gap_on_step(problem, cell, t0, h, y0, F):
    """The event function :meth:`_Problem.gap` along one step's interpolant, as a function of s on plain floats.

    The same arithmetic as :func:`_dop853_poly` and :meth:`_Problem.gap` (so the same values to the last
    bit), without the array overhead: Brent's method calls it about ten times per crossing.
    """
    lower, upper = problem._cell_bounds(cell[None])  # not the remembered bounds of the fan's cells
    (lu, lv), (hu, hv) = lower[0].tolist(), upper[0].tolist()
    wu, wv = hu - lu, hv - lv
    Fu, Fv = F[::-1, 0].tolist(), F[::-1, 1].tolist()
    u0, v0 = float(y0[0]), float(y0[1])
    odd = [i % 2 == 1 for i in range(len(Fu))]

    def gap(s):
        x = (s - t0) / h
        x1 = 1 - x
        pu = pv = 0.0
        for fu, fv, o in zip(Fu, Fv, odd):
            pu, pv = pu + fu, pv + fv
            f = x1 if o else x
            pu, pv = pu * f, pv * f
        u, v = pu + u0, pv + v0
        return min(min(u - lu, hu - u) / wu, min(v - lv, hv - v) / wv) + _CROSS_MARGIN

    return gap


def _dop853_poly(x, y_old, F):
    """Evaluate DOP853 dense-output polynomials: x (q,), y_old (q, m), F (q, 7, m)."""
    x = x[:, None]
    y = np.zeros_like(y_old)
    for i in range(F.shape[1] - 1, -1, -1):
        y = y + F[:, i]
        y = y * (x if (F.shape[1] - 1 - i) % 2 == 0 else (1 - x))
    return y + y_old


class _Segments:
    """Continuous state of one path from consecutive ``solve_ivp`` solutions (one per patch)."""

    def __init__(self, ends, solutions):
        self.ends = np.asarray(ends)
        self.solutions = solutions

    def __call__(self, s):
        s = np.atleast_1d(np.asarray(s, dtype=float))
        i = np.clip(np.searchsorted(self.ends, s, side="left"), 0, len(self.ends) - 1)
        out = None
        for k in np.unique(i):
            sel = i == k
            values = self.solutions[k](s[sel]).T
            if out is None:
                out = np.empty((len(s), values.shape[1]))
            out[sel] = values
        return out


# --------------------------------------------------------------------------- one path: solve_ivp


def _check_defined(problem, uv, s):
    """Where the solver failed: a ``ValueError`` if the surface's derivatives are not finite there (a user's surface
    undefined at that point, issue 35), so the failure is named as the surface's, not the solver's."""
    uv = problem.wrap(np.asarray(uv, dtype=float)[None])[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the surface's own DegeneratePointWarning: the error below says it
        d = problem.surface.derivatives(uv[:1], uv[1:])
    if not all(np.all(np.isfinite(x)) for x in d):
        raise ValueError(f"{problem.kind} reached a degenerate point of the surface at s = {s:.6g}, (u, v) = "
                         f"{_fmt(uv)}: its derivatives are not finite there (NaN or inf: the surface is not defined "
                         "or not differentiable there)")


def _solve_one(problem, y0, cell0, length, D, rtol, atol, method):
    """Integrate one path with solve_ivp, restarting at every patch edge (terminal event)."""
    t0, y, cell = 0.0, np.asarray(y0, dtype=float), np.asarray(cell0)[None]
    Drow = None if D is None else D[None]
    ends, sols, first_step, stop = [], [], None, 0
    while True:

        def fun(t, yy, cell=cell):
            return problem.rhs(yy[None], cell, Drow)[0]

        def gap(t, yy, cell=cell):
            return problem.gap(yy[None], cell)[0]

        def regular(t, yy, cell=cell):
            return problem.regular(yy[None], cell)[0]

        for event in (gap, regular):
            event.terminal, event.direction = True, -1
        res = solve_ivp(fun, (t0, length), y, method=method, rtol=rtol, atol=atol, events=(gap, regular),
                        dense_output=True, first_step=first_step)
        if res.status == -1:
            _check_defined(problem, res.y[:2, -1], res.t[-1])
            raise RuntimeError(
                f"{problem.kind} integration failed at s = {res.t[-1]:.6g} near (u, v) = "
                f"{_fmt(problem.wrap(res.y[:2, -1]))}: {res.message}"
            )
        sols.append(res.sol)
        if res.status == 0:
            ends.append(length)
            break
        if res.t_events[1].size:  # the earlier of the two terminal events is recorded
            ends.append(float(res.t_events[1][0]))
            stop = _DEGENERATE
            break
        t0, y = float(res.t_events[0][0]), res.y_events[0][0]
        ends.append(t0)
        cell, leaves = problem.cross(y[None], cell)
        if leaves[0]:
            stop = _BOUNDARY
            break
        if t0 >= length:
            break
        last = res.sol.interpolants[-1]
        first_step = min(abs(last.t - last.t_old), length - t0)
    return _Segments(ends, sols), ends[-1], stop


# --------------------------------------------------------------------------- many paths: vectorised DOP853


_A, _B, _C = DOP853.A, DOP853.B, DOP853.C
_E3, _E5, _Dd = DOP853.E3, DOP853.E5, DOP853.D
_A_EXTRA = DOP853.A_EXTRA
_N_STAGES = DOP853.n_stages
_ERR_EXP = -1.0 / (DOP853.error_estimator_order + 1)
_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0


def _rms(x):
    return np.sqrt(np.mean(x * x, axis=1))


def _combine(weights, K):
    """``sum_s weights[s] K[s]`` for stages ``K`` (s, n, m): one matrix-vector product (BLAS) instead of einsum."""
    s = len(weights)
    return (weights @ K[:s].reshape(s, -1)).reshape(K.shape[1:])


def _initial_step(problem, y0, cell, f0, length, D, rtol, atol):
    """:func:`scipy.integrate._ivp.common.select_initial_step` (Hairer, Nørsett, Wanner II.4) for every path at once.

    ``length`` (n,) is each path's interval of integration.
    """
    scale = atol + np.abs(y0) * rtol
    d0, d1 = _rms(y0 / scale), _rms(f0 / scale)
    with np.errstate(divide="ignore", invalid="ignore"):
        h0 = np.where((d0 < 1e-5) | (d1 < 1e-5), 1e-6, 0.01 * d0 / d1)
    h0 = np.minimum(h0, length)
    f1 = problem.rhs(y0 + h0[:, None] * f0, cell, D)
    d2 = _rms((f1 - f0) / scale) / h0
    with np.errstate(divide="ignore", invalid="ignore"):
        h1 = np.where((d1 <= 1e-15) & (d2 <= 1e-15), np.maximum(1e-6, h0 * 1e-3),
                      (0.01 / np.maximum(d1, d2)) ** (1.0 / (DOP853.error_estimator_order + 1)))
    return np.minimum(np.minimum(100 * h0, h1), length)


def _integrate_fan(problem, y0, cell0, length, D, rtol, atol):
    """Integrate n paths together; each makes the step decisions ``solve_ivp(method="DOP853")`` makes for it alone.

    Every iteration attempts one step for every unfinished path, each with its
    own step size: the 12 stages (plus 3 for the dense output of the accepted
    steps) are evaluated for all of them at once.  Accepted steps are checked
    for a patch-edge crossing (event function :meth:`_Problem.gap`) or the
    approach of a degenerate point (:meth:`_Problem.regular`), roots by
    Brent's method on the dense output, as solve_ivp does.  A path that
    crosses an edge continues from the crossing point in the neighbouring
    patch, or stops if the edge is the domain boundary.

    Parameters
    ----------
    problem : _Problem
    y0 : (n, m) ndarray
        Initial states.
    cell0 : (n, 2) int ndarray
        Initial cells (:meth:`_Problem.locate`).
    length : float or (n,) array_like
        Arc length to integrate, per path.
    D : (n, 3) ndarray or None
        Plane normals of normal sections.
    rtol, atol : float

    Returns
    -------
    pieces : list of _Pieces
    ends : (n,) ndarray
        Arc length reached by each path.
    stops : (n,) int ndarray
        Why each path ended: 0 (its length), ``_BOUNDARY`` or ``_DEGENERATE``.
    """
    n, m = y0.shape
    length = np.broadcast_to(np.asarray(length, dtype=float), (n,)).copy()
    t = np.zeros(n)
    y = y0.astype(float).copy()
    cell = cell0.copy()
    f, g2 = problem.rhs(y, cell, D, regular=True)
    h_abs = _initial_step(problem, y, cell, f, length, D, rtol, atol)
    g1 = problem.gap(y, cell)  # the two event functions, at the start of each path's next step
    rejected = np.zeros(n, dtype=bool)
    active = np.ones(n, dtype=bool)
    stops = np.zeros(n, dtype=int)
    ends = length.copy()
    dense = _DenseOutput(problem, D)
    while np.any(active):
        idx = np.flatnonzero(active)
        ti, yi, fi, ci = t[idx], y[idx], f[idx], cell[idx]
        Dk = None if D is None else D[idx]
        min_step = 10 * np.abs(np.nextafter(ti, np.inf) - ti)
        ha = np.where(rejected[idx], h_abs[idx], np.maximum(h_abs[idx], min_step))
        too_small = ha < min_step
        if np.any(too_small):
            j = idx[np.flatnonzero(too_small)[0]]
            _check_defined(problem, y[j, :2], t[j])
            raise RuntimeError(
                f"{problem.kind} integration failed at s = {t[j]:.6g} near (u, v) = {_fmt(problem.wrap(y[j, :2]))}: "
                "Required step size is less than spacing between numbers."
            )
        Li = length[idx]
        t_new = np.minimum(ti + ha, Li)
        h = t_new - ti
        ha = np.abs(h)
        K = np.empty((_N_STAGES + 1, len(idx), m))
        K[0] = fi
        for s in range(1, _N_STAGES):
            dy = _combine(_A[s, :s], K) * h[:, None]
            K[s] = problem.rhs(yi + dy, ci, Dk)
        y_new = yi + h[:, None] * _combine(_B, K)
        f_new, g2_new = problem.rhs(y_new, ci, Dk, regular=True)
        K[-1] = f_new
        scale = atol + np.maximum(np.abs(yi), np.abs(y_new)) * rtol
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            e5 = np.sum((_combine(_E5, K) / scale) ** 2, axis=1)
            e3 = np.sum((_combine(_E3, K) / scale) ** 2, axis=1)
            err = np.where((e5 == 0) & (e3 == 0), 0.0, ha * e5 / np.sqrt((e5 + 0.01 * e3) * m))
            grow = _SAFETY * err**_ERR_EXP
        ok = err < 1
        factor = np.where(err == 0, _MAX_FACTOR, np.minimum(_MAX_FACTOR, grow))
        factor = np.where(rejected[idx], np.minimum(1.0, factor), factor)
        shrink = np.where(np.isnan(grow), _MIN_FACTOR, np.maximum(_MIN_FACTOR, grow))
        h_abs[idx] = np.where(ok, ha * factor, ha * shrink)
        rejected[idx] = ~ok
        if not np.any(ok):
            continue
        # accepted steps: events, and the dense output (3 extra stages) of the steps with one
        a = np.flatnonzero(ok)
        ia, ha_, ya_old, ya_new, ca, Ka = idx[a], h[a], yi[a], y_new[a], ci[a], K[:, a]
        # events as solve_ivp finds them: a sign change from >= 0 to <= 0 over the step (direction -1),
        # its root by Brent's method on the dense output; the earlier of the two terminates the path
        g1_new, g2_new = problem.gap(ya_new, ca), g2_new[a]
        hit1 = (g1[ia] >= 0) & (g1_new <= 0)
        hit2 = (g2[ia] >= 0) & (g2_new <= 0)
        crossed = hit1 | hit2
        t_old = ti[a]
        t_hi = t_new[a].copy()
        degenerate = np.zeros(len(a), dtype=bool)
        F = np.empty((len(a), 7, m))
        if np.any(crossed):
            rc = np.flatnonzero(crossed)
            F[rc] = _dense_coefficients(problem, ha_[rc], ya_old[rc], ya_new[rc], Ka[:, rc], ca[rc],
                                        None if D is None else Dk[a][rc])
        for r in np.flatnonzero(crossed):
            j = ia[r]

            def state_at(tt, t0=t_old[r], h=ha_[r], y0=ya_old[r : r + 1], Fr=F[r : r + 1]):
                return _dop853_poly(np.array([(tt - t0) / h]), y0, Fr)

            roots = [np.inf, np.inf]
            if hit1[r]:
                roots[0] = brentq(_gap_on_step(problem, cell[j], t_old[r], ha_[r], ya_old[r], F[r]),
                                  t_old[r], t_hi[r], xtol=4 * _EPS, rtol=4 * _EPS)
            if hit2[r]:
                roots[1] = brentq(lambda tt, j=j: problem.regular(state_at(tt), cell[j : j + 1])[0],
                                  t_old[r], t_hi[r], xtol=4 * _EPS, rtol=4 * _EPS)
            degenerate[r] = roots[1] <= roots[0]
            t_hi[r] = min(roots)
        dense.add(ia, t_old, t_hi, ha_, ya_old, ya_new, Ka, ca, F, crossed)
        # paths without events: advance
        plain = ~crossed
        jp = ia[plain]
        t[jp], y[jp], f[jp] = t_new[a][plain], ya_new[plain], K[-1, a][plain]
        g1[jp], g2[jp] = g1_new[plain], g2_new[plain]
        done = jp[t[jp] >= length[jp]]
        active[done] = False
        # paths at a degenerate point stop there
        jd = ia[degenerate]
        ends[jd], stops[jd], active[jd] = t_hi[degenerate], _DEGENERATE, False
        # paths that crossed a patch edge: restart in the neighbour (or stop at the boundary)
        edge = crossed & ~degenerate
        if np.any(edge):
            rc = np.flatnonzero(edge)
            jc = ia[rc]
            yc = _dop853_poly((t_hi[rc] - t_old[rc]) / ha_[rc], ya_old[rc], F[rc])
            new_cell, leaves = problem.cross(yc, cell[jc])
            stop = leaves | (t_hi[rc] >= length[jc])
            ends[jc[stop]] = t_hi[rc][stop]
            stops[jc[leaves]] = _BOUNDARY
            active[jc[stop]] = False
            go = ~stop
            if np.any(go):
                jg = jc[go]
                t[jg], y[jg], cell[jg] = t_hi[rc][go], yc[go], new_cell[go]
                Dg = None if D is None else D[jg]
                f[jg], g2[jg] = problem.rhs(y[jg], cell[jg], Dg, regular=True)
                g1[jg] = problem.gap(y[jg], cell[jg])
                # as a restarted solve_ivp with first_step = the step just taken
                h_abs[jg] = np.minimum(ha_[rc][go], length[jg] - t[jg])
                rejected[jg] = False
    pieces = dense.pieces(n)
    return pieces, ends, stops


