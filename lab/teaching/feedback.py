"""Returning the graded reports to the students: ``curvature-lab feedback REPORTS HOMES``.

For every report of a graded folder (``REPORTS/<name>.json``, :mod:`lab.teaching.batch`) the student's home
``HOMES/<student>`` gets ``feedback/<assignment>.html``: a page in the student's language (the report's)
with the score, every task, every case with its status and, for each failing case, what was expected, what
came out and the hint, then the notes.  JupyterLab opens it from the file browser.

Nothing else in a home is touched.  The page is written as the home's owner would have it (owner and group
of the home), through descriptors opened without following links, so a ``feedback`` folder or file that a
student replaced by a symbolic link is refused, never followed (the instructor may run this as root).  Every
page ends with a stamp, the SHA-256 of all its bytes before it, and a ``feedback/<assignment>.html`` is replaced
only when it is exactly such a page: one the student edited or wrote (or a page written before the stamp) is
kept, and the new page goes next to it with a number (``<assignment>.2.html``).  A stamp a student forges makes
the command replace that file only, never another.

A late student's page says how late the notebook was handed in (``late_seconds`` in the report folder's
``summary.csv``) and, given the gradebook's ``--late-penalty`` (``--late-cap``, ``--grace``), the penalty.

One student's assignment in two report folders (``feedback reports/*`` with ``reports/05late``) is an error
naming both, before any page is written; of a student's two notebooks in one folder the better is returned,
the one the gradebook counts.
"""

import argparse
import hashlib
import json
import math
import os
import secrets
import sys
from pathlib import Path

from .. import i18n
from ..i18n import N_, _
from .gradebook import add_late_options, late_policy, one_per_student, summary_rows
from .grading import GradeResult
from .pages import STATUS_COLOURS, e, page
from .untrusted import UntrustedError, clean, read_file

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


def render(result, late_seconds=None, policy=None):
    """The feedback page of a :class:`~lab.teaching.grading.GradeResult`, in its language; ``late_seconds`` after
    the deadline and the :class:`~lab.teaching.gradebook.LatePolicy` (or None: no penalty stated)."""
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
    return "".join(c if c.isalnum() or c in "._-" else "_" for c in str(text))[:120] or "feedback"


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
    written."""
    flags = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW
    try:
        home_fd = os.open(home, flags)
    except OSError as exc:
        raise FeedbackError(f"{home}: not a home folder ({exc.strerror})") from None
    try:
        owner = os.fstat(home_fd)
        try:
            os.mkdir("feedback", 0o755, dir_fd=home_fd)
            created = True
        except FileExistsError:
            created = False
        try:
            folder_fd = os.open("feedback", flags, dir_fd=home_fd)
        except OSError as exc:
            raise FeedbackError(f"{home}/feedback is not a folder ({exc.strerror}): left as it is") from None
        try:
            if created and os.geteuid() == 0:
                os.fchown(folder_fd, owner.st_uid, owner.st_gid)
            for target in (f"{name}.html", *(f"{name}.{k}.html" for k in range(2, 100))):
                if not _foreign(target, folder_fd):
                    break
            else:
                raise FeedbackError(f"{home}/feedback: {name}.html … {name}.99.html are all the student's: nothing "
                                    "written")
            tmp = f".{target}.{secrets.token_hex(8)}.tmp"  # a new name: no file of the student's is removed
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644, dir_fd=folder_fd)
            with os.fdopen(fd, "wb") as fh:
                fh.write(stamped(text))
                if os.geteuid() == 0:
                    os.fchown(fh.fileno(), owner.st_uid, owner.st_gid)
            os.replace(tmp, target, src_dir_fd=folder_fd, dst_dir_fd=folder_fd)
            return Path(home) / "feedback" / target
        finally:
            os.close(folder_fd)
    finally:
        os.close(home_fd)


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


def _reports(folders):
    """``(folder, result, late seconds)`` of every report in ``folders``; the lateness from the folder's summary."""
    for folder in folders:
        late = {}
        if (Path(folder) / "summary.csv").is_file():
            late = {student: row.get("late_seconds") for student, row in summary_rows(folder)}
        for path in sorted(Path(folder).glob("*.json")):
            if path.name == "run.json" or path.name.endswith(".results.json"):
                continue
            data = json.loads(path.read_text())
            if isinstance(data, dict) and "tasks" in data and data.get("student"):
                result = GradeResult.from_dict(data)
                yield folder, result, late.get(result.student)


def feedback(reports, homes, *, late=None, log=sys.stderr):
    """Put every report of the folders ``reports`` into its student's home under ``homes``; returns the paths.

    ``late``: the gradebook's :class:`~lab.teaching.gradebook.LatePolicy`, for the penalty on a late student's page.
    """
    homes = Path(homes)
    if not homes.is_dir():
        raise FeedbackError(f"{homes} is not a folder of homes")
    folders = reports if isinstance(reports, (list, tuple)) else [reports]
    chosen = one_per_student(((folder, res.student, res.assignment, res.score, (res, seconds))
                              for folder, res, seconds in _reports(folders)), FeedbackError)
    written = []
    for result, late_seconds in chosen.values():
        home = homes / result.student
        if not home.is_dir() or home.is_symlink():
            print("curvature-lab feedback: " + _("no home for {student}: skipped").format(student=clean(result.student, 80)),
                  file=log)
            continue
        try:
            written.append(write_into_home(home, _safe_name(result.assignment or "feedback"),
                                           render(result, late_seconds, late)))
        except FeedbackError as exc:
            print(f"curvature-lab feedback: {exc}", file=log)
    if not chosen:
        raise FeedbackError(f"no reports (<name>.json written by curvature-lab grade) in "
                            f"{', '.join(map(str, folders))}")
    print(_("feedback for {n} of {total} reports").format(n=len(written), total=len(chosen)), file=log)
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
    add_late_options(parser, penalty=None)
    args = parser.parse_args(argv)
    try:
        feedback(args.reports, args.homes, late=late_policy(args))
    except (FeedbackError, OSError, ValueError) as exc:
        print(f"curvature-lab feedback: error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
