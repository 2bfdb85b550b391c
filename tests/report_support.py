"""Report folders as ``curvature-lab grade`` leaves them, made without grading: a report per row (written by the
grader's own writer) and ``summary.csv`` (its own rows, so names are quoted as in a real run)."""

import csv
import io
import os

from lab.teaching.course import files, grade
from lab.teaching.grader.notebook import GradeResult

ID = "05_visualize_curvature"


def result(student, assignment=ID, score=0.75, notebook=None):
    """A result of ``score`` of 10 points."""
    task = {"task": "visualize_curvature", "object": "MyBezierPatches", "points": 10, "score": score,
            "passed": score == 1.0, "report": "", "message": "K is wrong at the corners", "cases": []}
    return GradeResult(notebook=notebook or f"{student}/{assignment}.ipynb", assignment=assignment, student=student,
                       seed=1, tasks=[task])


def report_folder(folder, *results, late=None, summary=None):
    """``folder`` with a report per result and ``summary.csv``; ``late``: ``{student: late seconds}``;
    ``summary``: ``{student: {column: cell}}`` written over the row (a damaged summary)."""
    folder.mkdir(parents=True)
    late, summary = late or {}, summary or {}
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        for k, res in enumerate(results):
            grade._write_reports(fd, f"r{k}", res, "text", "visible")
    finally:
        os.close(fd)
    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow(files.SUMMARY_COLUMNS)
    for res in results:
        collected = {res.student: {"late_seconds": late.get(res.student, "")}}
        row = dict(zip(files.SUMMARY_COLUMNS, grade._summary_row(res.student, res.notebook, res, collected)))
        row.update(summary.get(res.student, {}))
        writer.writerow([row[c] for c in files.SUMMARY_COLUMNS])
    (folder / "summary.csv").write_text(buf.getvalue())
    return folder


def rows_of(path):
    """The rows of a CSV file as dicts (as a spreadsheet shows them: quotes not taken off)."""
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def text_file(path, text):
    """``path`` with ``text`` in it (a marking CSV an instructor saved)."""
    path.write_text(text)
    return path
