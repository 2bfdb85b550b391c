"""How a check calls a student's code, and the plain numbers it takes back.

This module runs where the student's code runs: in the notebook's kernel for the in-notebook check, and
inside the grader's sandbox for a graded run.  It holds no reference solution and no expected value: it
builds the student's object from the inputs a case prescribes, calls it, and turns whatever comes back
into plain numbers (:func:`encode`), which the caller checks (:func:`decode` validates shape, type and
size before anything is compared).  Errors become a status and a message (:func:`outcome`).
"""

import contextlib
import linecache
import math
import os
import signal
import sys
import threading
import time
import traceback

import numpy as np

from ... import library
from ...i18n import _

__all__ = ["MARKER", "MAX_VALUES", "BadOutput", "TimeUp", "call", "decode", "decode_args", "encode", "encode_args",
           "outcome", "stub_source", "time_limit"]

#: Text of the error a withheld reference implementation raises (blocked in a check, removed when grading).
MARKER = "the library's reference implementation is not available here"
#: Largest number of values a student's result may have (a bigger one is refused, not read): the largest answer of a
#: graded case has 768 numbers (the colours of 64 patches), so this leaves room for any wrong shape worth a message.
MAX_VALUES = 20_000

_LAB_DIR = library()
_used = []  # names of withheld library functions called during the current case


def _record(name):
    """Called by a withheld library function (see :mod:`lab.teaching.self_check` and :mod:`lab.teaching.sandbox.bubblewrap`)."""
    _used.append(name)


def stub_source(name, indent=""):
    """Source of the body every withheld function gets: record the call, raise the marker error."""
    return (f"{indent}__import__('lab.teaching.kernel.protocol', fromlist=['_record'])._record({name!r})\n"
            f"{indent}raise RuntimeError({MARKER!r} + ': ' + {name!r})\n")


class BadOutput(Exception):
    """The student's result is not numbers of the kind the task asks for."""


class TimeUp(BaseException):
    """Raised in student code at the time limit (a BaseException, so ``except Exception`` does not hide it)."""


def time_limit(seconds):
    """A context manager that interrupts its block after ``seconds`` with :class:`TimeUp` (no limit for ``None``).

    The same on every platform: a student's endless loop stops with :class:`TimeUp` after ``seconds``.  Two ways,
    chosen by what the platform has (feature detection, so a test can take the signals away on Linux):

    * **SIGALRM** (Linux, macOS), in the main thread: a real-time timer (``setitimer``) whose handler raises
      :class:`TimeUp`.  A blocking system call (``time.sleep``, waiting for input) is interrupted at once.
    * **a watchdog thread** everywhere else (Windows, which has no SIGALRM; and any thread that is not the main
      thread, where no signal can go): one sleeping daemon thread per process that at the limit raises
      :class:`TimeUp` in the block's thread (``PyThreadState_SetAsyncExc``).  Python delivers such an exception
      only between two bytecodes, so a block stuck in one long call into C that waits (``time.sleep(100)``, a
      blocking read, ``input()``) stops only when that call returns, and then with the same message.  (A long
      computation in C, e.g. one huge numpy operation, is the same with SIGALRM: its handler, too, runs only once
      the call returns.)

    Both are cooperative: code that catches BaseException can ignore the stop, so the grader also enforces its
    limits from outside.  Without either (an interpreter with no ``ctypes.pythonapi``) the block runs unlimited.
    """
    if seconds is None:
        return contextlib.nullcontext()
    if threading.current_thread() is threading.main_thread() and _has_alarm():
        return _alarm(seconds)
    if _set_async_exc is not None:
        return _WatchdogLimit(seconds)
    return contextlib.nullcontext()


def _has_alarm():
    return all(hasattr(signal, name) for name in ("SIGALRM", "setitimer", "ITIMER_REAL"))


@contextlib.contextmanager
def _alarm(seconds):
    """The time limit by SIGALRM (main thread only)."""
    def handler(signum, frame):
        raise TimeUp()

    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def _async_exc_functions():
    """``PyThreadState_SetAsyncExc`` twice: to raise an exception class in a thread, and to clear one not yet raised
    (NULL, which a ``py_object`` argument cannot pass); ``(None, None)`` where the C API is not reachable (not
    CPython).  Own prototypes, so that nobody else's ``argtypes`` on ``ctypes.pythonapi`` changes these calls."""
    try:
        import ctypes

        api = ctypes.pythonapi
        raise_ = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_ulong, ctypes.py_object)(("PyThreadState_SetAsyncExc", api))
        clear = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_ulong, ctypes.c_void_p)(("PyThreadState_SetAsyncExc", api))
    except (ImportError, AttributeError, OSError):
        return None, None
    return raise_, clear


_set_async_exc, _clear_async_exc = _async_exc_functions()


class _Limit:
    """One armed limit: the thread to stop, when, and whether the watchdog has raised in it."""

    __slots__ = ("deadline", "fired", "thread_id")

    def __init__(self, thread_id, deadline):
        self.thread_id, self.deadline, self.fired = thread_id, deadline, False


class _Watchdog:
    """One daemon thread for the process that raises :class:`TimeUp` in each thread whose limit has passed.

    It sleeps until the earliest armed deadline and is woken only when a sooner one is armed, so a check's cases
    cost it nothing: arming and disarming a limit take a lock and touch a set, no thread is started or waited for.
    """

    def __init__(self):
        self._cond = threading.Condition(threading.Lock())
        self._limits = set()
        self._wake_at = math.inf  # the deadline the thread sleeps towards
        threading.Thread(target=self._run, name="lab time limit", daemon=True).start()

    def _run(self):
        with self._cond:
            while True:
                now = time.monotonic()
                for limit in [limit for limit in self._limits if limit.deadline <= now]:
                    self._limits.discard(limit)
                    limit.fired = True
                    if _set_async_exc(limit.thread_id, TimeUp) > 1:  # cannot happen for one live id; the API says undo
                        _clear_async_exc(limit.thread_id, None)
                self._wake_at = min((limit.deadline for limit in self._limits), default=math.inf)
                self._cond.wait(None if self._wake_at == math.inf else self._wake_at - now)

    def arm(self, seconds):
        limit = _Limit(threading.get_ident(), time.monotonic() + seconds)
        with self._cond:
            self._limits.add(limit)
            if limit.deadline < self._wake_at:
                self._cond.notify()
        return limit

    def disarm(self, limit):
        with self._cond:
            self._limits.discard(limit)  # from here on the watchdog raises nothing in this block's thread
        if limit.fired:
            _clear_async_exc(limit.thread_id, None)  # raised but not yet delivered: dropped


_watchdog = None
_watchdog_lock = threading.Lock()


def _the_watchdog():
    global _watchdog  # one watchdog thread per process, started on first use
    with _watchdog_lock:
        if _watchdog is None:
            _watchdog = _Watchdog()
        return _watchdog


def _forget_watchdog():
    global _watchdog, _watchdog_lock  # a forked child has no watchdog thread: it starts its own
    _watchdog, _watchdog_lock = None, threading.Lock()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_watchdog)


class _WatchdogLimit:
    """The time limit by the watchdog thread (see :func:`time_limit`), for the calling thread.

    The race between the limit and the block's end: the watchdog raises only while the limit is armed (under its
    lock), and the end clears an exception it raised that Python has not delivered yet, so nothing is raised after
    the block.  One that is delivered while the end is being handled is swallowed: the block's own result (a value
    or its exception) stands, as the block finished before the stop reached it.  Not meant to be nested in one
    thread (an inner block's end would also clear an outer limit's undelivered stop).
    """

    def __init__(self, seconds):
        self._seconds = seconds
        self._watchdog = self._limit = None

    def __enter__(self):
        self._watchdog = _the_watchdog()
        self._limit = self._watchdog.arm(self._seconds)
        return self

    def __exit__(self, *exc_info):
        while True:
            try:
                self._watchdog.disarm(self._limit)  # idempotent: repeated when a pending TimeUp interrupts it
                break
            except TimeUp:
                continue
        return False


# -- plain numbers ------------------------------------------------------------------------------


def _array(value):
    """A numeric array as plain numbers; strings, None, booleans, complex numbers and objects are refused."""
    if value is None:
        raise BadOutput(_("None (did the function forget to return its result?)"))
    if isinstance(value, (str, bytes)):
        raise BadOutput(_("text {text}, not a number").format(text=_short(value)))
    a = np.asarray(value)
    if a.dtype.kind == "b" or isinstance(value, bool):
        raise BadOutput(_("True/False, not a number"))
    if a.dtype.kind == "c":
        raise BadOutput(_("complex numbers {text}; the result must be real").format(text=_short(value)))
    if a.dtype.kind not in "iuf":
        raise TypeError(f"not numbers: {a.dtype}")
    a = a.astype(float)
    if a.size > MAX_VALUES:
        raise BadOutput(_("{n} values; at most {limit} are read").format(n=a.size, limit=MAX_VALUES))
    return {"shape": list(a.shape), "data": [float(x) for x in a.ravel()]}


def _short(value):
    text = repr(value)
    return text if len(text) <= 200 else text[:200] + " …"


def encode(value):
    """Plain, JSON-able numbers from a student's result: one array, or a short sequence of arrays.

    Raises :class:`BadOutput` with a short description of ``value`` when it is neither.
    """
    try:
        return {"kind": "array", **_array(value)}
    except (TypeError, ValueError, OverflowError):
        pass
    if isinstance(value, (tuple, list)) and 0 < len(value) <= 16:
        try:
            return {"kind": "arrays", "items": [_array(v) for v in value]}
        except (TypeError, ValueError, OverflowError):
            pass
    raise BadOutput(_short(value))


def _decode_array(obj):
    if not isinstance(obj, dict) or not isinstance(obj.get("shape"), list) or not isinstance(obj.get("data"), list):
        raise ValueError("malformed array")  # noqa: TRY004 - decode's contract: ValueError for anything malformed
    if len(obj["shape"]) > 8 or not all(type(s) is int and 0 <= s <= MAX_VALUES for s in obj["shape"]):
        raise ValueError("malformed array shape")
    shape = tuple(obj["shape"])
    if math.prod(shape) != len(obj["data"]) or len(obj["data"]) > MAX_VALUES:
        raise ValueError(f"array of shape {shape} with {len(obj['data'])} values")
    if not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in obj["data"]):
        raise ValueError("array with non-numbers")
    return np.array(obj["data"], dtype=float).reshape(shape)


def decode(obj):
    """The numbers of :func:`encode` (or of :func:`call` for the patches protocol), validated.

    Returns an ndarray, a list of ndarrays, or a dict of ndarrays; raises ``ValueError`` for anything
    malformed (a result that did not come from :func:`encode`).
    """
    if not isinstance(obj, dict):
        raise ValueError("malformed result")  # noqa: TRY004 - decode's contract: ValueError for anything malformed
    kind = obj.get("kind")
    if kind == "array":
        return _decode_array(obj)
    if kind == "arrays" and isinstance(obj.get("items"), list) and 0 < len(obj["items"]) <= 16:
        return [_decode_array(a) for a in obj["items"]]
    if kind == "patches":
        return {"curvature": _decode_array(obj.get("curvature")), "colors": _decode_array(obj.get("colors"))}
    raise ValueError(f"malformed result of kind {kind!r}")


def encode_args(args):
    """A case's inputs as JSON: numbers, strings and arrays (an integer array, e.g. a mesh's vertex indices, marked as
    such, so that the student's code gets integers again)."""
    out = []
    for a in args:
        if isinstance(a, str):
            out.append(a)
        elif isinstance(a, np.ndarray):
            out.append({"kind": "array", **_array(a), **({"integer": True} if a.dtype.kind in "iu" else {})})
        else:
            out.append(float(a))
    return out


def _decode_arg(obj):
    a = _decode_array(obj)
    if obj.get("integer") is True:
        if not np.all(a == np.round(a)):
            raise ValueError("an integer array with fractions")
        return a.astype(np.int64)
    return a


def decode_args(items):
    """The inputs of :func:`encode_args`, as fresh objects the student may change."""
    return [_decode_arg(a) if isinstance(a, dict) else a for a in items]


# -- calling the student's code -----------------------------------------------------------------


def _call_patches(cls, nets, mode, color_map):
    """Build the student's class on the nets, call visualize_curvature, read the stored values and colours."""
    from ...geometry.colormaps import ColorMap
    from ...geometry.curvature import CurvatureMode
    from ...model.patches import BezierPatches

    if not (isinstance(cls, type) and issubclass(cls, BezierPatches)):
        raise TypeError(_("expected a subclass of lab.BezierPatches; got {obj}").format(obj=repr(cls)))
    if cls.visualize_curvature is BezierPatches.visualize_curvature:
        _record("lab.model.patches.BezierPatches.visualize_curvature")
        raise RuntimeError(MARKER + ": " + _("your class does not define visualize_curvature, it still uses the library's"))
    patches = cls(np.asarray(nets, dtype=float))
    patches.visualize_curvature(CurvatureMode(mode), ColorMap(color_map))
    try:
        curvature, colors = _array(patches.curvature), _array(patches.colors)
    except (TypeError, ValueError, OverflowError) as exc:
        raise BadOutput(_("the stored curvature and colours are not numbers ({error})").format(error=exc)) from None
    return {"kind": "patches", "curvature": curvature, "colors": colors}


def _call_model(func, items):
    """Build a :class:`lab.Model` of NURBS faces from the case's plain numbers, call ``func(model)``, read back the
    file indices it returns (a list, tuple, set or array of integers)."""
    from ...interrogation.cad.model import Face, Model
    from ...model.surface import BSplineSurface

    if not callable(func):
        raise TypeError(_("expected a function; got {kind}").format(kind=type(func).__name__))
    faces = []
    for k in range(int(items[0])):
        index, kind, P, knots_u, knots_v, degree_u, degree_v, W = items[1 + 8 * k : 9 + 8 * k]
        surface = BSplineSurface(P, knots_u, knots_v, int(degree_u), int(degree_v), weights=W if W.size else None)
        faces.append(Face(int(index), kind, surface))
    value = func(Model(faces, name="part"))
    if isinstance(value, (set, frozenset)):
        value = sorted(value)
    if isinstance(value, (list, tuple)) and not value:
        value = np.zeros(0)
    return encode(value)


def call(protocol, obj, args):
    """Call the student's ``obj`` on ``args`` by the task's protocol; the result as plain numbers (JSON-able).

    ``"function"``: ``obj(*args)``; ``"patches"``: ``obj`` is a subclass of lab.BezierPatches, built on the
    control nets ``args[0]`` and asked for ``visualize_curvature(args[1], args[2])``; ``"model"``: ``obj(model)``
    on a :class:`lab.Model` built from ``args`` (see :func:`lab.teaching.tasks.models`); ``"reported"``: ``obj`` is
    the numbers themselves (the grader reads them from the notebook as written, the check takes the value).
    """
    if protocol == "reported":
        return encode(obj)
    if protocol == "function":
        if not callable(obj):
            raise TypeError(_("expected a function; got {kind}").format(kind=type(obj).__name__))
        return encode(obj(*args))
    if protocol == "patches":
        return _call_patches(obj, *args)
    if protocol == "model":
        return _call_model(obj, args)
    raise ValueError(f"unknown protocol {protocol!r}")


def _student_location(exc, student_files):
    """'in your code, line N: source' of the deepest traceback frame in the student's code, if any."""
    tb = traceback.extract_tb(exc.__traceback__)
    frames = [f for f in tb if f.filename in student_files] or [
        f for f in tb if not f.filename.startswith(_LAB_DIR) and "site-packages" not in f.filename
        and not f.filename.startswith(sys.prefix) and not f.filename.startswith(sys.base_prefix)
    ]
    if not frames:
        return ""
    f = frames[-1]
    line = f.line or linecache.getline(f.filename, f.lineno).strip()
    return _("in your code, line {line}: {source}").format(line=f.lineno, source=line)


def _files_of(obj):
    members = [obj] + list(vars(obj).values()) if isinstance(obj, type) else [obj]
    files = set()
    for member in members:
        code = getattr(getattr(member, "__func__", member), "__code__", None)
        if code is not None:
            files.add(code.co_filename)
    return files


def outcome(protocol, obj, args, timeout):
    """Run one case: ``{"status": ..., "message": ..., "value": ...}``; never raises for the student's code.

    Status ``"ok"`` (with the value), ``"not implemented"``, ``"error"``, ``"timeout"``, ``"delegated"``
    (a withheld library function was called) or ``"bad output"``.
    """
    del _used[:]
    try:
        with time_limit(timeout):
            value = call(protocol, obj, args)
    except TimeUp:
        return {"status": "timeout", "message": _("stopped after {seconds} s. Is there an endless loop?").format(
            seconds=f"{timeout:g}")}
    except NotImplementedError as exc:
        return {"status": "not implemented", "message": str(exc) or _("not implemented yet")}
    except BadOutput as exc:
        return {"status": "bad output", "message": str(exc)}
    except KeyboardInterrupt:
        return {"status": "timeout", "message": _("interrupted (KeyboardInterrupt) before it finished")}
    except SystemExit as exc:
        return {"status": "error", "message": _("your code called exit (SystemExit: {code}); return a result instead").format(
            code=exc.code)}
    except BaseException as exc:  # noqa: BLE001 - whatever student code raises becomes this case's error
        if isinstance(exc, GeneratorExit):
            exc = RuntimeError("GeneratorExit")
        if _used or MARKER in str(exc):
            return {"status": "delegated", "message": ", ".join(sorted(set(_used))) or str(exc)}
        where = _student_location(exc, _files_of(obj))
        text = f"{type(exc).__name__}: {exc}"
        return {"status": "error", "message": text[:1000] + (f"\n{where}" if where else "")}
    if _used:
        return {"status": "delegated", "message": ", ".join(sorted(set(_used)))}
    return {"status": "ok", "value": value}
