"""The lab's own fuzzer (issue 35): the harness that runs one call and judges what came out.

Every call the fuzzer makes must end in one of

* a result whose floating-point values are finite, or whose non-finite values are flagged (a lab warning such as
  :class:`lab.DegeneratePointWarning`, or a ``degenerate`` / ``umbilic`` mask that is set);
* a ``ValueError`` or ``TypeError`` raised by the lab itself (or its ``IndexError`` for an index past the end of a
  collection, which Python's sequence protocol needs, or its ``FileNotFoundError`` naming a missing file) (the innermost frame of the traceback is in ``lab/``),
  whose message names what was expected and what was received and carries no Python-internal text;
* on the command line: a usage error (``SystemExit(2)``) or an exit status with a ``curvature-lab …: error:`` line;
* the user's own exception, raised by a user's function the fuzzer passed in (:class:`UserBug`).

Anything else is a :class:`Finding`, in one of the issue's four categories: ``crash by allocation`` (a
``MemoryError``), ``hang`` (a call longer than :data:`LIMIT_SECONDS`), ``silent garbage`` (non-finite values
without a flag, a numpy ``RuntimeWarning`` reaching the user, a string accepted where a number belongs) and
``unclear message`` (any other exception, or an error whose text is Python's or numpy's).

Nothing big is allocated: the lab's memory limit is lowered for the run (:data:`MEMORY_LIMIT`), so its own estimates
refuse large work, and the address space of the process is capped at :data:`HEADROOM` above its size during each
call, so that a call which allocates before estimating fails at once with a ``MemoryError`` (recorded as a crash by
allocation) instead of taking the machine's memory.  The time guard only flags: a call that returns after more than
:data:`LIMIT_SECONDS` is a hang; one still running after :data:`STOP_SECONDS` is interrupted (``_thread.interrupt_main``,
the tests run in the main thread) so that CI cannot stall.
"""

import _thread
import contextlib
import io
import math
import os
import re
import resource
import sys
import threading
import time
import traceback
import warnings
from dataclasses import dataclass, field, fields, is_dataclass
from pathlib import Path

import numpy as np

import lab

#: A call that takes longer than this is a hang (the issue: "never more than a set time"); generous, so that a
#: loaded CI machine never flags a call that is merely slow.
LIMIT_SECONDS = 60.0
#: A call still running after this long is interrupted and reported as a hang.
STOP_SECONDS = 240.0
#: The lab's memory limit during the fuzz (lab.set_memory_limit): its estimates refuse bigger work.
MEMORY_LIMIT = "512M"
#: Address space a call may add to the process; beyond it an allocation fails with MemoryError.
HEADROOM = 3 * 2**30

CATEGORIES = ("crash by allocation", "hang", "silent garbage", "unclear message")

#: Texts of Python's, numpy's and sympy's own exceptions: a message that contains one of them is not the lab's.
_INTERNAL_TEXTS = (
    r"could not convert", r"invalid literal for", r"unhashable type", r"object has no attribute",
    r"is not subscriptable", r"object is not iterable", r"object is not callable", r"out of bounds",
    r"index out of range", r"too large to convert", r"cannot convert float", r"operands could not be broadcast",
    r"setting an array element with a sequence", r"inhomogeneous", r"unsupported operand", r"not supported between",
    r"positional argument", r"required positional", r"unexpected keyword", r"must be real number, not",
    r"math domain error", r"division by zero", r"list indices must", r"embedded null", r"ufunc", r"Unable to allocate",
    r"zero-size array", r"only integer scalar arrays", r"only length-1 arrays", r"can't multiply sequence",
    r"argument must be a string or a", r"int\(\) argument", r"float\(\) argument", r"Maximum allowed size exceeded",
    r"Exceeds the limit .* for integer string conversion", r"Python int too large", r"array must not contain infs",
    r"expected str, bytes or os.PathLike", r"'NoneType' object", r"numpy\.", r"dtype\(", r"could not be coerced",
    r"truth value of an array", r"mismatch in size",
)
INTERNAL = re.compile("|".join(_INTERNAL_TEXTS))

_LIBRARY = Path(lab.library()).resolve()


class UserBug(Exception):
    """Raised by the user functions the fuzzer passes in: the user's own error may (and should) come through."""


@dataclass
class Finding:
    category: str
    target: str
    call: str
    detail: str
    where: str = ""

    def key(self):
        """What makes two findings the same failure: category, target, the kind of detail and where it was raised."""
        kind = re.sub(r"(?<![A-Za-z])[-+]?\d[\d.e+-]*", "#", self.detail)
        kind = re.sub(r"'[^']*'|\"[^\"]*\"", "'…'", kind)[:120]
        return self.category, self.target, kind, self.where

    def __str__(self):
        return f"[{self.category}] {self.target}: {self.call}\n    {self.detail}" + (f"\n    at {self.where}"
                                                                                      if self.where else "")


@dataclass
class Outcome:
    """What one call did: its result or exception, the warnings it gave, its time and the findings."""

    result: object = None
    error: BaseException | None = None
    warnings: list = field(default_factory=list)
    seconds: float = 0.0
    findings: list = field(default_factory=list)


def short(value, n=80):
    """A short repr of an argument for a report."""
    if isinstance(value, np.ndarray):
        text = f"ndarray{value.shape}:{value.dtype}"
        if value.size <= 4:
            text += f"={value.tolist()!r}"
        return text
    try:
        text = repr(value)
    except ValueError:  # an int too large to print
        text = "<huge int>"
    except Exception:  # noqa: BLE001 - a repr that fails is still an argument
        text = f"<{type(value).__name__}>"
    return text if len(text) <= n else text[: n - 1] + "…"


def call_text(name, kwargs):
    return f"{name}(" + ", ".join(f"{k}={short(v)}" for k, v in kwargs.items()) + ")"


def _where(exc):
    """``file:line`` of the innermost frame of ``exc`` (relative to the lab where it is the lab's)."""
    tb = traceback.extract_tb(exc.__traceback__)
    if not tb:
        return ""
    frame = tb[-1]
    path = Path(frame.filename)
    try:
        path = "lab/" + str(path.resolve().relative_to(_LIBRARY))
    except ValueError:
        parts = path.parts
        path = "/".join(parts[-3:])
    return f"{path}:{frame.lineno}"


def raised_by_lab(exc):
    """Whether the innermost frame of ``exc``'s traceback is in the lab package (its own raise, not numpy's)."""
    tb = traceback.extract_tb(exc.__traceback__)
    if not tb:
        return False
    try:
        Path(tb[-1].filename).resolve().relative_to(_LIBRARY)
    except ValueError:
        return False
    return True


def _is_lab_warning(w):
    return getattr(w.category, "__module__", "").partition(".")[0] == "lab"


_MASKS = ("degenerate", "umbilic", "finite", "flagged", "singular", "flat")  # flat: an infinite radius, flagged


def nonfinite(value, depth=0, seen=None):
    """The number of non-finite floats in ``value`` (arrays, dataclasses, sequences, mappings, PyVista data) and
    whether a mask in it flags them; a few levels deep, never copying more than a look at each array."""
    seen = set() if seen is None else seen
    if depth > 4 or id(value) in seen:
        return 0, False
    seen.add(id(value))
    if isinstance(value, (float, np.floating)):
        return int(not math.isfinite(value)), False
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc":
            return int(value.size - np.count_nonzero(np.isfinite(value))), False
        return 0, False
    bad, flagged = 0, False
    items = []
    if is_dataclass(value) and not isinstance(value, type):
        items = [(f.name, getattr(value, f.name, None)) for f in fields(value)]
    elif isinstance(value, tuple) and hasattr(value, "_fields"):
        items = list(zip(value._fields, value))
    elif isinstance(value, (list, tuple)):
        items = [(None, x) for x in value[:64]]
    elif isinstance(value, dict):
        items = [(str(k), x) for k, x in list(value.items())[:64]]
    elif type(value).__module__.startswith("pyvista"):
        data = getattr(value, "point_data", None)
        if data is not None:
            items = [("points", np.asarray(value.points))] + [(k, np.asarray(data[k])) for k in data]
    for name, x in items:
        if name in _MASKS and isinstance(x, (bool, np.bool_)):  # one point's flag (lab.probe)
            flagged |= bool(x) if name != "finite" else not x
            continue
        if name in _MASKS and isinstance(x, np.ndarray) and x.dtype == bool:
            flagged |= bool(x.any()) if name != "finite" else bool((~x).any())
            continue
        b, f = nonfinite(x, depth + 1, seen)
        bad, flagged = bad + b, flagged or f
    return bad, flagged


@contextlib.contextmanager
def _address_space_cap():
    """Cap the address space at the current size plus :data:`HEADROOM` (Linux): big allocations fail at once."""
    try:
        with open("/proc/self/statm") as f:
            size = int(f.read().split()[0]) * resource.getpagesize()
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    except (OSError, ValueError):
        yield
        return
    cap = size + HEADROOM
    if hard != resource.RLIM_INFINITY:
        cap = min(cap, hard)
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


@contextlib.contextmanager
def _watchdog():
    """Interrupt the main thread after :data:`STOP_SECONDS` (a runaway call); yields a dict that says whether it did."""
    state = {"fired": False}
    in_main = threading.current_thread() is threading.main_thread()

    def fire():
        state["fired"] = True
        if in_main:
            _thread.interrupt_main()

    timer = threading.Timer(STOP_SECONDS, fire)
    timer.daemon = True
    timer.start()
    try:
        yield state
    finally:
        timer.cancel()


@contextlib.contextmanager
def fuzzing():
    """The conditions of a fuzz run: the lab's memory limit lowered, English messages, warnings recorded."""
    previous = lab.set_memory_limit(MEMORY_LIMIT)
    try:
        from lab.i18n import using

        with using("en"):
            yield
    finally:
        lab.set_memory_limit(previous)


def run(name, func, kwargs, *, expect=None, numbers=(), cli=False):
    """Call ``func(**kwargs)`` under the guards and judge the outcome.

    Parameters
    ----------
    name : str
        The target, for the report.
    expect : callable, optional
        ``expect(result, kwargs)`` returns a text describing silent garbage in a result, or None.
    numbers : iterable of str
        The arguments that must be numbers (or arrays of numbers): a string there that is accepted is garbage.
    cli : bool
        A command line's ``main``: a usage error (``SystemExit(2)``) and the exit statuses are answers.
    """
    out = Outcome()
    text = call_text(name, kwargs)
    stderr = io.StringIO()
    start = time.monotonic()
    with warnings.catch_warnings(record=True) as caught, _watchdog() as dog:
        warnings.simplefilter("always")
        try:
            with _address_space_cap(), contextlib.redirect_stderr(stderr), contextlib.redirect_stdout(io.StringIO()):
                out.result = func(**kwargs)
        except KeyboardInterrupt:
            if not dog["fired"]:
                raise
            out.error = TimeoutError(f"interrupted after {STOP_SECONDS:g} s")
        except (Exception, SystemExit) as exc:  # noqa: BLE001 - judging every exception is the point
            out.error = exc
    out.seconds = time.monotonic() - start
    out.warnings = list(caught)
    add = out.findings.append
    if out.seconds > LIMIT_SECONDS or isinstance(out.error, TimeoutError):
        add(Finding("hang", name, text, f"took {out.seconds:.0f} s (limit {LIMIT_SECONDS:g} s)"))
    exc = out.error
    if exc is not None:
        detail = f"{type(exc).__name__}: {str(exc)[:300]}"
        if isinstance(exc, MemoryError):
            add(Finding("crash by allocation", name, text, detail, _where(exc)))
        elif isinstance(exc, (UserBug, TimeoutError)):
            pass
        elif isinstance(exc, SystemExit):
            code = exc.code
            if not cli or not (code in (0, 1, 2) or isinstance(code, str)):
                add(Finding("unclear message", name, text, f"SystemExit({code!r})", _where(exc)))
            elif code in (1, 2) and "error" not in stderr.getvalue():
                add(Finding("unclear message", name, text, f"exit status {code} without an error line"))
        elif isinstance(exc, (ValueError, TypeError)) and raised_by_lab(exc) and not INTERNAL.search(str(exc)):
            pass
        elif isinstance(exc, OSError) and raised_by_lab(exc) and not INTERNAL.search(str(exc)):
            pass  # a file that is not there, said by the lab (FileNotFoundError naming the path)
        elif isinstance(exc, IndexError) and raised_by_lab(exc) and "out of range for" in str(exc):
            pass  # an index past the end of a collection: Python's sequence protocol (iteration stops on it)
        else:
            add(Finding("unclear message", name, text, detail, _where(exc)))
        return out
    if cli:
        err = stderr.getvalue()
        if "Traceback" in err:
            add(Finding("unclear message", name, text, "a traceback on stderr: " + err[-300:]))
        if out.result not in (0, 1, 2, None):
            add(Finding("unclear message", name, text, f"returned {out.result!r}"))
        elif out.result in (1, 2) and "error" not in err:
            add(Finding("unclear message", name, text, f"exit status {out.result} without an error line: {err[-200:]!r}"))
        return out
    lab_warned = any(_is_lab_warning(w) for w in out.warnings)
    numpy_warnings = [w for w in out.warnings if issubclass(w.category, RuntimeWarning) and not _is_lab_warning(w)]
    if numpy_warnings:
        w = numpy_warnings[0]
        add(Finding("silent garbage", name, text, f"RuntimeWarning reached the user: {w.message}",
                    f"{Path(w.filename).name}:{w.lineno}"))
    bad, flagged = nonfinite(out.result)
    if bad and not (flagged or lab_warned):
        add(Finding("silent garbage", name, text, f"{bad} non-finite value(s) in the result, not flagged"))
    for arg in numbers:
        value = kwargs.get(arg)
        if isinstance(value, (str, bytes)) or (isinstance(value, (list, tuple)) and value and all(
                isinstance(x, (str, bytes)) for x in value)):
            add(Finding("silent garbage", name, text, f"{arg}={short(value)} (text) accepted as a number"))
    if expect is not None:
        problem = expect(out.result, kwargs)
        if problem:
            add(Finding("silent garbage", name, text, problem))
    return out


def report(findings, file=sys.stdout):
    """Distinct failures by category (and the first example of each), as printed by ``python -m tests.fuzz``."""
    distinct = {}
    for f in findings:
        distinct.setdefault(f.key(), f)
    print(f"{len(findings)} failing calls, {len(distinct)} distinct failures", file=file)
    for category in CATEGORIES:
        group = [f for k, f in distinct.items() if k[0] == category]
        print(f"\n== {category}: {len(group)} distinct", file=file)
        for f in sorted(group, key=lambda f: (f.target, f.detail)):
            print(f"  {f}", file=file)
    return distinct


def path_in(folder, *parts):
    return os.path.join(folder, *parts)
