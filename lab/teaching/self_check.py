"""The in-notebook check: a task's cases run on the student's code in the student's own process.

For self-study: the reference implementations a task forbids are blocked while the student's code runs
(their code objects swapped for one that raises, so also ``super()`` calls and names imported earlier are
caught) and a time limit interrupts endless loops.  These are conveniences, not protection: the student's
code could undo them.  Grading never trusts this path; it runs submissions in a sandbox and keeps the
answers outside (:mod:`lab.teaching.grader.notebook`).
"""

import contextlib
import importlib
import re
import secrets
import sys

import numpy as np

from ..geometry.validation import _short, as_number
from .kernel.protocol import decode_args, encode_args, outcome, stub_source
from .task import build_report, judge_outcome
from .untrusted import defines, reported_outcome

__all__ = ["DEFAULT_TIMEOUT", "blocked", "latest_syntax_error", "reported_as_written", "resolve", "run_task"]

#: Seconds a student function may run in one case of a check before it is stopped.
DEFAULT_TIMEOUT = 20.0


def resolve(qualname):
    """The function named ``lab.module.path.name`` or ``lab.module.path.Class.method``."""
    parts = qualname.split(".")
    for cut in range(len(parts) - 1, 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for name in parts[cut:]:
            obj = getattr(obj, name)
        return obj
    raise ValueError(f"cannot resolve {qualname!r}")


def _stub_code(name):
    ns = {}
    exec(compile(  # noqa: S102 - the stub's body is our own source (stub_source)
        "def _stub(*args, **kwargs):\n" + stub_source(name, "    "), "<lab.teaching.self_check>", "exec"), ns)
    return ns["_stub"].__code__


@contextlib.contextmanager
def blocked(qualnames):
    """Make the named library functions raise (and record their use) while the block runs."""
    saved, seen = [], set()
    for name in qualnames:
        func = resolve(name)
        func = func.fget if isinstance(func, property) else getattr(func, "__func__", func)
        if getattr(func, "__code__", None) is None or func.__closure__ or id(func) in seen:
            continue
        seen.add(id(func))
        saved.append((func, func.__code__))
        func.__code__ = _stub_code(name)
    try:
        yield
    finally:
        for func, code in saved:
            func.__code__ = code


def latest_syntax_error(obj):
    """Why ``obj`` is not what the student last wrote: the latest notebook cell that defines its name has a
    syntax error (so the object is an older version, often the stub), as a message; "" otherwise or outside
    IPython."""
    name = getattr(obj, "__name__", "")
    shell = getattr(sys.modules.get("IPython"), "get_ipython", lambda: None)()
    if not name or shell is None:
        return ""
    history = list(shell.user_ns.get("In", []))[:-1]  # the last input is the cell running this check
    for k in range(len(history) - 1, 0, -1):
        source = history[k]
        if not defines(source, name):
            continue
        try:
            compile(shell.transform_cell(source), f"In [{k}]", "exec")
        except SyntaxError as exc:
            from ..i18n import _

            return _("{name} as you last wrote it was never defined: the cell In [{cell}] that defines it has a "
                     "syntax error ({error}: {message}, line {line}); fix it and run that cell").format(
                         name=name, cell=k, error=type(exc).__name__, message=exc.msg, line=exc.lineno)
        return ""
    return ""


def reported_as_written(task_name):
    """How the grader will read the numbers the running cell passes to ``check.<task_name>(name)``: the outcome of
    :func:`lab.teaching.untrusted.reported_outcome` over the cells run so far (the running one up to the check), so
    that numbers computed by code are said to be code here already; None outside IPython, or when the check is not
    given a name."""
    shell = getattr(sys.modules.get("IPython"), "get_ipython", lambda: None)()
    history = list(shell.user_ns.get("In", [])) if shell is not None else []
    if not history:
        return None
    current = str(history[-1])
    found = re.search(rf"\b{re.escape(task_name)}\(\s*([A-Za-z_]\w*)\s*[,)]", current)
    if found is None:
        return None
    return reported_outcome([str(x) for x in history[1:-1]] + [current[:found.start()]], found.group(1))


#: The longest time limit a check accepts (seconds).
MAX_TIMEOUT = 86400.0


def _options(seed, timeout, graded):
    """The check's own options, validated (a bad option is the caller's mistake, not the student code's)."""
    if seed is None:
        seed = secrets.randbelow(2**32)  # recorded in the report: it reproduces the cases
    elif isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer; got {seed!r}")
    try:  # (an int beyond the float range too; at most a day: the timer takes no more)
        timeout = as_number(timeout, "timeout", positive=True, maximum=MAX_TIMEOUT)
    except (TypeError, ValueError):
        raise ValueError(f"timeout must be a positive number of seconds, at most {MAX_TIMEOUT:g}; got "
                         f"{_short(timeout)}") from None
    if not isinstance(graded, bool):
        raise TypeError(f"graded must be True or False; got {graded!r}")
    return int(seed), float(timeout)


def run_task(task, obj, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Run every case of ``task`` on the student's ``obj`` here, judge it, and return the Report.

    After a case that ran out of time the remaining cases are not run (they would most likely loop too).
    """
    seed, timeout = _options(seed, timeout, graded)
    cases = task.make_cases(np.random.default_rng(seed), graded)
    results, stop = [], False
    for case in cases:
        if stop:
            out = {"status": "not run", "message": "not run after an earlier case ran out of time"}
        else:
            with blocked(task.blocked):
                out = outcome(task.protocol, obj, decode_args(encode_args(case.args)), timeout)
            stop = out["status"] == "timeout"
        results.append(judge_outcome(task, case, out, lambda case=case: task.expected(case)))
    return build_report(task, cases, results, graded=graded, seed=seed)
