"""The sandboxed half of grading: run the notebook in a fresh kernel, then the graded calls.

``python -m lab.teaching.kernel.graded_run SPEC.json`` runs inside the grader's sandbox (:mod:`lab.teaching.sandbox.bubblewrap`),
started by :mod:`lab.teaching.grader.notebook`.  SPEC names the notebook (a fresh copy of the submission), the
output folder, the time limits and the tasks with their cases' inputs (never their answers).  It executes
every code cell (nbclient, each under the cell time limit; errors are recorded, not fatal), then for each
task one harness cell (:mod:`lab.teaching.kernel.harness`) that appends the student's results to
``OUT/task-K.jsonl``; cell errors go to ``OUT/cells.json``.  SPEC's ``variant`` (a per-student release) is the
student's own variant, handed to the kernel as ``LAB_VARIANT`` for ``lab.my_surface``; a task without cases
(numbers the student reports, which the grader reads from the notebook) gets no harness cell.

A cell that outlives its limit is interrupted; if the kernel ignores the interrupt (code that catches
BaseException and ignores SIGINT), it is killed and a new kernel re-runs the cells that worked before, so
the rest of the notebook and the tasks still run.  The grader bounds the whole run from outside.
"""

import contextlib
import json
import os
import sys
from pathlib import Path

import nbformat
from nbclient.exceptions import CellTimeoutError, DeadKernelError

from ...i18n import _
from .notebook_client import NotebookRunner
from .protocol import MARKER

#: Bytes of output kept per cell (a cell that prints gigabytes must not exhaust the sandbox's memory).
MAX_OUTPUT = 100_000
#: Kernel restarts allowed in one run.
MAX_RESTARTS = 6
#: Bytes of the working folder kept back for the results while the notebook's own cells run.
RESERVE = 4 << 20
#: Seconds an interrupted kernel has to answer again before it is replaced.
PROBE_TIMEOUT = 10


class _Client(NotebookRunner):
    """nbclient (with waits that cannot stall, :mod:`.runner_client`) and a bound on the output it keeps."""

    def output(self, outs, msg, display_id, cell_index):
        size = sum(len(json.dumps(o, default=str)) for o in outs)
        if size > MAX_OUTPUT:
            return None
        return super().output(outs, msg, display_id, cell_index)


class _Unresponsive(Exception):
    """The kernel does not answer after an interrupt: it must be replaced."""


class Run:
    """One graded run of a notebook, across kernel restarts."""

    def __init__(self, spec):
        self.spec = spec
        self.out = Path(spec["out"])
        self.nb = nbformat.read(spec["notebook"], as_version=4)
        self.code_cells = [i for i, c in enumerate(self.nb.cells) if c.cell_type == "code"]
        self.cell_errors = []
        self.worked = []  # cells that ran without error: replayed in a new kernel
        self.restarts = 0

    def client(self):
        return _Client(self.nb, timeout=self.spec["cell_timeout"], kernel_name="python3", allow_errors=True,
                       interrupt_on_timeout=False, shutdown_kernel="immediate", raise_on_iopub_timeout=False,
                       resources={"metadata": {"path": str(Path(self.spec["notebook"]).parent)}},
                       extra_arguments=["--IPKernelApp.log_level=ERROR"])

    def _execute(self, client, index, timeout):
        """Run cell ``index``: "ok", "error" (recorded) or "timeout" (interrupted; raises _Unresponsive if stuck)."""
        client.timeout = timeout
        cell = self.nb.cells[index]
        try:
            client.execute_cell(cell, index)
        except DeadKernelError:
            raise _Unresponsive("died") from None
        except CellTimeoutError:
            client.km.interrupt_kernel()
            probe = nbformat.v4.new_code_cell("pass")
            self.nb.cells.append(probe)
            try:
                client.timeout = PROBE_TIMEOUT
                client.execute_cell(probe, len(self.nb.cells) - 1)
            except (CellTimeoutError, DeadKernelError):
                raise _Unresponsive("stuck") from None
            finally:
                self.nb.cells.remove(probe)
            return "timeout"
        errors = [o for o in cell.get("outputs", []) if o.get("output_type") == "error"]
        if errors:
            e = errors[0]
            text = f"{e.get('ename')}: {e.get('evalue')}"
            kind = "withheld" if MARKER in text else ("interrupted" if e.get("ename") == "KeyboardInterrupt" else "error")
            if kind == "interrupted":
                return "timeout"
            if e.get("ename") in ("SyntaxError", "IndentationError", "TabError"):
                kind = "syntax"
            if kind == "error" and e.get("ename") == "NameError" and any(c["kind"] == "withheld" for c in self.cell_errors):
                kind = "follows"  # most likely a name a withheld cell did not define
            self._cell_error(index, text[:500], kind)
            return "error"
        return "ok"

    def _cell_error(self, index, text, kind):
        self.cell_errors.append({"cell": index, "error": text, "kind": kind})
        self._write_cells()  # at once: a run stopped from outside keeps what it found

    def _write_cells(self):
        """``cells.json`` through a rename: whatever the submission put there is replaced."""
        tmp = self.out / f".cells.{os.getpid()}.json"
        try:
            tmp.write_text(json.dumps({"cell_errors": self.cell_errors, "restarts": self.restarts}))
            os.replace(tmp, self.out / "cells.json")
        except OSError:  # a submission that filled its folder: the space kept back (RESERVE) is freed later
            with contextlib.suppress(OSError):
                tmp.unlink()

    def _reserve(self, keep):
        """Keep :data:`RESERVE` bytes of the folder's budget for the results (``keep=False`` gives them back)."""
        path = self.out / ".reserve"
        with contextlib.suppress(OSError):
            if keep:
                path.write_bytes(b"\0" * RESERVE)
            else:
                path.unlink()

    def _work(self):
        """The cells, then one harness cell per task: (kind, cell index or task index)."""
        return [("cell", i) for i in self.code_cells] + [("task", self._task_cell(k), k)
                                                          for k in range(len(self.spec["tasks"]))
                                                          if self.spec["tasks"][k]["cases"]]  # none: reported numbers

    def _task_cell(self, k):
        """A new harness cell for task ``k`` (its source says from which case on when it runs)."""
        source = (f"import lab.teaching.kernel.harness as _lab_harness\n_lab_harness.run(globals(), "
                  f"{self.spec['spec_path']!r}, {k}, {str(self.out / f'task-{k}.jsonl')!r}, "
                  f"{{start}}, {self.spec['case_timeout']!r})")
        self.nb.cells.append(nbformat.v4.new_code_cell(source))
        return len(self.nb.cells) - 1

    def _task_progress(self, k):
        """The index of the last case of task ``k`` with a result (-1: none)."""
        path = self.out / f"task-{k}.jsonl"
        done = []
        with contextlib.suppress(OSError):
            for line in path.read_text(errors="replace").splitlines():
                with contextlib.suppress(ValueError, AttributeError, RecursionError):
                    index = json.loads(line).get("index", -1)
                    done.append(index if isinstance(index, int) else -1)
        return max(done, default=-1)

    def _task_timeout(self, k, message, status="timeout"):
        """Record the case in progress as timed out (or its kernel as dead); the task's later cases run in a new
        kernel."""
        last = self._task_progress(k)
        with open(self.out / f"task-{k}.jsonl", "a") as fh:
            fh.write(json.dumps({"index": last + 1, "status": status, "message": message}) + "\n")

    def run(self):
        self._reserve(True)
        items = self._work()
        case_timeout = self.spec["case_timeout"]
        while items and self.restarts <= MAX_RESTARTS:
            stuck = False
            client = self.client()
            with client.setup_kernel():
                for index in list(self.worked):  # a new kernel: replay what worked before
                    try:
                        self._execute(client, index, self.spec["cell_timeout"])
                    except _Unresponsive:
                        stuck = True
                        break
                while items and not stuck:
                    kind, index, *rest = items.pop(0)
                    if kind == "task":
                        self._reserve(False)  # the results are written from here on
                    if kind == "cell":
                        limit = self.spec["cell_timeout"]
                    else:
                        limit = len(self.spec["tasks"][rest[0]]["cases"]) * case_timeout + 10
                        cell = self.nb.cells[index]
                        cell.source = cell.source.replace("{start}", str(self._task_progress(rest[0]) + 1))
                    try:
                        status = self._execute(client, index, limit)
                    except _Unresponsive as exc:
                        status, stuck = str(exc), True
                    if status == "died" and kind == "cell":
                        self._cell_error(index, _("the kernel died (did the code exit or crash?)"), "died")
                    elif status == "died":
                        self._task_timeout(rest[0], _("the kernel died while running this case (did the code exit?)"),
                                           "error")
                    elif status in ("timeout", "stuck") and kind == "cell":
                        self._cell_error(index, _("stopped after {seconds} s (endless loop?)").format(seconds=f"{limit:g}"),
                                         "timeout")
                    elif status in ("timeout", "stuck"):
                        self._task_timeout(rest[0], _("stopped after {seconds} s, and it did not stop when "
                                                      "interrupted (endless loop?)").format(seconds=f"{case_timeout:g}"))
                    if kind == "task" and status in ("died", "timeout", "stuck") and self._task_progress(rest[0]) + 1 < \
                            len(self.spec["tasks"][rest[0]]["cases"]):
                        items.insert(0, (kind, self._task_cell(rest[0]), rest[0]))  # the later cases, in a new kernel
                    elif kind == "cell" and status == "ok":
                        self.worked.append(index)
            self.restarts += stuck
        for kind, index, *rest in items:
            if kind == "cell":
                self._cell_error(index, _("not run: the kernel had to be replaced too often"), "not run")
            else:
                self._task_timeout(rest[0], _("not run: the kernel had to be replaced too often"), "not run")
        self._reserve(False)
        self._write_cells()


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    spec_path = Path(argv[0])
    spec = json.loads(spec_path.read_text())
    spec["spec_path"] = str(spec_path)
    if spec.get("variant"):  # the student's own variant, for lab.my_surface in the notebook's kernel
        from .variants import ENV_VARIANT

        os.environ[ENV_VARIANT] = json.dumps(spec["variant"])
    Run(spec).run()
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
