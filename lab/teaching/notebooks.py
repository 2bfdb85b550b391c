"""Exercise notebooks generated from the solution notebooks.

A solution notebook marks its answers:

* in code cells, the lines from ``### BEGIN SOLUTION`` to ``### END SOLUTION``
  (inclusive) become ``raise NotImplementedError("…")`` at the same
  indentation; the text after ``### BEGIN SOLUTION:`` is the message, so it
  says what to implement;
* in markdown cells, the text from ``<!-- BEGIN SOLUTION -->`` to
  ``<!-- END SOLUTION -->`` becomes ``*Your answer here.*``.

Outputs and execution counts are removed.  Each generated exercise records a
digest of its cell sources in its metadata; regeneration refuses to overwrite
an exercise whose sources no longer match that digest (a student changed
it), and names the file, so nothing is lost.
"""

import argparse
import copy
import hashlib
import json
import re
import sys
from pathlib import Path

import nbformat

__all__ = ["strip_code", "strip_markdown", "make_exercise", "digest", "generate", "StudentChangesError", "main"]

BEGIN = "### BEGIN SOLUTION"
END = "### END SOLUTION"
MD_BEGIN = "<!-- BEGIN SOLUTION -->"
MD_END = "<!-- END SOLUTION -->"
DEFAULT_MESSAGE = "replace this line with your solution"

_ROOT = Path(__file__).resolve().parents[2]


class StudentChangesError(RuntimeError):
    """An exercise notebook was edited after it was generated."""


def strip_code(source):
    """Replace every solution block of a code cell by a ``NotImplementedError`` stub."""
    out, inside = [], False
    for line in source.split("\n"):
        stripped = line.strip()
        if stripped.startswith(BEGIN):
            if inside:
                raise ValueError(f"nested {BEGIN!r} in:\n{source}")
            inside = True
            indent = line[: len(line) - len(line.lstrip())]
            message = stripped[len(BEGIN):].lstrip(" :").strip() or DEFAULT_MESSAGE
            out.append(f"{indent}raise NotImplementedError({message!r})")
        elif stripped.startswith(END):
            if not inside:
                raise ValueError(f"{END!r} without {BEGIN!r} in:\n{source}")
            inside = False
        elif not inside:
            out.append(line)
    if inside:
        raise ValueError(f"{BEGIN!r} without {END!r} in:\n{source}")
    return "\n".join(out)


def strip_markdown(source):
    """Replace the solution parts of a markdown cell by a placeholder."""
    pattern = re.compile(re.escape(MD_BEGIN) + r".*?" + re.escape(MD_END), re.DOTALL)
    return pattern.sub("*Your answer here.*", source)


def digest(nb):
    """SHA-256 of the cell types and sources: what a student edits."""
    cells = [(c.cell_type, c.source) for c in nb.cells]
    return hashlib.sha256(json.dumps(cells, ensure_ascii=False).encode()).hexdigest()


def make_exercise(solution):
    """The exercise notebook for a solution notebook (a new object; the input is unchanged)."""
    nb = copy.deepcopy(solution)
    for cell in nb.cells:
        if cell.cell_type == "code":
            cell.source = strip_code(cell.source)
            cell.outputs = []
            cell.execution_count = None
        elif cell.cell_type == "markdown":
            cell.source = strip_markdown(cell.source)
        cell.metadata.pop("execution", None)
    meta = nb.metadata.setdefault("lab", {})
    meta["role"] = "exercise"
    meta["generated_digest"] = digest(nb)
    return nb


def _read(path):
    return nbformat.read(str(path), as_version=4)


def _write(nb, path):
    path.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, str(path))


def generate(solutions_dir=_ROOT / "solutions", exercises_dir=_ROOT / "exercises", *, check_only=False):
    """Regenerate every ``exercises/NN_*.ipynb`` from ``solutions/NN_*.ipynb``.

    Parameters
    ----------
    check_only : bool
        Write nothing; report which exercises differ from freshly generated ones.

    Returns
    -------
    dict of exercise path -> "unchanged" | "written" | "differs"

    Raises
    ------
    StudentChangesError
        If an existing exercise was edited since it was generated; nothing is
        written in that case, and the message names the files.
    """
    solutions_dir, exercises_dir = Path(solutions_dir), Path(exercises_dir)
    plan, changed_by_student = {}, []
    for src in sorted(solutions_dir.glob("[0-9][0-9]_*.ipynb")):
        target = exercises_dir / src.name
        new = make_exercise(_read(src))
        if target.exists():
            old = _read(target)
            recorded = old.metadata.get("lab", {}).get("generated_digest")
            if recorded != digest(old):
                changed_by_student.append(target)
                continue
            if digest(old) == new.metadata["lab"]["generated_digest"] and old.metadata == new.metadata:
                plan[target] = ("unchanged", new)
                continue
        plan[target] = ("differs" if check_only else "written", new)
    if changed_by_student:
        names = ", ".join(str(p) for p in changed_by_student)
        raise StudentChangesError(
            f"refusing to overwrite exercise notebooks edited since they were generated: {names}. "
            "Move them away (or rename them) to keep the work, then generate again."
        )
    if not check_only:
        for target, (action, nb) in plan.items():
            if action == "written":
                _write(nb, target)
    return {target: action for target, (action, _) in plan.items()}


def main(argv=None):
    parser = argparse.ArgumentParser(prog="curvature-lab exercises", description="Generate exercises/ from solutions/.")
    parser.add_argument("--solutions", default=str(_ROOT / "solutions"))
    parser.add_argument("--exercises", default=str(_ROOT / "exercises"))
    parser.add_argument("--check", action="store_true", help="only report exercises that differ; exit 1 if any")
    args = parser.parse_args(argv)
    try:
        result = generate(args.solutions, args.exercises, check_only=args.check)
    except StudentChangesError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    for path, action in result.items():
        print(f"{action:9s} {path}")
    return 1 if args.check and any(a == "differs" for a in result.values()) else 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
