"""The autograder: submissions run in a sandbox, the answers and the verdicts stay outside.

``curvature-lab grade NOTEBOOK.ipynb`` (or a folder of submissions) grades a notebook on the tasks of
its assignment (the instructor's, :mod:`lab.teaching.assignments`):

1. The grader builds every case itself from a fresh seed (recorded in the report; ``--seed`` reproduces
   a run): control nets, modes, maps, numbers.  It computes the exact answers itself, in this process.
2. A fresh copy of the submission runs in the sandbox (:mod:`lab.teaching.sandbox`): nbclient and a new
   kernel execute its cells under time limits, then the student's objects are called on the cases'
   inputs (:mod:`lab.teaching.child`, :mod:`lab.teaching.harness`).  The sandbox sees no answer, no
   course file and no network, and the library's reference implementations of the graded tasks are
   withheld there.  Only plain numbers come back; they are validated (kind, shape, size) and judged here.
3. Credit is per case (weights in the report); a case that raised, ran out of time or did not run
   scores 0, the others still count.

This process never runs student code and never writes the submission.  Reports and ``summary.csv`` are
written after every sandbox has ended, each file atomically.
"""

import argparse
import concurrent.futures
import csv
import io
import json
import os
import secrets
import shutil
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import nbformat
import numpy as np

from .. import i18n
from ..i18n import _
from . import assignments as _assignments
from .protocol import encode_args
from .sandbox import MEMORY, Sandbox, prepare_package
from .spec import build_report, judge_outcome
from .tasks import TASKS
from .tasks_curvature import ANALYTIC_BLOCK

__all__ = ["WITHHELD", "GradeResult", "Prepared", "grade_folder", "grade_notebook", "main"]

#: Kinds of cell errors that come from the withheld reference implementations, not from the student.
WITHHELD = ("withheld", "follows")
#: Largest submission read (bytes).
MAX_NOTEBOOK = 20 << 20
#: Largest result file read back from the sandbox (bytes).
MAX_RESULTS = 64 << 20


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

    @property
    def score(self):
        return round(sum(t["points"] * t["score"] for t in self.tasks), 2)

    @property
    def max_score(self):
        return sum(t["points"] for t in self.tasks)

    @property
    def passed(self):
        """All tasks passed; a notebook without tasks passes when all its cells ran without errors."""
        if self.error:
            return False
        return all(t["passed"] for t in self.tasks) if self.tasks else not self.cell_errors

    def to_dict(self):
        return {"notebook": self.notebook, "assignment": self.assignment, "lang": self.lang, "seed": self.seed,
                "score": self.score,
                "max_score": self.max_score, "passed": self.passed, "tasks": self.tasks,
                "cell_errors": self.cell_errors, "notes": self.notes, "missing_protections": self.missing_protections,
                "error": self.error, "seconds": round(self.seconds, 2)}

    def text(self):
        with i18n.using(self.lang):
            return self._text()

    def _text(self):
        lines = [_("{notebook}: {score} / {max} points").format(notebook=self.notebook, score=f"{self.score:g}",
                                                                 max=f"{self.max_score:g}")
                 + ("  " + _("(assignment {id}, seed {seed})").format(id=self.assignment, seed=self.seed)
                    if self.assignment else "")]
        if self.error:
            lines.append("  " + _("error: {message}").format(message=self.error))
        for t in self.tasks:
            lines.append(f"- {t['task']} ({t['object']}): {t['points'] * t['score']:.4g} / {t['points']:g}")
            lines.extend("    " + line for line in t["report"].splitlines())
        errors = [e for e in self.cell_errors if e.get("kind") not in WITHHELD]
        withheld = [str(e["cell"]) for e in self.cell_errors if e.get("kind") in WITHHELD]
        for e in errors:
            lines.append("  " + _("cell {index}: {error}").format(index=e["cell"], error=e["error"]))
        if withheld:
            lines.append("  " + _("cells {indices}: the library's reference implementation (or a result of it) is "
                                  "withheld in the graded run; no points depend on it").format(indices=", ".join(withheld)))
        lines.extend("  " + _("note: {note}").format(note=n) for n in self.notes)
        if self.missing_protections:
            lines.append("  " + _("sandbox: missing {what}").format(what="; ".join(self.missing_protections)))
        return "\n".join(lines)

    def gradescope(self):
        """Gradescope's ``results.json``: one test per task."""
        return {
            "score": self.score,
            "execution_time": round(self.seconds, 2),
            "output": self.text(),
            "visibility": "visible",
            "tests": [{"name": f"{t['task']} ({t['object']})", "score": round(t["points"] * t["score"], 4),
                       "max_score": t["points"], "status": "passed" if t["passed"] else "failed",
                       "output": t["report"]} for t in self.tasks],
        }


class Prepared:
    """The cases, answers and sandbox package of one assignment for one run (shared by its submissions)."""

    def __init__(self, assignment, seed, workdir):
        self.assignment, self.seed, self.lang = assignment, seed, i18n.language()  # case names are in this language
        streams = np.random.SeedSequence(seed).spawn(len(assignment.tasks))
        self.cases = [TASKS[name].make_cases(np.random.default_rng(s), True)
                      for (name, _, _), s in zip(assignment.tasks, streams)]
        blocked = sorted({q for name, _, _ in assignment.tasks for q in TASKS[name].blocked} | set(ANALYTIC_BLOCK))
        self.package = prepare_package(blocked, list(TASKS), Path(workdir) / f"pkg-{assignment.id}")
        self._expected = None
        self._lock = threading.Lock()

    def expected(self):
        """The exact answers, per task and case (computed once, on first use)."""
        with self._lock:
            if self._expected is None:
                self._expected = [[TASKS[name].expected(c) for c in cases]
                                  for (name, _, _), cases in zip(self.assignment.tasks, self.cases)]
            return self._expected

    def spec(self, notebook, out, cell_timeout, case_timeout):
        return {"notebook": str(notebook), "out": str(out), "cell_timeout": cell_timeout, "case_timeout": case_timeout,
                "tasks": [{"task": name, "object": obj, "protocol": TASKS[name].protocol,
                           "cases": [encode_args(c.args) for c in cases]}
                          for (name, obj, _), cases in zip(self.assignment.tasks, self.cases)]}


def _read_results(path, n):
    """The outcome of each case from the sandbox's JSON lines (the last line per index counts)."""
    found = {}
    if path.is_file() and path.stat().st_size <= MAX_RESULTS:
        for line in path.read_text(errors="replace").splitlines():
            try:
                item = json.loads(line)
            except ValueError:
                continue
            if isinstance(item, dict) and isinstance(item.get("index"), int) and 0 <= item["index"] < n:
                found[item["index"]] = item
    return found


def _grade_in_sandbox(raw, prepared, *, timeout, check_timeout, total_timeout, memory, use_sandbox):
    """Run the submission ``raw`` in a sandbox; return (outcomes per task, cell info, missing protections, note)."""
    with tempfile.TemporaryDirectory(prefix="lab-grade-") as tmp:
        work = Path(tmp) / "work"
        (work / "out").mkdir(parents=True)
        box = Sandbox(prepared.package, work, memory=memory, use_bwrap=use_sandbox, lang=prepared.lang)
        inside = box.inside
        (work / "submission.ipynb").write_bytes(raw)
        spec = prepared.spec(inside / "submission.ipynb", inside / "out", timeout, check_timeout)
        (work / "spec.json").write_text(json.dumps(spec))
        result = {}

        def run():
            result["run"] = box.run([sys.executable, "-m", "lab.teaching.child", str(inside / "spec.json")],
                                    total_timeout)

        worker = threading.Thread(target=run)
        worker.start()
        prepared.expected()  # the answers, while the sandbox runs
        worker.join()
        code, timed_out, stderr = result["run"]
        outcomes = [_read_results(work / "out" / f"task-{k}.jsonl", len(cases)) for k, cases in enumerate(prepared.cases)]
        try:
            info = json.loads((work / "out" / "cells.json").read_text())
            cell_errors = [e for e in info["cell_errors"] if isinstance(e, dict)][:200]
        except (OSError, ValueError, KeyError, TypeError):
            cell_errors = []
        note = ""
        if timed_out:
            note = _("the submission was stopped after {seconds} s (its time limit); cases not reached score 0").format(
                seconds=f"{total_timeout:g}")
        elif code != 0 and not (work / "out" / "cells.json").exists():
            note = _("the graded run ended abnormally (exit status {code}): {stderr}").format(
                code=code, stderr=stderr.strip()[-300:])
        return outcomes, cell_errors, box.missing, note


def grade_notebook(path, *, assignment=None, seed=None, timeout=60, check_timeout=10.0, total_timeout=600,
                   memory=MEMORY, sandbox=None, prepared=None):
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
    memory : int
        Memory limit (writable data) per process in the sandbox, bytes.
    sandbox : bool, optional
        Use bubblewrap (default: when it works here); without it, limits and a process group only.
    prepared : Prepared, optional
        Cases and answers shared by a folder run.
    """
    start = time.perf_counter()
    path = Path(path)
    result = GradeResult(str(path), lang=i18n.language())
    try:
        if path.stat().st_size > MAX_NOTEBOOK:
            raise ValueError(_("the notebook is larger than {size} MiB").format(size=MAX_NOTEBOOK >> 20))
        raw = path.read_bytes()
        nb = nbformat.reads(raw.decode("utf-8"), as_version=4)
    except Exception as exc:  # unreadable notebook: a result, not a crash
        result.error = _("cannot read the notebook: {error}").format(error=f"{type(exc).__name__}: {exc}")
        return result
    result.lang = submission_language(nb)
    with i18n.using(result.lang):
        try:
            found, result.notes = _assignments.for_submission(nb, path, assignment)
        except _assignments.AssignmentError as exc:
            result.error = str(exc)
            return result
        own = None
        if prepared is None or prepared.assignment != found or prepared.lang != result.lang:
            own = tempfile.mkdtemp(prefix="lab-grade-pkg-")
            prepared = Prepared(found, secrets.randbelow(2**32) if seed is None else int(seed), own)
        try:
            result.assignment, result.seed = found.id, prepared.seed
            outcomes, result.cell_errors, result.missing_protections, note = _grade_in_sandbox(
                raw, prepared, timeout=timeout, check_timeout=check_timeout, total_timeout=total_timeout,
                memory=memory, use_sandbox=sandbox)
            expected = prepared.expected()
        finally:
            if own is not None:
                shutil.rmtree(own, ignore_errors=True)
        if note:
            result.notes.append(note)
        for k, (name, obj, points) in enumerate(found.tasks):
            task = TASKS[name]
            judged = []
            for i, case in enumerate(prepared.cases[k]):
                out = outcomes[k].get(i, {"status": "not run", "message": _("the graded run ended before this case")})
                judged.append(judge_outcome(task, case, out, lambda k=k, i=i: expected[k][i]))
            report = build_report(task, prepared.cases[k], judged, graded=True, seed=prepared.seed)
            result.tasks.append({**report.to_dict(), "object": obj, "points": points, "report": str(report)})
    result.seconds = time.perf_counter() - start
    return result


def submission_language(nb):
    """The language a submission is graded and reported in: its metadata ``lab.lang``, else the current one."""
    meta = nb.metadata.get("lab") if isinstance(nb.metadata.get("lab"), dict) else {}
    lang = str(meta.get("lang", ""))
    return lang if lang in i18n.LANGUAGES else i18n.language()


def _student(folder, nb_path):
    rel = nb_path.relative_to(folder)
    return (rel.parts[0] if len(rel.parts) > 1 else nb_path.stem), rel


def _write_atomic(path, text):
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def grade_folder(folder, out_dir, *, jobs=None, assignment=None, seed=None, fmt="text", **kwargs):
    """Grade every notebook under ``folder`` in parallel sandboxes; write reports and ``summary.csv`` to ``out_dir``.

    A submission is ``folder/<student>.ipynb`` or ``folder/<student>/<notebook>.ipynb``.  One seed serves
    the whole run (recorded in every report).  Nothing is written until every sandbox has ended.
    """
    folder, out_dir = Path(folder).resolve(), Path(out_dir)
    notebooks = sorted(p for p in folder.rglob("*.ipynb")
                       if ".ipynb_checkpoints" not in p.parts and not p.resolve().is_relative_to(out_dir.resolve()))
    seed = secrets.randbelow(2**32) if seed is None else int(seed)
    jobs = max(1, jobs or os.cpu_count() or 1)
    tmp = tempfile.mkdtemp(prefix="lab-grade-pkg-")
    prepared, lock = {}, threading.Lock()

    def one(nb_path):
        try:
            nb = nbformat.read(str(nb_path), as_version=4)
            found, _notes = _assignments.for_submission(nb, nb_path, assignment)
        except Exception:  # grade_notebook reports it
            return grade_notebook(nb_path, assignment=assignment, seed=seed, **kwargs)
        lang = submission_language(nb)
        with lock, i18n.using(lang):
            if (found.id, lang) not in prepared:
                prepared[found.id, lang] = Prepared(found, seed, tmp)
        return grade_notebook(nb_path, assignment=assignment, prepared=prepared[found.id, lang], **kwargs)

    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(one, notebooks))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows = []
    for nb_path, res in zip(notebooks, results):
        student, rel = _student(folder, nb_path)
        res.notebook = str(rel)
        stem = "__".join(rel.with_suffix("").parts)
        _write_atomic(out_dir / f"{stem}.json", json.dumps(res.to_dict(), indent=2, ensure_ascii=False))
        _write_atomic(out_dir / f"{stem}.txt", res.text() + "\n")
        if fmt == "gradescope":
            _write_atomic(out_dir / f"{stem}.results.json", json.dumps(res.gradescope(), indent=2, ensure_ascii=False))
        tasks = "; ".join(f"{t['task']}={t['points'] * t['score']:.4g}/{t['points']:g}" for t in res.tasks)
        rows.append([student, str(rel), res.score, res.max_score, res.passed, res.assignment, res.seed, tasks,
                     res.error])
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["student", "notebook", "score", "max_score", "passed", "assignment", "seed", "tasks", "error"])
    w.writerows(rows)
    _write_atomic(out_dir / "summary.csv", buf.getvalue())
    return results


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab grade",
        description="Grade curvature-lab notebooks (one, or a folder of submissions) in a sandbox.")
    parser.add_argument("path", help="a notebook, or a folder of submissions")
    parser.add_argument("--assignment", help="the instructor's notebook, or a folder of them (also its en/, de/; default: exercises/)")
    parser.add_argument("--out", help="folder for the reports and summary.csv (folder mode; default: <path>-reports)")
    parser.add_argument("-j", "--jobs", type=int, default=None, help="submissions graded in parallel (default: all cores)")
    parser.add_argument("--seed", type=int, default=None, help="seed of the cases (default: fresh, recorded in the report)")
    parser.add_argument("--format", choices=("text", "json", "gradescope"), default="text", help="report format")
    parser.add_argument("--json", action="store_true", help="the same as --format json")
    parser.add_argument("--timeout", type=float, default=60, help="seconds per cell (default 60)")
    parser.add_argument("--check-timeout", type=float, default=10, help="seconds per call of the student's code (default 10)")
    parser.add_argument("--total-timeout", type=float, default=600, help="seconds per submission (default 600)")
    parser.add_argument("--memory", type=int, default=MEMORY >> 20, help="MiB of memory (writable data) per process (default 2048)")
    parser.add_argument("--no-sandbox", action="store_true", help="do not use bubblewrap (limits and a process group only)")
    args = parser.parse_args(argv)
    fmt = "json" if args.json else args.format
    path = Path(args.path)
    if not path.exists():
        parser.error(f"{path} does not exist")
    if args.jobs is not None and args.jobs < 1:
        parser.error(f"--jobs must be at least 1; got {args.jobs}")
    kwargs = {"timeout": args.timeout, "check_timeout": args.check_timeout, "total_timeout": args.total_timeout,
              "memory": args.memory << 20, "sandbox": False if args.no_sandbox else None}
    if path.is_dir():
        out = Path(args.out) if args.out else path.with_name(path.name + "-reports")
        results = grade_folder(path, out, jobs=args.jobs, assignment=args.assignment, seed=args.seed, fmt=fmt, **kwargs)
        if fmt == "json":
            print(json.dumps([r.to_dict() for r in results], indent=2, ensure_ascii=False))
        else:
            for r in results:
                print(f"{r.notebook}: {r.score:g} / {r.max_score:g}" + (f"  ({r.error})" if r.error else ""))
            print(f"reports and summary.csv in {out}")
        return 0 if results and all(r.passed for r in results) else 1
    if path.suffix != ".ipynb":
        parser.error(f"expected a .ipynb notebook or a folder; got {path}")
    result = grade_notebook(path, assignment=args.assignment, seed=args.seed, **kwargs)
    if fmt == "gradescope":
        text = json.dumps(result.gradescope(), indent=2, ensure_ascii=False)
        if args.out:
            Path(args.out).mkdir(parents=True, exist_ok=True)
            _write_atomic(Path(args.out) / "results.json", text)
        else:
            print(text)
    else:
        print(json.dumps(result.to_dict(), indent=2, ensure_ascii=False) if fmt == "json" else result.text())
    return 0 if result.passed else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
