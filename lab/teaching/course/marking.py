"""The data behind marking written answers (``curvature-lab mark``, :mod:`lab.teaching.course.mark`): the answers of
a folder of submissions, the sheet their marks go to, and the rules that keep two markers from losing each other's
work.

**The sheet** is the ``SUBS/written-<id>.csv`` that ``curvature-lab collect`` wrote (:mod:`.written`): one row per
student and question, whose ``points`` and ``comment`` the marker fills.  ``gradebook --written`` and ``feedback
--written`` read it, and a spreadsheet can still edit it.  Every save is one :func:`save`: under an exclusive lock
of ``SUBS/.written-<id>.csv.lock`` (where the system has ``fcntl``), the sheet is read again, and a mark is written
only where the sheet still holds what the marker's panel read (``expected``); a mark that another marker, or a
spreadsheet, changed since is returned as a conflict and not overwritten.  The new sheet replaces the old one by a
rename (:func:`~lab.teaching.course.files.write_atomic`): a reader never sees half a file.

**The answers** come from the submissions (``SUBS/<student>/<id>.ipynb``), as the student wrote them, Markdown and
math with line breaks (the sheet keeps each answer on one line); read with the limits of untrusted input.  Answers
that are equal up to white space and case form a group: one mark applies to all of them.

**Blind marking**: a student is shown by a pseudonym, ``S-`` and six letters of the SHA-256 of the assignment and
the user name: the same for every marker and session, different between assignments, and in an order (sorted by
pseudonym) that has nothing to do with the names.

**Where a marker stopped** is kept per marker in ``SUBS/.marking/<marker>-<id>.json`` (question, position, names
shown, groups split).
"""

import base64
import contextlib
import hashlib
import json
import os
import re
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import nbformat
from nbformat.v4.nbjson import JSONReader

from ... import i18n, repository
from ...i18n import _
from ..grader.notebook import MAX_NOTEBOOK
from ..untrusted import MAX_CELLS, UntrustedError, csv_cell, csv_value, loads
from .files import write_atomic
from .written import MAX_ANSWER, Question, answers_of, questions_of, read_rows, sheet_text

try:  # the hub and every Unix
    import fcntl
except ImportError:  # pragma: no cover - Windows: no lock, the conflict check still holds between two saves
    fcntl = None

__all__ = ["Answer", "MarkingError", "Sheet", "check_points", "figures", "groups", "load", "pseudonym",
           "sample_answers", "save"]

#: Figures shown beside an answer at most (the last ones before the question).
MAX_FIGURES = 4
_SOLUTION_MARKS = re.compile(r"<!--\s*(BEGIN|END) SOLUTION\s*-->")


class MarkingError(ValueError):
    """A sheet or folder that cannot be marked (no sheet, two sheets, a damaged sheet)."""


def pseudonym(assignment, student):
    """The name a blind marker sees: ``S-`` and six letters of the SHA-256 of assignment and student."""
    return "S-" + hashlib.sha256(f"{assignment}\0{student}".encode()).hexdigest()[:6].upper()


def _key(text):
    """What makes two answers the same for grouping: the words, case folded."""
    return " ".join(str(text).split()).casefold()


def _norm(text):
    """A cell as the sheet stores it (one line, quoted formulas read back): what a comparison with the sheet sees."""
    return csv_value(csv_cell("" if text is None else str(text)))


def check_points(text, max_points):
    """The points a marker typed: a number from 0 to ``max_points`` in steps of ½ (a decimal comma is fine), or
    None for an empty field (not marked).  A ``ValueError`` in the marker's language says what was expected."""
    text = str(text).strip()
    if not text:
        return None
    try:
        value = i18n.parse_number(text)
    except ValueError:
        raise ValueError(i18n.decimal(_("{got!r} is not a number; expected points from 0 to {max:g}").format(
            got=text, max=max_points))) from None
    if not 0 <= value <= max_points or value * 2 != int(value * 2):
        raise ValueError(i18n.decimal(_("{got:g} points: expected 0 to {max:g} in steps of 0.5").format(
            got=value, max=max_points)))
    return value


@dataclass
class Answer:
    """One student's answer to one question, with its mark as the sheet holds it."""

    student: str
    question: str
    text: str
    points: str = ""
    comment: str = ""


@dataclass
class Sheet:
    """A folder of submissions ready to mark: its questions (in the marker's language), every answer, the sheet's
    path and max points, the sample answers, and the marks as last read (``marks``: ``{(student, question):
    (points, comment)}``)."""

    folder: Path
    assignment: str
    path: Path
    questions: list
    max_points: dict
    answers: dict  # {question: [Answer, …]} in the students' order
    samples: dict = field(default_factory=dict)
    marks: dict = field(default_factory=dict)
    notebooks: dict = field(default_factory=dict)  # {student: notebook or None}, for the figures

    def students(self):
        return sorted({a.student for answers in self.answers.values() for a in answers})

    def refresh(self):
        """Read the marks again from the sheet; returns the ``(student, question)`` whose mark changed on disk."""
        fresh = _read_marks(self.path)
        changed = {k for k in set(fresh) | set(self.marks) if fresh.get(k, ("", "")) != self.marks.get(k, ("", ""))}
        self.marks = fresh
        for answers in self.answers.values():
            for a in answers:
                a.points, a.comment = fresh.get((a.student, a.question), ("", ""))
        return changed

    def progress(self, question=None):
        """``(marked, total)`` answers of one question, or of all."""
        items = [a for q, answers in self.answers.items() if question in (None, q) for a in answers]
        return sum(1 for a in items if a.points.strip()), len(items)

    def distribution(self, question):
        """``Counter`` of the points given to a question (as numbers)."""
        return Counter(i18n.parse_number(a.points) for a in self.answers[question] if a.points.strip())


def groups(answers, split=()):
    """The answers of one question in groups of equal answers (:func:`_key`), in the order of their first member:
    one mark applies to a whole group.  A group whose members carry different marks, or whose key is in ``split``,
    is given as single answers."""
    by_key = {}
    for a in answers:
        by_key.setdefault(_key(a.text), []).append(a)
    out = []
    for key, members in by_key.items():
        marks = {(m.points, m.comment) for m in members}
        if len(members) > 1 and (len(marks) > 1 or key in split):
            out += [[m] for m in members]
        else:
            out.append(members)
    order = {id(a): i for i, a in enumerate(answers)}
    return sorted(out, key=lambda g: order[id(g[0])])


def _read_marks(path):
    return {(r["student"], r.get("question", "")): (r.get("points", "").strip(), r.get("comment", ""))
            for r in read_rows(path)[1]}


def _sheet_path(folder, assignment):
    folder = Path(folder)
    if assignment:
        path = folder / f"written-{assignment}.csv"
        if not path.is_file():
            raise MarkingError(f"{folder}: no written-{assignment}.csv (written by curvature-lab collect for an "
                               "assignment with written questions)")
        return path
    found = sorted(p for p in folder.glob("written-*.csv") if ".marked-" not in p.name)
    if len(found) != 1:
        raise MarkingError(f"{folder}: expected one written-<id>.csv of curvature-lab collect; found "
                           f"{len(found)}{': ' + ', '.join(p.name for p in found) if found else ''}")
    return found[0]


def _read_notebook(path):
    """A student's notebook (nbformat, not validated), or None when it is missing, too large or no notebook."""
    try:
        raw = path.read_bytes()
        if len(raw) > MAX_NOTEBOOK:
            return None
        data = loads(raw, max_depth=64)
        if not isinstance(data, dict) or len(data.get("cells", [])) > MAX_CELLS:
            return None
        return JSONReader().to_notebook(data)
    except (OSError, UntrustedError, ValueError, TypeError, AttributeError, RecursionError):
        return None


def _exercise(assignment, lang, exercises):
    for folder in (Path(exercises) / lang, Path(exercises) / "en", Path(exercises)):
        path = folder / f"{assignment}.ipynb"
        if path.is_file():
            return nbformat.read(str(path), as_version=4)
    return None


def sample_answers(assignment, lang, solutions=None):
    """``{question cell id: sample answer}`` from the solution notebook in ``lang`` (``solutions/<lang>/<id>.ipynb``
    of the course repository, or ``solutions``), without the solution markers; {} where there is none."""
    base = Path(solutions) if solutions else Path(repository()) / "solutions"
    for path in (base / lang / f"{assignment}.ipynb", base / "en" / f"{assignment}.ipynb"):
        if path.is_file():
            nb = nbformat.read(str(path), as_version=4)
            return {c.get("id"): _SOLUTION_MARKS.sub("", c.source).strip() for c in nb.cells
                    if c.cell_type == "markdown" and _SOLUTION_MARKS.search(c.source)}
    return {}


def figures(nb, question, limit=MAX_FIGURES):
    """The PNG pictures (bytes) of the code cells before the question's answer cell in a student's notebook, the last
    ``limit`` of them: what the student saw when answering."""
    pictures = []
    for cell in nb.cells if nb is not None else ():
        if cell.get("id") == question:
            break
        if cell.get("cell_type") != "code":
            continue
        for out in cell.get("outputs", []):
            data = out.get("data", {}) if isinstance(out, dict) else {}
            png = data.get("image/png")
            if isinstance(png, str) and len(png) < 8 << 20:
                with contextlib.suppress(ValueError):
                    pictures.append(base64.b64decode(png, validate=False))
    return pictures[-limit:]


def load(folder, assignment=None, *, lang=None, exercises=None, solutions=None, students=None):
    """The :class:`Sheet` of a folder of collected submissions (``SUBS``), for a marker in ``lang``; ``students``:
    only these students' answers (a share of the class for one marker), else all."""
    folder = Path(folder)
    if not folder.is_dir():
        raise MarkingError(f"{folder} is not a folder of collected submissions")
    path = _sheet_path(folder, assignment)
    _columns, rows = read_rows(path)
    assignment = assignment or path.stem[len("written-"):]
    lang = lang or i18n.language()
    exercise = _exercise(assignment, lang, exercises or Path(repository()) / "exercises")
    questions = questions_of(exercise) if exercise is not None else []
    known = [c.get("id") for c in exercise.cells] if exercise is not None else []
    order = list(dict.fromkeys(r.get("question", "") for r in rows))
    if not questions:  # no exercise at hand: the sheet's titles stand for the questions
        titles = {r.get("question", ""): r.get("title", "") for r in rows}
        questions = [Question(q, titles[q], 0.0) for q in order]
    questions = [q for q in questions if q.cell in order]
    max_points = {r.get("question", ""): i18n.parse_number(r.get("max_points") or 0) for r in rows}
    notebooks = {}
    answers = {q.cell: [] for q in questions}
    wanted = None if students is None else set(students)
    if wanted is not None and not wanted & {r["student"] for r in rows}:
        raise MarkingError(f"{path}: none of the {len(wanted)} students given has an answer here")
    for r in rows:
        student, question = r["student"], r.get("question", "")
        if question not in answers or (wanted is not None and student not in wanted):
            continue
        if student not in notebooks:
            notebooks[student] = _read_notebook(folder / student / f"{assignment}.ipynb")
        nb = notebooks[student]
        text = answers_of(nb, questions, known).get(question, "") if nb is not None else r.get("answer", "")
        answers[question].append(Answer(student, question, text[:MAX_ANSWER], r.get("points", "").strip(),
                                        r.get("comment", "")))
    return Sheet(folder, assignment, path, questions, max_points, answers, sample_answers(assignment, lang, solutions),
                 _read_marks(path), notebooks)


@contextlib.contextmanager
def _locked(path):
    lock = path.with_name(f".{path.name}.lock")
    with open(lock, "a") as fh:
        if fcntl is not None:
            fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            if fcntl is not None:
                fcntl.flock(fh, fcntl.LOCK_UN)


def save(sheet, students, question, points, comment):
    """Give ``students``' answers to ``question`` the mark ``points`` (a number or None: not marked) and ``comment``.

    Returns the students whose mark on disk is no longer the one the panel read (another marker's or a spreadsheet's
    change): theirs is kept, and the sheet's marks are read again.  The others are saved at once, in one rename."""
    value = "" if points is None else f"{points:g}"
    comment = _norm(comment)
    with _locked(sheet.path):
        columns, rows = read_rows(sheet.path)  # the sheet's own columns: a spreadsheet may have added some
        on_disk = {(r["student"], r.get("question", "")): r for r in rows}
        conflicts, changed = [], False
        for student in students:
            row = on_disk.get((student, question))
            if row is None:
                conflicts.append(student)
                continue
            now = (row.get("points", "").strip(), row.get("comment", ""))
            if now != sheet.marks.get((student, question), ("", "")):
                conflicts.append(student)
            elif now != (value, comment):
                row["points"], row["comment"], changed = value, comment, True
        if changed:
            write_atomic(sheet.path, sheet_text(rows, columns))
        sheet.refresh()
    return conflicts


def state_path(sheet, marker):
    safe = re.sub(r"[^A-Za-z0-9._-]", "_", marker or "marker")[:60]
    return sheet.folder / ".marking" / f"{safe}-{sheet.assignment}.json"


def read_state(sheet, marker):
    """Where ``marker`` stopped (a dict; {} the first time or when the file is damaged)."""
    try:
        data = json.loads(state_path(sheet, marker).read_text())
        return data if isinstance(data, dict) else {}
    except (OSError, ValueError):
        return {}


def write_state(sheet, marker, state):
    path = state_path(sheet, marker)
    path.parent.mkdir(exist_ok=True)
    write_atomic(path, json.dumps(state, indent=1, sort_keys=True))


def the_marker():
    """The marker's name: the hub's user, else the login name."""
    name = os.environ.get("JUPYTERHUB_USER")
    if name:
        return name
    try:
        import getpass

        return getpass.getuser()
    except Exception:  # noqa: BLE001 - no login name (a container without a passwd entry)
        return "marker"
