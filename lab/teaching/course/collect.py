"""Collecting an assignment from the students' homes: ``curvature-lab collect HOMES --assignment ID --deadline ISO
--out SUBS``.

``HOMES`` is a folder with one home per student, named by the user name: the local spawner's ``/home``, or
the hub's home volumes mounted in an admin pod (docs/instructors/collect.md).  In each home the notebook of the
assignment is the one whose metadata ``lab.assignment`` is ``ID`` (every exercise carries it, whatever the
student renamed the file to), else one whose file name is ``ID.ipynb``; of several, one the student changed
before one still as handed out (the hand-out has each exercise in English and German: a student who works in
one language keeps the other copy untouched), then the one saved last by its modification time (the others are
noted).  It is copied to ``SUBS/<student>/<ID>.ipynb``, with the hand-in time
as its modification time.

**The hand-in time** (``submitted``) comes from nothing the student controls.  It is the earlier of two times,
each an upper bound of when the notebook's bytes last changed:

* ``changed``, the file's status-change time (``ctime``): the kernel sets it, from its own clock, on every write,
  rename, ``chmod`` or change of the file's times, and its owner cannot set it back (``touch -d`` sets the
  modification time and moves the status-change time to now);
* ``first_seen``, the collector's first sight of exactly these bytes: the time, on the collecting machine's
  clock, at which a collect into this ``SUBS`` first read them.  It is kept from ``SUBS/collected.csv`` while
  the SHA-256 is unchanged, so that a collect at the deadline and another one later keep the on-time record of
  every notebook not changed in between.

Trusted are only the kernel's clock and the collector's, never a time the student can write.  ``modified``, the
file's modification time, is what JupyterLab's last save left, but its owner can set it to anything: it is
reported beside, never trusted, with a note when it is before the deadline and the hand-in time after it.  The
first sight is as good as the collector's clock; the status-change time is moved by any change to the file, never
back.  So a notebook changed in any way after the deadline (a save, even without an edit, a rename, a
``touch``) is late, unless an earlier collect saw the same bytes on time.  Copying the homes (``kubectl cp``,
``tar``, ``rsync``, a backup restore) gives every file the time of the copy as its status-change time: collect
from the live homes (a local ``/home``, the volumes mounted in a pod), or at least once at the deadline into the
``SUBS`` that later collects use.  On NFS the status-change time is the file server's clock.

``SUBS/collected.csv`` records per student the file, the hand-in time (``submitted``) and the three times it
comes from or is reported beside (``modified``, ``changed``, ``first_seen``, ISO 8601 in UTC), whether it is
late and by how many seconds (from the hand-in time), its SHA-256 and size, and a status: ``collected``,
``missing`` (no notebook of the assignment; also for students of ``--students`` without a home) or ``refused``
(a symbolic link, a FIFO or device, a hard link, a file over the size limit, a file that kept changing while it
was read).  Free-text answers of the assignment's questions go to ``SUBS/written-<ID>.html`` and ``.csv``
(:mod:`lab.teaching.course.written`).

A home is only read, and what is checked is what is read: ``HOMES`` is opened once, each home, folder and
notebook by one ``open`` relative to its parent's descriptor without following a symbolic link (a folder swapped
for a link to a classmate's home between two steps is not entered, a notebook that is a link is refused), and
every check (a regular file, one hard link, the size limit, the times) is made with ``fstat`` on the descriptor
the bytes are then read from.  The walk is bounded in depth and number, skips caches and hidden folders, and
nothing in a home is written, renamed or touched.  Collecting again into the same ``SUBS`` replaces the copies
it made before, but refuses to overwrite a copy that was changed since (an instructor's correction), naming it.
"""

import argparse
import csv
import errno
import hashlib
import io
import json
import os
import stat
import sys
from datetime import datetime, timedelta, timezone
from pathlib import Path

import nbformat
from nbformat.v4.nbjson import JSONReader

from ... import i18n
from ...i18n import _
from ..grader.assignments import DEFAULT_FOLDER
from ..grader.notebook import MAX_NOTEBOOK
from ..untrusted import MAX_CELLS, UntrustedError, clean, csv_cell, loads
from . import written
from .files import COLLECTED_COLUMNS, read_collected, read_roster, write_atomic

__all__ = ["COLLECTED_COLUMNS", "CollectError", "collect", "find_notebook", "main", "parse_deadline"]

#: Folders of a home never searched (caches, installed packages, checkpoints, the feedback the lab returns).
SKIP_DIRS = {".ipynb_checkpoints", ".cache", ".local", ".conda", ".npm", ".ipython", ".jupyter", "node_modules",
             "__pycache__", ".git", ".venv", "venv", "site-packages", "feedback"}
MAX_DEPTH = 6
MAX_FILES = 5000
#: Reads of a notebook that changed while it was read before it is refused.
READ_ATTEMPTS = 3

_CLOEXEC = getattr(os, "O_CLOEXEC", 0)
#: A folder of a home: one path component, never through a symbolic link.
_FOLDER = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | _CLOEXEC
#: A notebook: never through a symbolic link, and a FIFO never blocks the collector.
_FILE = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | _CLOEXEC
_EPOCH = datetime(1970, 1, 1, tzinfo=timezone.utc)


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


def _clock():
    """The collector's own clock: the time at which it sees a notebook's bytes (timezone-aware)."""
    return datetime.now(timezone.utc)


def _ns(when):
    """Nanoseconds since the epoch of a timezone-aware datetime (exact to the microsecond)."""
    return (when - _EPOCH) // timedelta(microseconds=1) * 1000


def _iso(ns):
    """ISO 8601 in UTC of a time in nanoseconds since the epoch (to the microsecond)."""
    return (_EPOCH + timedelta(microseconds=ns // 1000)).isoformat()


def _read_ns(text):
    """Nanoseconds of an ISO 8601 time from an earlier collected.csv, or None."""
    try:
        when = datetime.fromisoformat(str(text))
    except ValueError:
        return None
    return _ns(when.astimezone() if when.tzinfo is None else when)


def _entries(dir_fd):
    """``(folders, others)``: the names in the open folder ``dir_fd``, sorted; a folder by the entry's own type (a
    symbolic link to a folder is no folder)."""
    folders, others = [], []
    try:
        with os.scandir(dir_fd) as entries:
            for entry in entries:
                try:
                    (folders if entry.is_dir(follow_symlinks=False) else others).append(entry.name)
                except OSError:
                    continue
    except OSError:
        return [], []
    return sorted(folders), sorted(others)


def _notebooks(dir_fd, rel=Path(), depth=0, budget=None):
    """``(rel, dir_fd, name)`` of each ``.ipynb`` name in the open folder ``dir_fd`` and below: each sub-folder
    opened once, by its name relative to its parent's descriptor and without following a symbolic link (a folder
    replaced by a link since it was listed is not entered), bounded in depth and count.  ``dir_fd`` is the
    notebook's folder, open until the next item: read the notebook through it."""
    budget = [MAX_FILES] if budget is None else budget
    folders, others = _entries(dir_fd)
    for name in others:
        if name.endswith(".ipynb"):
            budget[0] -= 1
            if budget[0] < 0:
                return
            yield rel / name, dir_fd, name
    if depth >= MAX_DEPTH:
        return
    for name in folders:
        if name in SKIP_DIRS or name.startswith("."):
            continue
        try:
            sub = os.open(name, _FOLDER, dir_fd=dir_fd)
        except OSError:  # no longer a folder (a link in its place), or unreadable: not searched
            continue
        try:
            yield from _notebooks(sub, rel / name, depth + 1, budget)
        finally:
            os.close(sub)
        if budget[0] < 0:
            return


def _kind(mode):
    for test, name in ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a folder"), (stat.S_ISLNK, "a symbolic link")):
        if test(mode):
            return name
    return "not a regular file"


def _refusal(info):
    """Why the file of ``os.fstat`` result ``info`` is not collected (a short English reason), or None."""
    if not stat.S_ISREG(info.st_mode):
        return _kind(info.st_mode)
    if info.st_nlink > 1:
        return f"a hard link ({info.st_nlink} names for one file)"
    if info.st_size > MAX_NOTEBOOK:
        return f"{info.st_size} bytes; at most {MAX_NOTEBOOK} are read"
    return None


def _read(dir_fd, name):
    """``(raw, info)`` of the notebook ``name`` in the open folder ``dir_fd``: opened once, without following a
    symbolic link and without blocking; every check and the times (``info``, from ``os.fstat`` after the read) are
    of that descriptor, and the bytes are read from it.  A file that changed while it was read (its status-change
    time, modification time or size differ before and after) is read again, at most :data:`READ_ATTEMPTS` times.
    :class:`UntrustedError` with a short reason for a refused file."""
    try:
        fd = os.open(name, _FILE, dir_fd=dir_fd)
    except OSError as exc:
        raise UntrustedError("a symbolic link" if exc.errno == errno.ELOOP else
                             f"cannot be read ({exc.strerror})") from None
    try:
        for _attempt in range(READ_ATTEMPTS):
            before = os.fstat(fd)
            why = _refusal(before)
            if why:
                raise UntrustedError(why)
            chunks, size = [], 0
            while size <= MAX_NOTEBOOK:
                chunk = os.pread(fd, min(MAX_NOTEBOOK + 1 - size, 1 << 20), size)
                if not chunk:
                    break
                chunks.append(chunk)
                size += len(chunk)
            after = os.fstat(fd)
            why = _refusal(after) or (f"more than {MAX_NOTEBOOK} bytes" if size > MAX_NOTEBOOK else None)
            if why:
                raise UntrustedError(why)
            times = (before.st_ctime_ns, before.st_mtime_ns, before.st_size)
            if times == (after.st_ctime_ns, after.st_mtime_ns, after.st_size) and size == after.st_size:
                return b"".join(chunks), after
        raise UntrustedError(f"changed while it was being read ({READ_ATTEMPTS} times)")
    finally:
        os.close(fd)


def _meta_id(raw):
    """The assignment id a notebook's metadata claims, and the notebook (not validated: the grader does that once);
    (None, None) for what is no notebook.  Read with a bounded nesting and cell count, never quadratic."""
    try:
        data = loads(raw, max_depth=64)
        if not isinstance(data, dict) or not isinstance(data.get("cells", []), list) \
                or len(data.get("cells", [])) > MAX_CELLS or not isinstance(data.get("metadata", {}), dict):
            return None, None
        nb = JSONReader().to_notebook(data)  # as nbformat reads it (sources as one string), not validated
    except (UntrustedError, ValueError, TypeError, AttributeError, RecursionError):  # simply not this assignment's (by metadata)
        return None, None
    meta = nb.metadata.get("lab") if isinstance(nb.metadata.get("lab"), dict) else {}
    return (str(meta["assignment"]) if "assignment" in meta else None), nb


def _sources(nb):
    """What a student writes in a notebook: the kinds and sources of its cells (not outputs or metadata, which
    running or saving an untouched copy changes)."""
    return hashlib.sha256(json.dumps([(c.get("cell_type"), c.get("source")) for c in nb.cells]).encode()).hexdigest()


def _find(home_fd, assignment_id, handed_out=frozenset()):
    """``(found, notes)`` for the open home ``home_fd``: ``found`` is ``(rel, raw, notebook, info, seen)`` of the
    student's notebook of the assignment (``info`` the ``os.fstat`` of the descriptor its bytes were read from,
    ``seen`` the collector's time after reading them), or None; refused files of the assignment's name are in the
    notes.  A notebook whose cells are those of a hand-out copy (``handed_out``, of :func:`_sources`) comes after
    one the student changed."""
    candidates, notes = [], []
    for rel, dir_fd, name in _notebooks(home_fd):
        named = rel.stem == assignment_id
        try:
            raw, info = _read(dir_fd, name)
        except UntrustedError as exc:
            if named:
                notes.append(f"{rel} refused: {exc}")
            continue
        seen = _clock()
        claimed, nb = _meta_id(raw)
        by_meta, by_name = claimed == assignment_id, named and claimed is None
        if by_meta or by_name:
            untouched = nb is not None and _sources(nb) in handed_out
            candidates.append(((0 if by_meta else 1, untouched, -info.st_mtime_ns, str(rel)),
                               (rel, raw, nb, info, seen)))
    if not candidates:
        return None, notes
    candidates.sort(key=lambda c: c[0])
    others = [str(c[1][0]) for c in candidates[1:]]
    if others:
        notes.append(f"also found, not collected (as handed out, saved earlier or matched by file name only): {', '.join(others)}")
    return candidates[0][1], notes


def find_notebook(home, assignment_id, exercises=DEFAULT_FOLDER):
    """``(path, raw, notebook, notes)`` of the student's notebook of the assignment in ``home``, or ``(None, …)``;
    one the student changed before one as handed out (the exercises in ``exercises``).

    Refused files (links, oversized) are returned in the notes; the path is None then if nothing else matched.
    ``home`` is opened without following a symbolic link (an OSError if it is not a folder).
    """
    home_fd = os.open(home, _FOLDER)
    try:
        found, notes = _find(home_fd, assignment_id, _handed_out(exercises, assignment_id))
    finally:
        os.close(home_fd)
    if found is None:
        return None, None, None, notes
    rel, raw, nb, _info, _seen = found
    return Path(home) / rel, raw, nb, notes


def _students(homes_fd, roster):
    """The homes in the open folder of homes (folders by their own type, not links; no hidden ones, no
    ``lost+found``), and the students of the roster without one."""
    folders, _others = _entries(homes_fd)
    names = [name for name in folders if not name.startswith(".") and name != "lost+found"]
    return names, [s for s in roster if s not in names]


def _read_roster(path):
    """User names from a roster file (:func:`lab.teaching.course.files.read_roster`)."""
    return read_roster(path, CollectError)


def _find_in(homes_fd, student, assignment_id, handed_out=frozenset()):
    """:func:`_find` in the home ``student`` of the open folder of homes, opened without following a link."""
    try:
        home_fd = os.open(student, _FOLDER, dir_fd=homes_fd)
    except OSError as exc:  # replaced or removed since the homes were listed
        return None, [f"home refused: {'a symbolic link' if exc.errno == errno.ELOOP else exc.strerror}"]
    try:
        return _find(home_fd, assignment_id, handed_out)
    finally:
        os.close(home_fd)


def collect(homes, assignment_id, deadline, out_dir, *, roster=(), exercises=DEFAULT_FOLDER, log=sys.stderr):
    """Collect ``assignment_id`` from every home under ``homes`` into ``out_dir``; returns the rows of collected.csv."""
    homes, out_dir = Path(homes), Path(out_dir)
    deadline = parse_deadline(deadline) if not isinstance(deadline, datetime) else deadline
    deadline = deadline.astimezone() if deadline.tzinfo is None else deadline  # no offset: local time
    try:
        homes_fd = os.open(homes, os.O_RDONLY | os.O_DIRECTORY | _CLOEXEC)
    except OSError:
        raise CollectError(f"{homes} is not a folder of homes") from None
    try:
        return _collect(homes_fd, assignment_id, deadline, out_dir, roster, exercises, log)
    finally:
        os.close(homes_fd)


def _collect(homes_fd, assignment_id, deadline, out_dir, roster, exercises, log):
    students, without_home = _students(homes_fd, roster)
    previous = read_collected(out_dir)
    plan, rows, answers = [], [], {}
    exercise_nb, exercise_ids = _exercise(exercises, assignment_id)
    questions = written.questions_of(exercise_nb) if exercise_nb is not None else []
    handed_out = _handed_out(exercises, assignment_id)
    for student in students:
        notebook, notes = _find_in(homes_fd, student, assignment_id, handed_out)
        row = dict.fromkeys(COLLECTED_COLUMNS, "")
        row.update(student=student, assignment=assignment_id, deadline=deadline.isoformat())
        if notebook is None:
            row.update(status="refused" if notes else "missing", note="; ".join(notes))
            rows.append(row)
            continue
        rel, raw, nb, info, seen = notebook
        digest = hashlib.sha256(raw).hexdigest()
        target = out_dir / student / f"{assignment_id}.ipynb"
        old = previous.get(student)
        if target.exists() and old and hashlib.sha256(target.read_bytes()).hexdigest() != old.get("sha256"):
            raise CollectError(f"{target} was changed since it was collected; move it away to keep it, then collect "
                               "again")
        first_seen = _ns(seen)
        if old and old.get("assignment") == assignment_id and old.get("sha256") == digest:
            earlier = _read_ns(old.get("first_seen", ""))  # these bytes were seen before (a collect at the deadline)
            first_seen = min(first_seen, earlier) if earlier is not None else first_seen
        handed_in = min(info.st_ctime_ns, first_seen)
        late = max(0, handed_in - _ns(deadline)) / 1e9
        if info.st_mtime_ns <= _ns(deadline) < handed_in:
            notes.append(f"modification time {_iso(info.st_mtime_ns)} is before the deadline, but the file was last "
                         f"changed at {_iso(info.st_ctime_ns)} (a write, a rename or a change of its times)")
        row.update(status="collected", file=str(rel), submitted=_iso(handed_in), modified=_iso(info.st_mtime_ns),
                   changed=_iso(info.st_ctime_ns), first_seen=_iso(first_seen), late=late > 0,
                   late_seconds=round(late), sha256=digest, bytes=len(raw), note="; ".join(notes))
        plan.append((target, raw, handed_in))
        rows.append(row)
        if questions:
            answers[student] = written.answers_of(nb, questions, exercise_ids)
    for student in without_home:
        row = dict.fromkeys(COLLECTED_COLUMNS, "")
        row.update(student=student, assignment=assignment_id, status="missing", deadline=deadline.isoformat(),
                   note="no home")
        rows.append(row)
    out_dir.mkdir(parents=True, exist_ok=True)
    for target, raw, handed_in in plan:
        target.parent.mkdir(exist_ok=True)
        tmp = target.with_name(f".{target.name}.tmp")
        tmp.write_bytes(raw)
        os.utime(tmp, ns=(handed_in, handed_in))  # the hand-in time, for tools that read a file's time
        os.replace(tmp, target)
    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow(COLLECTED_COLUMNS)
    for row in sorted(rows, key=lambda r: r["student"]):
        writer.writerow([csv_cell(row[c]) for c in COLLECTED_COLUMNS])
    write_atomic(out_dir / "collected.csv", buf.getvalue())
    if questions:
        lang = (exercise_nb.metadata.get("lab") or {}).get("lang", "en")
        written.collect_answers(out_dir, assignment_id, exercise_nb, answers, lang, log=log)
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


def _handed_out(exercises, assignment_id):
    """:func:`_sources` of the exercise notebooks of the assignment in every language (the copies a student got)."""
    where = Path(exercises)
    paths = [folder / f"{assignment_id}.ipynb" for folder in (where, *(where / lang for lang in i18n.LANGUAGES))]
    return frozenset(_sources(nbformat.read(str(p), as_version=4)) for p in paths if p.is_file())


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
