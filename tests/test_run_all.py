"""Run All reaches the end of every exercise, English and German, with no task written (issue 20).

Every exercise is executed as a student gets it (nbclient, errors not allowed), in one shared kernel per
language (:mod:`tests.notebook_support`).  A cell that needs an unfinished task says so in one line in the
notebook's language; the explorers appear; the checks say "not implemented yet".
"""

import re
from pathlib import Path

import nbformat
import pytest

from tests.notebook_support import SharedKernel, text_of

ROOT = Path(__file__).resolve().parent.parent
EXERCISES = [p for lang in ("en", "de") for p in sorted((ROOT / "exercises" / lang).glob("[0-9][0-9]_*.ipynb"))]

pytestmark = pytest.mark.xdist_group("run_all")  # one kernel per language for all 22 notebooks, on one worker

#: How the one-line messages of exercise mode (lab.teaching.unfinished) and a check's stub report begin.
LINES = {"en": ("… Stopped here:", "… Not run:"), "de": ("… Hier angehalten:", "… Nicht ausgeführt:")}
NOT_IMPLEMENTED = {"en": "not implemented yet", "de": "noch nicht implementiert"}


@pytest.fixture(scope="module")
def kernels():
    shared = {}
    yield lambda lang: shared.setdefault(lang, SharedKernel(lang))
    for kernel in shared.values():
        kernel.close()


@pytest.mark.parametrize("path", EXERCISES, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_run_all_reaches_the_end_with_no_task_written(kernels, path):
    lang = path.parent.name
    nb = nbformat.read(path, as_version=4)
    kernels(lang).run(nb)  # raises CellExecutionError at the first cell that fails
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all(c.get("execution_count") for c in code), "every code cell ran"
    other = LINES["de" if lang == "en" else "en"]
    for cell in code:
        text = text_of(cell)
        assert not any(marker in text for marker in other), f"a message in the wrong language:\n{text}"
        for line in text.splitlines():
            if line.startswith(LINES[lang]):
                assert len(line) < 400, line
        if "Explorer(" in cell.source:  # the explorers appear (a static picture without a Jupyter front end)
            kinds = {k for o in cell.outputs if o.output_type in ("display_data", "execute_result") for k in o.data}
            assert kinds & {"image/png", "application/vnd.jupyter.widget-view+json"}, cell.source
    stubs = [c for c in code if "raise NotImplementedError(" in c.source]
    assert bool(stubs) == bool(nb.metadata["lab"].get("tasks")), "the graded tasks are the stubs"
    calls = [c for c in code if re.match(r"\s*check\.\w+\(", c.source)]
    for cell in calls:
        assert NOT_IMPLEMENTED[lang] in text_of(cell), cell.source
    stopped = [c for c in code if any(line.startswith(LINES[lang]) for line in text_of(c).splitlines())]
    for cell in stopped:  # one line, no traceback
        assert "Traceback" not in text_of(cell) and "Error" not in text_of(cell).split("…")[0], text_of(cell)
