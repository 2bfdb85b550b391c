"""Results of a check: :class:`Case` (one test case) and :class:`Report` (status, cases, first failure, hint)."""

import html
from dataclasses import asdict, dataclass, field

__all__ = ["Case", "Report"]


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
