"""The files the course verbs pass to each other, in one place: ``collected.csv`` (``collect`` → ``grade``),
``summary.csv`` (``grade`` → ``gradebook``, ``feedback``), and how every verb writes a file (atomically).

Every cell of these files was written through :func:`lab.teaching.untrusted.csv_cell` (never a spreadsheet formula)
and is read back through :func:`lab.teaching.untrusted.csv_rows` (the quote taken off again), so a student ``'bea`` is
``'bea`` and not ``bea``.
"""

import csv
import io
import os
import threading
from pathlib import Path

from ... import library, repository
from ...i18n import _
from ..untrusted import csv_rows

__all__ = ["COLLECTED_COLUMNS", "SUMMARY_COLUMNS", "NotACourseRepository", "course_repository", "one_per_student",
           "read_collected", "read_roster", "read_summary", "read_text", "summary_rows", "write_atomic"]

#: The columns of ``SUBS/collected.csv``, written by ``collect``.
COLLECTED_COLUMNS = ("student", "assignment", "status", "file", "submitted", "modified", "changed", "first_seen",
                     "deadline", "late", "late_seconds", "sha256", "bytes", "note")
#: The columns of ``REPORTS/summary.csv``, written by ``grade``.
SUMMARY_COLUMNS = ("student", "notebook", "score", "max_score", "passed", "assignment", "seed", "tasks", "error",
                   "submitted", "late", "late_seconds", "notes", "missing_protections")


class NotACourseRepository(RuntimeError):
    """A course command run where there is no course repository (the lab installed with pip)."""


def course_repository(verb):
    """The course repository the lab runs from (a checkout with ``solutions/`` and ``pyproject.toml``), for the
    command ``verb``; raises :class:`NotACourseRepository` saying so, and what a self-learner runs instead, where the
    lab is an installed package."""
    root = Path(repository())
    if (root / "solutions").is_dir() and (root / "pyproject.toml").is_file():
        return root
    raise NotACourseRepository(
        f"curvature-lab {verb} works in a course repository (a checkout of curvature-lab, with solutions/ and "
        f"pyproject.toml); here the lab is an installed package ({library()}). To work on the exercises, run "
        "curvature-lab start; to run a course, clone the repository and run the command there")


def write_atomic(path, text):
    """Write ``text`` to ``path`` through a temporary file in the same folder and a rename."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def read_text(path, error=ValueError):
    """The text of ``path`` in UTF-8 (a byte order mark dropped); bytes that are not UTF-8 raise ``error`` naming the
    file and where (issue 35: not Python's UnicodeDecodeError)."""
    data = Path(path).read_bytes()
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error(_("{path}: not a UTF-8 text file (byte {position} is {byte}); save it as UTF-8 text (in a "
                      "spreadsheet: CSV UTF-8)").format(path=path, position=exc.start,
                                                       byte=f"0x{data[exc.start]:02x}")) from None


def read_roster(path, error=ValueError):
    """User names from a roster file (``collect --students``, ``release --per-student``): one per line (``#`` starts a
    comment line), or a CSV with a column ``username`` (or ``student``, ``login``, ``SIS Login ID``); a CSV without
    one raises ``error``."""
    text = read_text(path, error)
    rows = list(csv.reader(io.StringIO(text)))
    if rows and len(rows[0]) > 1:
        head = [h.strip().lower() for h in rows[0]]
        col = next((head.index(k) for k in ("username", "student", "login", "sis login id") if k in head), None)
        if col is None:
            raise error(f"{path}: a CSV roster needs a column 'username'; got {rows[0]}")
        return [r[col].strip() for r in rows[1:] if len(r) > col and r[col].strip()]
    return [line.strip() for line in text.splitlines() if line.strip() and not line.startswith("#")]


def read_collected(folder):
    """``{student: row}`` of ``folder/collected.csv`` (written by ``collect``), or {} (none, or a symbolic link)."""
    path = Path(folder) / "collected.csv"
    if not path.is_file() or path.is_symlink():
        return {}
    with open(path, newline="") as fh:
        return {row.get("student", ""): row for row in csv_rows(fh)}


def read_summary(path):
    """The rows of a ``summary.csv`` as dicts of text (numbers left for the caller)."""
    with open(path, newline="") as fh:
        return csv_rows(fh)


def summary_rows(folder):
    """``(student, row)`` of each row of ``folder/summary.csv``, the user name as it is."""
    return [(row.get("student", ""), row) for row in read_summary(Path(folder) / "summary.csv")]


def one_per_student(items):
    """``(chosen, conflicts)`` of ``(folder, student, assignment, score, item)``.

    ``chosen``: ``{(student, assignment): item}``; of several items of one folder (a student who handed in two
    notebooks) the better score counts.  ``conflicts``: ``{(student, assignment): [folder, folder, …]}`` of a
    student's assignment in two or more folders (in the order given), left out of ``chosen``: the order of the
    folders must not decide a grade, so that student's assignment counts nothing until only one folder is passed
    (the caller says so, for that student alone)."""
    found, where = {}, {}
    for folder, student, aid, score, item in items:
        folders = where.setdefault((student, aid), [])
        if not any(Path(f).resolve() == Path(folder).resolve() for f in folders):
            folders.append(folder)
        old = found.get((student, aid))
        if old is None or score > old[0]:
            found[student, aid] = (score, item)
    conflicts = {key: folders for key, folders in where.items() if len(folders) > 1}
    return {key: item for key, (_score, item) in found.items() if key not in conflicts}, conflicts
