"""Exercise generation from the solution notebooks (lab.notebooks)."""

import shutil
from pathlib import Path

import nbformat
import pytest

from lab import notebooks

ROOT = Path(__file__).resolve().parent.parent


def test_committed_exercises_are_freshly_generated():
    result = notebooks.generate(ROOT / "solutions", ROOT / "exercises", check_only=True)
    assert result, "no solution notebooks found"
    differs = [str(p) for p, action in result.items() if action != "unchanged"]
    assert not differs, f"exercises differ from solutions/ (run `make exercises`): {differs}"
    assert sorted(p.name for p in (ROOT / "exercises").glob("*.ipynb")) == sorted(
        p.name for p in (ROOT / "solutions").glob("*.ipynb"))


def test_exercises_have_stubs_no_solutions_and_no_outputs():
    for path in sorted((ROOT / "exercises").glob("*.ipynb")):
        nb = nbformat.read(path, as_version=4)
        text = "\n".join(c.source for c in nb.cells)
        assert "BEGIN SOLUTION" not in text and "END SOLUTION" not in text, path
        if nb.metadata["lab"]["tasks"]:  # the gallery has questions (answers stripped) but no code task
            assert "raise NotImplementedError(" in text, path
        else:
            assert "*Your answer here.*" in text, path
        for cell in nb.cells:
            if cell.cell_type == "code":
                assert cell.outputs == [] and cell.execution_count is None, path
        assert "tasks" in nb.metadata["lab"], path


def test_visualize_stub_keeps_the_practicals_comments():
    nb = nbformat.read(ROOT / "exercises" / "05_visualize_curvature.ipynb", as_version=4)
    cell = next(c for c in nb.cells if "class MyBezierPatches" in c.source)
    lines = cell.source.splitlines()
    i = lines.index("        # calculate curvatures at each corner point")
    assert lines[i + 1].startswith("        raise NotImplementedError(")
    assert "        # set colors according to color map" in lines


def test_strip_code_keeps_indentation_and_message():
    src = "def f(x):\n    y = 1\n    ### BEGIN SOLUTION: return twice x\n    return 2 * x\n    ### END SOLUTION\n"
    assert notebooks.strip_code(src) == "def f(x):\n    y = 1\n    raise NotImplementedError('return twice x')\n"
    assert "replace this line with your solution" in notebooks.strip_code("### BEGIN SOLUTION\nx\n### END SOLUTION")
    with pytest.raises(ValueError, match="without '### END SOLUTION'"):
        notebooks.strip_code("### BEGIN SOLUTION\nx = 1\n")
    with pytest.raises(ValueError, match="'### END SOLUTION' without '### BEGIN SOLUTION'"):
        notebooks.strip_code("x = 1\n### END SOLUTION\n")
    md = "Q?\n<!-- BEGIN SOLUTION -->\nsecret\n<!-- END SOLUTION -->\nmore"
    assert notebooks.strip_markdown(md) == "Q?\n*Your answer here.*\nmore"


def test_regeneration_refuses_to_overwrite_student_work(tmp_path):
    sol, ex = tmp_path / "solutions", tmp_path / "exercises"
    shutil.copytree(ROOT / "solutions", sol)
    first = notebooks.generate(sol, ex)
    assert set(first.values()) == {"written"}
    assert set(notebooks.generate(sol, ex).values()) == {"unchanged"}
    # a student works on exercise 02
    target = ex / "02_fundamental_forms.ipynb"
    nb = nbformat.read(target, as_version=4)
    nb.cells[3].source += "\n# my work"
    nbformat.write(nb, target)
    before = target.read_bytes()
    # the instructor changes a solution and regenerates
    src = nbformat.read(sol / "02_fundamental_forms.ipynb", as_version=4)
    src.cells[0].source += "\n\nA new sentence."
    nbformat.write(src, sol / "02_fundamental_forms.ipynb")
    with pytest.raises(notebooks.StudentChangesError, match="02_fundamental_forms.ipynb"):
        notebooks.generate(sol, ex)
    assert target.read_bytes() == before  # nothing lost
    assert notebooks.main(["--solutions", str(sol), "--exercises", str(ex)]) == 1
    # an untouched exercise is regenerated once the edited one is moved away
    target.rename(tmp_path / "mine.ipynb")
    result = notebooks.generate(sol, ex)
    assert result[target] == "written"
