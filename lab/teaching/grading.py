"""The autograder: run a notebook in a fresh kernel, then the graded checks on what it defined.

``curvature-lab grade NOTEBOOK.ipynb`` executes the notebook top to bottom
(nbclient, each cell under a time limit; errors in cells are recorded, not
fatal), then runs :mod:`lab.check` with ``graded=True`` (the public cases plus
more) on the objects the notebook's metadata names, in the same kernel.  The
notebook file is only read, never written.

A notebook declares its tasks in its metadata::

    "lab": {"tasks": [{"task": "visualize_curvature", "object": "MyBezierPatches", "points": 10}]}
"""

import argparse
import csv
import json
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import nbformat

__all__ = ["GradeResult", "grade_notebook", "grade_folder", "run_tasks", "main"]

SENTINEL = "@@LAB-GRADING@@"

_KERNEL_ENV = {
    "PYVISTA_OFF_SCREEN": "true",
    "VTK_DEFAULT_OPENGL_WINDOW": "vtkEGLRenderWindow",
    "MPLBACKEND": "Agg",
    "LAB_GRADING": "1",
}


def run_tasks(namespace, tasks, timeout=20.0):
    """Run the graded checks on objects of ``namespace`` (called inside the notebook's kernel).

    Returns a list of report dictionaries, one per task.
    """
    from . import check

    out = []
    for t in tasks:
        name, obj_name = t["task"], t.get("object", t["task"])
        if obj_name not in namespace:
            rep = check.Report(name, "not implemented", [],
                               f"{obj_name} is not defined: run the cell that defines it (and keep its name).", True)
        else:
            rep = check.run(name, namespace[obj_name], graded=True, timeout=timeout)
        d = rep.to_dict()
        d["object"] = obj_name
        d["points"] = float(t.get("points", 1))
        d["text"] = str(rep)
        out.append(d)
    return out


@dataclass
class GradeResult:
    """Scores of one notebook."""

    notebook: str
    tasks: list = field(default_factory=list)
    cell_errors: list = field(default_factory=list)
    error: str = ""
    seconds: float = 0.0

    @property
    def score(self):
        return round(sum(t["points"] * t["score"] for t in self.tasks), 2)

    @property
    def max_score(self):
        return sum(t["points"] for t in self.tasks)

    @property
    def passed(self):
        """All tasks passed; a notebook without tasks passes when all its cells ran without errors."""
        if self.error:
            return False
        return all(t["passed"] for t in self.tasks) if self.tasks else not self.cell_errors

    def to_dict(self):
        return {
            "notebook": self.notebook,
            "score": self.score,
            "max_score": self.max_score,
            "passed": self.passed,
            "tasks": [{k: v for k, v in t.items() if k != "text"} | {"report": t["text"]} for t in self.tasks],
            "cell_errors": self.cell_errors,
            "error": self.error,
            "seconds": round(self.seconds, 2),
        }

    def text(self):
        lines = [f"{self.notebook}: {self.score:g} / {self.max_score:g} points"]
        if self.error:
            lines.append(f"  error: {self.error}")
        for t in self.tasks:
            lines.append(f"- {t['task']} ({t['object']}): {t['points'] * t['score']:g} / {t['points']:g}")
            lines.extend("    " + line for line in t["text"].splitlines())
        for e in self.cell_errors:
            lines.append(f"  cell {e['cell']}: {e['error']}")
        return "\n".join(lines)


def _tasks_of(nb, path):
    tasks = nb.metadata.get("lab", {}).get("tasks")
    if tasks is None:
        raise ValueError(f"{path} has no task list (metadata 'lab' -> 'tasks'); is it a curvature-lab notebook?")
    return tasks


def grade_notebook(path, *, timeout=60, check_timeout=20.0, kernel_name="python3"):
    """Execute ``path`` in a fresh kernel and grade its tasks. The file is not modified.

    Parameters
    ----------
    path : str or Path
    timeout : float
        Seconds each cell may run; a cell that runs longer is interrupted and
        recorded as an error, and the following cells still run.
    check_timeout : float
        Seconds each student function may run inside a check.
    """
    from nbclient import NotebookClient
    from nbclient.exceptions import CellTimeoutError, DeadKernelError

    path = Path(path)
    start = time.perf_counter()
    raw = path.read_bytes()
    try:
        nb = nbformat.reads(raw.decode("utf-8"), as_version=4)
    except Exception as exc:  # unreadable notebook: a result, not a crash
        return GradeResult(str(path), error=f"cannot read the notebook: {type(exc).__name__}: {exc}")
    try:
        tasks = _tasks_of(nb, path)
    except ValueError as exc:
        return GradeResult(str(path), error=str(exc))
    result = GradeResult(str(path))
    saved_env = {k: os.environ.get(k) for k in _KERNEL_ENV}
    os.environ.update(_KERNEL_ENV)
    client = NotebookClient(
        nb, timeout=timeout, kernel_name=kernel_name, allow_errors=True, interrupt_on_timeout=True,
        resources={"metadata": {"path": str(path.parent.resolve())}},
        extra_arguments=["--IPKernelApp.log_level=ERROR"],  # no transport warnings in the report
    )
    try:
        with client.setup_kernel():
            for index, cell in enumerate(nb.cells):
                if cell.cell_type != "code":
                    continue
                try:
                    client.execute_cell(cell, index)
                except CellTimeoutError:
                    result.cell_errors.append({"cell": index, "error": f"stopped after {timeout:g} s (endless loop?)"})
                    continue
                for out in cell.get("outputs", []):
                    if out.get("output_type") != "error":
                        continue
                    if out["ename"] == "KeyboardInterrupt":  # nbclient interrupted the cell at the time limit
                        message = f"stopped after {timeout:g} s (endless loop?)"
                    else:
                        message = f"{out['ename']}: {out['evalue']}"
                    result.cell_errors.append({"cell": index, "error": message})
            code = (
                "import json as _json, lab.teaching.grading as _grading\n"
                f"print({SENTINEL!r} + _json.dumps(_grading.run_tasks(globals(), {tasks!r}, {check_timeout!r})))"
            )
            cell = nbformat.v4.new_code_cell(code)
            nb.cells.append(cell)  # the in-memory copy only; the file is never written
            client.execute_cell(cell, len(nb.cells) - 1)
            text = "".join(o.get("text", "") for o in cell.outputs if o.get("output_type") == "stream")
            errors = [f"{o['ename']}: {o['evalue']}" for o in cell.outputs if o.get("output_type") == "error"]
            if SENTINEL not in text:
                result.error = "the graded checks did not run: " + ("; ".join(errors) or "no output")
            else:
                result.tasks = json.loads(text.split(SENTINEL, 1)[1].strip().splitlines()[0])
    except DeadKernelError as exc:
        result.error = f"the kernel died: {exc}"
    except Exception as exc:  # the grader reports, it does not crash
        result.error = f"{type(exc).__name__}: {exc}"
    finally:
        for k, v in saved_env.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    if path.read_bytes() != raw:  # pragma: no cover - guarded by design, checked by the tests
        result.error = "the notebook changed on disk while grading"
    result.seconds = time.perf_counter() - start
    return result


def grade_folder(folder, out_dir, **kwargs):
    """Grade every notebook under ``folder``; write one report per notebook and ``summary.csv`` to ``out_dir``.

    A submission is either ``folder/<student>.ipynb`` or ``folder/<student>/<notebook>.ipynb``.
    """
    folder, out_dir = Path(folder), Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    results = []
    for nb_path in sorted(p for p in folder.rglob("*.ipynb") if ".ipynb_checkpoints" not in p.parts):
        rel = nb_path.relative_to(folder)
        student = rel.parts[0] if len(rel.parts) > 1 else nb_path.stem
        res = grade_notebook(nb_path, **kwargs)
        stem = "__".join(rel.with_suffix("").parts)
        (out_dir / f"{stem}.json").write_text(json.dumps(res.to_dict(), indent=2, ensure_ascii=False))
        (out_dir / f"{stem}.txt").write_text(res.text() + "\n")
        results.append((student, rel, res))
    with open(out_dir / "summary.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["student", "notebook", "score", "max_score", "passed", "tasks", "error"])
        for student, rel, res in results:
            tasks = "; ".join(f"{t['task']}={t['points'] * t['score']:g}/{t['points']:g}" for t in res.tasks)
            w.writerow([student, str(rel), res.score, res.max_score, res.passed, tasks, res.error])
    return [r for _, _, r in results]


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab grade",
        description="Grade a curvature-lab notebook (or a folder of submissions) in a fresh kernel.",
    )
    parser.add_argument("path", help="a notebook, or a folder of submissions")
    parser.add_argument("--json", action="store_true", help="print a machine-readable report")
    parser.add_argument("--timeout", type=float, default=60, help="seconds per cell (default 60)")
    parser.add_argument("--check-timeout", type=float, default=20, help="seconds per checked function (default 20)")
    parser.add_argument("--out", help="folder for the reports and summary.csv (folder mode; default: <path>-reports)")
    args = parser.parse_args(argv)
    path = Path(args.path)
    if not path.exists():
        parser.error(f"{path} does not exist")
    kwargs = {"timeout": args.timeout, "check_timeout": args.check_timeout}
    if path.is_dir():
        out = Path(args.out) if args.out else path.with_name(path.name + "-reports")
        results = grade_folder(path, out, **kwargs)
        if args.json:
            print(json.dumps([r.to_dict() for r in results], indent=2, ensure_ascii=False))
        else:
            for r in results:
                print(f"{r.notebook}: {r.score:g} / {r.max_score:g}" + (f"  ({r.error})" if r.error else ""))
            print(f"reports and summary.csv in {out}")
        return 0 if results and all(r.passed for r in results) else 1
    if path.suffix != ".ipynb":
        parser.error(f"expected a .ipynb notebook or a folder; got {path}")
    result = grade_notebook(path, **kwargs)
    print(json.dumps(result.to_dict(), indent=2, ensure_ascii=False) if args.json else result.text())
    return 0 if result.passed else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
