"""Assignments: which tasks a notebook is graded on and for how many points (the instructor's, never the student's).

An assignment is the instructor's copy of a notebook (an exercise or a solution of ``solutions/<lang>/`` /
``exercises/<lang>/``): its metadata ``lab.tasks`` lists ``{"task", "object", "points"}`` and ``lab.assignment``
is its id (the file's stem, e.g. ``05_visualize_curvature``).  A submission names its assignment by that
id (exercises carry it); the grader looks the id up in the instructor's folder (``--assignment``, default:
the project's ``exercises/``), directly in it or in its language folders ``en/``, ``de/`` – the
submission's language (``lab.lang``) first.  English and German notebooks of one assignment have the same id
and the same tasks.  What the submission's own metadata says about tasks and points is ignored and only
reported when it differs.

A task listed with ``"per_student": true`` is about the student's own surface (:mod:`lab.teaching.kernel.variants`):
it is graded only with the variants table of a per-student release (``curvature-lab grade --variants``), and is then
part of the assignment's points (:attr:`Assignment.per_student`); with a common hand-out every student's numbers
would be the same, so it is left to the notebook's own check.
"""

from dataclasses import dataclass
from pathlib import Path

import nbformat

from ... import repository
from ...i18n import LANGUAGES, _
from ..tasks import TASKS

__all__ = ["DEFAULT_FOLDER", "REAL_PARTS", "Assignment", "AssignmentError", "for_submission", "load", "reads_cad"]

DEFAULT_FOLDER = Path(repository()) / "exercises"


#: What an instructor's notebook calls when the assignment reads CAD files (real parts): it then needs OpenCASCADE
#: (the extra ``cad``) in the grader's sandbox and in the Gradescope image; any other assignment's sandbox lacks it.
REAL_PARTS = ("lab.read(", "models.", "occ_curvature")


class AssignmentError(ValueError):
    """No assignment, or an invalid one."""


@dataclass(frozen=True)
class Assignment:
    id: str
    title: str
    tasks: tuple  # of (task, object, points)
    path: str
    per_student: tuple = ()  # of (task, object, points): graded only in a per-student release

    @property
    def max_score(self):
        return sum(p for _, _, p in self.tasks)

    def graded(self, per_student=False):
        """The tasks graded: :attr:`tasks`, and with ``per_student`` (a variants table) :attr:`per_student` too."""
        return self.tasks + (self.per_student if per_student else ())


def _tasks(meta, where, per_student=False):
    """The ``(task, object, points)`` of the metadata's task list: those without ``per_student``, or with it."""
    tasks = meta.get("tasks")
    if not isinstance(tasks, list):
        raise AssignmentError(_("{where} has no task list (metadata 'lab' -> 'tasks'); is it a curvature-lab notebook?").format(
            where=where))
    out, seen = [], set()
    for t in tasks:
        if not isinstance(t, dict) or t.get("task") not in TASKS:
            raise AssignmentError(_("{where}: unknown task {task}; expected one of {tasks}").format(
                where=where, task=repr(t), tasks=", ".join(TASKS)))
        if bool(t.get("per_student", False)) != per_student:
            continue
        obj, points = str(t.get("object", t["task"])), float(t.get("points", 1))
        if (t["task"], obj) in seen or not points >= 0:
            raise AssignmentError(_("{where}: task {task} on {object} is listed twice or has invalid points").format(
                where=where, task=t["task"], object=obj))
        seen.add((t["task"], obj))
        out.append((t["task"], obj, points))
    return tuple(out)


def load(path):
    """The assignment of an instructor's notebook."""
    path = Path(path)
    try:
        nb = nbformat.read(str(path), as_version=4)
    except Exception as exc:  # noqa: BLE001 - whatever makes it unreadable is said in the AssignmentError
        raise AssignmentError(_("cannot read the assignment {path}: {error}").format(
            path=path, error=f"{type(exc).__name__}: {exc}")) from None
    meta = nb.metadata.get("lab", {})
    return Assignment(str(meta.get("assignment", path.stem)), str(meta.get("title", path.stem)),
                      _tasks(meta, str(path)), str(path), _tasks(meta, str(path), per_student=True))


def _lookup(where, key, lang):
    """The instructor's notebook ``key``.ipynb in ``where`` or its language folders (``lang`` first), or None."""
    if not key:
        return None
    name = f"{Path(str(key)).name}.ipynb"
    folders = [where] + [where / code for code in sorted(LANGUAGES, key=lambda code: code != lang)]
    return next((f / name for f in folders if (f / name).is_file()), None)


def for_path(path, assignment=None, lang=""):
    """The instructor's assignment of a submission known only by its path (its file name), or None."""
    where = Path(assignment) if assignment is not None else DEFAULT_FOLDER
    if where.is_file():
        return load(where)
    found = _lookup(where, Path(path).stem, lang)
    return load(found) if found is not None else None


def for_submission(nb, path, assignment=None):
    """The instructor's assignment for a submission, and notes about mismatches.

    ``assignment``: a notebook (used as is), or a folder of instructor notebooks in which the submission is
    looked up by its file name (the instructor's: ``collect`` names every copy after its assignment), directly
    in it or in its language folders (the submission's language ``lab.lang`` first); only a file name that is
    no assignment falls back to the id the notebook claims.  Default: the project's ``exercises/``.  Whatever the
    notebook claims, its id or its task list, is only noted where it differs.
    """
    meta = nb.metadata.get("lab", {}) if isinstance(nb.metadata.get("lab"), dict) else {}
    claimed = meta.get("assignment")
    claimed = None if claimed is None else str(claimed)[:100]
    stem = Path(path).stem
    notes = []
    where = Path(assignment) if assignment is not None else DEFAULT_FOLDER
    if where.is_file():
        found = load(where)
        if claimed is not None and claimed != found.id:
            notes.append(_("the notebook says it is assignment {claimed}; graded as {id} as instructed").format(
                claimed=repr(claimed), id=repr(found.id)))
    else:
        lang = str(meta.get("lang", ""))
        by_name = _lookup(where, stem, lang)
        if by_name is not None:
            found = load(by_name)
            if claimed is not None and claimed != found.id:
                notes.append(_("the notebook says it is assignment {claimed}, its file name says {id}: graded as "
                               "{id}").format(claimed=repr(claimed), id=repr(found.id)))
        else:
            by_claim = _lookup(where, claimed, lang)
            if by_claim is None:
                raise AssignmentError(_("cannot tell which assignment {path} is (id {id} not found in {where}); pass "
                                        "--assignment").format(path=path, id=repr(claimed or stem), where=where))
            found = load(by_claim)
            notes.append(_("the file name {name} is no assignment: graded as {id}, the assignment the notebook "
                           "names").format(name=repr(stem), id=repr(found.id)))
    own = meta.get("tasks")
    if own is not None:
        try:
            mine = (_tasks(meta, str(path)), _tasks(meta, str(path), per_student=True))
        except AssignmentError:
            mine = None
        if mine != (found.tasks, found.per_student):
            notes.append(_("the notebook's own task list differs from the assignment's; the assignment's is used"))
    return found, notes


def reads_cad(assignment):
    """Whether the instructor's notebook of ``assignment`` (an :class:`Assignment`, or its text) reads CAD files: a
    code cell calls one of :data:`REAL_PARTS`."""
    text = assignment if isinstance(assignment, str) else Path(assignment.path).read_text()
    try:
        text = "\n".join(c.source for c in nbformat.reads(text, as_version=4).cells if c.cell_type == "code")
    except Exception:  # noqa: BLE001, S110 - not a notebook: its whole text is searched
        pass
    return any(call in text for call in REAL_PARTS)
