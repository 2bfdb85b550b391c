"""Executing notebooks in tests: one kernel per language, shared by the notebooks a test module runs.

Starting a kernel and importing the lab's view (PyVista, VTK, ipywidgets) costs seconds per notebook; a
shared kernel pays it once.  Between two notebooks the kernel forgets the previous one: its namespace is
reset (``%reset -f``), matplotlib's figures are closed, exercise mode is switched off and the language is set
again, so each notebook starts as in a fresh kernel except for the modules already imported.  Cells run
with nbclient (:class:`lab.teaching.kernel.notebook_client.NotebookRunner`), errors not allowed.
"""

import contextlib
import tempfile

import nbformat
from jupyter_client.manager import AsyncKernelManager
from jupyter_core.utils import run_sync

from lab.teaching.kernel.notebook_client import NotebookRunner

#: What runs before each notebook in a shared kernel (not part of the notebook's outputs).
RESET = ("get_ipython().run_line_magic('reset', '-f')\n"
         "import sys as _sys\n"
         "if 'matplotlib.pyplot' in _sys.modules:\n"
         "    _sys.modules['matplotlib.pyplot'].close('all')\n"
         "import lab as _lab\n"
         "_lab.exercise_mode(False)\n"
         "_lab.set_language({lang!r})\n"
         "del _sys, _lab")


class SharedKernel:
    """A kernel that executes one notebook after the other (``run``), in a private working folder."""

    def __init__(self, lang="en", timeout=600):
        self.lang, self.timeout = lang, timeout
        self._folder = tempfile.TemporaryDirectory(prefix=f"lab-notebooks-{lang}-")
        self.km = AsyncKernelManager(kernel_name="python3")  # nbclient awaits its methods
        run_sync(self.km.start_kernel)(cwd=self._folder.name, extra_arguments=["--IPKernelApp.log_level=ERROR"])

    def run(self, nb):
        """Execute the notebook ``nb`` (changed in place: outputs) after a reset; raises at the first error."""
        nb.cells.insert(0, nbformat.v4.new_code_cell(RESET.format(lang=self.lang)))
        client = NotebookRunner(nb, km=self.km, timeout=self.timeout, allow_errors=False,
                                resources={"metadata": {"path": self._folder.name}})
        try:
            client.execute()
        finally:
            nb.cells.pop(0)
            if client.kc is not None:
                client.kc.stop_channels()
        return nb

    def close(self):
        with contextlib.suppress(Exception):
            run_sync(self.km.shutdown_kernel)(now=True)
        self._folder.cleanup()


def text_of(cell):
    """Everything a code cell printed or displayed as text, joined."""
    parts = []
    for o in cell.get("outputs", []):
        if o.output_type == "stream":
            parts.append(o.text)
        elif o.output_type in ("execute_result", "display_data"):
            parts.append(o.data.get("text/plain", ""))
        elif o.output_type == "error":
            parts.append(f"{o.ename}: {o.evalue}")
    return "\n".join(parts)
