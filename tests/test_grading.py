"""The autograder: solutions get full marks, exercises zero, broken submissions a readable report."""

import csv
import json
import shutil
import time
from pathlib import Path

import nbformat
import pytest

from lab import grading

ROOT = Path(__file__).resolve().parent.parent
SOLUTIONS = sorted((ROOT / "solutions").glob("*.ipynb"))
EXERCISES = sorted((ROOT / "exercises").glob("*.ipynb"))


@pytest.mark.parametrize("path", SOLUTIONS, ids=lambda p: p.stem)
def test_solution_executes_and_gets_full_marks(path):
    before = path.read_bytes()
    result = grading.grade_notebook(path, timeout=300)
    assert not result.error, result.text()
    assert result.cell_errors == [], result.text()
    assert result.passed and result.score == result.max_score, result.text()
    assert result.max_score > 0 or not result.tasks  # the gallery has questions but no graded task
    assert path.read_bytes() == before  # never modified


@pytest.mark.parametrize("path", EXERCISES, ids=lambda p: p.stem)
def test_exercise_scores_zero_with_not_implemented(path):
    before = path.read_bytes()
    result = grading.grade_notebook(path, timeout=300)
    assert not result.error, result.text()
    assert result.score == 0
    assert not result.passed or not result.tasks
    for task in result.tasks:
        assert task["status"] == "not implemented", result.text()
        assert "not implemented yet" in task["report"] if "report" in task else "not implemented yet" in task["text"]
    assert path.read_bytes() == before


def _with_cell(src, dst, index, source):
    nb = nbformat.read(src, as_version=4)
    nb.cells.insert(index, nbformat.v4.new_code_cell(source))
    nbformat.write(nb, dst)
    return dst


def test_endless_loop_cell_is_stopped_and_grading_goes_on(tmp_path):
    path = _with_cell(ROOT / "solutions" / "00_start.ipynb", tmp_path / "loop.ipynb", 2, "while True:\n    pass")
    before = path.read_bytes()
    start = time.perf_counter()
    result = grading.grade_notebook(path, timeout=4)
    assert time.perf_counter() - start < 60
    assert {"cell": 2, "error": "stopped after 4 s (endless loop?)"} in result.cell_errors
    assert result.passed  # the following cells still ran, the task is still graded
    assert path.read_bytes() == before


def test_student_function_that_loops_is_stopped_inside_the_check(tmp_path):
    src = ROOT / "solutions" / "00_start.ipynb"
    nb = nbformat.read(src, as_version=4)
    cell = next(c for c in nb.cells if "def mean_curvature" in c.source)
    cell.source = "def mean_curvature(k1, k2):\n    while True:\n        pass"
    for c in nb.cells:
        if c.source.startswith("check."):
            c.source = "# the student removed the check cell"
    nbformat.write(nb, tmp_path / "slow.ipynb")
    result = grading.grade_notebook(tmp_path / "slow.ipynb", timeout=60, check_timeout=2)
    (task,) = result.tasks
    assert task["status"] == "timeout" and "warmup was stopped after 2 s" in task["message"]
    assert result.score == 0


def test_unreadable_and_foreign_notebooks_give_messages(tmp_path):
    (tmp_path / "broken.ipynb").write_text("{ not json")
    result = grading.grade_notebook(tmp_path / "broken.ipynb")
    assert result.error.startswith("cannot read the notebook") and result.score == 0
    nbformat.write(nbformat.v4.new_notebook(), tmp_path / "plain.ipynb")
    result = grading.grade_notebook(tmp_path / "plain.ipynb")
    assert "has no task list" in result.error


def test_folder_of_submissions_with_reports_and_summary(tmp_path, capsys):
    subs = tmp_path / "submissions"
    (subs / "ada").mkdir(parents=True)
    shutil.copy(ROOT / "solutions" / "01_curves_and_orientation.ipynb", subs / "ada" / "01.ipynb")
    shutil.copy(ROOT / "exercises" / "01_curves_and_orientation.ipynb", subs / "bob.ipynb")
    out = tmp_path / "reports"
    code = grading.main([str(subs), "--out", str(out)])
    assert code == 1  # bob has not done the task
    rows = list(csv.DictReader(open(out / "summary.csv")))
    by_student = {r["student"]: r for r in rows}
    assert float(by_student["ada"]["score"]) == 2 and by_student["ada"]["passed"] == "True"
    assert float(by_student["bob"]["score"]) == 0 and by_student["bob"]["passed"] == "False"
    report = json.loads((out / "ada__01.json").read_text())
    assert report["tasks"][0]["task"] == "curve_curvature" and report["tasks"][0]["passed"]
    assert "not implemented yet" in (out / "bob.txt").read_text()


def test_cli_json_and_exit_status(capsys):
    path = ROOT / "solutions" / "00_start.ipynb"
    assert grading.main([str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["score"] == data["max_score"] == 1 and data["tasks"][0]["cases"]
    assert grading.main([str(ROOT / "exercises" / "00_start.ipynb")]) == 1
    assert "not implemented yet" in capsys.readouterr().out
