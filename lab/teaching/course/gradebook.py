"""The gradebook: ``curvature-lab gradebook REPORTS... --format canvas|moodle|csv -o FILE``.

One row per student and a column per assignment, from the ``summary.csv`` of graded folders
(:mod:`lab.teaching.course.grade`; one folder per assignment, or several assignments in one).  Per assignment:

* the autograded score (a student without a submission scores 0; students listed missing in the
  summary, from ``collect``'s ``collected.csv``, are included),
* plus the written answers' points from marked ``written-<id>.csv`` files (``--written``; the reports of
  that assignment must be among the folders, else its grade would come out without them: an error),
* minus a **late penalty**: ``--late-penalty P`` percent of the points per started day late (after
  ``--grace`` minutes), at most ``--late-cap`` percent; the lateness comes from ``collected.csv`` through
  the summary.

One student's data never stops the gradebook of the class: that student's assignment in two report folders
(``reports/05late reports/05``, or a notebook of one student claiming, in its metadata, an assignment graded in
another folder) or a summary row that is not a number is that student's 0 for that assignment, with status
``refused`` and a note naming the folders (on stderr too): no order of the folders decides a grade.  The
instructor's own mistakes (written marks of an assignment whose reports are not among the folders, the same
marks twice, a folder without ``summary.csv``, bad options) stay errors.  In one folder a student with two
notebooks of an assignment gets the better score.

Names are the raw user names everywhere (``'bea`` and ``bea`` are two students); a cell is quoted only when
written (:func:`~lab.teaching.untrusted.csv_cell`) and read back through :func:`~lab.teaching.untrusted.csv_value`.

``--per-question`` adds, for an item analysis, a column per graded task (``<id>: <task>``, its points as graded,
before any late penalty; a task is the group of cases its points come from) and per written question
(``<id>: <question title> (written)``, the marked points) to the ``csv`` layout, after the assignment's columns.

Formats:

* ``csv``: ``student``, then per assignment its points, ``<id> late days``, ``<id> status`` (``submitted``;
  ``missing`` where no notebook was graded: none handed in, or ``collect`` refused it; ``refused`` where the
  student's reports of it cannot count, see above) and ``<id> note`` (why refused), then ``total`` and ``max``;
  the first row, ``(max)`` (no user name has parentheses, so a student called max keeps a row of their own), holds
  the points possible of each points column (under ``total`` and ``max`` the sum);
* ``canvas``: Canvas's gradebook import layout: ``Student, ID, SIS User ID, SIS Login ID, Section``, a
  column per assignment (named by its title: Canvas creates the assignment; rename a header to
  ``Title (123)`` to fill an existing one), a second row ``Points Possible``; students are matched by
  ``SIS Login ID`` = the hub's user name, or by ``ID`` when ``--roster`` gives Canvas's own export.  No total:
  Canvas computes its own, and a column it does not know becomes a new assignment (counted twice);
* ``moodle``: Moodle's grade import (Grades → Import → CSV file): ``Username, ID number, Email address`` and
  a column per assignment; map "Username" to "username" and each column to its grade item when importing.
  No total: the import cannot fill the course total (Moodle computes it), and a total mapped to a new grade
  item would count twice.
"""

import argparse
import csv
import io
import math
import re
import sys
from pathlib import Path

from ...i18n import _, parse_number
from ..untrusted import clean, csv_cell
from .files import one_per_student, read_text, summary_rows, write_atomic
from .late import LatePolicy, add_late_options, late_policy
from .written import read_rows, read_written

__all__ = ["FORMATS", "MAX_ROW", "GradebookError", "conflict_note", "gradebook", "main", "per_question", "read_roster"]

FORMATS = ("csv", "canvas", "moodle")
#: The first row of the ``csv`` layout, the points possible: not a user name (a student may be called max).
MAX_ROW = "(max)"


class GradebookError(ValueError):
    """Reports that cannot make a gradebook."""


def conflict_note(aid, folders):
    """What a student's assignment in several report folders means (a gradebook note)."""
    return _("{assignment} is in two report folders, {first} and {second}: 0 points here; pass only the folder that "
             "counts").format(assignment=clean(aid, 80, keep_newlines=False), first=folders[0],
                              second=", ".join(map(str, folders[1:])))


def _number(text):
    """The number in a summary cell ("" is 0); ValueError for anything else, NaN and infinities too."""
    value = float(text or 0)
    if not math.isfinite(value):
        raise ValueError(text)
    return value


def read_roster(path):
    """``{user name: row}`` from a roster CSV: Canvas's gradebook export (``SIS Login ID``) or any CSV with a
    ``username`` column (and optionally ``name``, ``id``, ``sis user id``, ``section``, ``email``, ``id number``)."""
    rows = list(csv.DictReader(io.StringIO(read_text(path, GradebookError), newline="")))
    out = {}
    for row in rows:
        low = {k.strip().lower(): (v or "").strip() for k, v in row.items() if k}
        user = low.get("sis login id") or low.get("username") or low.get("login id")
        if user and not user.startswith("Points Possible"):
            out[user] = low
    if rows and not out:
        raise GradebookError(f"{path}: no column 'SIS Login ID' or 'username'")
    return out


def _assignments(folders):
    """``{assignment id: {"max": points, "rows": {student: row}, "notes": {student: note}}}`` from the summaries;
    a student with a note scores 0 in that assignment (see the module docstring)."""
    found, items = {}, []
    for folder in folders:
        path = Path(folder) / "summary.csv"
        if not path.is_file():
            raise GradebookError(f"{folder}: no summary.csv (is it a folder of reports from curvature-lab grade?)")
        for student, row in summary_rows(folder):
            aid = row.get("assignment") or ""
            if not aid:
                continue
            entry = found.setdefault(aid, {"max": 0.0, "rows": {}, "notes": {}})
            try:
                top, score = _number(row.get("max_score")), _number(row.get("score"))
                _number(row.get("late_seconds"))
            except ValueError:
                entry["notes"][student] = _(
                    "score {score}, max_score {max} or late_seconds {late} in {file} is not a number: 0 points "
                    "here").format(**{k: repr(clean(row.get(c) or "", 80, keep_newlines=False)) for k, c in
                                      (("score", "score"), ("max", "max_score"), ("late", "late_seconds"))}, file=path)
                continue
            entry["max"] = max(entry["max"], top)
            items.append((folder, student, aid, score, row))
    if not found:
        raise GradebookError("the summaries name no assignment")
    chosen, conflicts = one_per_student(items)
    for (student, aid), row in chosen.items():
        found[aid]["rows"][student] = row
    for (student, aid), where in conflicts.items():
        found[aid]["notes"].setdefault(student, conflict_note(aid, where))
    return found


def _marks(written, found):
    """``{(student, assignment): (points, max points)}`` of the marked written CSVs, for assignments in ``found``."""
    marks, source = {}, {}
    for path in written:
        for key, value in read_written(path).items():
            student, aid = key
            if aid not in found:
                raise GradebookError(
                    f"{path}: written points of assignment {clean(aid, 80)}, whose reports are not among the report "
                    f"folders ({', '.join(sorted(found))}): pass the folder graded for {clean(aid, 80)} too (its "
                    "autograded points and lateness are part of the grade)")
            if key in marks:
                raise GradebookError(f"{clean(student, 80)}'s written points of {clean(aid, 80)} are in {source[key]} "
                                     f"and in {path}: pass each assignment's marks once")
            marks[key], source[key] = value, path
    return marks


#: A task's points in a summary's ``tasks`` cell: ``name=points/max`` separated by ``; ``.
_TASK = re.compile(r"\s*([^=;]+?)=([-+0-9.eE]+)/([-+0-9.eE]+)\s*(?:;|$)")


def per_question(folders, written=()):
    """``(columns, {column: max}, {(student, column): points})`` of the per-question columns: every graded task
    of every assignment and every written question (see the module docstring)."""
    found = _assignments(folders)
    columns, maxima, points = [], {}, {}
    for aid, entry in sorted(found.items()):
        for student, row in entry["rows"].items():
            if student in entry["notes"]:
                continue
            for name, got, top in _TASK.findall(row.get("tasks") or ""):
                column = f"{aid}: {name}"
                if column not in maxima:
                    columns.append(column)
                maxima[column] = max(maxima.get(column, 0.0), float(top))
                points[(student, column)] = float(got)
    for path in written:
        for row in read_rows(path)[1]:
            column = f"{row['assignment']}: {row.get('title') or row.get('question')} (written)"
            if column not in maxima:
                columns.append(column)
            maxima[column] = max(maxima.get(column, 0.0), parse_number(row.get("max_points") or 0))
            if (row.get("points") or "").strip():
                points[(row["student"], column)] = parse_number(row["points"])
    return columns, maxima, points


def gradebook(folders, *, late=None, written=(), roster=None):
    """``(assignment ids, {aid: max}, rows)``: per student ``{"student", aid: points, aid + " late days",
    aid + " status", aid + " note", "total"}``."""
    late = late or LatePolicy()
    found = _assignments(folders)
    marks = _marks(written, found)
    maxima = {aid: entry["max"] for aid, entry in found.items()}
    for (_student, aid), (_got, top) in marks.items():
        maxima[aid] = found[aid]["max"] + top
    students = sorted({s for entry in found.values() for s in (*entry["rows"], *entry["notes"])}
                      | {s for s, _aid in marks} | set(roster or ()))
    rows = []
    for student in students:
        row = {"student": student}
        total = 0.0
        for aid, entry in sorted(found.items()):
            note = entry["notes"].get(student, "")
            summary = {} if note else entry["rows"].get(student, {})  # a note: 0 points, written ones too
            auto = float(summary.get("score") or 0)
            extra = 0.0 if note else marks.get((student, aid), (0.0, 0.0))[0]
            points = late.apply(auto + extra, summary.get("late_seconds"))
            row[aid], row[f"{aid} late days"] = points, late.days(summary.get("late_seconds"))
            # batch: "" = no notebook
            row[f"{aid} status"] = "refused" if note else "submitted" if summary.get("notebook") else "missing"
            row[f"{aid} note"] = note
            total += points
        row["total"] = round(total, 2)
        rows.append(row)
    return sorted(found), maxima, rows


def _write(fmt, ids, maxima, rows, roster, items=None):
    """The file's text; ``items``: the :func:`per_question` columns (csv layout only)."""
    roster = roster or {}
    columns_max, points = (items[1], items[2]) if items else ({}, {})
    items = items[0] if items else []
    buf = io.StringIO()
    w = csv.writer(buf)
    max_total = round(sum(maxima.values()), 2)
    if fmt == "csv":
        columns = [c for aid in ids for c in (aid, f"{aid} late days", f"{aid} status", f"{aid} note")] + items
        w.writerow([csv_cell(c) for c in ["student"] + columns + ["total", "max"]])
        w.writerow([MAX_ROW] + [c for aid in ids for c in (maxima[aid], "", "", "")] + [columns_max[c] for c in items]
                   + [max_total, max_total])
        for r in rows:
            w.writerow([csv_cell(r["student"])] + [csv_cell(r[c]) for c in columns[:4 * len(ids)]]
                       + [points.get((r["student"], c), "") for c in items] + [r["total"], max_total])
    elif fmt == "canvas":
        w.writerow(["Student", "ID", "SIS User ID", "SIS Login ID", "Section"] + [csv_cell(aid) for aid in ids])
        w.writerow(["Points Possible", "", "", "", ""] + [maxima[aid] for aid in ids])
        for r in rows:
            info = roster.get(r["student"], {})
            w.writerow([csv_cell(info.get("student") or info.get("name") or r["student"]), csv_cell(info.get("id", "")),
                        csv_cell(info.get("sis user id", "")), csv_cell(r["student"]), csv_cell(info.get("section", ""))]
                       + [r[aid] for aid in ids])
    else:
        w.writerow(["Username", "ID number", "Email address"] + [csv_cell(aid) for aid in ids])
        for r in rows:
            info = roster.get(r["student"], {})
            w.writerow([csv_cell(r["student"]), csv_cell(info.get("id number", "")), csv_cell(info.get("email", ""))]
                       + [r[aid] for aid in ids])
    return buf.getvalue()


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab gradebook",
        description=_("One row per student and a column per assignment, from graded report folders (their "
                      "summary.csv), with written points and a late penalty; for Canvas or Moodle (which compute the "
                      "total themselves) or as plain CSV (with a total and whether each assignment was submitted)."))
    parser.add_argument("reports", nargs="+", help=_("report folders written by curvature-lab grade"))
    parser.add_argument("--format", choices=FORMATS, default="csv", help=_("layout of the file (default: csv)"))
    parser.add_argument("-o", "--output", required=True, help=_("the CSV file to write"))
    parser.add_argument("--written", action="append", default=[], help=_("a marked written-<id>.csv (repeatable)"))
    add_late_options(parser)
    parser.add_argument("--roster", help=_("Canvas's gradebook export or a CSV with 'username' (names, ids, sections)"))
    parser.add_argument("--per-question", action="store_true",
                        help=_("a column per graded task and per written question too (csv layout), for an item "
                               "analysis"))
    args = parser.parse_args(argv)
    if args.per_question and args.format != "csv":
        parser.error(_("--per-question needs --format csv (Canvas and Moodle would make each column an assignment)"))
    try:
        roster = read_roster(args.roster) if args.roster else None
        ids, maxima, rows = gradebook(args.reports, late=late_policy(args), written=args.written, roster=roster)
        items = per_question(args.reports, args.written) if args.per_question else None
        write_atomic(args.output, _write(args.format, ids, maxima, rows, roster, items))
    except (GradebookError, ValueError, OSError) as exc:
        print(f"curvature-lab gradebook: error: {exc}", file=sys.stderr)
        return 2
    for r in rows:  # a student's 0 with its reason, whatever the format (Canvas and Moodle have no note column)
        for aid in ids:
            if r[f"{aid} note"]:
                print(f"curvature-lab gradebook: {clean(r['student'], 100, keep_newlines=False)}: {r[f'{aid} note']}",
                      file=sys.stderr)
    print(_("{students} students, {assignments} assignments -> {file}").format(
        students=len(rows), assignments=len(ids), file=args.output), file=sys.stderr)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
