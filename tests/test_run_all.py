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

pytestmark = pytest.mark.xdist_group("run_all")  # one kernel per language for all 28 notebooks, on one worker

#: How the one-line messages of exercise mode (lab.teaching.kernel.exercise_mode) and a check's stub report begin.
LINES = {"en": ("… Stopped here:", "… Not run:"), "de": ("… Hier angehalten:", "… Nicht ausgeführt:")}
NOT_IMPLEMENTED = {"en": "not implemented yet", "de": "noch nicht implementiert"}


#: Numbers the English text states, checked against what the same notebook prints (issue 20, item 7):
#: (words of the text, a pattern of the printed output, a test of the pattern's numbers)
STATED = {
    "05_visualize_curvature": [
        ("$H \\approx +6.08", r"depth 1: K from \S+ to (\S+), H from \S+ to (\S+)",
         lambda K, H: abs(float(H) - 6.08) < 0.005 and abs(float(K) - 36.68) < 0.005)],
    "07_reflection_lines": [
        ("from about 10 % to under 1 %", r"torus 96: colours differ on (\S+) %(?s:.*?)torus 192: colours differ on (\S+) %",
         lambda coarse, fine: 7 <= float(coarse) <= 13 and float(fine) < 1)],
    "08_geodesics_isodistance": [
        ("From the middle of our sheet ten curves close", r"start \(0.5, 0.4\): (\d+) of 15 curves closed",
         lambda n: int(n) == 10),
        ("only the first two", r"start \(0.1, 0.5\): (\d+) of 15 curves closed \(s_L = ([^)]*)\)",
         lambda n, which: int(n) == 2 and which == "0.3, 0.6")],
    "11_real_part": [
        ("made of 32 bicubic Bézier patches", r"teapot\.bbp: (\d+) faces \(Bézier surface × (\d+)\)",
         lambda n, b: int(n) == int(b) == 32),
        ("a sheet of 99 B-spline faces", r"shell1\.brep: (\d+) faces \(B-spline surface × (\d+)\)",
         lambda n, b: int(n) == int(b) == 99)],
    "13_meshes_and_scans": [
        ("both estimators converge with **order 2**", r"torus, lab, diagonals regular(?s:.*?)order p +(\S+) +(\S+)",
         lambda K, H: abs(float(K) - 2) < 0.1 and abs(float(H) - 2) < 0.1),
        ("The mean curvature stays about 10 % wrong", r"saddle, lab(?s:.*?)order p +\S+ +\S+ +\S+ +(\S+)",
         lambda p: abs(float(p)) < 0.1)],
    "09_dill_gallery": [
        ("a crown with $K \\approx 0.01", r"crown\s+K = \+(\S+) 1/m²", lambda K: 0.005 <= float(K) < 0.015)],
}


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
    if lang == "en":
        prose = "\n".join(c.source for c in nb.cells if c.cell_type == "markdown")
        printed = "\n".join(text_of(c) for c in code)
        for words, pattern, holds in STATED.get(path.stem, ()):
            assert words in prose, f"the text no longer says {words!r}: update STATED"
            found = re.search(pattern, printed)
            assert found, f"{path.stem} does not print {pattern!r}:\n{printed[-2000:]}"
            assert holds(*found.groups()), f"the text says {words!r}, the notebook prints {found.group(0)!r}"


def test_a_cell_stopped_by_a_task_runs_once_the_task_is_written(kernels):
    """Stopped by the unfinished task, then run again after the task is written: the cell runs. A comprehension's
    loop variable is its own, not a name the cell assigns (notebook 11's cell ``[f.index for f in …]`` said
    "Not run: this cell needs f" after the task passed its check)."""
    cells = ["import lab\nlab.exercise_mode()",
             "def developable_faces(model):\n    raise NotImplementedError('return the file indices')",
             "mine = set(developable_faces(None))\nprint('found', [f for f in range(3) if f in mine])",
             "def developable_faces(model):\n    return [1]",
             "mine = set(developable_faces(None))\nprint('found', [f for f in range(3) if f in mine])"]
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in cells])
    kernels("en").run(nb)
    first, again = text_of(nb.cells[2]), text_of(nb.cells[4])
    assert first.startswith(LINES["en"][0]) and "developable_faces" in first, first
    assert again.strip() == "found [1]", again
