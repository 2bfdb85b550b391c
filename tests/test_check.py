"""lab.check: fresh exact cases, hints that name the mistake, robustness against broken student code."""

import math
import time

import numpy as np
import pytest
from lab.colormaps import f1, f2, f3, h

import lab
from lab import check
from lab.teaching.tasks import hints


def make_solution(mistake=None):
    """The notebook's visualize_curvature, optionally with one classic mistake."""

    class Student(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            values = []
            for patch in self:
                P = patch.control_points
                m, n = patch.degree
                if mistake in ("swapped_degrees", "swapped_index"):
                    m, n = n, m
                fu2, fv2 = (m, n) if mistake == "second_factor" else (m * (m - 1), n * (n - 1))
                if mistake == "no_factors":
                    m = n = fu2 = fv2 = 1
                bu = (1 if mistake == "missing_bu" else m) * (P[1:] - P[:-1])
                bv = n * (P[:, 1:] - P[:, :-1])
                buu = fu2 * (P[2:] - 2 * P[1:-1] + P[:-2])
                buv = m * n * (P[1:, 1:] - P[1:, :-1] - P[:-1, 1:] + P[:-1, :-1])
                bvv = fv2 * (P[:, 2:] - 2 * P[:, 1:-1] + P[:, :-2])
                corners = []
                for a, b in ((0, 0), (0, 1), (1, 0), (1, 1)):
                    i, j = (a * (m - 1), b * (n - 1)) if mistake == "swapped_index" else (-a, -b)
                    N = np.cross(bu[i, j], bv[i, j])
                    if mistake != "unnormalised":
                        N = N / np.linalg.norm(N)
                    if mistake == "orientation":
                        N = -N
                    E, F, G = bu[i, j] @ bu[i, j], bu[i, j] @ bv[i, j], bv[i, j] @ bv[i, j]
                    e, f, g = N @ buu[i, j], N @ buv[i, j], N @ bvv[i, j]
                    K = (e * g - f * f) / (E * G - F * F)
                    H = (e * G - 2 * f * F + g * E) / (E * G - F * F)
                    if mistake != "no_half":
                        H = 0.5 * H
                    root = math.sqrt(H * H - K) if mistake == "sqrt" else math.sqrt(max(H * H - K, 0.0))
                    corners.append({self.CURVATURE_GAUSSIAN: K, self.CURVATURE_AVERAGE: H,
                                    self.CURVATURE_PRINCIPAL_MAX: H + root,
                                    self.CURVATURE_PRINCIPAL_MIN: H - root}[curvature_mode])
                if mistake == "corner_order":
                    corners = [corners[0], corners[2], corners[1], corners[3]]
                patch.set_curvature(*corners)
                values.extend(corners)
            P = self.control_points.reshape(-1, 3)
            size = np.linalg.norm(P.max(axis=0) - P.min(axis=0))
            tol = 1e-9 / size ** (2 if curvature_mode == self.CURVATURE_GAUSSIAN else 1)
            if mistake == "f3_absolute":
                tol = 1e-3
            kmin, kmax = min(values), max(values)
            if kmax - kmin <= tol and mistake != "f2_noise":
                kmin = kmax
            for patch in self:
                colours = []
                for x in patch.curvature.ravel():
                    if color_map == self.COLOR_MAP_LINEAR:
                        t = (x - kmin) / (kmax - kmin) if mistake == "f2_zero" else f2(x, kmin, kmax)
                    elif color_map == self.COLOR_MAP_CUT:
                        t = f1(x)
                    else:
                        t = (0.5 if x == 0 else float(x > 0)) if mistake == "f3_exact" else f3(x, tol)
                    colours.append(tuple(h(t)))
                patch.set_colors(*colours)

    return Student


def test_reference_solution_passes_public_and_graded():
    for graded in (False, True):
        rep = check.visualize_curvature(make_solution(), graded=graded)
        assert rep.passed, str(rep)
        assert rep.score == 1.0
    public = check.visualize_curvature(make_solution())
    assert "Public checks passed; the graded run adds more cases." in str(public)
    graded = check.visualize_curvature(make_solution(), graded=True)
    assert len(graded.cases) > len(public.cases) and "graded run adds" not in str(graded)


MUTANT_HINTS = {
    "swapped_degrees": "m and n are swapped",
    "swapped_index": "an IndexError also on a square patch",  # m − 1 as the last index of every net
    "no_factors": "need the degree factors",
    "second_factor": "need m(m-1) and n(n-1)",
    "missing_bu": "b_u has the factor 1 = 1 instead of m = 3",
    "unnormalised": "you used the cross product without dividing by its length",
    "orientation": "opposite orientation",
    "no_half": "the factor ½ is missing",
    "corner_order": "c01 = the value at u = 0, v = 1",
    "sqrt": "use √(max(H² − K, 0))",
    "f2_zero": "f2 must not divide by zero",
    "f2_noise": "only by rounding noise, so κmax − κmin must count as 0",
    "f3_exact": "f3 must compare with a tolerance",
    "f3_absolute": "your f3 tolerance is absolute and too large for this model",
}


@pytest.mark.parametrize("seed", [7, 8])
@pytest.mark.parametrize("mistake", sorted(MUTANT_HINTS))
def test_each_classic_mistake_fails_with_its_hint(mistake, seed):
    """Deterministically: every seed has the cases that expose each mistake (fixed kinds, not random luck)."""
    rep = check.visualize_curvature(make_solution(mistake), seed=seed)
    assert not rep.passed
    assert MUTANT_HINTS[mistake] in str(rep), str(rep)


def test_swapped_degrees_only_shows_on_non_square_patches():
    rep = check.visualize_curvature(make_solution("swapped_degrees"), seed=3)
    first_square = rep.cases[0]
    assert first_square.name.startswith("one 3×3 patch") and first_square.passed
    assert not all(c.passed for c in rep.cases)


def test_umbilic_sqrt_mistake_names_umbilics_when_numpy_gives_nan():
    class NanSqrt(make_solution()):
        def visualize_curvature(self, curvature_mode, color_map):
            super_impl = make_solution()
            super_impl.visualize_curvature(self, curvature_mode, color_map)
            self.curvature[0, 0, 0] = np.nan  # what np.sqrt of a negative number leaves behind

    rep = check.visualize_curvature(NanSqrt, seed=1)
    assert "umbilic" in str(rep) and "max(H² − K, 0)" in str(rep)


def test_stub_garbage_errors_and_endless_loops_are_reported():
    class Stub(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            raise NotImplementedError("compute the curvature at the corners")

    rep = check.visualize_curvature(Stub)
    assert rep.status == "not implemented" and "not implemented yet" in str(rep)
    assert "compute the curvature at the corners" in str(rep)

    class Crash(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            values = {}
            return values["K"]

    rep = check.visualize_curvature(Crash)
    assert rep.status == "error"
    assert "KeyError: 'K'" in rep.message and 'return values["K"]' in rep.message
    assert "lab/check.py" not in rep.message  # no checker internals

    class Nothing(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            pass

    rep = check.visualize_curvature(Nothing)
    assert not rep.passed and "call patch.set_curvature(c00, c01, c10, c11) for every patch" in str(rep)

    class Forever(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            while True:
                pass

    start = time.perf_counter()
    rep = check.visualize_curvature(Forever, timeout=1.5)
    assert time.perf_counter() - start < 10
    assert rep.status == "timeout" and "visualize_curvature: stopped after 1.5 s" in rep.message

    class Swallow(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            try:
                while True:
                    pass
            except Exception:  # noqa: BLE001, S110 - the student's code under test swallows everything on purpose
                pass

    assert check.visualize_curvature(Swallow, timeout=1.0).status == "timeout"


def test_delegation_to_the_library_is_refused():
    class Super(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            super().visualize_curvature(curvature_mode, color_map)

    rep = check.visualize_curvature(Super)
    assert rep.status == "delegated" and "BezierPatches.visualize_curvature" in rep.message
    assert "allowed helpers: lab.colormaps.h, f1, f2, f3, math, numpy." in rep.message  # as the task text says

    from lab.curvature import from_derivatives  # imported before the check: still caught

    class Alias(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            d = lab.bezier.Derivatives(*(np.ones((2, 2, 3)),) * 6)
            try:
                from_derivatives(d)
            except Exception:  # noqa: BLE001, S110 - the student's code under test swallows everything on purpose
                pass
            make_solution().visualize_curvature(self, curvature_mode, color_map)

    rep = check.visualize_curvature(Alias)
    assert rep.status == "delegated" and "lab.geometry.curvature.from_derivatives" in rep.message
    assert lab.curvature.from_derivatives(lab.bezier.derivatives(np.eye(3)[None].repeat(2, 0), 0.5, 0.5)).K.shape == ()

    class NoOverride(lab.BezierPatches):
        pass

    assert check.visualize_curvature(NoOverride).status == "delegated"


def test_non_class_input_gives_a_message():
    rep = check.visualize_curvature(lambda self: None)
    assert rep.status == "error" and "expected a subclass of lab.BezierPatches" in rep.message


def test_small_tasks_and_their_hints():
    good = {
        "warmup": lambda k1, k2: (k1 + k2) / 2,
        "curve_curvature": lambda d1, d2: np.linalg.norm(np.cross(d1, d2)) / np.linalg.norm(d1) ** 3,
        "h": lambda x: tuple(lab.colormaps.h.__wrapped__(x)) if hasattr(lab.colormaps.h, "__wrapped__") else
        ((0, 4 * x, 1) if x <= 0.25 else (0, 1, 2 - 4 * x) if x <= 0.5 else (4 * x - 2, 1, 0) if x <= 0.75 else (1, 4 - 4 * x, 0)),
        "f1": lambda x: min(max(x, 0.0), 1.0),
        "f2": lambda x, lo, hi: 0.5 if hi == lo else (x - lo) / (hi - lo),
        "f3": lambda x, tol=1e-9: 0.5 if abs(x) <= tol else float(x > 0),
    }
    for task, func in good.items():
        rep = check.run(task, func)
        assert rep.passed, str(rep)

    bad = [
        ("curve_curvature", lambda d1, d2: np.linalg.norm(np.cross(d1, d2)) / np.linalg.norm(d1) ** 2, "divide by |c'|³"),
        ("curve_curvature", lambda d1, d2: np.linalg.norm(d2), "only when the curve has unit speed"),
        ("warmup", lambda k1, k2: k1 * k2, "k1 * k2 is the Gaussian curvature"),
        ("f2", lambda x, lo, hi: (x - lo) / (hi - lo), "return 0.5 (green)"),
        ("f3", lambda x, tol=1e-9: 0.5 if x == 0 else float(x > 0), "compare |x| with the tolerance tol"),
        ("f3", lambda x, tol=1e-9: 0.5 if abs(x) <= 1e-9 else float(x > 0), "use the tolerance you are given"),
        ("f3", lambda x: 0.5 if abs(x) <= 1e-9 else float(x > 0), "f3 takes the model's tolerance as its second"),
        ("h", lambda x: (0, 255 * x, 255), "not 0–255"),
    ]
    for task, func, hint in bad:
        rep = check.run(task, func)
        assert not rep.passed and hint in str(rep), (task, str(rep))


def _ff(bu, bv, buu, buv, bvv, unit=True, sign=1):
    N = np.cross(bu, bv)
    if unit:
        N = N / np.linalg.norm(N)
    N = sign * N
    return bu @ bu, bu @ bv, bv @ bv, N @ buu, N @ buv, N @ bvv


def _curv(E, F, G, e, f, g, half=True, clamp=True):
    det = E * G - F * F
    K = (e * g - f * f) / det
    H = (e * G - 2 * f * F + g * E) / det * (0.5 if half else 1)
    root = math.sqrt(max(H * H - K, 0)) if clamp else math.sqrt(H * H - K)
    return K, H, H + root, H - root


def test_fundamental_forms_and_curvatures_hints():
    assert check.fundamental_forms(_ff).passed
    assert VARIANT("unnormalised") in str(check.fundamental_forms(lambda *a: _ff(*a, unit=False)))
    assert "opposite orientation" in str(check.fundamental_forms(lambda *a: _ff(*a, sign=-1)))
    assert check.curvatures(_curv).passed
    assert "factor ½ is missing" in str(check.curvatures(lambda *a: _curv(*a, half=False)))
    rep = check.curvatures(lambda *a: _curv(*a, clamp=False))
    assert rep.status == "error" and "max(H² − K, 0)" in rep.message and "math domain error" in str(rep)
    rep = check.curvatures(lambda *a: np.array(_curv(*a))[[0, 1, 3, 2]])
    assert "larger principal curvature" in str(rep)


def VARIANT(name):
    return hints.VARIANT_HINTS[name][:40]


def _nets(P):
    m, n = P.shape[0] - 1, P.shape[1] - 1
    return (m * np.diff(P, axis=0), n * np.diff(P, axis=1), m * (m - 1) * np.diff(P, 2, axis=0),
            m * n * np.diff(np.diff(P, axis=0), axis=1), n * (n - 1) * np.diff(P, 2, axis=1))


def test_derivative_nets_and_corners_hints():
    assert check.derivative_nets(_nets).passed
    no_factors = lambda P: (np.diff(P, axis=0), np.diff(P, axis=1), np.diff(P, 2, axis=0),
                            np.diff(np.diff(P, axis=0), axis=1), np.diff(P, 2, axis=1))
    assert "need the degree factors" in str(check.derivative_nets(no_factors))

    def swapped(P):
        n, m = P.shape[0] - 1, P.shape[1] - 1
        return (m * np.diff(P, axis=0), n * np.diff(P, axis=1), m * (m - 1) * np.diff(P, 2, axis=0),
                m * n * np.diff(np.diff(P, axis=0), axis=1), n * (n - 1) * np.diff(P, 2, axis=1))

    assert "m and n are swapped" in str(check.derivative_nets(swapped))
    corners = lambda P: tuple(D[[0, -1]][:, [0, -1]] for D in _nets(P))
    assert check.corner_derivatives(corners).passed
    transposed = lambda P: tuple(np.swapaxes(D[[0, -1]][:, [0, -1]], 0, 1) for D in _nets(P))
    assert "corners mixed up" in str(check.corner_derivatives(transposed))
    blocked = lambda P: tuple(lab.bezier.corner_derivatives(P)[1:])
    assert check.corner_derivatives(blocked).status == "delegated"


def test_cases_are_fresh_each_run_and_reproducible_with_a_seed():
    from lab.teaching.tasks.references import rand_net as _rand_net

    a = _rand_net(np.random.default_rng(), 2, 3)
    b = _rand_net(np.random.default_rng(), 2, 3)
    assert not np.array_equal(a, b)
    c = _rand_net(np.random.default_rng(5), 2, 3)
    d = _rand_net(np.random.default_rng(5), 2, 3)
    np.testing.assert_array_equal(c, d)


def test_reference_solution_passes_under_every_seed_of_a_sweep():
    for seed in range(12):
        rep = check.visualize_curvature(make_solution(), graded=True, seed=seed)
        assert rep.passed, (seed, str(rep))


def test_an_alternative_correct_implementation_gets_full_marks():
    """Other formulas (the Weingarten map, vectorised over all corners) and its own scale-aware tolerance."""

    class Vectorised(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            P = self.control_points
            m, n = P.shape[1] - 1, P.shape[2] - 1
            d = {"u": m * np.diff(P, axis=1), "v": n * np.diff(P, axis=2)}
            d["uu"] = m * (m - 1) * np.diff(P, 2, axis=1)
            d["uv"] = m * n * np.diff(np.diff(P, axis=1), axis=2)
            d["vv"] = n * (n - 1) * np.diff(P, 2, axis=2)
            c = {k: v[:, [0, -1]][:, :, [0, -1]] for k, v in d.items()}  # (N, 2, 2, 3) at the corners
            N = np.cross(c["u"], c["v"])
            N /= np.linalg.norm(N, axis=-1, keepdims=True)
            first = np.stack([np.stack([np.einsum("...i,...i", c[a], c[b]) for b in "uv"], -1) for a in "uv"], -2)
            second = np.stack([np.stack([np.einsum("...i,...i", N, c[a + b if a + b in c else b + a])
                                         for b in "uv"], -1) for a in "uv"], -2)
            S = np.linalg.solve(first, second)  # Weingarten map
            K, H = np.linalg.det(S), 0.5 * np.trace(S, axis1=-2, axis2=-1)
            disc = ((S[..., 0, 0] - S[..., 1, 1]) / 2) ** 2 + S[..., 0, 1] * S[..., 1, 0]
            root = np.sqrt(np.clip(disc, 0, None))
            value = {"gaussian": K, "mean": H, "k1": H + root, "k2": H - root}[curvature_mode.value]
            scale = np.ptp(P.reshape(-1, 3), axis=0).max()
            zero = 1e-10 / scale ** (2 if curvature_mode.value == "gaussian" else 1)
            lo, hi = value.min(), value.max()
            if color_map.value == "linear":
                t = np.full_like(value, 0.5) if hi - lo <= zero else (value - lo) / (hi - lo)
            elif color_map.value == "cut":
                t = np.clip(value, 0, 1)
            else:
                t = np.where(np.abs(value) <= zero, 0.5, (value > 0).astype(float))
            for k, patch in enumerate(self):
                patch.set_curvature(*value[k].ravel())
                patch.set_colors(*(tuple(h(x)) for x in t[k].ravel()))

    for seed in (1, 2, 3):
        rep = check.visualize_curvature(Vectorised, graded=True, seed=seed)
        assert rep.passed and rep.score == 1.0, str(rep)


def test_constant_answers_get_no_credit_from_flat_cases():
    class Flat(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            for patch in self:
                patch.set_curvature(0.0, 0.0, 0.0, 0.0)
                patch.set_colors(*[(0.0, 1.0, 0.0)] * 4)

    rep = check.visualize_curvature(Flat, graded=True, seed=4)
    assert rep.score == 0 and "a constant answer fits it by accident" in str(rep)


def test_an_exception_in_one_case_does_not_zero_the_others():
    class OnlySquare(make_solution()):
        def visualize_curvature(self, curvature_mode, color_map):
            if self.degree[0] != self.degree[1]:
                raise IndexError("index 3 is out of bounds for axis 0 with size 3")
            super().visualize_curvature(curvature_mode, color_map)

    rep = check.visualize_curvature(OnlySquare, graded=True, seed=5)
    statuses = {c.status for c in rep.cases}
    assert statuses == {"passed", "error"} and 0 < rep.score < 1
    assert "m and n are swapped" in str(rep)  # the IndexError on non-square patches is named
    for case in rep.cases:  # every failing case is listed, with its status
        assert (f"✘ {case.name}  (error)" if case.status == "error" else f"✔ {case.name}") in str(rep)


def test_every_blocked_name_is_a_function_of_the_library():
    """A renamed library function must not silently drop out of a task's blocked list (or break every check)."""
    from lab.teaching.self_check import resolve
    from lab.teaching.tasks import TASKS

    for task in TASKS.values():
        for name in task.blocked:
            assert callable(resolve(name)) or isinstance(resolve(name), property), name


def _all_finite(value):
    if isinstance(value, dict):
        return all(_all_finite(v) for v in value.values())
    return bool(np.all(np.isfinite(np.asarray(value, dtype=float))))


@pytest.mark.parametrize("name", sorted(set(check.TASKS) - {"visualize_curvature"}))
def test_every_case_of_a_seed_sweep_has_a_finite_exact_answer(name):
    """Random cases are valid input: CI once drew an indefinite first fundamental form (EG − F² = 0)."""
    task = check.TASKS[name]
    for seed in range(60):
        for graded in (False, True):
            for case in task.make_cases(np.random.default_rng(seed), graded):
                assert _all_finite(task.expected(case)), (seed, graded, case.name)


# -- the check's own options, and what student code may raise or return (issue 19) -------------------------------

@pytest.mark.parametrize("timeout", [-1, 0, float("nan"), float("inf"), "10", True])
def test_bad_check_options_are_the_callers_mistake(timeout):
    with pytest.raises(ValueError, match="timeout must be a positive number of seconds"):
        check.warmup(lambda k1, k2: (k1 + k2) / 2, timeout=timeout)
    with pytest.raises(ValueError, match="seed must be a non-negative integer; got -3"):
        check.warmup(lambda k1, k2: (k1 + k2) / 2, seed=-3)


def test_exit_and_keyboard_interrupt_in_student_code_do_not_escape():
    import sys

    def leaves(k1, k2):
        sys.exit(3)

    report = check.warmup(leaves)
    assert report.status == "error" and "SystemExit: 3" in report.cases[0].got

    def interrupted(k1, k2):
        raise KeyboardInterrupt

    report = check.warmup(interrupted)
    assert report.status == "timeout" and "KeyboardInterrupt" in report.cases[0].got
    assert [c.status for c in report.cases[1:]] == ["not run"] * (len(report.cases) - 1)


@pytest.mark.parametrize("value, shown", [
    ("0.5", "text '0.5', not a number"),
    (None, "None (did the function forget to return its result?)"),
    (True, "True/False, not a number"),
    (1 + 2j, "complex numbers (1+2j)"),
])
def test_results_of_the_wrong_kind_are_named(value, shown):
    report = check.f1(lambda x: value)
    assert report.status == "failed" and report.score == 0
    assert shown in report.cases[0].got, report.cases[0].got
