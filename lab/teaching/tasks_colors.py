"""Checks of the colour tasks (notebooks 04, 05): h, f1, f2, f3 and the practical's visualize_curvature."""

import inspect

import numpy as np

from ..geometry import colormaps
from ..model.patches import BezierPatches
from .hints import _close, _diagnose_colors, _diagnose_values, _error_hint, _fmt
from .references import MODE_FIELD, _exact_corners, _expected_colors, _rand_net
from .report import Case, Report, _Stop
from .runner import _COLOR_BLOCK, DEFAULT_TIMEOUT, _call, _report, _rng, _visualize_block

__all__ = ["h", "f1", "f2", "f3", "visualize_curvature"]


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
