"""What a task is: its cases, the exact answers, how a result is judged, and what the student may not call.

A :class:`Task` is data plus pure functions, used unchanged by the in-notebook check and by the grader:

* ``make_cases(rng, graded)`` → :class:`CaseSpec` list: the inputs sent to the student's code (numbers,
  strings, arrays) and trusted notes for judging (never sent);
* ``expected(case)`` → the exact answer (sympy or rational arithmetic where it matters);
* ``judge(case, value, expected)`` → ``(passed, expected_text, got_text, hint)`` for a result that came
  back as numbers (:func:`lab.teaching.kernel.protocol.decode`);
* ``error_hint(case, message)`` → a hint for an exception (e.g. an IndexError on a non-square patch);
* ``blocked``: the library functions the student's code must not call for this task (qualified names):
  blocked in the in-notebook check, removed from the package the grader's sandbox sees;
* ``diagnose(specs, cases)`` → one diagnosis for the whole report: it may rewrite the cases' hints once
  all are judged (an IndexError means swapped degrees only when the square cases pass);
* ``protocol``: how the student's object is called (:func:`lab.teaching.kernel.protocol.call`); ``"reported"`` is
  no call: the object is numbers the student reports, and the grader reads them as written in the notebook;
* ``variant``: the assignment whose per-student surface the cases are about (:mod:`lab.teaching.kernel.variants`),
  and ``variant_cases(student, params, exact=True)`` → the cases of that student's variant (``params`` None: the
  common surface; ``exact=False``: answers from floating point, enough to recognise a classmate's numbers).

A hint may be a :class:`Hint`, a text that also names its mistake (``key``), so that ``diagnose`` can
reason about the cases and the report can group cases with the same mistake.
"""

from dataclasses import dataclass, field

import numpy as np

from ..i18n import N_, _, decimal
from .report import Case

__all__ = ["CaseSpec", "Hint", "Task", "build_report", "close", "fmt", "judge_outcome"]


#: What most tasks ask for (translated when shown).
ONE_NUMBER = N_("one number")


class Hint(str):
    """A hint's text, with the ``key`` of the mistake it names (e.g. ``"index_error"``)."""

    def __new__(cls, text, key=""):
        self = super().__new__(cls, text)
        self.key = key
        return self


@dataclass
class CaseSpec:
    """One case: a name, the inputs for the student's code, a weight, and notes for judging (not sent)."""

    name: str
    args: tuple
    weight: float = 1.0
    info: dict = field(default_factory=dict)
    guard: bool = False  # a case a constant answer can pass by accident: counts only beside a passed ordinary one
    #: False for an ordinary case that a wrong formula can pass (an invariance of its data): it counts, but it does
    #: not make the guard cases count
    decides: bool = True


@dataclass(frozen=True)
class Task:
    """A task of the lab (see the module docstring)."""

    name: str
    make_cases: object
    expected: object
    judge: object
    protocol: str = "function"
    blocked: tuple = ()
    allowed: str = ""
    error_hint: object = None
    summary: str = ""
    diagnose: object = None
    variant: str = ""
    variant_cases: object = None
    #: Installed distributions that compute the answer (or a part of it) on their own: absent from the graded
    #: sandbox of an assignment with this task, as OpenCASCADE is from one that reads no CAD file.
    foreign: tuple = ()


def close(a, b, rtol=1e-7, scale=None):
    """Same shape, no NaN, and equal within ``rtol`` relative to ``scale`` (default max(1, max |b|))."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if a.shape != b.shape or np.any(np.isnan(a)) or np.any(np.isnan(b)):
        return False
    if scale is None:
        scale = max(1.0, float(np.max(np.abs(b)))) if b.size else 1.0
    return bool(np.all(np.abs(a - b) <= rtol * scale))


def fmt(x, digits=6):
    """Numbers for a report's "expected"/"got", in the language's notation (array elements are apart by spaces, so a
    German decimal comma stays unambiguous: "[0,5 1,25]")."""
    arr = np.asarray(x, dtype=float)
    return decimal(np.array2string(arr, precision=digits, suppress_small=False, max_line_width=100, threshold=12))


_STATUS = {"not implemented": "not implemented", "timeout": "timeout", "delegated": "delegated",
           "error": "error", "bad output": "failed", "not run": "not run"}


def scalar_judge(hint_fn, what=ONE_NUMBER):
    """A task's judge for an answer of numbers of a known shape: ``(passed, expected, got, hint)``, equal to 10⁻⁹
    relative; ``hint_fn(args, value, expected)`` names the mistake of a wrong answer, ``what`` the shape asked for."""
    def judge(case, value, exp):
        exp = np.asarray(exp, dtype=float)
        if not isinstance(value, np.ndarray) or value.shape != exp.shape:
            got = fmt(value) if isinstance(value, np.ndarray) else repr(value)
            return False, fmt(exp), got, _("return {what}.").format(what=_(what))
        ok = bool(np.all(np.isfinite(value))) and close(value, exp, rtol=1e-9)
        return ok, fmt(exp), fmt(value), "" if ok else hint_fn(case.args, value, exp)

    return judge


def judge_outcome(task, case, outcome, expected_fn):
    """A :class:`Case` from the outcome of running the student's code on ``case`` (see protocol.outcome).

    ``expected_fn()`` gives the exact answer; it is only called when the code returned numbers.
    """
    status = outcome.get("status") if isinstance(outcome, dict) else None
    status = status if isinstance(status, str) else repr(status)[:40]
    message = str(outcome.get("message", "") if isinstance(outcome, dict) else "")[:2000]
    if status == "ok":
        try:
            from .kernel.protocol import decode

            value = outcome.get("value")
            if not isinstance(value, (np.ndarray, list)) and not (isinstance(value, dict) and "kind" not in value):
                value = decode(value)  # as the harness wrote it (the grader's reader hands it over decoded)
            if isinstance(value, dict) != (task.protocol == "patches"):
                raise ValueError(_("a result of the wrong kind for {task}").format(task=task.name))
        except (ValueError, TypeError) as exc:
            return Case(case.name, False, _(task.summary), "", _("the result could not be read ({error}).").format(
                error=exc), "failed", case.weight)
        try:
            passed, exp_text, got_text, hint = task.judge(case, value, expected_fn())
        except (ValueError, TypeError, IndexError, KeyError) as exc:  # malformed numbers: a failure, not a crash
            passed, exp_text, got_text, hint = False, _(task.summary), "", _("the result could not be judged ({error}).").format(
                error=exc)
        return Case(case.name, bool(passed), exp_text, got_text, "" if passed else hint,
                    "passed" if passed else "failed", case.weight, "" if passed else getattr(hint, "key", ""))
    if status not in _STATUS:
        status, message = "error", _("the check could not run this case ({status})").format(status=repr(status))
    hint = ""
    if status == "bad output":
        hint = _("return {what}.").format(what=_(task.summary)) if task.summary else _("return numbers.")
        return Case(case.name, False, _(task.summary), message, hint, "failed", case.weight)
    if status == "error" and task.error_hint is not None:
        hint = task.error_hint(case, message) or ""
    if status == "delegated":
        hint = (_("write the computation yourself; allowed helpers: {helpers}.").format(helpers=task.allowed)
                if task.allowed else _("write the computation yourself."))
        message = message or _("a withheld library function")
    if status == "not implemented":  # the stub's text says what to write: a hint, not an answer it gave
        return Case(case.name, False, "", "", message, "not implemented", case.weight)
    return Case(case.name, False, "", message, hint, _STATUS[status], case.weight, getattr(hint, "key", ""))


def build_report(task, specs, cases, *, graded=False, seed=None):
    """The :class:`~lab.teaching.report.Report` of a task from its judged ``cases`` (same in notebook and grader).

    ``specs`` are the :class:`CaseSpec` of the cases: guard cases count only if an ordinary case passed.
    """
    from .report import Report, task_status

    cases = list(cases)
    if not any(c.passed for c, spec in zip(cases, specs) if not spec.guard and spec.decides):
        for c, spec in zip(cases, specs):
            if spec.guard and c.passed:
                c.status, c.passed, c.got = "failed", False, _("(right here, but nothing else is)")
                c.hint = _("this case is flat, so a constant answer fits it by accident: it counts only "
                           "when a curved case that decides the formulas passes too.")
    if task.diagnose is not None and not all(c.passed for c in cases):
        task.diagnose(specs, cases)
    status = task_status(cases)
    message = ""
    first = next((c for c in cases if c.status == status), None) if status not in ("passed", "failed") else None
    if status in ("error", "failed"):  # one diagnosis: the first failing case's (the block below shows it)
        first = next(c for c in cases if c.status not in ("passed", "not run"))
    if first is not None:
        if status == "not implemented":
            message = first.hint or _("{task} is not implemented yet.").format(task=task.name)
        elif status == "timeout":
            message = _("{task}: {message}").format(task=task.name, message=first.got)
        elif status == "delegated":
            message = _("Your {task} calls the library's own implementation ({names}).").format(
                task=task.name, names=first.got) + " " + first.hint[0].upper() + first.hint[1:]
        elif status in ("error", "failed"):
            message = first.hint or (first.got if first.status == "error" else "")
        elif status == "not run":
            message = first.got
    return Report(task.name, status, cases, message, graded, seed)

