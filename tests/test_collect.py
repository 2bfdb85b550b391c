"""``collect`` reads what it checks and takes the hand-in time from nothing a student controls.

A student who swaps a folder of the home for a symbolic link to a classmate's, at any step of the collector's walk,
never has the classmate's notebook collected as their own; a notebook whose modification time was set back
(``touch -d``) is late by the kernel's status-change time; collecting again keeps the first sight of unchanged bytes.
(tests/test_course.py collects a whole course; these homes are small and made here.)"""

import csv
import datetime
import hashlib
import io
import os
import time

import nbformat
import pytest

from lab.teaching.course import collect
from tests.test_course import ID, _snapshot

UTC = datetime.timezone.utc
PAST = datetime.datetime(2025, 12, 15, 23, 59, tzinfo=UTC)  # a deadline before any file written here


def _notebook(path, marker, mtime=None):
    """A notebook of assignment ID (by its metadata) whose only cell says ``marker``; its bytes."""
    nb = nbformat.v4.new_notebook(metadata={"lab": {"assignment": ID}})
    nb.cells.append(nbformat.v4.new_code_cell(f"# {marker}"))
    path.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, str(path))
    if mtime is not None:
        os.utime(path, (mtime.timestamp(),) * 2)
    return path.read_bytes()


def _sha(data):
    return hashlib.sha256(data).hexdigest()


def _at(ns):
    """A file's time (nanoseconds) as collected.csv writes it: ISO 8601 in UTC, to the microsecond."""
    return (datetime.datetime(1970, 1, 1, tzinfo=UTC) + datetime.timedelta(microseconds=ns // 1000)).isoformat()


def _collect(homes, subs, deadline=PAST, **kw):
    return {r["student"]: r for r in collect.collect(homes, ID, deadline.isoformat(), subs, log=io.StringIO(),
                                                     exercises=homes.parent / "no-exercises", **kw)}


#: The file-system calls through which any collector looks at a home; the swap comes just before the k-th of them.
_CALLS = ("open", "lstat", "stat", "scandir", "listdir", "fstat", "read", "pread")


def test_a_folder_swapped_for_a_link_never_collects_a_classmates_notebook(tmp_path):
    """mal swaps his folder ``work`` for a symbolic link to ada's ``work`` (same notebook name) just before the
    collector's k-th look at the file system, for every k in turn: ada's notebook is never collected as mal's."""
    homes = tmp_path / "home"
    theirs = _notebook(homes / "ada" / "work" / f"{ID}.ipynb", "ada's own work")
    mine = _notebook(homes / "mal" / "work" / f"{ID}.ipynb", "mal's own work")
    work, kept = homes / "mal" / "work", homes / "mal" / ".work"  # hidden: not searched
    real = {name: getattr(os, name) for name in _CALLS}
    state = {"calls": 0, "at": None, "swapped": False}

    def wrapped(name):
        def call(*args, **kwargs):
            state["calls"] += 1
            if state["calls"] == state["at"]:
                os.rename(work, kept)
                os.symlink(homes / "ada" / "work", work)
                state["swapped"] = True
            return real[name](*args, **kwargs)
        return call

    def run(at, subs):
        state.update(calls=0, at=at, swapped=False)
        with pytest.MonkeyPatch.context() as mp:
            for name in _CALLS:
                mp.setattr(os, name, wrapped(name))
            rows = _collect(homes, subs)
        if state["swapped"]:  # mal puts his folder back for the next run
            os.unlink(work)
            os.rename(kept, work)
        return rows, state["calls"]

    rows, total = run(None, tmp_path / "subs-0")
    assert rows["mal"]["sha256"] == _sha(mine) and rows["ada"]["sha256"] == _sha(theirs)
    assert total > 10, total
    outcomes = {}
    for k in range(1, total + 1):
        subs = tmp_path / f"subs-{k}"
        rows, _calls = run(k, subs)
        mal = rows["mal"]
        assert mal["sha256"] != _sha(theirs), f"ada's notebook collected as mal's (swap before call {k})"
        if mal["status"] == "collected":
            assert mal["sha256"] == _sha(mine) and (subs / "mal" / f"{ID}.ipynb").read_bytes() == mine, k
        else:
            assert mal["status"] in ("missing", "refused") and not (subs / "mal").exists(), (k, mal)
        assert rows["ada"]["sha256"] == _sha(theirs), k
        outcomes.setdefault(mal["status"], []).append(k)
    # a swap before mal's folder is opened hides his notebook (the link is not entered); after it, his own is collected
    assert set(outcomes) == {"missing", "collected"}, outcomes
    assert max(outcomes["missing"]) < min(outcomes["collected"]), outcomes
    assert os.path.isdir(work) and not os.path.islink(work) and not kept.exists()


def test_a_modification_time_set_back_does_not_make_a_late_notebook_on_time(tmp_path):
    """mal wrote his notebook after the deadline (an hour ago) and set its modification time 3 hours before it
    (``touch -d``): late by the kernel's status-change time, which its owner cannot set back; the modification
    time reported beside it, with a note."""
    homes, subs = tmp_path / "home", tmp_path / "subs"
    deadline = datetime.datetime.fromtimestamp(int(time.time()) - 3600, UTC)
    set_back = deadline - datetime.timedelta(hours=3)
    path = homes / "mal" / f"{ID}.ipynb"
    data = _notebook(path, "written after the deadline", mtime=set_back)
    changed = os.stat(path).st_ctime_ns
    assert os.stat(path).st_mtime == set_back.timestamp() and changed > deadline.timestamp() * 1e9
    before = _snapshot(homes)
    row = _collect(homes, subs, deadline)["mal"]
    assert row["status"] == "collected" and row["sha256"] == _sha(data)
    assert row["late"] is True and row["late_seconds"] == round(changed / 1e9 - deadline.timestamp()) >= 3600
    assert row["submitted"] == row["changed"] == _at(changed)
    assert row["modified"] == set_back.isoformat()
    assert row["first_seen"] >= _at(changed)  # the collector saw it just now
    assert row["note"] == (f"modification time {set_back.isoformat()} is before the deadline, but the file was last "
                           f"changed at {_at(changed)} (a write, a rename or a change of its times)")
    assert os.stat(subs / "mal" / f"{ID}.ipynb").st_mtime_ns == changed  # the copy carries the hand-in time
    with open(subs / "collected.csv", newline="") as fh:
        written = next(csv.DictReader(fh))
    assert written["late"] == "True" and written["modified"] == set_back.isoformat()
    assert written["submitted"] == _at(changed) and written["late_seconds"] == str(row["late_seconds"])
    assert _snapshot(homes) == before  # only read


def test_collecting_again_keeps_the_first_sight_of_unchanged_bytes(tmp_path, monkeypatch):
    """Collected at the deadline and again a day later: ada's unchanged notebook keeps the time the collector first
    saw it (on time, though the files were written after PAST); bea's, changed in between, is seen anew (late)."""
    homes, subs = tmp_path / "home", tmp_path / "subs"
    ada = _notebook(homes / "ada" / f"{ID}.ipynb", "ada, done early")
    _notebook(homes / "bea" / f"{ID}.ipynb", "bea, a first try")
    at_deadline, a_day_later = PAST - datetime.timedelta(minutes=5), PAST + datetime.timedelta(days=1)
    monkeypatch.setattr(collect, "_clock", lambda: at_deadline)
    first = _collect(homes, subs)
    for student in ("ada", "bea"):
        assert first[student]["first_seen"] == first[student]["submitted"] == at_deadline.isoformat()
        assert first[student]["late"] is False and first[student]["late_seconds"] == 0
    bea = _notebook(homes / "bea" / f"{ID}.ipynb", "bea, after the deadline")
    monkeypatch.setattr(collect, "_clock", lambda: a_day_later)
    again = _collect(homes, subs)
    assert again["ada"]["sha256"] == _sha(ada) and again["ada"]["first_seen"] == at_deadline.isoformat()
    assert again["ada"]["submitted"] == at_deadline.isoformat() and again["ada"]["late"] is False
    assert again["bea"]["sha256"] == _sha(bea) and again["bea"]["first_seen"] == a_day_later.isoformat()
    assert again["bea"]["late"] is True and again["bea"]["late_seconds"] == 86400
    assert os.stat(subs / "ada" / f"{ID}.ipynb").st_mtime == at_deadline.timestamp()
    assert os.stat(subs / "bea" / f"{ID}.ipynb").st_mtime == a_day_later.timestamp()
    # an earlier collected.csv of another assignment in the folder is no sight of these bytes
    other = tmp_path / "other"
    other.mkdir()
    with open(subs / "collected.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    with open(other / "collected.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows([{**r, "assignment": "04_color_maps"} for r in rows])
    assert _collect(homes, other)["ada"]["first_seen"] == a_day_later.isoformat()


def test_refused_files_are_noted_from_the_descriptor_that_was_checked(tmp_path):
    """A FIFO, a hard link and a file over the size limit under the assignment's name are refused with a note each;
    a FIFO never blocks the collector; nothing in a home changes."""
    homes, subs = tmp_path / "home", tmp_path / "subs"
    (homes / "fifo").mkdir(parents=True)
    os.mkfifo(homes / "fifo" / f"{ID}.ipynb")
    _notebook(homes / "twin" / "mine.ipynb", "one file, two names")
    os.link(homes / "twin" / "mine.ipynb", homes / "twin" / f"{ID}.ipynb")
    big = homes / "big" / f"{ID}.ipynb"
    big.parent.mkdir()
    with open(big, "wb") as fh:
        fh.truncate(collect.MAX_NOTEBOOK + 1)
    before = _snapshot(homes)
    rows = _collect(homes, subs)
    assert rows["fifo"]["status"] == "refused" and rows["fifo"]["note"] == f"{ID}.ipynb refused: a FIFO"
    assert rows["twin"]["status"] == "refused"
    assert rows["twin"]["note"] == f"{ID}.ipynb refused: a hard link (2 names for one file)", rows["twin"]["note"]
    assert rows["big"]["status"] == "refused" and rows["big"]["note"] == (
        f"{ID}.ipynb refused: {collect.MAX_NOTEBOOK + 1} bytes; at most {collect.MAX_NOTEBOOK} are read")
    assert _snapshot(homes) == before and not any((subs / s).exists() for s in ("fifo", "twin", "big"))


def test_the_walk_keeps_its_bounds_and_never_follows_a_link(tmp_path):
    """Skipped folders, hidden folders and folders deeper than MAX_DEPTH are not searched; a folder that is a
    symbolic link to a classmate's is not entered."""
    homes, subs = tmp_path / "home", tmp_path / "subs"
    _notebook(homes / "ada" / "work" / f"{ID}.ipynb", "ada's")
    deep = homes / "deep" / "/".join(f"d{i}" for i in range(collect.MAX_DEPTH + 1)) / f"{ID}.ipynb"
    _notebook(deep, "too deep")
    _notebook(homes / "deep" / ".ipynb_checkpoints" / f"{ID}.ipynb", "a checkpoint")
    _notebook(homes / "deep" / ".hidden" / f"{ID}.ipynb", "hidden")
    (homes / "link").mkdir()
    (homes / "link" / "work").symlink_to(homes / "ada" / "work")
    shallow = homes / "ok" / "/".join(f"d{i}" for i in range(collect.MAX_DEPTH)) / f"{ID}.ipynb"
    data = _notebook(shallow, "deep enough")
    rows = _collect(homes, subs)
    assert rows["deep"]["status"] == "missing" and rows["deep"]["note"] == ""
    assert rows["link"]["status"] == "missing"
    assert rows["ok"]["status"] == "collected" and rows["ok"]["sha256"] == _sha(data)
    assert rows["ok"]["file"] == str(shallow.relative_to(homes / "ok"))


def test_the_copy_a_student_worked_on_is_collected_not_the_untouched_other_language(tmp_path):
    """The hand-out has each exercise in English and German; a student who works in German leaves the English copy as
    handed out, and it is newer (the hand-out was pulled after the work was saved).  The edited copy is collected,
    the untouched one noted; with both changed, the one saved last."""
    exercises = collect.DEFAULT_FOLDER
    home = tmp_path / "homes" / "uli" / "curvature-lab-student" / "exercises"
    for lang in ("en", "de"):
        (home / lang).mkdir(parents=True)
        (home / lang / f"{ID}.ipynb").write_bytes((exercises / lang / f"{ID}.ipynb").read_bytes())
    german = nbformat.read(str(home / "de" / f"{ID}.ipynb"), as_version=4)
    german.cells[-1].source += "\n# meine Antwort"
    nbformat.write(german, str(home / "de" / f"{ID}.ipynb"))
    os.utime(home / "de" / f"{ID}.ipynb", (PAST.timestamp(),) * 2)  # saved long before the English copy
    path, _raw, nb, notes = collect.find_notebook(tmp_path / "homes" / "uli", ID)
    assert path == home / "de" / f"{ID}.ipynb" and nb.cells[-1].source.endswith("# meine Antwort")
    assert notes == [("also found, not collected (as handed out, saved earlier or matched by file name only): "
                      f"curvature-lab-student/exercises/en/{ID}.ipynb")]
    english = nbformat.read(str(home / "en" / f"{ID}.ipynb"), as_version=4)
    english.cells[-1].source += "\n# my answer"
    nbformat.write(english, str(home / "en" / f"{ID}.ipynb"))  # both changed: the one saved last
    path, *_ = collect.find_notebook(tmp_path / "homes" / "uli", ID)
    assert path == home / "en" / f"{ID}.ipynb"
