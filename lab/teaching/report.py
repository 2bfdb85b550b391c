"""Results of a check: :class:`Case` (one test case with its status) and :class:`Report` (a task's cases and score).

The same report serves the in-notebook check (self-study) and the grader.  A task's credit is per case:
each case has a weight, and the score is the weighted fraction of passed cases, so an exception in one
case does not zero the others.  A case that did not run scores 0 and says "not run", never "passed".
"""

import html
from dataclasses import asdict, dataclass, field

from ..i18n import N_, _, language, using

__all__ = ["STATUSES", "Case", "Report"]

#: Statuses of a case (and of a task): the student's code ran and was right, was wrong, raised, is a stub,
#: ran too long, called the library's reference implementation, or was never reached.
STATUSES = ("passed", "failed", "error", "not implemented", "timeout", "delegated", "not run")

_MARK = {"passed": "✔", "not run": "·"}
_HEAD = {
    "passed": N_("✔ {task}: all {n} cases passed."),
    "failed": N_("✘ {task}: {k} of {n} cases passed."),
    "not implemented": N_("… {task}: not implemented yet."),
    "error": N_("✘ {task}: your code raised an error ({k} of {n} cases passed)."),
    "timeout": N_("✘ {task}: stopped, it ran too long ({k} of {n} cases passed)."),
    "delegated": N_("✘ {task}: uses the library's reference implementation ({k} of {n} cases passed)."),
    "not run": N_("✘ {task}: the check did not run."),
}
#: The statuses as a case line shows them.
_STATUS_WORDS = {"failed": N_("failed"), "error": N_("error"), "not implemented": N_("not implemented"), "timeout": N_("timeout"),
                 "delegated": N_("delegated"), "not run": N_("not run")}


@dataclass
class Case:
    """One test case: its status, and for a failure what was expected, what came out and a hint."""

    name: str
    passed: bool
    expected: str = ""
    got: str = ""
    hint: str = ""
    status: str = ""
    weight: float = 1.0
    #: the key of the mistake the hint names (:class:`lab.teaching.task.Hint`), "" when it names none
    mistake: str = ""

    def __post_init__(self):
        if not self.status:
            self.status = "passed" if self.passed else "failed"
        if self.status not in STATUSES:
            raise ValueError(f"case status must be one of {STATUSES}; got {self.status!r}")
        self.passed = self.status == "passed"


def task_status(cases, default="not run"):
    """The status of a task from its cases: the most telling status among the cases that did not pass."""
    if not cases:
        return default
    statuses = [c.status for c in cases]
    if all(s == "passed" for s in statuses):
        return "passed"
    ran = [s for s in statuses if s != "not run"]
    if not ran:
        return "not run"
    if all(s == "not implemented" for s in ran):
        return "not implemented"
    for s in ("delegated", "timeout", "error"):
        if s in ran:
            return s
    return "failed"


@dataclass
class Report:
    """The result of one check: status, cases, and for the first failure what was expected and a hint."""

    task: str
    status: str
    cases: list = field(default_factory=list)
    message: str = ""
    graded: bool = False
    seed: int = None
    #: the language the report was made in: it is shown in that language wherever it is printed later
    lang: str = field(default_factory=language, repr=False, compare=False)

    @property
    def passed(self):
        return self.status == "passed"

    @property
    def score(self):
        """Weighted fraction of passed cases (0 when no case passed or none ran)."""
        total = sum(c.weight for c in self.cases)
        return sum(c.weight for c in self.cases if c.status == "passed") / total if total else 0.0

    def to_dict(self):
        d = asdict(self)
        del d["lang"]
        d["score"] = self.score
        d["passed"] = self.passed
        return d

    def lines(self):
        with using(self.lang):
            return self._lines()

    def _lines(self):
        n, k = len(self.cases), sum(c.status == "passed" for c in self.cases)
        out = [_(_HEAD[self.status]).format(task=self.task, n=n, k=k)]
        if self.message and self.status == "not implemented":  # the stub's text says what to write
            out.append("  " + _("the task: {text}").format(text=self.message.replace("\n", "\n  ")))
        elif self.message:
            out.append("  " + self.message.replace("\n", "\n  "))
        weights = {c.weight for c in self.cases}
        for c in self.cases:
            extra = "" if c.status in ("passed", "failed") else f"  ({_(_STATUS_WORDS[c.status])})"
            weight = "  [" + _("weight {w}").format(w=f"{c.weight:g}") + "]" if len(weights) > 1 else ""
            out.append(f"  {_MARK.get(c.status, '✘')} {c.name}{extra}{weight}")
        if self.graded and self.cases:
            out.append("  " + (_("credit: each case counts equally ({n} cases).") if len(weights) == 1 else
                               _("credit: weighted as shown ({n} cases).")).format(n=n))
        failed = [c for c in self.cases if c.status not in ("passed", "not run")]
        if failed and self.status != "not implemented":  # an empty task has no answer to show as "got"
            c = failed[0]
            out.append(_("First failing case: {name}").format(name=c.name))
            labels = [_("expected:"), _("got:"), _("hint:")]
            width = max(len(x) for x in labels)
            # the hint is the report's headline (message) already: not twice
            texts = (c.expected, c.got if c.got != self.message else "", c.hint if c.hint and c.hint not in self.message else "")
            for label, text in zip(labels, texts):
                if text:
                    text = text.replace("\n", "\n" + " " * (width + 3))
                    out.append(f"  {label:<{width}} {text}")
            out.extend(_others(failed))
        if self.passed and not self.graded:
            out.append(_("Public checks passed; the graded run adds more cases."))
        return out

    def __str__(self):
        return "\n".join(self.lines())

    def __repr__(self):
        return str(self)

    def _repr_html_(self):
        colour = "#1a7f37" if self.passed else ("#9a6700" if self.status == "not implemented" else "#cf222e")
        body = html.escape("\n".join(self.lines()))
        # JupyterLab breaks an output's <pre> anywhere (word-break: break-all): at word boundaries here
        return (f'<pre style="border-left:4px solid {colour};padding:0.4em 0.8em;white-space:pre-wrap;'
                f'word-break:normal;overflow-wrap:break-word">{body}</pre>')


def _others(failed):
    """Lines for the failing cases after the first: cases with the same mistake, hint or error grouped, counted."""

    def key(c):  # the same mistake reads differently on patches of other degrees: its key groups them
        return (c.mistake or c.hint, "" if c.hint else c.status, "" if c.hint or c.status != "error" else c.got)

    first, groups, hints = failed[0], {}, {}
    for c in failed[1:]:
        groups.setdefault(key(c), []).append(c.name)
        hints.setdefault(key(c), c.hint)
    if not groups:
        return []
    out = [_("Other failing cases:")]
    for k, names in list(groups.items())[:6]:
        hint, status = hints[k], k[1]
        shown = "; ".join(names[:4]) + (" …" if len(names) > 4 else "")
        if hint and k[0] in (first.mistake or first.hint, first.hint):
            out.append("  " + _("{n} with the same hint ({names})").format(n=len(names), names=shown))
        elif hint:
            out.append("  " + _("{n} with the hint: {hint} ({names})").format(n=len(names), hint=hint, names=shown))
        elif k == key(first):
            out.append("  " + _("{n} the same ({names})").format(n=len(names), names=shown))
        else:
            out.append("  " + _("{n} {status} ({names})").format(n=len(names), status=_(_STATUS_WORDS[status]),
                                                               names=shown))
    if len(groups) > 6:
        out.append("  …")
    return out
