"""Running student code inside a check: time limit, the library's reference implementations blocked, errors.

Used by the in-notebook checks (self-study): the student's code runs in the
student's own process, so these are conveniences, not protection; grading
runs submissions in a sandbox (:mod:`lab.teaching.grading`).
"""

import contextlib
import inspect
import linecache
import os
import signal
import sys
import threading
import traceback

import numpy as np

from ..geometry import analytic, bezier, colormaps
from ..geometry import curvature as _curv
from .report import Report, _Stop, _TimeUp

#: Seconds a student function may run in one check before it is stopped.
DEFAULT_TIMEOUT = 20.0

_LAB_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


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
        f"    __import__('lab.teaching.runner', fromlist=['_record'])._record({name!r})\n"
        f"    raise RuntimeError('lab reference implementation {name} is blocked during this check')\n"
    )
    ns = {}
    exec(compile(src, "<lab.teaching.runner>", "exec"), ns)
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
    from ..model import patches as P
    from ..model import surface as S

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
    "visualize_curvature": "lab.colormaps.h, f1, f2, f3, numpy, math",
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
