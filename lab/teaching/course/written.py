"""Written answers: the notebooks' free-text questions, collected per question for the instructor to mark.

A question of an assignment is a markdown cell of the instructor's exercise that holds only the answer
placeholder (``*Your answer here.*``, made by :func:`lab.teaching.course.exercises.make_exercise` from a
``<!-- BEGIN SOLUTION -->`` part); the question's text is the markdown cell before it.  Its points are in
the assignment's metadata ``lab.questions`` (``{cell id: points}``; the cell ids are the same in English and
German).  A student's answer is the cell with the same id in the submission (cells a student added right
after it are added to the answer).

:func:`collect_answers` writes, for one assignment, ``written-<id>.html`` (every question with every
student's answer below it, escaped, so one question is marked for the whole class at once) and
``written-<id>.csv`` (a row per student and question: ``question`` its cell id, ``title`` its first line,
``points`` and ``comment`` empty, for the instructor; ``max_points`` from the metadata).  The instructor marks
it with ``curvature-lab mark`` (:mod:`lab.teaching.course.mark`) or in a spreadsheet; ``curvature-lab gradebook
--written FILE`` adds the points, and ``curvature-lab feedback --written FILE`` shows them with the comments; a
spreadsheet's decimal comma (``2,5``) and semicolon-separated file are read too.  Collecting again keeps every
mark of an answer that did not change; the marks of answers that changed are set aside, never applied to the new
text: the marked file is kept as ``written-<id>.marked-<time>.csv`` and the students are named.
"""

import csv
import io
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from ...i18n import _, decimal, language, parse_number, using
from ..untrusted import clean, csv_cell, csv_value
from .exercises import ANSWER_PLACEHOLDER
from .files import write_atomic
from .pages import e, page

__all__ = ["WRITTEN_COLUMNS", "Question", "answers_of", "collect_answers", "questions_of", "read_rows", "read_written",
           "sheet_text"]

WRITTEN_COLUMNS = ("student", "assignment", "question", "title", "max_points", "points", "comment", "answer")
_PLACEHOLDERS = {p.strip() for p in ANSWER_PLACEHOLDER.values()}
#: Longest answer kept (characters).
MAX_ANSWER = 20_000


@dataclass(frozen=True)
class Question:
    cell: str
    text: str
    points: float

    @property
    def title(self):
        """The question's first line (a heading without its ``#``), cut at a word after 60 characters."""
        line = next((t.strip().lstrip("#").strip() for t in self.text.splitlines() if t.strip()), "")
        return line if len(line) <= 60 else line[:60].rsplit(" ", 1)[0] + " …"


def questions_of(nb):
    """The questions of an instructor's exercise notebook (see the module docstring)."""
    meta = nb.metadata.get("lab", {}) if isinstance(nb.metadata.get("lab"), dict) else {}
    points = meta.get("questions", {}) if isinstance(meta.get("questions"), dict) else {}
    found = []
    for i, cell in enumerate(nb.cells):
        if cell.cell_type == "markdown" and cell.source.strip() in _PLACEHOLDERS:
            text = nb.cells[i - 1].source if i and nb.cells[i - 1].cell_type == "markdown" else ""
            found.append(Question(cell.get("id", str(i)), text, float(points.get(cell.get("id"), 0))))
    return found


def answers_of(nb, questions, known=()):
    """``{question cell id: answer text}`` of a submission (an empty text where none was written).

    ``known``: the cell ids of the instructor's exercise; markdown cells right after an answer cell whose id is
    not among them were added by the student and belong to the answer.
    """
    cells = nb.cells
    index = {c.get("id"): i for i, c in enumerate(cells)}
    known = set(known)
    out = {}
    for q in questions:
        i = index.get(q.cell)
        if i is None or cells[i].cell_type != "markdown":
            out[q.cell] = ""
            continue
        parts, k = [cells[i].source], i + 1
        while k < len(cells) and cells[k].cell_type == "markdown" and cells[k].get("id") not in known:
            parts.append(cells[k].source)
            k += 1
        text = "\n\n".join(p for p in parts if p.strip() not in _PLACEHOLDERS).strip()
        out[q.cell] = clean(text, MAX_ANSWER)
    return out


def _rows(assignment_id, questions, answers_by_student):
    for student, answers in sorted(answers_by_student.items()):
        for q in questions:
            yield {"student": student, "assignment": assignment_id, "question": q.cell, "title": q.title,
                   "max_points": q.points, "points": "", "comment": "", "answer": answers.get(q.cell, "")}


def sheet_text(rows, columns=WRITTEN_COLUMNS):
    """The text of a ``written-<id>.csv`` with ``rows`` (dicts of ``columns``), every cell through
    :func:`~lab.teaching.untrusted.csv_cell`."""
    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow(columns)
    for row in rows:
        writer.writerow([csv_cell(row.get(c, "")) for c in columns])
    return buf.getvalue()


def _keep_marks(csv_path, rows, log):
    """Carry the marks of ``csv_path`` (a marked sheet of an earlier collect) over to ``rows`` where the answer is
    unchanged; where a marked answer changed, keep the old sheet under another name and say so."""
    if not csv_path.is_file():
        return
    _fields, old = read_rows(csv_path)
    marks = {(r.get("student"), r.get("question")): r for r in old if (r.get("points") or r.get("comment") or "").strip()}
    changed = []
    for row in rows:
        mark = marks.get((row["student"], row["question"]))
        if mark is None:
            continue
        if csv_value(csv_cell(row["answer"])) == mark.get("answer", ""):
            row["points"], row["comment"] = mark.get("points", ""), mark.get("comment", "")
        else:
            changed.append(f"{row['student']} ({row['title']})")
    if changed:
        kept = csv_path.with_name(f"{csv_path.stem}.marked-{time.strftime('%Y%m%d-%H%M%S')}.csv")
        csv_path.replace(kept)
        print(_("{n} marked written answers changed since they were marked; their marks are not carried over and the "
                "marked sheet is kept as {file}: {names}").format(n=len(changed), file=kept.name,
                                                                  names=", ".join(clean(c, 100) for c in changed)),
              file=log)


def collect_answers(out_dir, assignment_id, exercise_nb, answers_by_student, lang="en", log=None):
    """Write ``written-<id>.html`` and ``written-<id>.csv`` into ``out_dir``; returns their paths (or () without
    questions).  ``answers_by_student``: ``{student: {cell id: text}}``; ``exercise_nb``: the instructor's.  The
    marks of an earlier sheet are kept where the answer is unchanged (the module docstring)."""
    questions = questions_of(exercise_nb)
    if not questions:
        return ()
    out_dir = Path(out_dir)
    csv_path = out_dir / f"written-{assignment_id}.csv"
    rows = list(_rows(assignment_id, questions, answers_by_student))
    _keep_marks(csv_path, rows, sys.stderr if log is None else log)
    write_atomic(csv_path, sheet_text(rows))
    html_path = out_dir / f"written-{assignment_id}.html"
    with using(lang):
        html_path.write_text(_page(assignment_id, questions, answers_by_student))
    return html_path, csv_path


def _page(assignment_id, questions, answers_by_student):
    title = _("Written answers: {id}").format(id=assignment_id)
    none = _("(no answer)")
    parts = [f"<h1>{e(title)}</h1>"]
    for k, q in enumerate(questions, 1):
        head = _("Question {k}").format(k=k)
        points = _("{points} points").format(points=decimal(f"{q.points:g}"))
        parts.append(f"<section><h2>{e(head)} <small>({e(q.cell)}, {e(points)})</small></h2>"
                     f"<div class='q'>{e(q.text)}</div>")
        for student, answers in sorted(answers_by_student.items()):
            text = answers.get(q.cell, "")
            body = e(text) if text else f"<span class='none'>{e(none)}</span>"
            parts.append(f"<h3>{e(clean(student, 100))}</h3><div class='a'>{body}</div>")
        parts.append("</section>")
    return page(title, "".join(parts), language())


def read_rows(path):
    """``(columns, rows)`` of a ``written-<id>.csv``: its header and its rows as dicts of text, each cell read back
    through :func:`~lab.teaching.untrusted.csv_value` (the student ``'bea``, written ``''bea``, is ``'bea``).  Read as
    a spreadsheet saves it too: cells separated by semicolons, a byte order mark.  A ``ValueError`` names a missing
    column or a row with more cells than the header."""
    with open(path, newline="", encoding="utf-8-sig") as fh:
        text = fh.read()
    head = text.split("\n", 1)[0]
    lines = io.StringIO(text)
    reader = csv.DictReader(lines, delimiter=";" if ";" in head and "," not in head else ",")
    columns = list(reader.fieldnames or ())
    if missing := {"student", "assignment", "max_points", "points"} - set(columns):
        raise ValueError(f"{path}: no column {', '.join(sorted(missing))} (is it a written-<id>.csv of curvature-lab "
                         "collect?)")
    rows = []
    for raw in reader:
        if None in raw:  # more cells than columns: an unquoted 2,5 in a comma-separated file
            raise ValueError(f"{path}, line {reader.line_num}: more cells than the header has columns; write 2.5, or "
                             "\"2,5\" in quotes, in a comma-separated file")
        rows.append({k: csv_value(v) for k, v in raw.items()} | {"line": reader.line_num})
    return columns, rows


def read_written(path):
    """``{(student, assignment): (points, max points)}`` summed over the questions of a marked ``written-*.csv``.

    A row whose ``points`` is empty counts 0 (unmarked); points outside ``0 … max_points`` are refused.  A
    spreadsheet's decimal comma (``2,5``) is read too (:func:`read_rows`).
    """
    totals = {}
    for row in read_rows(path)[1]:
        n = row["line"]
        try:
            top = parse_number(row["max_points"] or 0)
            got = parse_number(row["points"]) if (row["points"] or "").strip() else 0.0
        except ValueError:
            raise ValueError(f"{path}, line {n}: points and max_points must be numbers; got "
                             f"{row['points']!r}, {row['max_points']!r}") from None
        if not 0 <= got <= top:
            raise ValueError(f"{path}, line {n}: {got:g} points for question {row.get('question')} of "
                             f"{row['student']}; expected 0 … {top:g}")
        key = (row["student"], row["assignment"])
        p, m = totals.get(key, (0.0, 0.0))
        totals[key] = (p + got, m + top)
    return totals
