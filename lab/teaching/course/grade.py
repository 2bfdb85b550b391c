"""``curvature-lab grade``: a notebook, or a folder of submissions (``curvature-lab grade SUBS --out REPORTS -j N
[--resume]``).

A submission is ``SUBS/<student>/<notebook>.ipynb`` (what ``curvature-lab collect`` writes) or
``SUBS/<student>.ipynb``.  Every notebook is graded by :func:`lab.teaching.grader.notebook.grade_notebook` in its own
sandbox, ``jobs`` at a time, with one seed for the whole run:

* **Only plain files** are graded: a symbolic link (to a classmate's notebook, the solution, a host file),
  a file with further hard links, a FIFO or a device is refused and reported, never read.  A notebook is
  size-checked on the open file before it is parsed.
* **One failure stops nothing**: a submission that crashes the grader itself becomes that submission's
  error (the traceback, naming the notebook, goes to stderr); the others are graded.
* **Names are data, not paths**: a student (the folder ``SUBS/<student>``, the file ``SUBS/<student>.ipynb``)
  must be a user name (:func:`~lab.teaching.untrusted.student_id`); ``..`` (a file ``...ipynb``), a leading dot,
  a line break or an invisible character is refused like a symbolic link, with the name escaped.  Names are
  kept raw in the results and quoted only in a spreadsheet cell (``'bea`` and ``bea`` stay two students); a
  file name's newline never makes a line of a report or of the output.
* **Reports are written as soon as a submission is done**, each atomically into the report folder opened once,
  by a single file name (``<name>.json``, ``<name>.txt``, for Gradescope ``<name>.results.json``); names are
  made unique when two submissions would share one, and never take a name of the run's own files (``run``,
  ``summary``, ``collected``, ``written-*``, ``*.results``: a flat ``run.ipynb`` reports as ``run~2``); either is
  noted.  A report that cannot be written is noted and stops nothing.  ``run.json`` records the seed and the
  assignment, so ``--resume`` after a crash or a stop grades only what has no report yet (or whose notebook
  changed); ``summary.csv`` is written at the end from every report.
* **No silent fallback**: where bubblewrap cannot run, a folder is graded only with ``--no-sandbox``; the
  protections missing are printed on stderr and listed in ``summary.csv``.
* ``summary.csv`` has a row per submission and per refused file (columns :data:`SUMMARY_COLUMNS`); every
  cell is cleaned and can never be a spreadsheet formula (read it back with :func:`read_summary`).  With
  ``SUBS/collected.csv`` (from ``collect``) the hand-in time and lateness of each student are copied into it.
* **Per-student surfaces**: ``--variants variants.json`` (the table of ``release --per-student``) grades each
  student's per-student tasks on the student's own variant (the folder ``SUBS/<student>``; ``--student`` for one
  notebook) and notes numbers that answer a classmate's variant; a notebook of a per-student hand-out graded
  without the table is an error that says so.  ``run.json`` records the table's id: ``--resume`` needs the same.
"""

import argparse
import concurrent.futures
import csv
import hashlib
import io
import json
import math
import os
import secrets
import shutil
import sys
import tempfile
import threading
import traceback
from pathlib import Path

from ... import i18n
from ...i18n import _
from ..grader import assignments as _assignments
from ..grader.notebook import (
    VISIBILITY,
    GradeResult,
    Prepared,
    _zero_tasks,
    grade_notebook,
    read_submission,
    submission_language,
)
from ..kernel.variants import read_table
from ..sandbox.bubblewrap import DISK, LAB_DIR, MEMORY, bwrap_works, probe
from ..untrusted import UntrustedError, clean, csv_cell, loads, plain_file, read_file, student_id, write_at
from .files import SUMMARY_COLUMNS, read_collected, write_atomic

__all__ = ["GradingError", "find_submissions", "grade_folder", "main", "report_names", "result_line"]



class GradingError(ValueError):
    """A folder run that cannot start (nothing to grade, no sandbox, a resume that does not match)."""


def find_submissions(folder, skip=None):
    """``(notebooks, refused)`` under ``folder``: plain ``.ipynb`` files, and ``(path, reason)`` of those refused.

    Folders are walked without following symbolic links; ``.ipynb_checkpoints`` and ``skip`` (the reports
    folder) are left out.  A notebook whose student (its folder ``SUBS/<student>``, or the file
    ``SUBS/<student>.ipynb``) is no user name (:func:`~lab.teaching.untrusted.student_id`: ``..``, a leading dot,
    a line break, an invisible character, …) is refused, never graded.
    """
    folder = Path(folder)
    skip = Path(skip).resolve() if skip is not None else None
    notebooks, refused = [], []
    for here, dirs, files in os.walk(folder, followlinks=False):
        here = Path(here)
        dirs[:] = sorted(d for d in dirs if d != ".ipynb_checkpoints" and (skip is None or (here / d).resolve() != skip))
        for d in list(dirs):
            if (here / d).is_symlink():
                dirs.remove(d)
                refused.append((here / d, _name_problem(folder, here / d) or "a symbolic link"))
        for name in sorted(files):
            path = here / name
            if not name.endswith(".ipynb"):
                continue
            why = _name_problem(folder, path) or plain_file(path, folder)
            (refused.append((path, why)) if why else notebooks.append(path))
    return notebooks, refused


def _student(folder, path):
    """``(student, path relative to folder)``: the first folder below ``folder``, or a flat file's name without
    ``.ipynb``; raw (check it with :func:`_name_problem`)."""
    rel = Path(path).relative_to(folder)
    return (rel.parts[0] if len(rel.parts) > 1 else rel.name.removesuffix(".ipynb")), rel


def _name_problem(folder, path):
    """Why the student of ``path`` is no user name, or None."""
    try:
        student_id(_student(folder, path)[0])
    except UntrustedError as exc:
        return str(exc)
    return None


def _shown(text):
    """A name that is no user name, as reports and summary.csv show it: escaped, one line."""
    return clean(text, 300, keep_newlines=False)


#: Report names a folder run keeps for its own files (``run.json``, ``summary.csv``), and for the files ``collect``
#: writes into a folder of submissions (``collected.csv``, ``written-<id>.csv``); compared in lower case.
RESERVED = ("run", "summary", "collected")
#: Longest report stem (bytes): with ``~N``, ``.results.json`` and a temporary name's 22 bytes far below 255.
MAX_STEM = 150


def _reserved(stem):
    low = stem.lower()
    return low in RESERVED or low.startswith(("written-", ".")) or low.endswith(".results")


def _stem(text):
    """A report stem of ``text``: letters, digits and ``._-`` (others ``_``), no leading dot, at most
    :data:`MAX_STEM` bytes."""
    stem = "".join(c if c.isalnum() or c in "._-" else "_" for c in text)
    stem = "_" + stem[1:] if stem.startswith(".") else stem
    return stem.encode()[:MAX_STEM].decode("utf-8", "ignore") or "submission"


def _take(stem, used):
    """``(stem made unique among used and not reserved, note or "")``; adds it to ``used``."""
    unique, k = stem, 1
    while unique.lower() in used or (unique == stem and _reserved(stem)):
        k += 1
        unique = f"{stem}~{k}"
    used.add(unique.lower())
    if unique == stem:
        return unique, ""
    if _reserved(stem):
        return unique, _("its report name {stem} is reserved for the files of the folder run (run.json, summary.csv): "
                         "{unique}").format(stem=repr(stem), unique=repr(unique))
    return unique, _("its report name {stem} was taken by another submission: {unique}").format(
        stem=repr(stem), unique=repr(unique))


def report_names(folder, paths, used=None):
    """``{path: (report stem, note or "")}``: ``student__notebook`` (a flat file: its name), made unique where two
    would collide, never a name of the run's own files (:data:`RESERVED`, ``*.results``; these get ``~2``).
    ``used``: the stems taken so far (lower case; filled in)."""
    names, used = {}, set() if used is None else used
    for path in paths:
        _student_name, rel = _student(folder, path)
        names[path] = _take(_stem("__".join(rel.with_suffix("").parts)), used)
    return names


def _summary_row(student, rel, res, collected):
    late = collected.get(student, {})
    tasks = "; ".join(f"{t['task']}={t['points'] * t['score']:.4g}/{t['points']:g}" for t in res.tasks)
    values = {"student": student, "notebook": str(rel), "score": res.score, "max_score": res.max_score,
              "passed": res.passed, "assignment": res.assignment, "seed": res.seed, "tasks": tasks,
              "error": res.error, "submitted": late.get("submitted", ""), "late": late.get("late", ""),
              "late_seconds": late.get("late_seconds", ""), "notes": " | ".join(res.notes + res.private_notes),
              "missing_protections": "; ".join(res.missing_protections)}
    return [csv_cell(values[c]) for c in SUMMARY_COLUMNS]


def _open_out(out_dir):
    """A descriptor of the report folder (the instructor's path: a link to it is followed); every report is
    written relative to it."""
    return os.open(out_dir, os.O_RDONLY | os.O_DIRECTORY | getattr(os, "O_CLOEXEC", 0))


def _run_record(out_dir, seed, assignment, resume, *, dir_fd=None, variants=None):
    """The seed of the run: from ``run.json`` when resuming (it must agree with ``seed`` if given, and was graded
    with the same variants table, id ``variants``).

    ``dir_fd``: the open report folder (else ``out_dir`` is opened)."""
    fd = _open_out(out_dir) if dir_fd is None else dir_fd
    try:
        return _run_record_at(fd, out_dir, seed, assignment, resume, variants)
    finally:
        if dir_fd is None:
            os.close(fd)


def _run_record_at(fd, out_dir, seed, assignment, resume, variants=None):
    try:
        os.stat("run.json", dir_fd=fd, follow_symlinks=False)
        exists = True
    except FileNotFoundError:
        exists = False
    if resume and exists:
        try:
            old = loads(read_file("run.json", 1 << 20, dir_fd=fd))
            if not isinstance(old, dict) or not isinstance(old.get("seed"), int):
                raise UntrustedError("no seed in it")
        except UntrustedError as exc:
            raise GradingError(f"--resume: {out_dir}/run.json is not the record of a run of curvature-lab grade "
                               f"({exc})") from None
        if seed is not None and int(seed) != old["seed"]:
            raise GradingError(f"--resume: the reports in {out_dir} were graded with seed {old['seed']}, not {seed}")
        if _assignment_key(assignment) != (None if old.get("assignment") in (None, "None") else old["assignment"]):
            raise GradingError(f"--resume: the reports in {out_dir} were graded against {old.get('assignment')}, "
                               f"not {assignment}")
        if old.get("variants") != variants:
            raise GradingError(f"--resume: the reports in {out_dir} were graded with the variants table "
                               f"{old.get('variants')}, not {variants}")
        return old["seed"]
    seed = secrets.randbelow(2**32) if seed is None else int(seed)
    record = {"seed": seed, "assignment": _assignment_key(assignment)}
    write_at(fd, "run.json", json.dumps(record if variants is None else {**record, "variants": variants}))
    return seed


def _assignment_key(assignment):
    """How run.json records ``--assignment``: its path as text, or null for the project's exercises."""
    return None if assignment is None else str(assignment)


#: Largest report read back by ``--resume`` (bytes).
MAX_REPORT_FILE = 64 << 20


def _resumed(path, stem, out_fd, seed):
    """The result already in the report folder ``out_fd`` for this notebook (same seed, same bytes), or None."""
    try:
        data = loads(read_file(f"{stem}.json", MAX_REPORT_FILE, dir_fd=out_fd), constants=True)
        raw, _nb = read_submission(path)
    except (ValueError, OSError):
        return None
    if not isinstance(data, dict) or data.get("seed") != seed or data.get("sha256") != hashlib.sha256(raw).hexdigest():
        return None
    try:
        return GradeResult.from_dict(data)
    except TypeError:
        return None


def grade_folder(folder, out_dir, *, jobs=None, assignment=None, seed=None, fmt="text", resume=False,
                 visibility="visible", sandbox=None, log=sys.stderr, variants=None, **kwargs):
    """Grade every notebook under ``folder`` in parallel sandboxes; reports and ``summary.csv`` into ``out_dir``.

    Returns the results, in the order of the submissions.  ``variants``: the table of a per-student release (a
    :class:`~lab.teaching.kernel.variants.Table`, or the path of its file).  See the module docstring.
    """
    if variants is not None and not hasattr(variants, "students"):
        try:
            variants = read_table(variants)
        except (OSError, ValueError) as exc:
            raise GradingError(f"--variants: {exc}") from None
    folder, out_dir = Path(folder).resolve(), Path(out_dir)
    if not folder.is_dir():
        raise GradingError(f"{folder} is not a folder of submissions")
    if sandbox is None and not bwrap_works():
        raise GradingError("bubblewrap (bwrap) cannot run here, so a submission could read the course's files and "
                           "the other submissions. Install it (apt install bubblewrap) or, knowing this, pass "
                           "--no-sandbox")
    out_dir.mkdir(parents=True, exist_ok=True)
    notebooks, refused = find_submissions(folder, skip=out_dir)
    if not notebooks and not refused:
        raise GradingError(f"no notebooks (.ipynb) in {folder}")
    broken, lacking = probe(use_bwrap=sandbox)
    if broken is not None:
        raise GradingError(f"the sandbox cannot start a submission's kernel here ({sys.executable} with the lab "
                           f"in {LAB_DIR}), so every student would get 0 points; nothing was graded. Check the "
                           f"installation. The sandbox said:\n{broken}")
    if lacking and sandbox is not False:
        raise GradingError("the sandbox lacks protections that a submission could use against the grading machine "
                           "or the other students: " + "; ".join(lacking) + ". Nothing was graded. Fix the "
                           "installation (see the instructors' guide on the sandbox) or, knowing this, pass "
                           "--no-sandbox")
    used = set()
    names = report_names(folder, notebooks + [p for p, _ in refused], used)
    out_fd = _open_out(out_dir)
    try:
        seed = _run_record(out_dir, seed, assignment, resume, dir_fd=out_fd,
                           variants=None if variants is None else variants.id)
        results = _grade_all(folder, out_fd, notebooks, refused, names, used, jobs=jobs, assignment=assignment,
                             seed=seed, fmt=fmt, resume=resume, visibility=visibility, sandbox=sandbox, log=log,
                             variants=variants, **kwargs)
    finally:
        os.close(out_fd)
    return results


def _grade_all(folder, out_fd, notebooks, refused, names, used, *, jobs, assignment, seed, fmt, resume, visibility,
               sandbox, log, variants=None, **kwargs):
    """The folder run after its checks: grade ``notebooks``, report ``refused``, write every report and
    ``summary.csv`` into the open report folder ``out_fd``."""
    jobs = max(1, jobs or os.cpu_count() or 1)
    tmp = tempfile.mkdtemp(prefix="lab-grade-pkg-")
    prepared, packages, lock = {}, {}, threading.Lock()
    warned = set()

    def one(nb_path):
        stem, note = names[nb_path]
        student, rel = _student(folder, nb_path)
        if resume and (done := _resumed(nb_path, stem, out_fd, seed)) is not None:
            return done
        try:
            try:
                submission = read_submission(nb_path)
            except ValueError:
                submission = None  # grade_notebook reports it
            shared = None
            if submission is not None:
                lang = submission_language(submission[1])
                with i18n.using(lang):
                    try:
                        found, _notes = _assignments.for_submission(submission[1], nb_path, assignment)
                    except _assignments.AssignmentError:
                        found = None
                    if found is not None:
                        with lock:
                            if found.id not in packages:
                                packages[found.id] = Prepared.package_for(found, tmp)
                            if (found.id, lang) not in prepared:
                                prepared[found.id, lang] = Prepared(found, seed, packages[found.id], variants)
                            shared = prepared[found.id, lang]
            res = grade_notebook(nb_path, assignment=assignment, seed=seed, prepared=shared, submission=submission,
                                 sandbox=sandbox, variants=variants, student=student, **kwargs)
        except Exception as exc:  # noqa: BLE001 - one submission's failure never stops the others
            print(f"curvature-lab grade: internal error while grading {_shown(str(rel))}:\n{traceback.format_exc()}",
                  file=log)
            res = GradeResult(str(rel), error=_("internal error of the grader while grading this notebook ({error}); "
                                                "it scores 0 here, grade it again alone").format(
                                                    error=clean(f"{type(exc).__name__}: {exc}", 300)))
        res.notebook, res.student = str(rel), student
        if note:
            res.notes.append(note)
        for what in res.missing_protections:
            if what not in warned:
                warned.add(what)
                print(f"curvature-lab grade: warning: missing protection: {what}", file=log)
        _write_reports(out_fd, stem, res, fmt, visibility, log)
        return res

    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(one, notebooks))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    for path, why in refused:
        student, rel = _student(folder, path)
        if _name_problem(folder, path) is None:
            error = _("refused: {why}; a submission must be a plain notebook file").format(why=why)
        else:  # no user name: shown escaped, never part of a path
            student, rel = _shown(student), _shown(str(rel))
            error = _("refused: {why}; a submission is SUBS/<user name>/<notebook>.ipynb or SUBS/<user name>.ipynb"
                      ).format(why=why)
        res = GradeResult(str(rel), student=student, error=error)
        with i18n.using("en"):
            _write_reports(out_fd, names[path][0], res, fmt, visibility, log)
        results.append(res)
    collected = read_collected(folder)
    graded = {r.student for r in results}
    for student, row in sorted(collected.items()):
        if row.get("status") != "collected" and student not in graded:  # listed by collect: no submission
            results.append(_missing(student, row, assignment, out_fd, fmt, visibility, used, log, variants))
    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow(SUMMARY_COLUMNS)
    for res in results:
        writer.writerow(_summary_row(res.student, res.notebook, res, collected))
    write_at(out_fd, "summary.csv", buf.getvalue())
    return results


def _missing(student, row, assignment, out_fd, fmt, visibility, used, log=sys.stderr, variants=None):
    """The result of a student ``collect`` found no notebook for: 0 out of the assignment's points."""
    aid = row.get("assignment", "")
    try:
        student_id(student)
    except UntrustedError:
        student = _shown(student)
    res = GradeResult("", student=student, assignment=aid,
                      error=_("no submission ({status}{note})").format(status=row.get("status", "missing"),
                                                                      note=f": {row['note']}" if row.get("note") else ""))
    try:
        found = _assignments.for_path(f"{aid}.ipynb", assignment)
    except _assignments.AssignmentError:
        found = None
    if found is not None:
        res.assignment, res.tasks = found.id, _zero_tasks(found, res.error, found.graded(variants is not None))
    stem, _note = _take(_stem(f"{student}__{aid}"), used)
    with i18n.using("en"):
        _write_reports(out_fd, stem, res, fmt, visibility, log)
    return res


def _write_reports(out_fd, stem, res, fmt, visibility, log=sys.stderr):
    """The reports of ``res`` into the open report folder: ``<stem>.json``, ``.txt`` (and ``.results.json``).  A
    report that cannot be written is said on ``log`` and in the result's notes; it stops nothing."""
    try:
        write_at(out_fd, f"{stem}.json", json.dumps(res.to_dict(), indent=2, ensure_ascii=False))
        write_at(out_fd, f"{stem}.txt", res.text() + "\n")
        if fmt == "gradescope":
            write_at(out_fd, f"{stem}.results.json", json.dumps(res.gradescope(visibility), indent=2,
                                                                 ensure_ascii=False))
    except (OSError, ValueError) as exc:
        message = _("the report {name} could not be written: {error}").format(
            name=f"{stem}.json", error=clean(exc, 300, keep_newlines=False))
        print(f"curvature-lab grade: {_shown(res.notebook or res.student)}: {message}", file=log)
        res.notes.append(message)


def result_line(res):
    """The line ``grade`` prints per submission: the notebook (the student where there is none), the score, an error."""
    return clean(f"{res.notebook or res.student}: {res.score:g} / {res.max_score:g}"
                 + (f"  ({res.error})" if res.error else ""), 400, keep_newlines=False)


def _positive(kind):
    def parse(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number; got {text!r}") from None
        if not math.isfinite(value) or value <= 0:
            raise argparse.ArgumentTypeError(f"expected a positive number; got {text!r}")
        return value

    return parse


def build_parser():
    parser = argparse.ArgumentParser(
        prog="curvature-lab grade",
        description=_("Grade curvature-lab notebooks (one, or a folder of submissions) in a sandbox. A folder is "
                    "SUBS/<student>/<assignment>.ipynb (as `curvature-lab collect` writes it) or SUBS/<student>.ipynb."))
    parser.add_argument("path", help=_("a notebook, or a folder of submissions"))
    parser.add_argument("--assignment", help=_("the instructor's notebook, or a folder of them (also its en/, de/; "
                                             "default: exercises/)"))
    parser.add_argument("--out", help=_("folder for the reports and summary.csv (folder mode; default: <path>-reports; "
                                      "a notebook with --format gradescope: where results.json goes)"))
    parser.add_argument("-j", "--jobs", type=int, default=None, help=_("submissions graded in parallel (default: all cores)"))
    parser.add_argument("--seed", type=int, default=None, help=_("seed of the cases (default: fresh, recorded in the report)"))
    parser.add_argument("--resume", action="store_true",
                        help=_("folder mode: keep the reports of an interrupted run (same seed, same notebooks), grade "
                             "the rest"))
    parser.add_argument("--format", choices=("text", "json", "gradescope"), default="text", help=_("report format"))
    parser.add_argument("--json", action="store_true", help=_("the same as --format json"))
    parser.add_argument("--visibility", choices=VISIBILITY, default="visible",
                        help=_("Gradescope: when students see the results (default: visible)"))
    parser.add_argument("--timeout", type=_positive(float), default=60, help=_("seconds per cell (default 60)"))
    parser.add_argument("--check-timeout", type=_positive(float), default=10,
                        help=_("seconds per call of the student's code (default 10)"))
    parser.add_argument("--total-timeout", type=_positive(float), default=600,
                        help=_("seconds per submission (default 600)"))
    parser.add_argument("--memory", type=_positive(int), default=MEMORY >> 20,
                        help=_("MiB of memory per submission, all its processes and files together (default 2048)"))
    parser.add_argument("--disk", type=_positive(int), default=DISK >> 20,
                        help=_("MiB a submission may write (default 512)"))
    parser.add_argument("--variants", metavar="FILE",
                        help=_("the variants table of a per-student release (variants.json of the hand-out): grade "
                               "each student's per-student tasks on the student's own surface"))
    parser.add_argument("--student", help=_("one notebook with --variants: whose variant it is (a folder: the "
                                            "folder SUBS/<student>)"))
    parser.add_argument("--no-sandbox", action="store_true",
                        help=_("grade without bubblewrap (limits and a process group only: the submission can read "
                             "the course's files); required to grade a folder where bubblewrap cannot run"))
    return parser


def main(argv=None):
    parser = build_parser()
    args = parser.parse_args(argv)
    fmt = "json" if args.json else args.format
    path = Path(args.path)
    if not path.exists():
        parser.error(f"{path} does not exist")
    if args.jobs is not None and args.jobs < 1:
        parser.error(f"--jobs must be at least 1; got {args.jobs}")
    if args.memory < 256:
        parser.error(f"--memory must be at least 256 (MiB; a kernel needs about 200); got {args.memory}")
    if args.disk < 16:
        parser.error(f"--disk must be at least 16 (MiB); got {args.disk}")
    kwargs = {"timeout": args.timeout, "check_timeout": args.check_timeout, "total_timeout": args.total_timeout,
              "memory": args.memory << 20, "disk": args.disk << 20, "sandbox": False if args.no_sandbox else None}
    variants = None
    if args.variants:
        try:
            variants = read_table(args.variants)
        except (OSError, ValueError) as exc:
            print(f"curvature-lab grade: error: --variants: {exc}", file=sys.stderr)
            return 2
    if path.is_dir() and args.student:
        parser.error("--student names the student of one notebook; a folder's students are its folders")
    if variants is not None and not path.is_dir() and not args.student:
        parser.error("--variants with one notebook needs --student (whose variant it is)")
    if variants is not None:
        kwargs["variants"] = variants
    if path.is_dir():
        out = Path(args.out) if args.out else path.with_name(path.name + "-reports")
        try:
            results = grade_folder(path, out, jobs=args.jobs, assignment=args.assignment, seed=args.seed,
                                         fmt=fmt, resume=args.resume, visibility=args.visibility, **kwargs)
        except GradingError as exc:
            print(f"curvature-lab grade: error: {exc}", file=sys.stderr)
            return 2
        if fmt == "json":
            print(json.dumps([r.to_dict() for r in results], indent=2, ensure_ascii=False))
        else:
            for r in results:
                print(result_line(r))
            print(_("reports and summary.csv in {out}").format(out=out))
        return 0 if results and all(r.passed for r in results) else 1
    if path.suffix != ".ipynb":
        parser.error(f"expected a .ipynb notebook or a folder; got {path}")
    if args.resume:
        parser.error("--resume applies to a folder of submissions")
    result = grade_notebook(path, assignment=args.assignment, seed=args.seed, student=args.student, **kwargs)
    for what in result.missing_protections:
        print(f"curvature-lab grade: warning: missing protection: {what}", file=sys.stderr)
    if fmt == "gradescope":
        text = json.dumps(result.gradescope(args.visibility), indent=2, ensure_ascii=False)
        if args.out:
            Path(args.out).mkdir(parents=True, exist_ok=True)
            write_atomic(Path(args.out) / "results.json", text)
        else:
            print(text)
    else:
        print(json.dumps(result.to_dict(), indent=2, ensure_ascii=False) if fmt == "json" else result.text())
    return 0 if result.passed else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
