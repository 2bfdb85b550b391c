"""In-notebook checks with hints: one call per task, e.g. ``check.visualize_curvature(MyBezierPatches)``.

Every check builds fresh random test cases (control nets with rational
coordinates, so the ground truth is computed exactly with sympy and no answer
can be hard-coded), runs the student's code under a time limit and with the
library's reference implementations blocked, and returns a :class:`Report`:
which cases passed, and for the first failing case what was expected, what
came out and a hint.  Hints come from comparing the output with deliberately
wrong variants of the computation (degree factors missing, m and n swapped,
unnormalised normal, H without ½, corners in the wrong order, ...).

``graded=True`` (used by :mod:`lab.grading`) adds further cases.
"""

import contextlib
import html
import inspect
import linecache
import math
import os
import signal
import sys
import threading
import traceback
from dataclasses import asdict, dataclass, field
from fractions import Fraction

import numpy as np
import sympy as sp

from . import analytic, bezier, colormaps
from . import curvature as _curv
from .patches import BezierPatches

__all__ = [
    "Report",
    "Case",
    "TASKS",
    "run",
    "warmup",
    "curve_curvature",
    "fundamental_forms",
    "curvatures",
    "derivative_nets",
    "corner_derivatives",
    "h",
    "f1",
    "f2",
    "f3",
    "visualize_curvature",
    "focal_points",
    "reflect",
    "christoffel",
    "start_velocity",
]

#: Seconds a student function may run in one check before it is stopped.
DEFAULT_TIMEOUT = 20.0

_LAB_DIR = os.path.dirname(os.path.abspath(__file__))


# -- reports ----------------------------------------------------------------------


@dataclass
class Case:
    """One test case of a check."""

    name: str
    passed: bool
    expected: str = ""
    got: str = ""
    hint: str = ""


@dataclass
class Report:
    """The result of one check: status, cases, and for the first failure what was expected and a hint."""

    task: str
    status: str  # "passed", "failed", "not implemented", "error", "timeout", "delegated"
    cases: list = field(default_factory=list)
    message: str = ""
    graded: bool = False

    @property
    def passed(self):
        return self.status == "passed"

    @property
    def score(self):
        """Fraction of passed cases (0 unless the code ran)."""
        if not self.cases or self.status in ("not implemented", "error", "timeout", "delegated"):
            return 0.0
        return sum(c.passed for c in self.cases) / len(self.cases)

    def to_dict(self):
        d = asdict(self)
        for c in d["cases"]:
            c["passed"] = bool(c["passed"])
        d["score"] = self.score
        d["passed"] = self.passed
        return d

    def lines(self):
        head = {
            "passed": "✔ {task}: all {n} cases passed.",
            "failed": "✘ {task}: {k} of {n} cases passed.",
            "not implemented": "… {task}: not implemented yet.",
            "error": "✘ {task}: your code raised an error.",
            "timeout": "✘ {task}: stopped, it ran too long.",
            "delegated": "✘ {task}: uses the library's reference implementation.",
        }[self.status]
        n, k = len(self.cases), sum(c.passed for c in self.cases)
        out = [head.format(task=self.task, n=n, k=k)]
        if self.message:
            out.append("  " + self.message.replace("\n", "\n  "))
        for c in self.cases:
            out.append(f"  {'✔' if c.passed else '✘'} {c.name}")
        failed = [c for c in self.cases if not c.passed]
        if failed:
            c = failed[0]
            out.append(f"First failing case: {c.name}")
            if c.expected:
                out.append(f"  expected: {c.expected}")
            if c.got:
                out.append(f"  got:      {c.got}")
            if c.hint:
                out.append(f"  hint:     {c.hint}")
        if self.passed and not self.graded:
            out.append("Public checks passed; the graded run adds more cases.")
        return out

    def __str__(self):
        return "\n".join(self.lines())

    def __repr__(self):
        return str(self)

    def _repr_html_(self):
        colour = "#1a7f37" if self.passed else ("#9a6700" if self.status == "not implemented" else "#cf222e")
        body = html.escape("\n".join(self.lines()))
        return f'<pre style="border-left:4px solid {colour};padding:0.4em 0.8em;white-space:pre-wrap">{body}</pre>'


class _Stop(Exception):
    """Ends a check early with a status and message."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status
        self.message = message


class _TimeUp(BaseException):
    """Raised inside student code when the time limit is reached (BaseException: `except Exception` cannot hide it)."""


# -- running student code safely --------------------------------------------------


@contextlib.contextmanager
def _time_limit(seconds):
    """Interrupt the block after ``seconds`` (main thread only; elsewhere no limit is enforced)."""
    if threading.current_thread() is not threading.main_thread() or seconds is None:
        yield
        return

    def handler(signum, frame):
        raise _TimeUp()

    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


_used_reference = []


def _record(name):
    """Called by blocked reference functions (see :func:`_blocked`)."""
    _used_reference.append(name)


def _stub_code(name):
    # Only builtins are available in the stub (it runs with the blocked function's globals).
    src = (
        "def _stub(*args, **kwargs):\n"
        f"    __import__('lab.check', fromlist=['_record'])._record({name!r})\n"
        f"    raise RuntimeError('lab reference implementation {name} is blocked during this check')\n"
    )
    ns = {}
    exec(compile(src, "<lab.check>", "exec"), ns)
    return ns["_stub"].__code__


def _function(obj):
    return getattr(obj, "__func__", obj)


@contextlib.contextmanager
def _blocked(functions):
    """Make library functions raise (and record their use) while the block runs.

    The functions' code objects are swapped, so every reference to them is
    caught, also ``super().visualize_curvature()`` and names imported earlier.
    """
    saved = []
    for name, obj in functions.items():
        func = _function(obj)
        if getattr(func, "__code__", None) is None or func.__closure__:
            continue
        saved.append((func, func.__code__))
        func.__code__ = _stub_code(name)
    del _used_reference[:]
    try:
        yield
    finally:
        for func, code in saved:
            func.__code__ = code


def _student_location(exc, student_files):
    """'line N: source' of the deepest traceback frame in the student's code, if any."""
    tb = traceback.extract_tb(exc.__traceback__)
    frames = [f for f in tb if f.filename in student_files] or [
        f for f in tb if not f.filename.startswith(_LAB_DIR) and "site-packages" not in f.filename
        and not f.filename.startswith(sys.prefix) and f.filename != __file__
    ]
    if not frames:
        return ""
    f = frames[-1]
    line = f.line or linecache.getline(f.filename, f.lineno).strip()
    return f"in your code, line {f.lineno}: {line}"


def _files_of(obj):
    files = set()
    for member in [obj] + [v for v in vars(obj).values()] if inspect.isclass(obj) else [obj]:
        code = getattr(_function(member), "__code__", None)
        if code is not None:
            files.add(code.co_filename)
    return files


def _call(task, student, func, args=(), kwargs=None, *, timeout=DEFAULT_TIMEOUT, blocked=None):
    """Run student code; turn NotImplementedError, exceptions, time-outs and delegation into :class:`_Stop`."""
    kwargs = kwargs or {}
    try:
        with _blocked(blocked or {}), _time_limit(timeout):
            result = func(*args, **kwargs)
    except _TimeUp:
        raise _Stop("timeout", f"{task} was stopped after {timeout:g} s. Is there an endless loop?") from None
    except NotImplementedError as exc:
        raise _Stop("not implemented", str(exc) or f"{task} is not implemented yet.") from None
    except Exception as exc:
        if _used_reference:
            raise _Stop("delegated", _delegation_message(task)) from None
        where = _student_location(exc, _files_of(student))
        msg = f"{type(exc).__name__}: {exc}"
        raise _Stop("error", msg + (f"\n{where}" if where else "")) from None
    if _used_reference:
        raise _Stop("delegated", _delegation_message(task))
    return result


def _delegation_message(task):
    used = ", ".join(sorted(set(_used_reference)))
    allowed = ALLOWED_HELPERS.get(task)
    msg = (
        f"Your {task} calls the library's own implementation ({used}). "
        "Write the computation yourself"
    )
    return msg + (f"; allowed helpers: {allowed}." if allowed else ".")


# -- exact references -------------------------------------------------------------


def _rand_net(rng, m, n, kind="random"):
    """A control net with rational coordinates; kinds: random, level (z = 0), flat (tilted plane), umbilic (paraboloid vertex at the (0,0) corner)."""
    if kind == "level":
        # the plane z = 0: curvature exactly 0 everywhere, so all values are equal
        P = analytic.random_rational_net(rng, m, n)
        P[..., 2] = 0.0
        return P
    if kind == "flat":
        # a tilted plane z = a x + b y with dyadic a, b: exactly planar in binary, but rounding
        # in N makes the computed K and H tiny non-zero noise (as on real flat regions)
        P = analytic.random_rational_net(rng, m, n)
        a, b = rng.integers(1, 8, 2) / 8
        P[..., 2] = a * P[..., 0] + b * P[..., 1]
        return P
    if kind == "umbilic":
        # z = c (x^2 + y^2) over [0, s]^2 (needs m, n >= 2), umbilic at the corner (0, 0), turned about
        # the z axis by a rational rotation (3/5, 4/5): the same paraboloid, but the coordinates round,
        # and the net is chosen so that the textbook formula computes H^2 - K < 0 at that corner.
        i, j = np.arange(m + 1), np.arange(n + 1)
        for _ in range(200):
            s = float(rng.integers(1, 4))
            c = int(rng.integers(1, 5)) / 4
            ca, sa = [(0.6, 0.8), (0.8, 0.6), (5 / 13, 12 / 13), (12 / 13, 5 / 13)][int(rng.integers(4))]
            # Bernstein coefficients: x = s u -> s i / m; x^2 -> s^2 i (i - 1) / (m (m - 1)); sums add up.
            X, Y = np.meshgrid(s * i / m, s * j / n, indexing="ij")
            Z = c * s * s * ((i * (i - 1) / (m * (m - 1)))[:, None] + (j * (j - 1) / (n * (n - 1)))[None, :])
            P = np.stack([ca * X - sa * Y, sa * X + ca * Y, Z], axis=-1)
            d = _variant_corner_derivatives(P)
            if _naive_discriminant(d)[0, 0] < 0:
                break
        return P
    return analytic.random_rational_net(rng, m, n)


def _exact_corners(nets):
    """Exact K, H, k1, k2 at the corners of every net: dict of arrays (N, 2, 2)."""
    out = {k: np.zeros((len(nets), 2, 2)) for k in ("K", "H", "k1", "k2")}
    for p, P in enumerate(nets):
        for (a, b), c in analytic.bezier_corner_curvature_exact(P).items():
            c = analytic.to_float(c)
            for k in out:
                out[k][p, a, b] = getattr(c, k)
    return out


MODE_FIELD = {"gaussian": "K", "mean": "H", "k1": "k1", "k2": "k2"}


def _expected_colors(values, cmap):
    """Colours the practical's maps give to exact ``values`` (f3 with exact zeros)."""
    if cmap == "linear":
        return colormaps.h(colormaps.f2(values, rtol=0))
    if cmap == "cut":
        return colormaps.h(colormaps.f1(values))
    return colormaps.h(colormaps.f3(values, tol=0))


# -- wrong variants for hints -----------------------------------------------------


def _variant_nets(P, variant=None):
    """Derivative nets (bu, bv, buu, buv, bvv) by forward differences, with a deliberate mistake (or none)."""
    m, n = P.shape[0] - 1, P.shape[1] - 1
    fu1, fu2, fv1, fv2, fuv = m, m * (m - 1), n, n * (n - 1), m * n
    if variant == "no_factors":
        fu1 = fu2 = fv1 = fv2 = fuv = 1
    elif variant == "second_factor":
        fu2, fv2 = m, n
    elif variant == "swapped_degrees":
        fu1, fu2, fv1, fv2, fuv = n, n * (n - 1), m, m * (m - 1), n * m
    return {
        "bu": fu1 * np.diff(P, axis=0),
        "bv": fv1 * np.diff(P, axis=1),
        "buu": fu2 * np.diff(P, 2, axis=0),
        "buv": fuv * np.diff(np.diff(P, axis=0), axis=1),
        "bvv": fv2 * np.diff(P, 2, axis=1),
    }


def _variant_corner_derivatives(P, variant=None):
    """Corner derivatives (bu, bv, buu, buv, bvv), each (2, 2, 3), computed with a deliberate mistake."""
    return {k: D[[0, -1]][:, [0, -1]] for k, D in _variant_nets(P, variant).items()}


def _naive_discriminant(d):
    """H^2 - K at the corners computed with the textbook formulas, unclamped (may round below 0)."""
    c = _variant_curvature(d)
    return c["H"] * c["H"] - c["K"]


def _variant_curvature(d, variant=None):
    """K, H, k1, k2 from corner derivatives, with a deliberate mistake."""
    bu, bv = d["bu"], d["bv"]
    Q = np.cross(bu, bv)
    W = np.linalg.norm(Q, axis=-1)
    N = Q / (W[..., None] if variant != "unnormalised" else 1.0)
    if variant == "orientation":
        N = -N
    dot = lambda a, b: np.sum(a * b, axis=-1)  # noqa: E731
    E, F, G = dot(bu, bu), dot(bu, bv), dot(bv, bv)
    e, f, g = dot(N, d["buu"]), dot(N, d["buv"]), dot(N, d["bvv"])
    K = (e * g - f * f) / (E * G - F * F)
    H = (e * G - 2 * f * F + g * E) / (E * G - F * F)
    if variant != "no_half":
        H = 0.5 * H
    root = np.sqrt(np.maximum(H * H - K, 0))
    k1, k2 = H + root, H - root
    if variant == "principal_swapped":
        k1, k2 = k2, k1
    return {"K": K, "H": H, "k1": k1, "k2": k2}


VARIANT_HINTS = {
    "corner_order": "set_curvature(c00, c01, c10, c11) and set_colors(...) take c01 = the value at u = 0, v = 1; "
    "your corners are in another order (c01 and c10 exchanged).",
    "no_factors": "the derivative nets need the degree factors: b_u = m Δ^{1,0} b, b_uu = m(m-1) Δ^{1,0}Δ^{1,0} b, "
    "b_uv = mn Δ^{1,0}Δ^{0,1} b (practical section 3).",
    "second_factor": "the second derivatives need m(m-1) and n(n-1), not m and n (practical section 3).",
    "swapped_degrees": "m and n are swapped: m is the degree along u (first index of the control net), n along v. "
    "It only shows on non-square patches.",
    "unnormalised": "e, f, g need the unit normal N = b_u × b_v / |b_u × b_v|; you used the cross product without "
    "dividing by its length.",
    "orientation": "the normal is N = b_u × b_v / |b_u × b_v| (practical 2.2); you used the opposite orientation, "
    "so H, κ1 and κ2 have the wrong sign.",
    "no_half": "H = ½ (eG − 2fF + gE) / (EG − F²): the factor ½ is missing (practical eq. 4).",
    "principal_swapped": "κ1 = H + √(H² − K) is the larger principal curvature, κ2 = H − √(H² − K) the smaller.",
    "mode_ignored": "the values do not depend on curvature_mode: choose K, H, κ1 or κ2 according to it.",
}


def _diagnose_values(nets, mode, got, expected):
    """Name the classic mistake whose values match ``got``."""
    field_name = MODE_FIELD[mode]
    if np.any(np.isnan(got)):
        return (
            "some values are NaN. At umbilic points (κ1 = κ2, e.g. the vertex of a paraboloid) rounding makes "
            "H² − K slightly negative: use √(max(H² − K, 0))."
        )
    if _close(got, np.swapaxes(expected, 1, 2)):
        return VARIANT_HINTS["corner_order"]
    for variant in ("no_factors", "second_factor", "swapped_degrees"):
        vals = np.stack([_variant_curvature(_variant_corner_derivatives(P, variant))[field_name] for P in nets])
        if _close(got, vals):
            return VARIANT_HINTS[variant]
    for variant in ("unnormalised", "orientation", "no_half", "principal_swapped"):
        vals = np.stack([_variant_curvature(_variant_corner_derivatives(P), variant)[field_name] for P in nets])
        if _close(got, vals):
            return VARIANT_HINTS[variant]
    for other in MODE_FIELD.values():
        if other != field_name:
            vals = np.stack([_variant_curvature(_variant_corner_derivatives(P))[other] for P in nets])
            if _close(got, vals):
                return VARIANT_HINTS["mode_ignored"] + f" (you stored {other}, expected {field_name})"
    return "compare your formulas with practical eqs. (3), (4) and section 3."


def _close(a, b, rtol=1e-7):
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if a.shape != b.shape or np.any(np.isnan(a)) or np.any(np.isnan(b)):
        return False
    scale = max(1.0, float(np.max(np.abs(b)))) if b.size else 1.0
    return bool(np.all(np.abs(a - b) <= rtol * scale))


def _fmt(x, digits=6):
    arr = np.asarray(x, dtype=float)
    return np.array2string(arr, precision=digits, suppress_small=False, max_line_width=100, threshold=12)


# -- the tasks --------------------------------------------------------------------

# Reference functions blocked while each task's student code runs.
_COMMON_BLOCK = {
    "lab.analytic.curvature_from_derivatives": analytic.curvature_from_derivatives,
    "lab.analytic.bezier_curvature_exact": analytic.bezier_curvature_exact,
    "lab.analytic.bezier_derivatives_exact": analytic.bezier_derivatives_exact,
}
_CURVATURE_BLOCK = {
    **_COMMON_BLOCK,
    "lab.curvature.from_derivatives": _curv.from_derivatives,
    "lab.curvature.fundamental_forms": _curv.fundamental_forms,
    "lab.curvature.principal_curvatures": _curv.principal_curvatures,
    "lab.curvature.unit_normal": _curv.unit_normal,
}
_BEZIER_BLOCK = {
    "lab.bezier.derivative_net": bezier.derivative_net,
    "lab.bezier.derivatives": bezier.derivatives,
    "lab.bezier.corner_derivatives": bezier.corner_derivatives,
    "lab.bezier._corner_values": bezier._corner_values,
}
_COLOR_BLOCK = {
    "lab.colormaps.h": colormaps.h,
    "lab.colormaps.f1": colormaps.f1,
    "lab.colormaps.f2": colormaps.f2,
    "lab.colormaps.f3": colormaps.f3,
    "lab.colormaps.apply": colormaps.apply,
}


def _visualize_block():
    from . import patches as P
    from . import surface as S

    return {
        **_CURVATURE_BLOCK,
        **_BEZIER_BLOCK,
        "lab.colormaps.apply": colormaps.apply,
        "BezierPatches.visualize_curvature": P.BezierPatches.visualize_curvature,
        "BezierPatches.corner_curvature": P.BezierPatches.corner_curvature,
        "BezierPatches.curvature_at": P.BezierPatches.curvature_at,
        "BezierPatches.derivatives": P.BezierPatches.derivatives,
        "lab.patches.colors_for": P.colors_for,
        "lab.patches.curvature_values": P.curvature_values,
        "Surface.curvature": S.Surface.curvature,
        "Surface.derivatives": S.Surface.derivatives,
        "Surface.fundamental_forms": S.Surface.fundamental_forms,
    }


#: Helpers a task may call, named in the task text.
ALLOWED_HELPERS = {
    "visualize_curvature": "lab.colormaps.h, f1, f2, f3, numpy",
    "derivative_nets": "numpy (np.diff)",
    "corner_derivatives": "numpy",
    "fundamental_forms": "numpy (np.cross, np.dot, np.linalg.norm)",
    "curvatures": "math / numpy",
}


def _report(task, graded, cases_fn):
    """Run ``cases_fn`` (which yields Case objects) into a Report; _Stop ends it with its status."""
    cases = []
    try:
        for case in cases_fn():
            cases.append(case)
    except _Stop as stop:
        return Report(task, stop.status, cases, stop.message, graded)
    status = "passed" if cases and all(c.passed for c in cases) else "failed"
    return Report(task, status, cases, "", graded)


def _rng(seed):
    return np.random.default_rng(seed)


def warmup(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(k1, k2)`` returns the mean curvature (k1 + k2) / 2 (the start notebook's exercise)."""
    rng = _rng(seed)

    def cases():
        values = [(1.0, 1.0), (2.0, -2.0)] + [tuple(rng.integers(-20, 21, 2) / 4) for _ in range(4 if graded else 2)]
        for k1, k2 in values:
            got = _call("warmup", func, func, (k1, k2), timeout=timeout)
            exp = (k1 + k2) / 2
            ok = isinstance(got, (int, float, np.floating, np.integer)) and abs(float(got) - exp) <= 1e-12
            hint = ""
            if not ok and isinstance(got, (int, float)) and abs(got - (k1 + k2)) < 1e-12:
                hint = "the mean of two numbers is their sum divided by 2."
            elif not ok and isinstance(got, (int, float)) and abs(got - k1 * k2) < 1e-12:
                hint = "k1 * k2 is the Gaussian curvature K; the mean curvature is (k1 + k2) / 2."
            yield Case(f"H for k1 = {k1:g}, k2 = {k2:g}", ok, f"{exp:g}", repr(got), hint)

    return _report("warmup", graded, cases)


def curve_curvature(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(d1, d2)``: curvature κ = |c' × c''| / |c'|³ of a space curve from its first two derivatives."""
    rng = _rng(seed)
    t = sp.Symbol("t")

    def cases():
        r = Fraction(int(rng.integers(2, 9)), 2)
        w = int(rng.integers(2, 5))
        circle = sp.Matrix([r * sp.cos(w * t), r * sp.sin(w * t), 0])
        samples = [("circle of radius %s at speed %s" % (r, r * w), circle, sp.Rational(1, 3))]
        samples.append(("straight line", sp.Matrix([1 + 2 * t, 3 * t, -t]), sp.Rational(1, 2)))
        for k in range(3 if graded else 1):
            coeffs = rng.integers(-4, 5, size=(3, 4))
            c = sp.Matrix([sum(int(coeffs[i, j]) * t**j for j in range(4)) for i in range(3)])
            samples.append((f"random cubic space curve {k + 1}", c, sp.Rational(int(rng.integers(1, 8)), 8)))
        for name, c, t0 in samples:
            d1 = np.array([float(x) for x in c.diff(t).subs(t, t0)])
            d2 = np.array([float(x) for x in c.diff(t, 2).subs(t, t0)])
            cross = c.diff(t).cross(c.diff(t, 2)).subs(t, t0)
            speed = c.diff(t).subs(t, t0).norm()
            exact = float(sp.N(cross.norm() / speed**3, 30))
            got = _call("curve_curvature", func, func, (d1.copy(), d2.copy()), timeout=timeout)
            try:
                val = float(got)
            except (TypeError, ValueError):
                yield Case(name, False, f"a number ≈ {exact:.6g}", f"{got!r}", "return one number (a float).")
                continue
            ok = abs(val - exact) <= 1e-9 * max(1.0, abs(exact))
            hint = ""
            if not ok:
                s1 = float(np.linalg.norm(d1))
                cr = float(np.linalg.norm(np.cross(d1, d2)))
                if math.isclose(val, cr / s1**2, rel_tol=1e-9):
                    hint = "divide by |c'|³, not |c'|²: the curvature of a curve is |c' × c''| / |c'|³."
                elif math.isclose(val, float(np.linalg.norm(d2)), rel_tol=1e-9):
                    hint = "|c''| is the curvature only when the curve has unit speed; use |c' × c''| / |c'|³."
                elif math.isclose(val, cr, rel_tol=1e-9):
                    hint = "|c' × c''| must be divided by |c'|³."
            yield Case(name, ok, f"{exact:.10g}", f"{val:.10g}", hint)

    return _report("curve_curvature", graded, cases)


def _exact_forms(vectors):
    """Exact E, F, G, e, f, g (floats) from five sympy vectors."""
    bu, bv, buu, buv, bvv = vectors
    Q = bu.cross(bv)
    W = sp.sqrt(Q.dot(Q))
    N = Q / W
    vals = [bu.dot(bu), bu.dot(bv), bv.dot(bv), N.dot(buu), N.dot(buv), N.dot(bvv)]
    return np.array([float(sp.N(x, 30)) for x in vals])


def _random_vectors(rng):
    return [sp.Matrix([sp.Rational(int(x), 4) for x in rng.integers(-12, 13, size=3)]) for _ in range(5)]


def fundamental_forms(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(bu, bv, buu, buv, bvv)`` returns ``(E, F, G, e, f, g)`` (practical 2.5)."""
    rng = _rng(seed)
    names = ("E", "F", "G", "e", "f", "g")

    def cases():
        for k in range(6 if graded else 3):
            vecs = _random_vectors(rng)
            while vecs[0].cross(vecs[1]).norm() == 0:
                vecs = _random_vectors(rng)
            args = [np.array([float(x) for x in v]) for v in vecs]
            exact = _exact_forms(vecs)
            got = _call("fundamental_forms", func, func, [a.copy() for a in args], timeout=timeout)
            try:
                got = np.array([float(x) for x in got])
                assert got.shape == (6,)
            except (TypeError, ValueError, AssertionError):
                yield Case(f"random derivatives {k + 1}", False, "a tuple (E, F, G, e, f, g) of six numbers",
                           repr(got)[:200], "return the six numbers in the order E, F, G, e, f, g.")
                continue
            ok = _close(got, exact, rtol=1e-10)
            hint = ""
            if not ok:
                W = float(np.linalg.norm(np.cross(args[0], args[1])))
                if _close(got[:3], exact[:3]) and _close(got[3:], exact[3:] * W):
                    hint = VARIANT_HINTS["unnormalised"]
                elif _close(got[:3], exact[:3]) and _close(got[3:], -exact[3:]):
                    hint = VARIANT_HINTS["orientation"]
                elif not _close(got[:3], exact[:3]):
                    wrong = [names[i] for i in range(3) if not _close(got[i], exact[i])]
                    hint = f"{', '.join(wrong)} wrong: E = ⟨b_u, b_u⟩, F = ⟨b_u, b_v⟩, G = ⟨b_v, b_v⟩."
                else:
                    wrong = [names[i] for i in range(3, 6) if not _close(got[i], exact[i])]
                    hint = f"{', '.join(wrong)} wrong: e = ⟨N, b_uu⟩, f = ⟨N, b_uv⟩, g = ⟨N, b_vv⟩."
            yield Case(f"random derivatives {k + 1}", ok, _fmt(exact), _fmt(got), hint)

    return _report("fundamental_forms", graded, cases)


def _umbilic_forms(rng):
    """(E, F, G, e, f, g) of an umbilic (II = λ I) for which H² − K computes slightly negative in floats."""
    for _ in range(1000):
        E, G = rng.uniform(0.5, 3, 2)
        F = rng.uniform(-0.4, 0.4) * math.sqrt(E * G)
        lam = rng.uniform(0.2, 2)
        e, f, g = lam * E, lam * F, lam * G
        det = E * G - F * F
        K = (e * g - f * f) / det
        H = 0.5 * (e * G - 2 * f * F + g * E) / det
        if H * H - K < 0:
            return (E, F, G, e, f, g), lam
    raise RuntimeError("no umbilic case with negative rounding found")  # pragma: no cover


def curvatures(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(E, F, G, e, f, g)`` returns ``(K, H, k1, k2)`` with k1 >= k2 (practical eqs. 1–4)."""
    rng = _rng(seed)

    def exact_of(vals):
        E, F, G, e, f, g = (sp.Rational(x) for x in vals)
        det = E * G - F * F
        K = (e * g - f * f) / det
        H = (e * G - 2 * f * F + g * E) / (2 * det)
        root = sp.sqrt(H * H - K)
        return np.array([float(sp.N(x, 30)) for x in (K, H, H + root, H - root)])

    def cases():
        samples = []
        for k in range(4 if graded else 2):
            E, G = rng.integers(1, 12, 2) / 4
            F = rng.integers(-3, 4) / 8
            e, f, g = rng.integers(-12, 13, 3) / 4
            samples.append((f"random forms {k + 1}", (E, F, G, e, f, g)))
        samples.append(("umbilic point (κ1 = κ2, H² − K rounds below 0)", _umbilic_forms(rng)[0]))
        samples.append(("saddle (K < 0)", (1.0, 0.0, 1.0, 1.0, 0.0, -1.0)))
        for name, vals in samples:
            exact = exact_of(vals) if "umbilic" not in name else None
            if exact is None:
                E, F, G, e, f, g = vals
                lam = e / E
                exact = np.array([lam * lam, lam, lam, lam])
            got = _call("curvatures", func, func, vals, timeout=timeout)
            try:
                got = np.array([float(x) for x in got])
                assert got.shape == (4,)
            except (TypeError, ValueError, AssertionError):
                yield Case(name, False, "a tuple (K, H, k1, k2) of four numbers", repr(got)[:200],
                           "return the four numbers in the order K, H, k1, k2.")
                continue
            rtol = 1e-6 if "umbilic" in name else 1e-10  # at umbilics k1, k2 are only sqrt(eps)-accurate
            ok = _close(got, exact, rtol=rtol)
            hint = ""
            if not ok:
                if np.any(np.isnan(got)):
                    hint = ("NaN: at umbilic points H² − K is 0 in theory but slightly negative after rounding; "
                            "take √(max(H² − K, 0)).")
                elif _close(got[1], 2 * exact[1]):
                    hint = VARIANT_HINTS["no_half"]
                elif _close(got[1], -exact[1]):
                    hint = "H has the wrong sign: H = ½ (eG − 2fF + gE) / (EG − F²)."
                elif _close(got[2:], exact[2:][::-1]):
                    hint = VARIANT_HINTS["principal_swapped"]
                elif not _close(got[0], exact[0]):
                    hint = "K = (eg − f²) / (EG − F²) (practical eq. 3)."
            yield Case(name, ok, _fmt(exact), _fmt(got), hint)

    return _report("curvatures", graded, cases)


_NET_NAMES = ("bu", "bv", "buu", "buv", "bvv")


def derivative_nets(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(P)`` returns the Bézier nets of b_u, b_v, b_uu, b_uv, b_vv (practical section 3)."""
    rng = _rng(seed)

    def cases():
        degrees = [(3, 3), (2, 3), (3, 2)] + ([(4, 2), (2, 5), (5, 4)] if graded else [])
        for m, n in degrees:
            P = _rand_net(rng, m, n)
            exp = list(_variant_nets(P).values())
            got = _call("derivative_nets", func, func, (P.copy(),), timeout=timeout, blocked=_BEZIER_BLOCK)
            name = f"random {m}×{n} net"
            try:
                got = [np.asarray(x, dtype=float) for x in got]
                assert len(got) == 5
            except (TypeError, ValueError, AssertionError):
                yield Case(name, False, "five arrays (bu, bv, buu, buv, bvv)", repr(got)[:200],
                           "return a tuple of the five derivative nets in this order.")
                continue
            bad = [k for k, (g, e) in enumerate(zip(got, exp)) if not _close(g, e, rtol=1e-12)]
            if not bad:
                yield Case(name, True)
                continue
            k = bad[0]
            g, e = got[k], exp[k]
            hint = ""
            if g.shape != e.shape:
                hint = (f"the net of {_NET_NAMES[k]} of a degree ({m}, {n}) patch has shape {e.shape}: "
                        "Δ^{1,0} reduces the first index, Δ^{0,1} the second.")
                if g.shape == e.shape[1::-1] + e.shape[2:]:
                    hint += " Yours looks transposed."
            else:
                for variant in ("no_factors", "second_factor", "swapped_degrees"):
                    if _close(g, _variant_nets(P, variant)[_NET_NAMES[k]], rtol=1e-12):
                        hint = VARIANT_HINTS[variant]
                        break
            yield Case(name, False, f"{_NET_NAMES[k]} = {_fmt(e)}", f"{_NET_NAMES[k]} = {_fmt(g)}",
                       hint or f"{_NET_NAMES[k]} is wrong; compare with the formulas of practical section 3.")

    return _report("derivative_nets", graded, cases)


def corner_derivatives(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(P)`` returns b_u, b_v, b_uu, b_uv, b_vv at the four corners, each (2, 2, 3) indexed [a, b] for (u, v) = (a, b)."""
    rng = _rng(seed)

    def cases():
        degrees = [(3, 3), (2, 3), (3, 2)] + ([(4, 2), (2, 5)] if graded else [])
        for m, n in degrees:
            P = _rand_net(rng, m, n)
            exp = _variant_corner_derivatives(P)
            got = _call("corner_derivatives", func, func, (P.copy(),), timeout=timeout, blocked=_BEZIER_BLOCK)
            name = f"random {m}×{n} net"
            try:
                got = [np.asarray(x, dtype=float) for x in got]
                assert len(got) == 5
            except (TypeError, ValueError, AssertionError):
                yield Case(name, False, "five (2, 2, 3) arrays (bu, bv, buu, buv, bvv)", repr(got)[:200],
                           "return a tuple of five arrays, each indexed [a, b] for the corner (u, v) = (a, b).")
                continue
            bad = [k for k, key in enumerate(_NET_NAMES) if not _close(got[k], exp[key], rtol=1e-12)]
            if not bad:
                yield Case(name, True)
                continue
            k = bad[0]
            g, e = got[k], exp[_NET_NAMES[k]]
            hint = ""
            if g.shape != (2, 2, 3):
                hint = "each field must have shape (2, 2, 3): [a, b] is the corner (u, v) = (a, b)."
            elif _close(g, np.swapaxes(e, 0, 1), rtol=1e-12):
                hint = "corners mixed up: index [a, b] is (u, v) = (a, b); [0, 1] is u = 0, v = 1."
            else:
                for variant in ("no_factors", "second_factor", "swapped_degrees"):
                    if _close(g, _variant_corner_derivatives(P, variant)[_NET_NAMES[k]], rtol=1e-12):
                        hint = VARIANT_HINTS[variant]
                        break
            yield Case(name, False, f"{_NET_NAMES[k]} = {_fmt(e)}", f"{_NET_NAMES[k]} = {_fmt(g)}",
                       hint or "the value at a corner is the corner point of the derivative net (practical fig. 3).")

    return _report("corner_derivatives", graded, cases)


def _numeric_task(task, func, samples, expected_fn, diagnose, *, graded, timeout, shape_text, blocked=None):
    """Run ``func(*args)`` for every ``(name, args)`` and compare with ``expected_fn(*args)`` (rtol 1e-9)."""

    def cases():
        for name, args in samples:
            exp = np.asarray(expected_fn(*args), dtype=float)
            got = _call(task, func, func, tuple(np.array(a, copy=True) if isinstance(a, np.ndarray) else a
                                                for a in args), timeout=timeout, blocked=blocked)
            try:
                val = np.asarray(got, dtype=float)
                assert val.shape == exp.shape
            except (TypeError, ValueError, AssertionError):
                yield Case(name, False, shape_text, repr(got)[:200], f"return {shape_text}.")
                continue
            ok = bool(np.all(np.isfinite(val))) and _close(val, exp, rtol=1e-9)
            yield Case(name, ok, _fmt(exp), _fmt(val), "" if ok else diagnose(args, val, exp))

    return _report(task, graded, cases)


def h(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check the colour ramp ``func(x)`` → (r, g, b) of practical section 4."""
    rng = _rng(seed)
    xs = [0.0, 0.25, 0.5, 0.75, 1.0] + list(np.round(rng.uniform(0, 1, 6 if graded else 3), 4))

    def hint(args, val, exp):
        x = args[0]
        if np.all(val == np.round(val)) and np.max(val) > 1:
            return "colours are (r, g, b) in [0, 1], not 0–255."
        piece = min(int(x * 4), 3)
        return f"check the piece for x in [{piece / 4:g}, {(piece + 1) / 4:g}]: " + [
            "(0, 4x, 1)", "(0, 1, 2 − 4x)", "(4x − 2, 1, 0)", "(1, 4 − 4x, 0)"][piece]

    return _numeric_task("h", func, [(f"h({x:g})", (float(x),)) for x in xs], lambda x: colormaps.h(x), hint,
                         graded=graded, timeout=timeout, shape_text="an (r, g, b) tuple", blocked=_COLOR_BLOCK)


def f1(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check the cut map ``func(x)`` (f1 of practical section 4)."""
    rng = _rng(seed)
    xs = [-2.0, 0.0, 0.3, 1.0, 7.5] + list(np.round(rng.uniform(-2, 3, 4 if graded else 2), 3))
    return _numeric_task("f1", func, [(f"f1({x:g})", (float(x),)) for x in xs], lambda x: min(max(x, 0.0), 1.0),
                         lambda a, v, e: "values below 0 give 0, above 1 give 1, others stay.",
                         graded=graded, timeout=timeout, shape_text="one number", blocked=_COLOR_BLOCK)


def f2(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check the linear map ``func(x, kmin, kmax)`` (f2), including kmin = kmax (→ 0.5)."""
    rng = _rng(seed)
    samples = [("f2(3, 1, 5)", (3.0, 1.0, 5.0)), ("f2(-2, -2, 6)", (-2.0, -2.0, 6.0)),
               ("all values equal: f2(0.7, 0.7, 0.7)", (0.7, 0.7, 0.7))]
    for _ in range(4 if graded else 1):
        lo, hi = sorted(rng.integers(-20, 20, 2) / 4)
        hi = hi + 1
        samples.append((f"f2(x, {lo:g}, {hi:g})", (float(rng.uniform(lo, hi)), float(lo), float(hi))))

    def expected(x, lo, hi):
        return 0.5 if hi == lo else (x - lo) / (hi - lo)

    def hint(args, val, exp):
        x, lo, hi = args
        if hi == lo:
            return ("when all curvature values are equal, κmax − κmin = 0 and the quotient is 0/0: "
                    "return 0.5 (green) in that case.")
        return "f2(x) = (x − κmin) / (κmax − κmin)."

    rep = _numeric_task("f2", func, samples, expected, hint, graded=graded, timeout=timeout, shape_text="one number",
                        blocked=_COLOR_BLOCK)
    if rep.status == "error" and "ZeroDivision" in rep.message:
        rep.message += ("\nhint: when all curvature values are equal, κmax − κmin = 0; return 0.5 (green) "
                        "in that case instead of dividing.")
    return rep


def f3(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check the classification map ``func(x)`` (f3), with rounding noise around 0 counted as 0."""
    samples = [("f3(-2)", (-2.0,)), ("f3(0)", (0.0,)), ("f3(0.5)", (0.5,)),
               ("rounding noise: f3(1e-17)", (1e-17,)), ("rounding noise: f3(-3e-16)", (-3e-16,))]
    if graded:
        samples += [("f3(-1e-3)", (-1e-3,)), ("f3(1e-4)", (1e-4,))]

    def expected(x):
        return 0.5 if abs(x) <= 1e-9 else (1.0 if x > 0 else 0.0)

    def hint(args, val, exp):
        if abs(args[0]) < 1e-12:
            return ("computed curvature is never exactly 0 (a cylinder gives K ≈ 1e-17): "
                    "compare |x| with a small tolerance, e.g. 1e-9, instead of x == 0.")
        return "f3 is 0 for negative, 0.5 for zero, 1 for positive values."

    return _numeric_task("f3", func, samples, expected, hint, graded=graded, timeout=timeout, shape_text="one number",
                         blocked=_COLOR_BLOCK)


def _visualize_cases(graded, rng):
    """(name, nets, refine, mode, cmap) of the visualize_curvature check."""
    B = BezierPatches
    cases = [
        ("one 3×3 patch, Gaussian curvature, linear map", [_rand_net(rng, 3, 3)], 0, B.CURVATURE_GAUSSIAN, B.COLOR_MAP_LINEAR),
        ("three 2×3 patches, mean curvature", [_rand_net(rng, 2, 3) for _ in range(3)], 0, B.CURVATURE_AVERAGE, B.COLOR_MAP_LINEAR),
        ("two 3×2 patches, κ1 (max)", [_rand_net(rng, 3, 2) for _ in range(2)], 0, B.CURVATURE_PRINCIPAL_MAX, B.COLOR_MAP_LINEAR),
        ("two 2×3 patches refined once, κ2 (min)", [_rand_net(rng, 2, 3) for _ in range(2)], 1, B.CURVATURE_PRINCIPAL_MIN, B.COLOR_MAP_LINEAR),
        ("two 3×2 patches, Gaussian curvature, cut map", [_rand_net(rng, 3, 2) for _ in range(2)], 0, B.CURVATURE_GAUSSIAN, B.COLOR_MAP_CUT),
        ("two 2×3 patches, classification map", [_rand_net(rng, 2, 3) for _ in range(2)], 0, B.CURVATURE_GAUSSIAN, B.COLOR_MAP_CLASSIFICATION),
        ("umbilic corners (paraboloid vertices), κ1", [_rand_net(rng, 2, 3, "umbilic") for _ in range(6)], 0, B.CURVATURE_PRINCIPAL_MAX, B.COLOR_MAP_LINEAR),
        ("plane z = 0, linear map (all values equal)", [_rand_net(rng, 2, 2, "level")], 0, B.CURVATURE_GAUSSIAN, B.COLOR_MAP_LINEAR),
        ("tilted flat patch refined once, classification map", [_rand_net(rng, 3, 2, "flat")], 1, B.CURVATURE_GAUSSIAN, B.COLOR_MAP_CLASSIFICATION),
    ]
    if graded:
        cases += [
            ("three 2×4 patches refined twice, mean curvature", [_rand_net(rng, 2, 4) for _ in range(3)], 2, B.CURVATURE_AVERAGE, B.COLOR_MAP_LINEAR),
            ("two 4×2 patches, κ2, classification map", [_rand_net(rng, 4, 2) for _ in range(2)], 0, B.CURVATURE_PRINCIPAL_MIN, B.COLOR_MAP_CLASSIFICATION),
            ("umbilic corner refined once, Gaussian curvature, cut map", [_rand_net(rng, 3, 3, "umbilic")], 1, B.CURVATURE_GAUSSIAN, B.COLOR_MAP_CUT),
            ("four 3×3 patches, κ1, cut map", [_rand_net(rng, 3, 3) for _ in range(4)], 0, B.CURVATURE_PRINCIPAL_MAX, B.COLOR_MAP_CUT),
        ]
    return cases


def visualize_curvature(cls, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check a :class:`lab.BezierPatches` subclass whose ``visualize_curvature`` the student wrote (practical 5.1).

    For every case: the class is built from random rational nets (optionally
    refined), ``visualize_curvature(mode, color_map)`` is called, and the
    values stored with ``set_curvature`` and the colours stored with
    ``set_colors`` are compared with sympy-exact curvature and the practical's
    colour maps.
    """
    rng = _rng(seed)
    if not (inspect.isclass(cls) and issubclass(cls, BezierPatches)):
        return Report("visualize_curvature", "error", [], f"expected a subclass of lab.BezierPatches; got {cls!r}", graded)
    if cls.visualize_curvature is BezierPatches.visualize_curvature:
        return Report("visualize_curvature", "delegated", [],
                      "your class does not define visualize_curvature: it still uses the library's.", graded)
    blocked = _visualize_block()

    def cases():
        for name, nets, depth, mode, cmap in _visualize_cases(graded, rng):
            nets = np.array(nets)
            patches = cls(nets.copy())
            patches.refine(depth)
            refined = patches.control_points.copy()
            exact = _exact_corners(refined)
            values = exact[MODE_FIELD[mode.value]]
            colours = _expected_colors(values, cmap.value)
            try:
                _call("visualize_curvature", cls, patches.visualize_curvature, (mode, cmap), timeout=timeout,
                      blocked=blocked)
            except _Stop as stop:
                if stop.status == "error":
                    stop.message = f"{stop.message}\n(in the case: {name})" + _error_hint(stop.message, values)
                raise
            got_v, got_c = patches.curvature, patches.colors
            missing = np.isnan(got_v).all(axis=(1, 2))
            if np.any(missing) and not np.isnan(values).any():
                k = int(np.argmax(missing))
                yield Case(name, False, "set_curvature called for every patch",
                           f"patch {k} (of {len(patches)}) has no curvature values",
                           "call patch.set_curvature(c00, c01, c10, c11) for every patch of the collection.")
                continue
            tol_scale = max(1.0, float(np.max(np.abs(values))))
            # at umbilics κ1, κ2 = H ± √(H² − K) are only accurate to √eps relative
            rtol = 1e-7 if mode.value in ("k1", "k2") else 1e-8
            if not (got_v.shape == values.shape and np.all(np.abs(got_v - values) <= rtol * tol_scale)):
                yield Case(name, False, f"{mode.value} at the corners: {_fmt(values)}", _fmt(got_v),
                           _diagnose_values(refined, mode.value, got_v, values))
                continue
            if np.isnan(got_c).all(axis=(1, 2, 3)).any():
                yield Case(name, False, "set_colors called for every patch", "some patches have no colours",
                           "call patch.set_colors(c00, c01, c10, c11) with (r, g, b) tuples for every patch.")
                continue
            if np.all(np.abs(got_c - colours) <= 1e-6):
                yield Case(name, True)
                continue
            yield Case(name, False, f"colours {_fmt(colours, 3)}", _fmt(got_c, 3),
                       _diagnose_colors(values, got_c, cmap.value, len(patches)))

    return _report("visualize_curvature", graded, cases)


def _error_hint(message, values):
    """A hint for an exception in visualize_curvature, from its message and the case's values."""
    if "math domain error" in message or ("NaN" in message and np.ptp(values) > 0):
        return ("\nhint: at umbilic points (κ1 = κ2) rounding makes H² − K slightly negative, and the square "
                "root fails: use √(max(H² − K, 0)).")
    if "ZeroDivision" in message or ("NaN" in message and np.ptp(values) == 0):
        return ("\nhint: all curvature values are equal here, so κmax − κmin = 0: f2 must not divide by zero "
                "(give 0.5, green, in that case).")
    return ""


def _diagnose_colors(values, got, cmap, n_patches):
    if np.any(np.isnan(got)):
        if cmap == "linear" and np.ptp(values) == 0:
            return ("all curvature values are equal, so κmax − κmin = 0: f2 must not divide by zero "
                    "(give 0.5, green, in that case).")
        return "some colours are NaN."
    if _close(got, np.swapaxes(_expected_colors(values, cmap), 1, 2), rtol=1e-6):
        return VARIANT_HINTS["corner_order"]
    if cmap == "linear":
        per_patch = np.stack([colormaps.h(colormaps.f2(v, rtol=0)) for v in values])
        if _close(got, per_patch, rtol=1e-6):
            return "κmin and κmax are the minimum and maximum over the corners of ALL patches, not per patch."
    if cmap == "classification":
        noisy = np.abs(values) == 0
        if np.any(noisy):
            return ("at K = 0 (flat or parabolic points) the computed values are rounding noise like 1e-17: "
                    "f3 must compare with a tolerance, not with == 0.")
    for other in ("linear", "cut", "classification"):
        if other != cmap and _close(got, _expected_colors(values, other), rtol=1e-6):
            return f"these are the colours of the {other} map; use the colour map given by color_map."
    return "apply the colour map to the curvature values, then h (practical section 4)."


#: The tasks the autograder knows: name -> check function.
TASKS = {
    "warmup": warmup,
    "curve_curvature": curve_curvature,
    "fundamental_forms": fundamental_forms,
    "curvatures": curvatures,
    "derivative_nets": derivative_nets,
    "corner_derivatives": corner_derivatives,
    "h": h,
    "f1": f1,
    "f2": f2,
    "f3": f3,
    "visualize_curvature": visualize_curvature,
}


# -- the interrogation tasks (notebooks 06-08) ------------------------------------------------------


def _unit(v):
    return v / np.linalg.norm(v)


def focal_points(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(X, N, k1, k2)`` returns the points ``X + N/k1`` and ``X + N/k2`` of the classical focal sheets."""
    rng = _rng(seed)
    samples = []
    for k in range(5 if graded else 3):
        X = rng.integers(-8, 9, 3) / 4
        N = _unit(rng.normal(size=3))
        k1, k2 = sorted(rng.choice([-2, -1, -0.5, 0.25, 0.5, 1.0, 2.0, 4.0], 2, replace=False))[::-1]
        samples.append((f"random point {k + 1} (k1 = {k1:g}, k2 = {k2:g})", (X, N, float(k1), float(k2))))
    samples.append(("sphere of radius 2, outward normal (k1 = k2 = -1/2)", (np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 1.0]), -0.5, -0.5)))

    def expected(X, N, k1, k2):
        return np.stack([X + N / k1, X + N / k2])

    def diagnose(args, val, exp):
        X, N, k1, k2 = args
        if _close(val, np.stack([X + k1 * N, X + k2 * N])):
            return "the focal point lies at the radius of curvature 1/κ along N: F = X + N/κ, not X + κN."
        if _close(val, np.stack([X - N / k1, X - N / k2])):
            return "the sign: F = X + N/κ with the practical's N; a negative κ puts F on the −N side by itself."
        if _close(val[::-1], exp):
            return "return the sheets in the order (X + N/κ1, X + N/κ2)."
        return "F_i = X + N / κ_i (seeds/002, section 4)."

    return _numeric_task("focal_points", func, samples, expected, diagnose, graded=graded, timeout=timeout,
                         shape_text="two points (F1, F2), an array of shape (2, 3)")


def reflect(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(v, N)``: the view vector ``v`` reflected about the unit normal ``N``, R = v − 2 (v·N) N."""
    rng = _rng(seed)
    samples = [("straight down onto a horizontal plane", (np.array([0.0, 0.0, -1.0]), np.array([0.0, 0.0, 1.0]))),
               ("at 45 degrees", (_unit(np.array([1.0, 0.0, -1.0])), np.array([0.0, 0.0, 1.0])))]
    for k in range(4 if graded else 2):
        samples.append((f"random view and normal {k + 1}", (_unit(rng.normal(size=3)), _unit(rng.normal(size=3)))))

    def expected(v, N):
        return v - 2 * np.dot(v, N) * N

    def diagnose(args, val, exp):
        v, N = args
        if _close(val, v + 2 * np.dot(v, N) * N):
            return "the sign: R = v − 2 (v·N) N; the part along N changes its sign, the tangential part stays."
        if _close(val, v - np.dot(v, N) * N):
            return "that is the projection onto the tangent plane: the factor 2 is missing."
        if _close(val, -exp):
            return "R points away from the surface: R = v − 2 (v·N) N, not its negative."
        return "R = v − 2 (v·N) N (seeds/002, section 3)."

    return _numeric_task("reflect", func, samples, expected, diagnose, graded=graded, timeout=timeout,
                         shape_text="a 3-vector")


def _random_first_form(rng):
    while True:
        E, G = rng.integers(1, 16, 2) / 4
        F = rng.integers(-6, 7) / 8
        if E * G - F * F > 0.1:
            return float(E), float(F), float(G)


def christoffel(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(E, F, G, Eu, Ev, Fu, Fv, Gu, Gv)`` returns (Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂)."""
    rng = _rng(seed)
    samples = []
    for k in range(5 if graded else 3):
        E, F, G = _random_first_form(rng)
        derivs = tuple(float(x) for x in rng.integers(-12, 13, 6) / 4)
        samples.append((f"random first form {k + 1}", (E, F, G) + derivs))
    samples.append(("orthogonal parameters (F = 0)", (1.0, 0.0, 4.0, 0.0, 0.5, 0.0, 0.0, 2.0, 0.0)))

    def expected(E, F, G, Eu, Ev, Fu, Fv, Gu, Gv):
        D = 2 * (E * G - F * F)
        return np.array([
            (G * Eu - 2 * F * Fu + F * Ev) / D,
            (G * Ev - F * Gu) / D,
            (2 * G * Fv - G * Gu - F * Gv) / D,
            (2 * E * Fu - E * Ev - F * Eu) / D,
            (E * Gu - F * Ev) / D,
            (E * Gv - 2 * F * Fv + F * Gu) / D,
        ])

    def diagnose(args, val, exp):
        if _close(val, 2 * exp):
            return "the denominator is 2(EG − F²), not EG − F²."
        if _close(val, -exp):
            return "every symbol has the wrong sign; compare with the formulas in the notebook."
        if _close(val[[3, 4, 5, 0, 1, 2]], exp):
            return "Γ¹ and Γ² exchanged: return (Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂)."
        names = ("Γ¹₁₁", "Γ¹₁₂", "Γ¹₂₂", "Γ²₁₁", "Γ²₁₂", "Γ²₂₂")
        wrong = [names[i] for i in range(6) if not _close(val[i], exp[i])]
        return f"{', '.join(wrong)} wrong; compare with the formulas in the notebook (Struik, chapter 4)."

    return _numeric_task("christoffel", func, samples, expected, diagnose, graded=graded, timeout=timeout,
                         shape_text="six numbers (Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂)")


def start_velocity(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(xu, xv, alpha)`` returns (u'(0), v'(0)) of the unit direction at angle α from x_v (seeds/003 eqs. 9–16)."""
    rng = _rng(seed)
    samples = []
    for k in range(5 if graded else 3):
        xu, xv = rng.integers(-8, 9, (2, 3)) / 4
        while np.linalg.norm(np.cross(xu, xv)) < 0.2:
            xu, xv = rng.integers(-8, 9, (2, 3)) / 4
        alpha = float(rng.uniform(0, 2 * np.pi))
        samples.append((f"random tangent plane {k + 1}, α = {np.degrees(alpha):.0f}°", (xu, xv, alpha)))
    samples.append(("α = 0: along x_v", (np.array([1.0, 0.0, 0.0]), np.array([0.5, 2.0, 0.0]), 0.0)))
    samples.append(("α = 90°: along x_v⊥ = −G x_u + F x_v", (np.array([1.0, 0.0, 0.0]), np.array([0.5, 2.0, 0.0]), np.pi / 2)))

    def expected(xu, xv, alpha):
        E, F, G = xu @ xu, xu @ xv, xv @ xv
        perp = -G * xu + F * xv
        lv, lp = np.sqrt(G), np.linalg.norm(perp)
        return np.array([-np.sin(alpha) * G / lp, np.cos(alpha) / lv + F * np.sin(alpha) / lp])

    def diagnose(args, val, exp):
        xu, xv, alpha = args
        E, F, G = xu @ xu, xu @ xv, xv @ xv
        speed = E * val[0] ** 2 + 2 * F * val[0] * val[1] + G * val[1] ** 2
        if _close(val, exp[::-1]):
            return "u' and v' exchanged: return (u'(0), v'(0))."
        if _close(val, -exp):
            return "the direction is reversed: at α = 0 the path starts along +x_v."
        if not math.isclose(speed, 1.0, rel_tol=1e-6):
            return (f"the direction must have unit length on the surface: E u'² + 2F u'v' + G v'² = 1 "
                    f"(yours gives {speed:.4g}; eq. 14).")
        return "α is measured from x_v towards x_v⊥ = −G x_u + F x_v (eqs. 9, 10, 15)."

    return _numeric_task("start_velocity", func, samples, expected, diagnose, graded=graded, timeout=timeout,
                         shape_text="two numbers (u'(0), v'(0))")


TASKS.update({
    "focal_points": focal_points,
    "reflect": reflect,
    "christoffel": christoffel,
    "start_velocity": start_velocity,
})


def run(task, obj, **kwargs):
    """Run the check called ``task`` on ``obj``; never raises for problems in ``obj``."""
    if task not in TASKS:
        raise ValueError(f"unknown task {task!r}; expected one of {', '.join(TASKS)}")
    try:
        return TASKS[task](obj, **kwargs)
    except _Stop as stop:  # pragma: no cover - tasks convert their own stops
        return Report(task, stop.status, [], stop.message, kwargs.get("graded", False))
