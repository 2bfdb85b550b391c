"""Returning the graded reports to the students: ``curvature-lab feedback REPORTS HOMES``.

For every report of a graded folder (``REPORTS/<name>.json``, :mod:`lab.teaching.course.grade`) the student's home
``HOMES/<student>`` gets ``feedback/<assignment>.html``: a page in the student's language (the report's)
with the score, every task, every case with its status and, for each failing case, what was expected, what
came out and the hint, then the notes.  JupyterLab opens it from the file browser.

Nothing else in a home is touched.  The page is written as the home's owner would have it (owner and group
of the home), through descriptors opened without following links, so a home, a ``feedback`` folder or a file
that a student replaced by a symbolic link is refused, never followed (the instructor may run this as root).
``HOMES`` is opened once; a report's student must be a user name (:func:`~lab.teaching.untrusted.student_id`:
never ``..``, a leading dot, a separator, a line break or an invisible character), opened as one folder in it,
and the page is one file name in its ``feedback`` folder: no page lands outside the homes.  Every
page ends with a stamp, the SHA-256 of all its bytes before it, and a ``feedback/<assignment>.html`` is replaced
only when it is exactly such a page: one the student edited or wrote (or a page written before the stamp) is
kept, and the new page goes next to it with a number (``<assignment>.2.html``).  A stamp a student forges makes
the command replace that file only, never another.

With ``--written FILE`` (a ``written-<id>.csv`` marked with ``curvature-lab mark`` or a spreadsheet, repeatable) the
page also shows each written answer's points and the marker's comment, under the question's title in the student's
language; an answer not marked yet says so.

A late student's page says how late the notebook was handed in (``late_seconds`` in the report folder's
``summary.csv``) and, given the gradebook's ``--late-penalty`` (``--late-cap``, ``--grace``), the penalty.

One student's data never stops the pages of the class; each of these is a line on stderr and that student's
report is skipped: the assignment in two report folders (``feedback reports/*`` with ``reports/05late``, or a
notebook claiming an assignment graded in another folder; the line names both, and no order of the folders
decides which page a student gets), a student that is no user name, no home, a report that is not valid JSON or
larger than :data:`MAX_REPORT`, a page that cannot be made or written.  Of a student's two notebooks in one
folder the better is returned, the one the gradebook counts.  Errors of the instructor's (no reports at all,
``HOMES`` not a folder, bad options) stop the command.
"""

import argparse
import hashlib
import math
import os
import sys
from pathlib import Path

import nbformat

from ... import i18n
from ...i18n import N_, _
from ..grader.assignments import DEFAULT_FOLDER
from ..grader.notebook import GradeResult
from ..untrusted import UntrustedError, clean, file_name, loads, open_folder, read_file, student_id, write_at
from .files import one_per_student, summary_rows
from .late import add_late_options, late_policy
from .pages import STATUS_COLOURS, e, page
from .written import questions_of, read_rows, read_written

__all__ = ["GENERATOR", "STAMP", "FeedbackError", "feedback", "main", "render", "stamped", "write_into_home"]

#: The statuses of a case, as a page shows them.
STATUS_WORDS = {"passed": N_("passed"), "failed": N_("failed"), "error": N_("error"),
                "not implemented": N_("not implemented"), "timeout": N_("timeout"), "delegated": N_("delegated"),
                "not run": N_("not run")}
#: Names this command in its pages.
GENERATOR = "<meta name='generator' content='curvature-lab feedback'>"
#: The last line of every page: the SHA-256 of all its bytes before it (see the module docstring).
STAMP = "<!-- curvature-lab feedback sha256:{} -->\n"
#: Largest file read back to check its stamp (bytes); a larger one is not a page of this command.
MAX_PAGE = 64 << 20
#: Largest report read (bytes); a larger one is skipped, with a line on stderr.
MAX_REPORT = 64 << 20


class FeedbackError(ValueError):
    """Feedback that cannot be returned (no reports, a home that is not a folder)."""


def _case_table(task):
    """The table of a task's cases: name, status and, where a case failed with something to show, the detail."""
    labels = (_("expected:"), _("got:"), _("hint:"))
    cells = []
    for c in task.get("cases", []):
        status = c.get("status", "")
        detail = ""
        if status not in ("passed", "not implemented"):  # an empty task: the section's text says what to write
            texts = (c.get("expected", ""), c.get("got", ""), c.get("hint", ""))
            detail = "<br>".join(f"<b>{e(label)}</b> {e(clean(text))}" for label, text in zip(labels, texts) if text)
        word = _(STATUS_WORDS[status]) if status in STATUS_WORDS else ""
        row = f"<td>{e(clean(c.get('name', ''), 300))}</td><td class='{STATUS_COLOURS.get(status, '')}'>{e(word)}</td>"
        cells.append((row, detail))
    if not cells:
        return ""
    details = any(detail for _row, detail in cells)  # no empty column when no case has a detail
    head = f"<tr><th>{e(_('case'))}</th><th>{e(_('status'))}</th>" + ("<th></th>" if details else "") + "</tr>"
    return "<table>" + head + "".join(f"<tr>{row}" + (f"<td>{detail}</td>" if details else "") + "</tr>"
                                      for row, detail in cells) + "</table>"


def _lateness(late_seconds, policy, score):
    """What a page says about a late hand-in ("" for one on time); the penalty only with a ``policy``."""
    seconds = float(late_seconds or 0)
    if seconds <= 0:
        return ""
    days, minutes = divmod(math.ceil(seconds / 60), 1440)
    text = _("Handed in {late} after the deadline.").format(
        late=_("{d} d {h} h {m} min").format(d=days, h=minutes // 60, m=minutes % 60))
    if policy is not None and policy.penalty(seconds):
        text += " " + _("Late penalty: {percent} percent of the points (started days late: {days}); of the points "
                        "above ({score}), {kept} count.").format(
            percent=f"{policy.penalty(seconds):g}", days=policy.days(seconds), score=f"{score:g}",
            kept=f"{policy.apply(score, seconds):g}")
    elif policy is not None:
        text += " " + _("No late penalty.")
    return i18n.decimal(text)


def _written_section(rows, lang, assignment):
    """The written answers' marks of one student (rows of a marked ``written-<id>.csv``), as HTML."""
    titles = {q.cell: q.title for q in _questions(assignment, lang)}
    got = sum(float(i18n.parse_number(r["points"])) for r in rows if r["points"].strip())
    top = sum(float(i18n.parse_number(r["max_points"] or 0)) for r in rows)
    head = i18n.decimal(_("Written answers: {score} of {max} points").format(score=f"{got:g}", max=f"{top:g}"))
    parts = [f"<section><h2>{e(head)}</h2>"]
    for r in rows:
        title = titles.get(r.get("question", ""), r.get("title", ""))
        if r["points"].strip():
            mark = i18n.decimal(f"{i18n.parse_number(r['points']):g} / {i18n.parse_number(r['max_points'] or 0):g}")
        else:
            mark = _("not marked yet")
        parts.append(f"<h3>{e(clean(title, 200))}: {e(mark)}</h3>")
        if r.get("comment", "").strip():
            parts.append(f"<div class='a'>{e(clean(r['comment'], 5000))}</div>")
    parts.append("</section>")
    return "".join(parts)


def _questions(assignment, lang):
    """The questions of the assignment's exercise in ``lang`` (for their titles), or []."""
    path = Path(DEFAULT_FOLDER) / lang / f"{assignment}.ipynb"
    if not path.is_file():
        return []
    return questions_of(nbformat.read(str(path), as_version=4))


def render(result, late_seconds=None, policy=None, written=()):
    """The feedback page of a :class:`~lab.teaching.grader.notebook.GradeResult`, in its language; ``late_seconds`` after
    the deadline and the :class:`~lab.teaching.course.late.LatePolicy` (or None: no penalty stated); ``written``: the
    student's rows of a marked ``written-<id>.csv`` of this assignment."""
    with i18n.using(result.lang):
        title = _("Feedback: {assignment}").format(assignment=result.assignment or result.notebook)
        score = i18n.decimal(_("{score} of {max} points").format(score=f"{result.score:g}", max=f"{result.max_score:g}"))
        body = [GENERATOR, f"<h1>{e(title)}</h1>", f"<p class='score'>{e(score)}</p>"]
        if late := _lateness(late_seconds, policy, result.score):
            body.append(f"<p class='late'>{e(late)}</p>")
        if result.error:
            body.append(f"<p class='error'>{e(clean(result.error))}</p>")
        for t in result.tasks:
            points = i18n.decimal(f"{round(t['points'] * t['score'], 2):g} / {t['points']:g}")
            body.append(f"<section><h2>{e(t['task'])} ({e(clean(t['object'], 100))}): {points}</h2>"
                        f"<pre>{e(clean(t.get('message', '')))}</pre>")
            body.append(_case_table(t))
            body.append("</section>")
        if written:
            body.append(_written_section(written, result.lang, result.assignment))
        notes = [clean(n) for n in result.notes] + [
            _("cell {index}: {error}").format(index=x["cell"], error=clean(x["error"]))
            for x in result.cell_errors if x.get("kind") not in ("withheld", "follows")]
        if notes:
            body.append("<h2>" + e(_("Notes")) + "</h2><ul>")
            body.append("".join(f"<li>{e(n)}</li>" for n in notes) + "</ul>")
        if result.seed is not None:
            seed = _("seed {seed}: the cases of this run").format(seed=result.seed)
            body.append(f"<p class='none'>{e(seed)}</p>")
        return page(title, "\n".join(body), result.lang)


def _safe_name(text):
    name = "".join(c if c.isalnum() or c in "._-" else "_" for c in str(text))[:120] or "feedback"
    return "_" + name[1:] if name.startswith(".") else name


def stamped(text):
    """The bytes of the page ``text`` with its stamp (:data:`STAMP`)."""
    data = text.encode()
    return data + STAMP.format(hashlib.sha256(data).hexdigest()).encode()


def _ours(data):
    """Whether ``data`` is exactly a page of this command: it ends with the stamp of all its bytes before it."""
    n = len(STAMP.format("0" * 64))
    return len(data) > n and data[-n:] == STAMP.format(hashlib.sha256(data[:-n]).hexdigest()).encode()


def write_into_home(home, name, text):
    """Write the page ``text`` to ``home/feedback/<name>.html`` (see the module docstring); returns the path
    written.  ``home``: the home's path (a symbolic link there is refused); ``name``: one file name."""
    try:
        home_fd = open_folder(home)
    except UntrustedError as exc:
        raise FeedbackError(f"{home}: not a home folder ({exc})") from None
    try:
        return _write_page(home_fd, home, name, text)
    finally:
        os.close(home_fd)


def _write_page(home_fd, home, name, text):
    """:func:`write_into_home` into the home opened as ``home_fd`` (``home``: its path, for messages)."""
    try:
        file_name(f"{name}.html") and file_name(f"{name}.99.html")
    except UntrustedError as exc:
        raise FeedbackError(f"{home}: the page {exc}") from None
    owner = os.fstat(home_fd)
    try:
        os.mkdir("feedback", 0o755, dir_fd=home_fd)
        created = True
    except FileExistsError:
        created = False
    try:
        folder_fd = os.open("feedback", os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=home_fd)
    except OSError as exc:
        raise FeedbackError(f"{home}/feedback is not a folder ({exc.strerror}): left as it is") from None
    try:
        root = os.geteuid() == 0
        if created and root:
            os.fchown(folder_fd, owner.st_uid, owner.st_gid)
        for target in (f"{name}.html", *(f"{name}.{k}.html" for k in range(2, 100))):
            if not _foreign(target, folder_fd):
                break
        else:
            raise FeedbackError(f"{home}/feedback: {name}.html … {name}.99.html are all the student's: nothing "
                                "written")
        # a new temporary name: no file of the student's is removed; the rename replaces a link, never follows it
        write_at(folder_fd, target, stamped(text), owner=(owner.st_uid, owner.st_gid) if root else None, mode=0o644)
        return Path(home) / "feedback" / target
    finally:
        os.close(folder_fd)


def _foreign(name, folder_fd):
    """Whether ``name`` exists in the folder and is not exactly a page of this command (or not a plain file)."""
    try:
        os.stat(name, dir_fd=folder_fd, follow_symlinks=False)
    except FileNotFoundError:
        return False
    try:
        return not _ours(read_file(name, MAX_PAGE, dir_fd=folder_fd))
    except UntrustedError:
        return True


def _reports(folders, log):
    """``(folder, result, score, late seconds)`` of every report in ``folders``; the lateness from the folder's
    summary.  A report that cannot be read (not JSON, too large, not a result) is a line on ``log``, and skipped."""
    for folder in folders:
        late = {}
        if (Path(folder) / "summary.csv").is_file():
            late = {student: row.get("late_seconds") for student, row in summary_rows(folder)}
        for path in sorted(Path(folder).glob("*.json")):
            if path.name == "run.json" or path.name.endswith(".results.json"):
                continue
            try:
                data = loads(read_file(path, MAX_REPORT), constants=True)
                if not (isinstance(data, dict) and "tasks" in data and data.get("student")):
                    continue  # another JSON file
                result = GradeResult.from_dict(data)
                score = float(result.score)  # its tasks' points: one_per_student compares them
            except (UntrustedError, TypeError, KeyError, ValueError) as exc:
                print("curvature-lab feedback: " + _("{file}: not a report of curvature-lab grade ({error}): "
                                                     "skipped").format(file=path, error=clean(
                          exc if isinstance(exc, UntrustedError) else f"{type(exc).__name__}: {exc}", 300,
                          keep_newlines=False)),
                      file=log)
                continue
            yield folder, result, score, late.get(result.student)


def _shown(student):
    """A name that is no user name, as a message shows it: escaped, one line, in quotes."""
    return f"'{clean(student, 100, keep_newlines=False)}'"


def _marks(paths):
    """``{(student, assignment): [row, …]}`` of marked ``written-<id>.csv`` files, checked as the gradebook checks
    them (a ``ValueError`` names the file and line)."""
    out = {}
    for path in paths:
        read_written(path)  # numbers, and points within 0 … max
        for row in read_rows(path)[1]:
            out.setdefault((row["student"], row["assignment"]), []).append(row)
    return out


def feedback(reports, homes, *, late=None, log=None, written=()):
    """Put every report of the folders ``reports`` into its student's home under ``homes``; returns the paths.

    ``late``: the gradebook's :class:`~lab.teaching.course.late.LatePolicy`, for the penalty on a late student's page.
    ``log``: where a student's skipped page is said (default: stderr).  ``written``: marked ``written-<id>.csv``
    files whose points and comments the pages show.
    """
    marks = _marks(written)
    log = sys.stderr if log is None else log
    homes = Path(homes)
    try:
        homes_fd = os.open(homes, os.O_RDONLY | os.O_DIRECTORY | getattr(os, "O_CLOEXEC", 0))
    except OSError:
        raise FeedbackError(f"{homes} is not a folder of homes") from None
    try:
        return _feedback(reports, homes, homes_fd, late, log, marks)
    finally:
        os.close(homes_fd)


def _feedback(reports, homes, homes_fd, late, log, marks):
    folders = reports if isinstance(reports, (list, tuple)) else [reports]
    items = [(folder, res.student, res.assignment, score, (res, seconds))
             for folder, res, score, seconds in _reports(folders, log)]
    if not items:
        raise FeedbackError(f"no reports (<name>.json written by curvature-lab grade) in "
                            f"{', '.join(map(str, folders))}")
    chosen, conflicts = one_per_student(items)

    def say(text):
        print("curvature-lab feedback: " + text, file=log)

    for (student, aid), where in conflicts.items():
        say(_("{student} has assignment {assignment} in two report folders, {first} and {second}: no page written; "
              "pass only the folder that counts").format(
                  student=clean(student, 100, keep_newlines=False), assignment=clean(aid, 100, keep_newlines=False),
                  first=where[0], second=", ".join(map(str, where[1:]))))
    written = []
    for result, late_seconds in chosen.values():
        try:
            student = student_id(result.student)
        except UntrustedError as exc:
            say(_("the report of {student} skipped: {why}").format(student=_shown(result.student), why=exc))
            continue
        try:
            home_fd = open_folder(student, dir_fd=homes_fd)
        except UntrustedError:
            say(_("no home for {student}: skipped").format(student=student))
            continue
        try:
            try:
                text = render(result, late_seconds, late, marks.get((result.student, result.assignment), ()))
            except Exception as exc:  # noqa: BLE001 - one student's damaged report never stops the others
                say(_("{student}: the page could not be made: {error}").format(
                    student=student, error=clean(f"{type(exc).__name__}: {exc}", 300, keep_newlines=False)))
                continue
            written.append(_write_page(home_fd, homes / student, _safe_name(result.assignment or "feedback"), text))
        except (FeedbackError, OSError) as exc:
            say(clean(exc, 500, keep_newlines=False))
        finally:
            os.close(home_fd)
    print(_("feedback for {n} of {total} reports").format(n=len(written), total=len(chosen) + len(conflicts)), file=log)
    return written


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab feedback",
        description=_("Put each student's graded report, as a page in the student's language with every case and hint, "
                      "into the student's home: HOMES/<student>/feedback/<assignment>.html. Nothing else is touched, "
                      "and a page the student changed is kept. A late student's page says how late and, with the "
                      "gradebook's --late-penalty, the penalty."))
    parser.add_argument("reports", nargs="+", metavar="REPORTS", help=_("report folders written by curvature-lab grade"))
    parser.add_argument("homes", metavar="HOMES", help=_("folder of the students' homes, one per user name (e.g. /home)"))
    parser.add_argument("--written", action="append", default=[],
                        help=_("a marked written-<id>.csv: its points and comments on the pages (repeatable)"))
    add_late_options(parser, penalty=None)
    args = parser.parse_args(argv)
    try:
        feedback(args.reports, args.homes, late=late_policy(args), written=args.written)
    except (FeedbackError, OSError, ValueError) as exc:
        print(f"curvature-lab feedback: error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
