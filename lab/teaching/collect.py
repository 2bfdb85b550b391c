"""Collecting an assignment from the students' homes: ``curvature-lab collect HOMES --assignment ID --deadline ISO
--out SUBS``.

``HOMES`` is a folder with one home per student, named by the user name: the local spawner's ``/home``, or
the hub's home volumes mounted in an admin pod (``deploy/collect.md``).  In each home the notebook of the
assignment is the one whose metadata ``lab.assignment`` is ``ID`` (every exercise carries it, whatever the
student renamed the file to), else one whose file name is ``ID.ipynb``; of several, the one saved last (the
others are noted).  It is copied to ``SUBS/<student>/<ID>.ipynb`` with its modification time, which is the
hand-in time: the time the student last saved it (JupyterLab saves on every change and checkpoint).

``SUBS/collected.csv`` records per student the file, the hand-in time, whether it is late and by how many
seconds, its SHA-256 and size, and a status: ``collected``, ``missing`` (no notebook of the assignment;
also for students of ``--students`` without a home) or ``refused`` (a symbolic link, a hard link, a file
over the size limit).  Free-text answers of the assignment's questions go to ``SUBS/written-<ID>.html`` and
``.csv`` (:mod:`lab.teaching.written`).

A home is only read: files are opened without following links, folders walked without following links
and bounded in depth and number, and nothing in a home is written, renamed or touched.  Collecting again into the same ``SUBS``
replaces the copies it made before, but refuses to overwrite a copy that was changed since (an instructor's
correction), naming it.
"""

import argparse
import csv
import hashlib
import io
import json
import os
import sys
from datetime import datetime, timezone
from pathlib import Path

import nbformat

from .. import i18n
from ..i18n import _
from . import written
from .assignments import DEFAULT_FOLDER
from .grading import MAX_NOTEBOOK, write_atomic
from .untrusted import UntrustedError, clean, csv_cell, plain_file, read_file

__all__ = ["COLLECTED_COLUMNS", "CollectError", "collect", "find_notebook", "main", "parse_deadline"]

COLLECTED_COLUMNS = ("student", "assignment", "status", "file", "submitted", "deadline", "late", "late_seconds",
                     "sha256", "bytes", "note")
#: Folders of a home never searched (caches, installed packages, checkpoints, the feedback the lab returns).
SKIP_DIRS = {".ipynb_checkpoints", ".cache", ".local", ".conda", ".npm", ".ipython", ".jupyter", "node_modules",
             "__pycache__", ".git", ".venv", "venv", "site-packages", "feedback"}
MAX_DEPTH = 6
MAX_FILES = 5000


class CollectError(ValueError):
    """A collection that cannot be made (bad deadline, no homes, a changed copy in the way)."""


def parse_deadline(text):
    """A timezone-aware deadline from ISO 8601 (``2026-12-15T23:59+01:00``, ``…Z``); a time without offset is
    the machine's local time."""
    try:
        when = datetime.fromisoformat(str(text).replace("Z", "+00:00"))
    except ValueError:
        raise CollectError(f"--deadline must be an ISO 8601 time such as 2026-12-15T23:59+01:00; got {text!r}") from None
    return when.astimezone() if when.tzinfo is None else when


def _notebooks(home):
    """Plain-looking ``.ipynb`` paths in ``home``: walked without following links, bounded in depth and count."""
    count = 0
    for here, dirs, files in os.walk(home, followlinks=False):
        depth = len(Path(here).relative_to(home).parts)
        dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith(".") and depth < MAX_DEPTH)
        for name in sorted(files):
            if name.endswith(".ipynb"):
                count += 1
                if count > MAX_FILES:
                    return
                yield Path(here) / name


def _meta_id(raw):
    try:
        nb = nbformat.reads(raw.decode("utf-8"), as_version=4)
    except Exception:  # noqa: BLE001 - an unreadable notebook is simply not this assignment's (by metadata)
        return None, None
    meta = nb.metadata.get("lab") if isinstance(nb.metadata.get("lab"), dict) else {}
    return (str(meta["assignment"]) if "assignment" in meta else None), nb


def find_notebook(home, assignment_id):
    """``(path, raw, notebook, notes)`` of the student's notebook of the assignment in ``home``, or ``(None, …)``.

    Refused files (links, oversized) are returned in the notes; the path is None then if nothing else matched.
    """
    candidates, notes = [], []
    for path in _notebooks(home):
        why = plain_file(path, home)
        if why:
            if path.stem == assignment_id:
                notes.append(f"{path.relative_to(home)} refused: {why}")
            continue
        try:
            raw = read_file(path, MAX_NOTEBOOK)
        except UntrustedError as exc:
            if path.stem == assignment_id:
                notes.append(f"{path.relative_to(home)} refused: {exc}")
            continue
        claimed, nb = _meta_id(raw)
        by_meta, by_name = claimed == assignment_id, path.stem == assignment_id and claimed is None
        if by_meta or by_name:
            candidates.append((0 if by_meta else 1, -os.lstat(path).st_mtime, path, raw, nb))
    if not candidates:
        return None, None, None, notes
    candidates.sort(key=lambda c: (c[0], c[1], str(c[2])))
    _rank, _t, path, raw, nb = candidates[0]
    others = [str(c[2].relative_to(home)) for c in candidates[1:]]
    if others:
        notes.append(f"also found, not collected (saved earlier or matched by file name only): {', '.join(others)}")
    return path, raw, nb, notes


def _students(homes, roster):
    names = sorted(d.name for d in Path(homes).iterdir()
                   if d.is_dir() and not d.is_symlink() and not d.name.startswith(".") and d.name != "lost+found")
    return names, [s for s in roster if s not in names]


def _read_roster(path):
    """User names from a file: one per line, or a CSV with a column ``username`` (or ``student``, ``login``)."""
    text = Path(path).read_text()
    rows = list(csv.reader(io.StringIO(text)))
    if rows and len(rows[0]) > 1:
        head = [h.strip().lower() for h in rows[0]]
        col = next((head.index(k) for k in ("username", "student", "login", "sis login id") if k in head), None)
        if col is None:
            raise CollectError(f"{path}: a CSV roster needs a column 'username'; got {rows[0]}")
        return [r[col].strip() for r in rows[1:] if len(r) > col and r[col].strip()]
    return [line.strip() for line in text.splitlines() if line.strip() and not line.startswith("#")]


def _previous(out_dir):
    path = Path(out_dir) / "collected.csv"
    if not path.is_file():
        return {}
    with open(path, newline="") as fh:
        return {r["student"]: r for r in csv.DictReader(fh)}


def collect(homes, assignment_id, deadline, out_dir, *, roster=(), exercises=DEFAULT_FOLDER, log=sys.stderr):
    """Collect ``assignment_id`` from every home under ``homes`` into ``out_dir``; returns the rows of collected.csv."""
    homes, out_dir = Path(homes), Path(out_dir)
    if not homes.is_dir():
        raise CollectError(f"{homes} is not a folder of homes")
    deadline = parse_deadline(deadline) if not isinstance(deadline, datetime) else deadline
    students, without_home = _students(homes, roster)
    previous = _previous(out_dir)
    plan, rows, answers = [], [], {}
    exercise_nb, exercise_ids = _exercise(exercises, assignment_id)
    questions = written.questions_of(exercise_nb) if exercise_nb is not None else []
    for student in students:
        path, raw, nb, notes = find_notebook(homes / student, assignment_id)
        row = dict.fromkeys(COLLECTED_COLUMNS, "")
        row.update(student=student, assignment=assignment_id, deadline=deadline.isoformat())
        if path is None:
            row.update(status="refused" if notes else "missing", note="; ".join(notes))
            rows.append(row)
            continue
        mtime = os.lstat(path).st_mtime
        submitted = datetime.fromtimestamp(mtime, timezone.utc)
        late = max(0.0, (submitted - deadline).total_seconds())
        digest = hashlib.sha256(raw).hexdigest()
        target = out_dir / student / f"{assignment_id}.ipynb"
        old = previous.get(student)
        if target.exists() and old and hashlib.sha256(target.read_bytes()).hexdigest() != old.get("sha256"):
            raise CollectError(f"{target} was changed since it was collected; move it away to keep it, then collect "
                               "again")
        row.update(status="collected", file=str(path.relative_to(homes / student)), submitted=submitted.isoformat(),
                   late=late > 0, late_seconds=round(late), sha256=digest, bytes=len(raw), note="; ".join(notes))
        plan.append((target, raw, mtime))
        rows.append(row)
        if questions:
            answers[student] = written.answers_of(nb, questions, exercise_ids)
    for student in without_home:
        row = dict.fromkeys(COLLECTED_COLUMNS, "")
        row.update(student=student, assignment=assignment_id, status="missing", deadline=deadline.isoformat(),
                   note="no home")
        rows.append(row)
    out_dir.mkdir(parents=True, exist_ok=True)
    for target, raw, mtime in plan:
        target.parent.mkdir(exist_ok=True)
        tmp = target.with_name(f".{target.name}.tmp")
        tmp.write_bytes(raw)
        os.utime(tmp, (mtime, mtime))
        os.replace(tmp, target)
    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow(COLLECTED_COLUMNS)
    for row in sorted(rows, key=lambda r: r["student"]):
        writer.writerow([csv_cell(row[c]) for c in COLLECTED_COLUMNS])
    write_atomic(out_dir / "collected.csv", buf.getvalue())
    if questions:
        lang = (exercise_nb.metadata.get("lab") or {}).get("lang", "en")
        written.collect_answers(out_dir, assignment_id, exercise_nb, answers, lang)
    missing = [r["student"] for r in rows if r["status"] != "collected"]
    print(_("collected {n} of {total}: {late} late; without a submission: {names}").format(
        n=len(plan), total=len(rows), late=sum(r["late"] is True for r in rows),
        names=", ".join(clean(m, 60) for m in missing) or _("none")), file=log)
    return rows


def _exercise(exercises, assignment_id):
    """The instructor's exercise notebook of the assignment (for its questions) and its cell ids, or (None, ()):
    the one in the instructor's language (``LAB_LANG``) first, so that the written-answer page is in it."""
    where = Path(exercises)
    first = i18n.language()
    for folder in (where, where / first, *(where / lang for lang in i18n.LANGUAGES if lang != first)):
        path = folder / f"{assignment_id}.ipynb"
        if path.is_file():
            nb = nbformat.read(str(path), as_version=4)
            return nb, [c.get("id") for c in nb.cells]
    return None, ()


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab collect",
        description=_("Collect one assignment from the students' homes into a folder of submissions, with hand-in "
                      "times and lateness (SUBS/collected.csv) and the written answers (SUBS/written-ID.html, .csv). "
                      "Homes are only read."))
    parser.add_argument("homes", help=_("folder of homes, one per student named by the user name (e.g. /home)"))
    parser.add_argument("--assignment", required=True, help=_("assignment id, e.g. 05_visualize_curvature"))
    parser.add_argument("--deadline", required=True, help=_("ISO 8601, e.g. 2026-12-15T23:59+01:00 (no offset: local time)"))
    parser.add_argument("--out", required=True, help=_("folder of submissions to write (SUBS)"))
    parser.add_argument("--students", help=_("roster: one user name per line, or a CSV with a column 'username'; "
                                           "students without a home are listed as missing"))
    parser.add_argument("--exercises", default=str(DEFAULT_FOLDER),
                        help=_("the instructor's exercises (for the written questions; default: exercises/)"))
    args = parser.parse_args(argv)
    try:
        roster = _read_roster(args.students) if args.students else ()
        rows = collect(args.homes, args.assignment, args.deadline, args.out, roster=roster, exercises=args.exercises)
    except (CollectError, OSError) as exc:
        print(f"curvature-lab collect: error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps({"collected": sum(r["status"] == "collected" for r in rows), "students": len(rows)}))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
