"""The autograder: submissions run in a sandbox, the answers and the verdicts stay outside.

``curvature-lab grade NOTEBOOK.ipynb`` (or a folder of submissions; the command and folders are in
:mod:`lab.teaching.course.grade`) grades a notebook
on the tasks of its assignment (the instructor's, :mod:`lab.teaching.grader.assignments`):

1. The grader builds every case itself from a fresh seed (recorded in the report; ``--seed`` reproduces
   a run): control nets, modes, maps, numbers.  It computes the exact answers itself, in this process.
2. A fresh copy of the submission runs in the sandbox (:mod:`lab.teaching.sandbox.bubblewrap`): nbclient and a new
   kernel execute its cells under time limits, then the student's objects are called on the cases'
   inputs (:mod:`lab.teaching.kernel.graded_run`, :mod:`lab.teaching.kernel.harness`).  The sandbox sees no answer, no
   course file and no network, and the library's reference implementations of the graded tasks are
   withheld there.  Only plain numbers come back; what the sandbox leaves behind is read as hostile input
   (:mod:`lab.teaching.grader.sandbox_output`): anything malformed makes the submission's results invalid (0 points and a
   note), never an exception of the grader.
3. Credit is per case (weights in the report); a case that raised, ran out of time or did not run
   scores 0, the others still count.

This process never runs student code and never writes the submission.  Every text that comes from the
submission is cleaned before it is shown (:func:`lab.teaching.untrusted.clean`).

**Per-student surfaces** (``variants``, the table of a per-student release, :mod:`lab.teaching.kernel.variants`):
the assignment's per-student tasks are graded too, each on the cases of the student's own variant (the folder
``SUBS/<student>``), with exact answers computed for that variant here.  Numbers a student reports
(protocol ``"reported"``) are read from the notebook as written (:func:`lab.teaching.untrusted.reported_outcome`);
numbers that are wrong for the student's own variant but right for classmates' are noted with the classmates'
names (for the instructor's eyes only: :attr:`GradeResult.private_notes`, in ``summary.csv`` and the JSON
report, never in what the student sees).  A student not in the table is graded on the common
surface, with a note.  The graded run's ``lab.my_surface`` gives the student's own variant (``LAB_VARIANT``).
"""

import copy
import hashlib
import importlib.metadata
import json
import math
import os
import re
import secrets
import shutil
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from ... import i18n
from ...i18n import _, decimal
from ..kernel.protocol import encode_args
from ..sandbox.bubblewrap import DISK, MEMORY, Sandbox
from ..sandbox.withhold import prepare_package, withheld
from ..task import build_report, judge_outcome
from ..tasks import TASKS
from ..untrusted import UntrustedError, clean, definitions, read_file, read_notebook, reported_outcome
from . import assignments as _assignments
from .sandbox_output import InvalidResults, open_folder, read_cells, read_outcomes
from .variants import classmates_numbers, per_student_hand_out, variant_notes

__all__ = ["CAD_DISTRIBUTIONS", "MAX_NOTEBOOK", "VISIBILITY", "WITHHELD", "GradeResult", "Prepared", "grade_notebook",
           "hidden_modules", "read_submission", "submission_language"]

#: Kinds of cell errors that come from the withheld reference implementations, not from the student.
WITHHELD = ("withheld", "follows")
#: Largest submission read (bytes): checked on the open file, before anything is parsed.
MAX_NOTEBOOK = 20 << 20
#: Largest text report (characters); beyond it the report is cut with a note.
MAX_REPORT = 256 << 10
#: Gradescope's visibilities of results (https://gradescope-autograders.readthedocs.io).
VISIBILITY = ("visible", "hidden", "after_due_date", "after_published")


def _points(x):
    """Points as every report, CSV and Gradescope file shows them: rounded to 2 decimals."""
    return round(float(x) + 0.0, 2)


@dataclass
class GradeResult:
    """The grade of one notebook."""

    notebook: str
    assignment: str = ""
    seed: int = None
    tasks: list = field(default_factory=list)
    cell_errors: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    missing_protections: list = field(default_factory=list)
    error: str = ""
    seconds: float = 0.0
    lang: str = "en"
    student: str = ""
    sha256: str = ""
    #: The largest memory use of the whole submission (bytes, from its cgroup), or None where none was measured.
    peak_memory: int = None
    #: Notes for the instructor only (another student's name): in the JSON report and summary.csv, never in the
    #: text report, the feedback page or Gradescope's output.
    private_notes: list = field(default_factory=list)

    @property
    def score(self):
        return _points(sum(_points(t["points"] * t["score"]) for t in self.tasks))

    @property
    def max_score(self):
        return _points(sum(t["points"] for t in self.tasks))

    @property
    def passed(self):
        """Every task passed.  A notebook without graded tasks has not passed anything: 0 / 0 is not a pass."""
        return not self.error and bool(self.tasks) and all(t["passed"] for t in self.tasks)

    def to_dict(self):
        return {"notebook": self.notebook, "student": self.student, "assignment": self.assignment, "lang": self.lang,
                "seed": self.seed, "score": self.score, "max_score": self.max_score, "passed": self.passed,
                "tasks": self.tasks, "cell_errors": self.cell_errors, "notes": self.notes,
                "missing_protections": self.missing_protections, "error": self.error,
                "seconds": round(self.seconds, 2), "sha256": self.sha256, "peak_memory": self.peak_memory,
                "private_notes": self.private_notes}

    @classmethod
    def from_dict(cls, data):
        """A result written by :meth:`to_dict` (read back by ``--resume``, ``feedback`` and ``gradebook``)."""
        names = {f.name for f in fields(cls)}
        return cls(**{k: v for k, v in data.items() if k in names})

    def text(self):
        with i18n.using(self.lang):
            text = self._text()
        if len(text) > MAX_REPORT:
            text = text[:MAX_REPORT] + "\n" + _("… (the report is longer than {n} characters; cut here)").format(
                n=MAX_REPORT)
        return text

    def _text(self):
        # the first line is one line: a newline in a file name never forges a line of the report; a message's own
        # lines are indented below it (_under)
        head = _("{notebook}: {score} / {max} points").format(notebook=clean(self.notebook or self.student, 300,
                                                                             keep_newlines=False),
                                                               score=decimal(f"{self.score:g}"),
                                                               max=decimal(f"{self.max_score:g}"))
        if self.assignment:
            head += "  " + _("(assignment {id}, seed {seed})").format(
                id=clean(self.assignment, 100, keep_newlines=False), seed="–" if self.seed is None else self.seed)
        lines = [head]
        if self.error:
            lines.append("  " + _("error: {message}").format(message=_under(clean(self.error))))
        if not self.tasks and not self.error:
            lines.append("  " + _("no graded tasks: this notebook has nothing to pass (0 / 0 is not a pass)"))
        for t in self.tasks:
            lines.append(f"- {t['task']} ({clean(t['object'], 100, keep_newlines=False)}): "
                         + decimal(f"{_points(t['points'] * t['score']):g} / {t['points']:g}"))
            lines.extend("    " + line for line in clean(t["report"], MAX_REPORT).splitlines())
        errors = [e for e in self.cell_errors if e.get("kind") not in WITHHELD]
        withheld = [str(e["cell"]) for e in self.cell_errors if e.get("kind") in WITHHELD]
        names = sorted({e["error"].rsplit(": ", 1)[-1].strip() for e in self.cell_errors
                        if e.get("kind") == "withheld" and ": lab." in e.get("error", "")})
        for e in errors:
            lines.append("  " + _("cell {index}: {error}").format(index=e["cell"],
                                                                  error=_under(clean(e["error"], 500))))
        if withheld:
            lines.append("  " + _("cells {indices}: the library's reference implementation (or a result of it) is "
                                  "withheld in the graded run; no points depend on it").format(indices=", ".join(withheld))
                         + (" (" + clean(", ".join(names), 300, keep_newlines=False) + ")" if names else ""))
        lines.extend("  " + _("note: {note}").format(note=_under(clean(n))) for n in self.notes)
        if self.missing_protections:
            lines.append("  " + _("sandbox: missing {what}").format(what="; ".join(self.missing_protections)))
        return "\n".join(lines)

    def gradescope(self, visibility="visible"):
        """Gradescope's ``results.json``: one test per task (its group of cases), scores rounded as everywhere."""
        if visibility not in VISIBILITY:
            raise ValueError(f"visibility must be one of {', '.join(VISIBILITY)}; got {visibility!r}")
        tests = [{"name": f"{t['task']} ({clean(t['object'], 100)})", "score": _points(t["points"] * t["score"]),
                  "max_score": t["points"], "status": "passed" if t["passed"] else "failed",
                  "output": clean(t["report"], MAX_REPORT), "visibility": visibility} for t in self.tasks]
        return {"score": _points(sum(t["score"] for t in tests)), "execution_time": round(self.seconds, 2),
                "output": self.text(), "visibility": visibility, "stdout_visibility": "hidden", "tests": tests}


#: Installed distributions that compute curvature on their own (OpenCASCADE's ``BRepLProp_SLProps``, rhino3dm's
#: ``Surface.CurvatureAt``) and the readers built on them: absent from the sandbox of an assignment that reads no CAD
#: file, so that none of their functions is a road to an answer.
CAD_DISTRIBUTIONS = ("cadquery-ocp-novtk", "cadquery-ocp", "cadquery-ocp-proxy", "rhino3dm", "pyiges")


def hidden_modules(assignment):
    """The installed folders and files (packages, extension modules, bundled shared libraries) that the sandbox of
    ``assignment`` covers with an empty folder or file: those of :data:`CAD_DISTRIBUTIONS` unless the assignment
    reads CAD files, and those of every distribution a graded task names as ``foreign`` (one that computes its
    answer on its own, e.g. libigl for the angle deficit)."""
    names = set() if _assignments.reads_cad(assignment) else set(CAD_DISTRIBUTIONS)
    names |= {d for task, _obj, _pts in assignment.graded(per_student=True) for d in TASKS[task].foreign}
    hidden = set()
    for name in sorted(names):
        try:
            dist = importlib.metadata.distribution(name)
        except importlib.metadata.PackageNotFoundError:
            continue
        for file in dist.files or ():
            top = file.parts[0]
            if top.endswith((".dist-info", ".data")) or top in ("..", "__pycache__"):
                continue
            path = Path(dist.locate_file(top)).resolve()
            if path.exists():
                hidden.add(str(path))
    return tuple(sorted(hidden))


class Prepared:
    """The cases and answers of one assignment for one run in one language (shared by its submissions).

    ``package``: the sandbox's copy of the library (:func:`prepare_package`); one copy serves an assignment
    in every language.  ``variants``: the table of a per-student release (:class:`lab.teaching.kernel.variants.Table`),
    or None; with it the assignment's per-student tasks are graded too, each submission on its student's variant
    (:meth:`for_student`).
    """

    def __init__(self, assignment, seed, package, variants=None):
        self.assignment, self.seed, self.lang = assignment, seed, i18n.language()  # case names are in this language
        self.variants, self.student, self.params = variants, None, {}
        self.tasks = assignment.graded(per_student=variants is not None)
        streams = np.random.SeedSequence(seed).spawn(len(self.tasks))  # the first ones: as without per-student tasks
        self.cases = [TASKS[name].variant_cases(None, None) if TASKS[name].variant else
                      TASKS[name].make_cases(np.random.default_rng(s), True)
                      for (name, _, _), s in zip(self.tasks, streams)]
        self.package = Path(package)
        self.hide = hidden_modules(assignment)
        self._expected = None
        self._lock = threading.Lock()
        self._shared, self._others = None, {}

    @staticmethod
    def package_for(assignment, workdir):
        """The sandbox's copy of the library for ``assignment``, in ``workdir``."""
        return prepare_package(withheld([name for name, _, _ in assignment.graded(per_student=True)]), list(TASKS),
                               Path(workdir) / f"pkg-{assignment.id}")

    def for_student(self, student):
        """These cases and answers for ``student``: the per-student tasks on the student's variant of the table (the
        common surface for a student not in it, :attr:`params` then None); the others shared."""
        if self.variants is None or not any(TASKS[name].variant for name, _, _ in self.tasks):
            return self
        view = copy.copy(self)
        view.student, view.params, view._shared = student, {}, self
        view._expected, view._lock, view.cases = None, threading.Lock(), list(self.cases)
        for k, (name, _obj, _points) in enumerate(self.tasks):
            task = TASKS[name]
            if task.variant:
                view.params[task.variant] = self.variants.params(student, task.variant)
                view.cases[k] = task.variant_cases(student, view.params[task.variant])
        return view

    def expected(self):
        """The exact answers, per task and case (computed once, on first use; a student's view computes those of
        its per-student tasks and shares the others')."""
        with self._lock:
            if self._expected is None:
                shared = self._shared.expected() if self._shared is not None else None
                self._expected = [shared[k] if shared is not None and not TASKS[name].variant else
                                  [TASKS[name].expected(c) for c in cases]
                                  for k, ((name, _, _), cases) in enumerate(zip(self.tasks, self.cases))]
            return self._expected

    def owners(self, k, value):
        """The other students of the table whose variant the numbers ``value`` answer right for task ``k`` (sorted);
        their answers are computed once per run, in floating point (enough to tell the variants apart)."""
        name = self.tasks[k][0]
        task, root = TASKS[name], self._shared or self
        with root._lock:
            answers = root._others.get(name)
            if answers is None:
                answers = root._others[name] = {}
                for student in sorted(self.variants.students):
                    params = self.variants.params(student, task.variant)
                    if params is not None:
                        case = task.variant_cases(student, params, exact=False)[0]
                        answers[student] = (case, task.expected(case))
        found = []
        for student, (case, exp) in answers.items():
            if student != self.student:
                try:
                    if task.judge(case, value, exp)[0]:
                        found.append(student)
                except (ValueError, TypeError, IndexError, KeyError):
                    continue
        return found

    def spec(self, notebook, out, cell_timeout, case_timeout):
        spec = {"notebook": str(notebook), "out": str(out), "cell_timeout": cell_timeout, "case_timeout": case_timeout,
                "tasks": [{"task": name, "object": obj, "protocol": TASKS[name].protocol,
                           "cases": [] if TASKS[name].protocol == "reported" else [encode_args(c.args) for c in cases]}
                          for (name, obj, _), cases in zip(self.tasks, self.cases)]}
        if self.student is not None:  # the graded run's lab.my_surface: the student's own variant
            spec["variant"] = {"student": self.student, "variants": {a: p for a, p in self.params.items() if p}}
        return spec


def _under(text):
    """A message's further lines indented below its first (a report line of its own never starts with them)."""
    return text.replace("\n", "\n    ")


def read_submission(path):
    """``(raw bytes, notebook)`` of a submission: a regular file of at most :data:`MAX_NOTEBOOK` bytes (checked on
    the open file before anything is parsed), valid nbformat 4, read once (:func:`lab.teaching.untrusted.read_notebook`).
    Raises ``ValueError`` saying what is wrong."""
    try:
        raw = read_file(path, MAX_NOTEBOOK)
    except UntrustedError as exc:
        raise ValueError(str(exc)) from None
    return raw, read_notebook(raw)


def _zero_tasks(found, message, tasks=None):
    """The assignment's tasks (or ``tasks``), each with 0 points and ``message`` (a notebook that could not be
    graded)."""
    graded, tasks = found.tasks if tasks is None else tasks, []
    for name, obj, points in graded:
        report = build_report(TASKS[name], [], [], graded=True)
        report.message = message
        tasks.append({**report.to_dict(), "object": obj, "points": points, "report": str(report)})
    return tasks


def _defining_cells(nb):
    """``{name: index of the last code cell that defines it}`` (``def name`` / ``class name`` / ``name =``), built in
    one pass over the notebook (:func:`lab.teaching.untrusted.definitions`), so that any number of lookups costs the
    notebook's size once."""
    found = {}
    for i, cell in enumerate(nb.cells):
        if cell.cell_type == "code":
            for name in definitions(cell.source):
                found[name] = i
    return found


def _failed_definition(defined, name, cell_errors):
    """``(index, error)`` of the cell that defines ``name`` when that cell failed (not a withheld call), else None."""
    index = defined.get(name)
    error = next((e for e in cell_errors if e.get("cell") == index), None) if index is not None else None
    return None if error is None or error.get("kind") in WITHHELD else (index, error)


def _undefined_message(defined, obj, cell_errors):
    """Why ``obj`` was never defined, when the cell that defines it failed (a SyntaxError, a dead kernel …)."""
    if (failed := _failed_definition(defined, obj, cell_errors)) is None:
        return None
    index, error = failed
    if error["kind"] == "syntax":
        return _("{name} was never defined: cell {cell}, which defines it, has a syntax error ({error}); fix it "
                 "and run the cell").format(name=obj, cell=index, error=error["error"])
    if error["kind"] == "died":
        return _("{name} was never defined: the kernel died while cell {cell}, which defines it, ran (did the code "
                 "exit or crash?)").format(name=obj, cell=index)
    return _("{name} was never defined: cell {cell}, which defines it, raised {error}").format(
        name=obj, cell=index, error=error["error"])


_NAME_ERROR = re.compile(r"NameError: name '(\w+)' is not defined")


def _explain_name_errors(defined, cell_errors):
    """A NameError of a cell whose name an earlier cell should have defined but failed (stopped, raised): say so,
    instead of a bare "name 'mine' is not defined" that reads as the student's typo."""
    for e in cell_errors:
        found = _NAME_ERROR.search(e.get("error", "")) if e.get("kind") == "error" else None
        failed = _failed_definition(defined, found.group(1), cell_errors) if found else None
        if failed is not None and isinstance(e.get("cell"), int) and failed[0] < e["cell"]:
            e["error"] = _("{error} (cell {cell}, which defines {name}, did not finish: {why})").format(
                error=e["error"], cell=failed[0], name=found.group(1), why=clean(failed[1]["error"], 200))


def _grade_in_sandbox(raw, prepared, result, *, timeout, check_timeout, total_timeout, memory, disk, use_sandbox):
    """Run the submission ``raw`` in a sandbox; fill ``result``'s cell errors, missing protections and peak memory;
    return (outcomes per task, notes, whether the results are invalid)."""
    with tempfile.TemporaryDirectory(prefix="lab-grade-") as tmp:
        box = Sandbox(prepared.package, Path(tmp) / "work", memory=memory, disk=disk, use_bwrap=use_sandbox,
                      lang=prepared.lang, hide=prepared.hide)
        with box.workspace() as work:
            (work / "out").mkdir()
            inside = box.inside
            (work / "submission.ipynb").write_bytes(raw)
            spec = prepared.spec(inside / "submission.ipynb", inside / "out", timeout, check_timeout)
            (work / "spec.json").write_text(json.dumps(spec))
            box.hand_over()
            ran = {}

            def run():
                ran["run"] = box.run([sys.executable, "-m", "lab.teaching.kernel.graded_run", str(inside / "spec.json")],
                                     total_timeout)

            worker = threading.Thread(target=run)
            worker.start()
            prepared.expected()  # the answers, while the sandbox runs
            worker.join()
            code, timed_out, stderr = ran["run"]
            result.missing_protections, result.peak_memory = box.missing, box.peak_memory
            notes = _memory_notes(box.peak_memory, memory)
            try:
                folder = open_folder(work / "out")
                try:
                    outcomes = [read_outcomes(folder, f"task-{k}.jsonl", len(cases))
                                for k, cases in enumerate(prepared.cases)]
                    cell_errors, _restarts, complete = read_cells(folder)
                finally:
                    os.close(folder)
            except InvalidResults as exc:
                outcomes, cell_errors, complete = [{} for _ in prepared.cases], [], True
                notes.append(_("invalid results: the graded run's output was changed or is malformed ({error}); "
                               "the submission scores 0").format(error=clean(exc, 300)))
                result.cell_errors = cell_errors
                return outcomes, notes, True
        if timed_out:
            notes.append(_("the submission was stopped after {seconds} s (its time limit); cases not reached score 0")
                         .format(seconds=f"{total_timeout:g}"))
        elif code != 0 and not complete:
            notes.append(_("the graded run ended abnormally (exit status {code}): {stderr}").format(
                code=code, stderr=clean(stderr.strip()[-300:], 300)))
        result.cell_errors = cell_errors
        return outcomes, notes, False


def _memory_notes(peak, memory):
    """A note when the submission used (nearly) all of its memory: the cause of a killed kernel or of a stall."""
    if peak is None or peak < 0.95 * memory:
        return []
    return [_("the submission used {peak} MiB of its {limit} MiB memory limit (all of it, for all its processes "
              "together): a kernel at the limit is killed or slowed down").format(peak=peak >> 20, limit=memory >> 20)]


def _check_limits(timeout, check_timeout, total_timeout, memory, disk):
    for name, value in (("timeout", timeout), ("check_timeout", check_timeout), ("total_timeout", total_timeout)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
            raise ValueError(f"{name} must be a positive number of seconds; got {value!r}")
    for name, value, least in (("memory", memory, 256 << 20), ("disk", disk, 16 << 20)):
        if isinstance(value, bool) or not isinstance(value, int) or value < least:
            raise ValueError(f"{name} must be at least {least >> 20} MiB (a kernel needs about 200 MiB); "
                             f"got {value!r} bytes")


def grade_notebook(path, *, assignment=None, seed=None, timeout=60, check_timeout=10.0, total_timeout=600,
                   memory=MEMORY, disk=DISK, sandbox=None, prepared=None, submission=None, variants=None,
                   student=None):
    """Grade one notebook in a sandbox; the file is only read.

    Parameters
    ----------
    path : str or Path
    assignment : str or Path, optional
        The instructor's notebook, or a folder of them, looked up directly or in its language folders
        ``en/``, ``de/`` (default: the project's ``exercises/``).
    seed : int, optional
        Seed of the cases (default: fresh; recorded in the result).
    timeout : float
        Seconds each cell may run; ``check_timeout`` seconds each call of the student's code;
        ``total_timeout`` seconds the whole submission.
    memory, disk : int
        Bytes of memory of the whole submission (and of writable data per process), bytes it may write.
    sandbox : bool, optional
        Use bubblewrap (default: when it works here); without it, limits and a process group only.
    prepared : Prepared, optional
        Cases and answers shared by a folder run.
    submission : (bytes, notebook), optional
        What :func:`read_submission` gave, when the caller has read it already.
    variants : lab.teaching.kernel.variants.Table, optional
        The variants table of a per-student release: the assignment's per-student tasks are graded on ``student``'s
        variant (see the module docstring).  A notebook of a per-student hand-out graded without it is an error.
    student : str, optional
        Whose variant (a folder run: the folder ``SUBS/<student>``).
    """
    _check_limits(timeout, check_timeout, total_timeout, memory, disk)
    start = time.perf_counter()
    path = Path(path)
    result = GradeResult(str(path), lang=i18n.language())
    try:
        raw, nb = read_submission(path) if submission is None else submission
    except ValueError as exc:
        result.error = _("cannot read the notebook: {error}").format(error=exc)
        try:
            found = _assignments.for_path(path, assignment)
        except _assignments.AssignmentError:
            found = None
        if found is not None:  # 0 out of the assignment's points, not 0 / 0
            result.assignment, result.tasks = found.id, _zero_tasks(
                found, result.error, found.graded(per_student=variants is not None))
        return result
    result.sha256 = hashlib.sha256(raw).hexdigest()
    result.lang = submission_language(nb)
    with i18n.using(result.lang):
        try:
            found, result.notes = _assignments.for_submission(nb, path, assignment)
        except _assignments.AssignmentError as exc:
            result.error = str(exc)
            return result
        if variants is None and found.per_student and per_student_hand_out(nb):
            result.assignment = found.id
            result.error = _("this notebook comes from a per-student hand-out (variants table {table}): grade it "
                             "with that table, curvature-lab grade --variants variants.json (the hand-out's)").format(
                                 table=clean(per_student_hand_out(nb), 40, keep_newlines=False))
            result.tasks = _zero_tasks(found, result.error, found.graded(per_student=True))
            return result
        if variants is not None and student is None:
            raise ValueError("grading against a variants table needs the student whose variant it is")
        own = None
        if prepared is None or prepared.assignment != found or prepared.lang != result.lang or \
                prepared.variants is not variants:
            own = tempfile.mkdtemp(prefix="lab-grade-pkg-")
            prepared = Prepared(found, secrets.randbelow(2**32) if seed is None else int(seed),
                                Prepared.package_for(found, own), variants)
        prepared = prepared.for_student(student)
        result.notes += variant_notes(prepared, student)
        try:
            result.assignment, result.seed = found.id, prepared.seed
            outcomes, notes, invalid = _grade_in_sandbox(
                raw, prepared, result, timeout=timeout, check_timeout=check_timeout, total_timeout=total_timeout,
                memory=memory, disk=disk, use_sandbox=sandbox)
            expected = prepared.expected()
        finally:
            if own is not None:
                shutil.rmtree(own, ignore_errors=True)
        result.notes += notes
        defined = _defining_cells(nb)
        _explain_name_errors(defined, result.cell_errors)
        if invalid:
            result.tasks = _zero_tasks(found, notes[-1], prepared.tasks)
        for k, (name, obj, points) in enumerate(prepared.tasks if not invalid else ()):
            task = TASKS[name]
            why = _undefined_message(defined, obj, result.cell_errors)
            if task.protocol == "reported":  # numbers as written in the notebook, not as the run computed them
                outcomes[k] = dict.fromkeys(range(len(prepared.cases[k])), reported_outcome(
                    [c.source for c in nb.cells if c.cell_type == "code"], obj))
            judged = []
            for i, case in enumerate(prepared.cases[k]):
                out = outcomes[k].get(i, {"status": "not run", "message": _("the graded run ended before this case")})
                if out.get("undefined") and why:
                    out = {"status": "error", "message": why}
                judged.append(judge_outcome(task, case, out, lambda k=k, i=i: expected[k][i]))
            report = build_report(task, prepared.cases[k], judged, graded=True, seed=prepared.seed)
            result.tasks.append({**report.to_dict(), "object": obj, "points": points, "report": str(report)})
            if task.variant and prepared.variants is not None and not report.passed:
                result.private_notes += classmates_numbers(prepared, k, outcomes[k], student)
    result.seconds = time.perf_counter() - start
    return result


def submission_language(nb):
    """The language a submission is graded and reported in: its metadata ``lab.lang``, else the current one."""
    meta = nb.metadata.get("lab") if isinstance(nb.metadata.get("lab"), dict) else {}
    lang = str(meta.get("lang", ""))
    return lang if lang in i18n.LANGUAGES else i18n.language()
