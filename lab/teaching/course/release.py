"""The students' hand-out: ``curvature-lab release OUT`` writes a tree that ``make lab`` works in, without answers.

What ``OUT`` holds: ``exercises/en``, ``exercises/de`` (the generated exercises, checked to be fresh), a
student README, a Makefile with the set-up and ``make lab`` only (``jupyter/setup.mk``, the same rules the
course repository uses), ``pyproject.toml``, ``jupyter/`` (JupyterLab's settings) and the library.  Not in it:
``solutions/``, ``tests/`` (with the hostile submissions), ``benchmarks/``, ``deploy/``, ``.git``, ``docs/``.

**The library, with the answers withheld.**  Every function the grading sandbox withholds for some task (the
union of the tasks' ``blocked`` lists: the reference implementations of the graded tasks and the helpers that
compute their answers) has its body removed from the source in ``OUT``: its signature and docstring stay, the
body is a line saying it is withheld (line numbers are kept).  The teaching modules that hold the cases, the
exact answers and the hints (``tasks*.py``, ``references.py``, ``hints.py``) are withheld whole.  So that the
checks, the pictures and the explorers keep working, the original code of those modules is shipped compiled:
``__pycache__/<module>.<tag>.pyc`` for each Python the release is built for (``--python``; default the one
running), written in "unchecked hash" mode (PEP 552), which Python loads without comparing it with the
source.  A Python without its ``.pyc`` runs the withheld source and gets a message saying so.  Compiled code
is not source: no line of a solution appears in ``OUT`` (checked by :func:`solution_lines_in`, which
``release`` runs on its result and which refuses to finish when one does), but a determined student can
disassemble bytecode; the grader never relies on it (its sandbox withholds the functions entirely).

``--self-study`` keeps the library as it is (the references readable, for learners who work alone); the
solutions stay out either way.  ``--git`` makes ``OUT`` a git repository and commits the hand-out, so that
``git push`` publishes it for nbgitpuller (the instructors' guide, docs/instructors/handout.md); releasing again into the same ``OUT``
replaces the hand-out and commits the difference, which nbgitpuller merges into the students' copies
without overwriting their edits.  ``OUT`` must be empty or an earlier release (marked by ``.lab-release``).

``--per-student ROSTER --secret-file FILE`` gives every student of the roster (one user name per line, or a CSV
with a ``username`` column, as ``collect --students`` reads it) their own variant of each assignment's surface that
has one (:mod:`lab.teaching.course.variants`): ``OUT/variants.json`` is the table student → parameters, which
``lab.my_surface`` reads in the student's JupyterLab and ``curvature-lab grade --variants`` in the grader; those
exercises carry the table's id in their metadata (``lab.variants``), so that grading one without the table is an
error.  The secret stays with the instructor: ``release`` checks that its bytes appear in no file of ``OUT``.
"""

import argparse
import datetime
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import nbformat

from ... import repository
from ...i18n import _
from ..kernel.variants import TABLE
from ..sandbox import withhold
from . import exercises as notebooks
from . import variants as _variants
from .files import NotACourseRepository, course_repository, read_roster

__all__ = ["MARK", "ReleaseError", "main", "release", "solution_lines", "solution_lines_in"]

ROOT = Path(repository())
MARK = ".lab-release"
#: Top-level files and folders of the hand-out, taken from the course repository.
COPIED = ("pyproject.toml", "jupyter")
#: Solution lines shorter than this (after removing spaces) are not searched: ``return K``, ``else:``.
MIN_LINE = 12
#: Lines of a solution that are general Python, not a solution's content, and may appear in the library.
GENERIC = {"forpatchinself:", "returnbu,bv,buu,buv,bvv", "P=np.asarray(loop,dtype=float)",
           "fora,bin((0,0),(0,1),(1,0),(1,1)):"}


class ReleaseError(RuntimeError):
    """The hand-out cannot be made (stale exercises, a foreign OUT, a solution line found)."""


def _compile(pythons, pairs):
    """Compile the original sources to unchecked-hash .pyc next to the release's stubs, for every Python."""
    script = ("import json, py_compile, sys, importlib.util\n"
              "for src, dst in json.loads(sys.argv[1]):\n"
              "    cfile = importlib.util.cache_from_source(dst)\n"
              "    py_compile.compile(src, cfile=cfile, dfile=dst, doraise=True,\n"
              "                       invalidation_mode=py_compile.PycInvalidationMode.UNCHECKED_HASH)\n"
              "print(sys.implementation.cache_tag)\n")
    tags = []
    for python in pythons:
        try:
            done = subprocess.run([python, "-I", "-c", script, json.dumps([[str(a), str(b)] for a, b in pairs])],
                                  capture_output=True, text=True, check=True, timeout=600)
        except (OSError, subprocess.CalledProcessError) as exc:
            raise ReleaseError(f"cannot compile the withheld code with {python}: "
                               f"{getattr(exc, 'stderr', '') or exc}") from None
        tags.append(done.stdout.strip())
    return tags


def _library(out, self_study, pythons):
    """Copy ``lab/`` into ``out``; unless ``self_study``, withhold the answers (see the module docstring)."""
    dest = out / "lab"
    shutil.copytree(ROOT / "lab", dest, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    if self_study:
        return []
    return _compile(pythons, withhold.hand_out(dest, ROOT / "lab"))


# -- no line of a solution ---------------------------------------------------------------------------------

def _normal(line):
    return re.sub(r"\s+", "", line)


def solution_lines(sources=ROOT / "solutions"):
    """``{normalised line: (notebook, the line)}`` of every solution part (code and written answers), both
    languages, that is long enough to mean something and is not part of the exercise itself."""
    found = {}
    for src in sorted(Path(sources).glob("[0-9][0-9]_*.ipynb")):
        bilingual = nbformat.read(str(src), as_version=4)
        for lang in notebooks.LANGUAGES:
            solution = notebooks.localize(bilingual, lang)
            exercise = notebooks.make_exercise(solution)
            outside = {_normal(x) for c in exercise.cells for x in c.source.split("\n")}
            for cell in solution.cells:
                for block in _solution_blocks(cell):
                    for line in block:
                        key = _normal(line)
                        if len(key) >= MIN_LINE and key not in outside and key not in GENERIC:
                            found.setdefault(key, (src.name, line.strip()))
    return found


def _solution_blocks(cell):
    if cell.cell_type == "code":
        pattern = re.compile(re.escape(notebooks.BEGIN) + r"[^\n]*\n(.*?)\n[ \t]*" + re.escape(notebooks.END), re.DOTALL)
    else:
        pattern = re.compile(re.escape(notebooks.MD_BEGIN) + r"(.*?)" + re.escape(notebooks.MD_END), re.DOTALL)
    return [m.group(1).split("\n") for m in pattern.finditer(cell.source)]


def solution_lines_in(tree, lines=None, skip=()):
    """``[(file, notebook, solution line)]``: every solution line found in any file under ``tree`` (text files line
    by line with spaces ignored, every other file as bytes); top-level folders ``skip`` are not searched."""
    lines = solution_lines() if lines is None else lines
    hits = []
    for path in sorted(p for p in Path(tree).rglob("*") if p.is_file() and ".git" not in p.relative_to(tree).parts
                       and p.relative_to(tree).parts[0] not in skip):
        data = path.read_bytes()
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            hits += [(path, nb, line) for key, (nb, line) in lines.items() if line.encode() in data]
            continue
        if path.suffix == ".ipynb":  # a notebook's source lines are JSON strings
            nb = nbformat.reads(text, as_version=4)
            text = "\n".join(c.source for c in nb.cells)
        present = {_normal(x) for x in text.split("\n")}
        squeezed = _normal(text)
        hits += [(path, nb, line) for key, (nb, line) in lines.items() if key in present or key in squeezed]
    return hits


# -- the tree ------------------------------------------------------------------------------------------------

def _prepare(out):
    out = Path(out)
    if out.exists() and any(out.iterdir()) and not (out / MARK).exists():
        raise ReleaseError(f"{out} is not empty and not an earlier release (no {MARK}): choose an empty folder")
    out.mkdir(parents=True, exist_ok=True)
    for item in out.iterdir():
        if item.name != ".git":
            shutil.rmtree(item) if item.is_dir() and not item.is_symlink() else item.unlink()
    return out


def _check_exercises():
    stale = [str(p) for p, action in notebooks.generate(check_only=True).items()
             if action == "differs" and "exercises" in Path(p).parts]
    if stale:
        raise ReleaseError("the exercises are not freshly generated from solutions/ (run make exercises): "
                           + ", ".join(stale))


def _titles(per_student=False):
    rows = []
    for path in sorted((ROOT / "exercises" / "en").glob("[0-9][0-9]_*.ipynb")):
        en = nbformat.read(str(path), as_version=4).metadata.get("lab", {})
        de_path = ROOT / "exercises" / "de" / path.name
        de = nbformat.read(str(de_path), as_version=4).metadata.get("lab", {}) if de_path.is_file() else {}
        tasks = ", ".join(f"`{t['task']}` ({t['points']:g}{', per student' if t.get('per_student') else ''})"
                          for t in en.get("tasks", []) if per_student or not t.get("per_student")) or "–"
        rows.append(f"| `{path.stem}` | {en.get('title', path.stem)} | {de.get('title', '')} | {tasks} |")
    return "\n".join(rows)


README = """# curvature-lab: exercises / Übungen

Curvature of free-form surfaces, after the practical *Versuch 6: Krümmungsvisualisierung*: exact curvature of
Bézier and B-spline surfaces, colour maps, focal surfaces, reflection lines, geodesics. / *Krümmung von
Freiformflächen nach dem Praktikum „Versuch 6: Krümmungsvisualisierung“.*

```bash
make lab            # set up (.venv, Python packages, the Debian packages offscreen rendering needs), open JupyterLab on exercises/en
make lab LANG=de    # dasselbe auf Deutsch: JupyterLab und die Notebooks in exercises/de
```

On a course JupyterHub none of this is needed: open the exercises from the file browser. / *Auf dem
JupyterHub des Kurses ist nichts davon nötig: öffnen Sie die Übungen im Dateibrowser.*

| notebook | topic | Thema | tasks (points) / Aufgaben (Punkte) |
|---|---|---|---|
{table}

**How it works.** Each notebook explains the idea with its formulas, lets you try it, and asks you to write a
function where a cell raises `NotImplementedError`. `check.<task>(your_function)` tests it at once on fresh
random cases, with exact answers and a hint that names your mistake. Your instructor grades the notebook you
hand in on further fresh cases, in a sandbox. **So funktioniert es:** `check.<aufgabe>(ihre_funktion)` prüft
Ihre Lösung sofort an neuen Zufallsfällen mit exakten Antworten und einem Hinweis, der den Fehler benennt.

{library}

Feedback on graded work appears in `~/feedback/<assignment>.html`. / *Rückmeldungen zu bewerteten Abgaben
erscheinen in `~/feedback/<aufgabe>.html`.*

Hand-out of {date}{build}.
"""

#: What the README says of the library: a course's hand-out withholds the answers, a self-learner's keeps them.
WITHHELD = """The library's own implementations of the tasks are withheld in this hand-out (their source is not here;
their compiled code is, so that the pictures and explorers work). / *Die Musterlösungen der Bibliothek sind
in dieser Ausgabe zurückgehalten.*"""
SELF_STUDY = """This hand-out is for self-study: the library's own implementations of the tasks are included and readable
(look at them after you have written yours; the checks block them while they test your code). / *Diese Ausgabe ist
für das Selbststudium: die Musterlösungen der Bibliothek sind enthalten und lesbar.*"""

MAKEFILE = """# The students' hand-out: `make lab` (set up, then JupyterLab on exercises/en) or `make lab LANG=de`.
include jupyter/setup.mk
"""


PER_STUDENT = """**Your own surface.** In this hand-out some notebooks give every student a variant of their surface:
`lab.my_surface("05_visualize_curvature")` is yours (from your user name on the hub); the numbers you report are
graded for your variant. / *In dieser Ausgabe hat jede Studentin und jeder Student eine eigene Variante der Fläche
einiger Notebooks: `lab.my_surface("05_visualize_curvature")` ist Ihre.*
"""


def _per_student(out, roster, secret):
    """Write ``OUT/variants.json`` for ``roster`` under ``secret`` and mark the exercises it is about; returns the
    table's id."""
    students = _variants.build(roster, secret)
    ident = _variants.write_table(out / TABLE, students)
    assignments = {a for variants in students.values() for a in variants}
    for lang in notebooks.LANGUAGES:
        for assignment in sorted(assignments):
            path = out / "exercises" / lang / f"{assignment}.ipynb"
            if path.is_file():
                nb = nbformat.read(str(path), as_version=4)
                nb.metadata.setdefault("lab", {})["variants"] = ident
                nbformat.write(nb, str(path))
    return ident


def secret_in(tree, secret):
    """The files under ``tree`` (not ``.git``) that contain the bytes of ``secret`` (or its hex or base64 text)."""
    import base64

    forms = {secret, secret.hex().encode(), base64.b64encode(secret)}
    return [p for p in sorted(Path(tree).rglob("*")) if p.is_file() and ".git" not in p.relative_to(tree).parts
            and any(form in p.read_bytes() for form in forms)]


def release(out, *, self_study=False, pythons=(sys.executable,), git=False, check=True, per_student=None):
    """Write the hand-out into ``out`` (see the module docstring); returns ``out``.

    ``per_student``: ``(roster, secret)``, the user names and the course secret (bytes) of a per-student release.
    """
    course_repository("release")
    if check:
        _check_exercises()
    out = _prepare(out)
    for item in COPIED:
        src = ROOT / item
        shutil.copytree(src, out / item) if src.is_dir() else shutil.copy2(src, out / item)
    for lang in notebooks.LANGUAGES:
        shutil.copytree(ROOT / "exercises" / lang, out / "exercises" / lang,
                        ignore=shutil.ignore_patterns(".ipynb_checkpoints"))
    ident = _per_student(out, *per_student) if per_student is not None else None
    tags = _library(out, self_study, list(pythons))
    (out / "Makefile").write_text(MAKEFILE)
    build = " (self-study: the library's references included)" if self_study else f", compiled for {', '.join(tags)}"
    library = (SELF_STUDY if self_study else WITHHELD) + ("\n\n" + PER_STUDENT if ident else "")
    (out / "README.md").write_text(README.format(table=_titles(ident is not None), date=datetime.date.today().isoformat(),
                                                 build=build, library=library))
    (out / ".gitignore").write_text(".venv/\n*.egg-info/\n.ipynb_checkpoints/\n")
    (out / MARK).write_text(json.dumps({"self_study": self_study, "python": tags, "variants": ident,
                                        "date": datetime.datetime.now().isoformat(timespec="seconds")}) + "\n")
    hits = solution_lines_in(out, skip=("lab",) if self_study else ())  # self-study: the references are meant
    if hits:
        raise ReleaseError("solution lines in the hand-out: " + "; ".join(
            f"{p.relative_to(out)}: {line!r} (from {nb})" for p, nb, line in hits[:10]))
    if per_student is not None and (leaks := secret_in(out, per_student[1])):
        raise ReleaseError("the course secret is in the hand-out: " + ", ".join(str(p.relative_to(out)) for p in leaks))
    if git:
        _commit(out)
    return out


def _commit(out):
    def run(*args):
        return subprocess.run(["git", "-c", "user.name=curvature-lab release", "-c", "user.email=release@localhost",
                               *args], cwd=out, check=True, capture_output=True, text=True)

    if not (out / ".git").exists():
        run("init", "-q", "-b", "main")
    run("add", "-A")
    if run("status", "--porcelain").stdout.strip():
        run("commit", "-q", "-m", f"Hand-out of {datetime.date.today().isoformat()}")


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab release",
        description=_("Write the students' hand-out into OUT: exercises/en and exercises/de, a student README, "
                    "`make lab`, and the library with the reference implementations of the graded tasks "
                    "withheld (compiled only). No solutions, tests or hidden data."))
    parser.add_argument("out", help=_("an empty folder, or an earlier release to replace"))
    parser.add_argument("--self-study", action="store_true",
                        help=_("keep the library's reference implementations readable (for learners on their own)"))
    parser.add_argument("--python", action="append", dest="pythons",
                        help=_("also compile the withheld code for this Python (repeatable; default: the running one)"))
    parser.add_argument("--git", action="store_true", help=_("make OUT a git repository and commit the hand-out"))
    parser.add_argument("--per-student", metavar="ROSTER",
                        help=_("give every student of ROSTER (one user name per line, or a CSV with a username column) "
                               "their own variant of the surfaces that have one (OUT/variants.json); needs "
                               "--secret-file"))
    parser.add_argument("--secret-file", metavar="FILE",
                        help=_("the course's secret (at least 16 bytes; keep it out of every repository): the "
                               "variants are derived from it and the user names"))
    args = parser.parse_args(argv)
    if bool(args.per_student) != bool(args.secret_file):
        parser.error(_("--per-student and --secret-file go together"))
    try:
        per_student = None
        if args.per_student:
            per_student = (read_roster(args.per_student, _variants.VariantError), _variants.read_secret(args.secret_file))
        out = release(args.out, self_study=args.self_study, pythons=args.pythons or [sys.executable], git=args.git,
                      per_student=per_student)
    except (ReleaseError, notebooks.StudentChangesError, notebooks.SourceError, NotACourseRepository, OSError,
            _variants.VariantError) as exc:
        print(f"curvature-lab release: error: {exc}", file=sys.stderr)
        return 2
    print(_("wrote the hand-out to {out}").format(out=out))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
