"""The autograder: solutions get full marks, exercises zero, broken submissions a readable report (English and German)."""

import csv
import json
import shutil
import signal
from pathlib import Path

import nbformat
import pytest

from lab import grading
from lab.teaching.course import grade
from lab.teaching.grader import assignments
from lab.teaching.sandbox import bubblewrap

ROOT = Path(__file__).resolve().parent.parent
LANGS = ("en", "de")
SOLUTIONS = [p for lang in LANGS for p in sorted((ROOT / "solutions" / lang).glob("*.ipynb"))]
EXERCISES = [p for lang in LANGS for p in sorted((ROOT / "exercises" / lang).glob("*.ipynb"))]
SOLUTION = ROOT / "solutions" / "en"
EXERCISE = ROOT / "exercises" / "en"
NOT_IMPLEMENTED = {"en": "not implemented yet", "de": "noch nicht implementiert"}


def name(path):
    return f"{path.parent.name}/{path.stem}"


def real_errors(result):
    """Cell errors other than the library's withheld reference implementations."""
    return [e for e in result.cell_errors if e.get("kind") not in grading.WITHHELD]


def test_both_languages_are_graded():
    assert len(SOLUTIONS) == len(EXERCISES) == 28


@pytest.mark.parametrize("path", SOLUTIONS, ids=name)
def test_solution_executes_and_gets_full_marks(path):
    before = path.read_bytes()
    result = grading.grade_notebook(path, timeout=300)
    assert not result.error, result.text()
    assert real_errors(result) == [], result.text()
    assert result.score == result.max_score, result.text()
    if result.tasks:
        assert result.passed and result.max_score > 0, result.text()
    else:  # the gallery has questions but no graded task: 0 / 0 is "no tasks", not a pass
        assert not result.passed and "no graded tasks" in grading.GradeResult(**{**vars(result), "lang": "en"}).text()
    assert result.assignment == path.stem and isinstance(result.seed, int)
    assert path.read_bytes() == before  # never modified


@pytest.mark.parametrize("path", EXERCISES, ids=name)
def test_exercise_scores_zero_with_not_implemented(path):
    before = path.read_bytes()
    result = grading.grade_notebook(path, timeout=300)
    assert not result.error, result.text()
    assert result.score == 0
    assert not result.passed or not result.tasks
    assert result.assignment == path.stem and result.max_score == assignments.load(EXERCISE / path.name).max_score
    lang = path.parent.name
    for task in result.tasks:
        assert task["status"] == "not implemented", result.text()
        assert NOT_IMPLEMENTED[lang] in task["report"], result.text()  # the report speaks the notebook's language
        if lang == "de":
            assert NOT_IMPLEMENTED["en"] not in task["report"], result.text()
    assert path.read_bytes() == before


def test_a_submission_finds_its_assignment_in_its_language_folder(tmp_path):
    """Default folder exercises/: the id is found in exercises/de for a German submission, exercises/en for an English one."""
    for lang in LANGS:
        path = ROOT / "exercises" / lang / "05_visualize_curvature.ipynb"
        found, notes = assignments.for_submission(nbformat.read(path, as_version=4), path)
        assert Path(found.path) == path and notes == []
    en = assignments.load(ROOT / "exercises" / "en" / "05_visualize_curvature.ipynb")
    de = assignments.load(ROOT / "exercises" / "de" / "05_visualize_curvature.ipynb")
    assert en.id == de.id and en.tasks == de.tasks and en.title != de.title
    # a German submission graded against the English assignment: the same tasks, no note
    nb = nbformat.read(ROOT / "solutions" / "de" / "05_visualize_curvature.ipynb", as_version=4)
    found, notes = assignments.for_submission(nb, "x.ipynb", ROOT / "exercises" / "en" / "05_visualize_curvature.ipynb")
    assert found.tasks == de.tasks and notes == []
    # without an id, the file name is looked up in the language folders
    del nb.metadata["lab"]["assignment"]
    found, _ = assignments.for_submission(nb, tmp_path / "02_fundamental_forms.ipynb")
    assert found.id == "02_fundamental_forms" and Path(found.path).parent.name == "de"


def _with_cell(src, dst, index, source):
    nb = nbformat.read(src, as_version=4)
    nb.cells.insert(index, nbformat.v4.new_code_cell(source))
    nbformat.write(nb, dst)
    return dst


def test_endless_loop_cell_is_stopped_and_grading_goes_on(tmp_path):
    path = _with_cell(SOLUTION / "00_start.ipynb", tmp_path / "00_start.ipynb", 2, "while True:\n    pass")
    before = path.read_bytes()
    result = grading.grade_notebook(path, timeout=4)
    assert {"cell": 2, "error": "stopped after 4 s (endless loop?)", "kind": "timeout"} in result.cell_errors
    assert result.passed  # the following cells still ran, the task is still graded
    assert path.read_bytes() == before


def test_student_function_that_loops_is_stopped_inside_the_check(tmp_path):
    nb = nbformat.read(SOLUTION / "00_start.ipynb", as_version=4)
    cell = next(c for c in nb.cells if "def mean_curvature" in c.source)
    cell.source = "def mean_curvature(k1, k2):\n    while True:\n        pass"
    nbformat.write(nb, tmp_path / "00_start.ipynb")
    result = grading.grade_notebook(tmp_path / "00_start.ipynb", timeout=60, check_timeout=2)
    (task,) = result.tasks
    assert task["status"] == "timeout" and "warmup: stopped after 2 s" in task["message"]
    assert {c["status"] for c in task["cases"]} == {"timeout"}  # every case stopped on its own, none "passed"
    assert result.score == 0


@pytest.mark.parametrize("ignores_interrupts", [False, True], ids=["interruptible", "ignores-interrupts"])
def test_a_case_that_loops_costs_that_case_only(tmp_path, ignores_interrupts):
    """The README's promise: an endless loop in one case does not zero the others (also when the loop catches
    every exception and the kernel must be replaced)."""
    nb = nbformat.read(SOLUTION / "00_start.ipynb", as_version=4)
    cell = next(c for c in nb.cells if "def mean_curvature" in c.source)
    loop = ("        while True:\n            try:\n                pass\n            except BaseException:\n"
            "                pass\n" if ignores_interrupts else "        while True:\n            pass\n")
    cell.source = f"def mean_curvature(k1, k2):\n    if k1 == 2.0 and k2 == -2.0:\n{loop}    return (k1 + k2) / 2"
    nbformat.write(nb, tmp_path / "00_start.ipynb")
    result = grading.grade_notebook(tmp_path / "00_start.ipynb", timeout=30, check_timeout=2, seed=5)
    (task,) = result.tasks
    statuses = [c["status"] for c in task["cases"]]
    assert statuses[1] == "timeout" and statuses.count("passed") == len(statuses) - 1, result.text()
    assert result.score == round(1 - 1 / len(statuses), 2)


def test_unreadable_and_foreign_notebooks_give_messages(tmp_path):
    (tmp_path / "broken.ipynb").write_text("{ not json")
    result = grading.grade_notebook(tmp_path / "broken.ipynb")
    assert result.error.startswith("cannot read the notebook") and result.score == 0
    nbformat.write(nbformat.v4.new_notebook(), tmp_path / "plain.ipynb")
    result = grading.grade_notebook(tmp_path / "plain.ipynb")
    assert "cannot tell which assignment" in result.error and "pass --assignment" in result.error


def test_tasks_and_points_come_from_the_instructor(tmp_path):
    """The submission's metadata cannot rename, add or re-weight tasks; a mismatch is reported."""
    nb = nbformat.read(SOLUTION / "01_curves_and_orientation.ipynb", as_version=4)
    nb.metadata["lab"]["tasks"] = [{"task": "curve_curvature", "object": "curvature", "points": 50}] * 2
    nbformat.write(nb, tmp_path / "01_curves_and_orientation.ipynb")
    result = grading.grade_notebook(tmp_path / "01_curves_and_orientation.ipynb")
    assert result.max_score == 2 and result.score == 2
    assert any("task list differs" in n for n in result.notes)
    other = grading.grade_notebook(tmp_path / "01_curves_and_orientation.ipynb",
                                   assignment=EXERCISE / "00_start.ipynb")
    assert other.assignment == "00_start" and other.score == 0 and other.max_score == 1
    assert any("says it is assignment '01_curves_and_orientation'" in n for n in other.notes)


def test_the_seed_is_recorded_and_reproduces_the_cases():
    path = SOLUTION / "00_start.ipynb"
    a = grading.grade_notebook(path, seed=1234)
    b = grading.grade_notebook(path, seed=1234)
    c = grading.grade_notebook(path, seed=4321)
    names = [[case["name"] for case in r.tasks[0]["cases"]] for r in (a, b, c)]
    assert a.seed == b.seed == 1234 and names[0] == names[1] and names[0] != names[2]


def test_folder_of_submissions_with_reports_summary_and_gradescope(tmp_path):
    subs = tmp_path / "submissions"
    (subs / "ada").mkdir(parents=True)
    shutil.copy(SOLUTION / "01_curves_and_orientation.ipynb", subs / "ada" / "01_curves_and_orientation.ipynb")
    shutil.copy(EXERCISE / "01_curves_and_orientation.ipynb", subs / "bob.ipynb")
    out = tmp_path / "reports"
    code = grade.main([str(subs), "--out", str(out), "-j", "2", "--seed", "7", "--format", "gradescope",
                         "--assignment", str(EXERCISE / "01_curves_and_orientation.ipynb")])
    assert code == 1  # bob has not done the task
    rows = list(csv.DictReader((out / "summary.csv").read_text().splitlines()))
    assert list(rows[0])[:4] == ["student", "notebook", "score", "max_score"]
    by_student = {r["student"]: r for r in rows}
    assert float(by_student["ada"]["score"]) == 2 and by_student["ada"]["passed"] == "True"
    assert float(by_student["bob"]["score"]) == 0 and by_student["bob"]["passed"] == "False"
    assert {r["seed"] for r in rows} == {"7"}
    report = json.loads((out / "ada__01_curves_and_orientation.json").read_text())
    assert report["tasks"][0]["task"] == "curve_curvature" and report["tasks"][0]["passed"]
    assert "not implemented yet" in (out / "bob.txt").read_text()
    gs = json.loads((out / "ada__01_curves_and_orientation.results.json").read_text())
    assert gs["score"] == 2 and gs["tests"][0]["max_score"] == 2 and gs["tests"][0]["status"] == "passed"


def test_a_sandbox_that_cannot_import_the_lab_stops_a_folder_run_before_any_zero(tmp_path, monkeypatch, capsys):
    """A broken installation (here: the library the sandbox shows is an empty folder) would give every student
    0 points with the reason only in each report: the folder run refuses to start instead."""
    empty = tmp_path / "site" / "lab"
    empty.mkdir(parents=True)
    monkeypatch.setattr(bubblewrap, "LAB_DIR", empty)
    monkeypatch.setattr(grade, "LAB_DIR", empty)
    (tmp_path / "subs" / "ada").mkdir(parents=True)
    shutil.copy(SOLUTION / "00_start.ipynb", tmp_path / "subs" / "ada" / "00_start.ipynb")
    code = grade.main([str(tmp_path / "subs"), "--out", str(tmp_path / "out")] +
                      ([] if bubblewrap.bwrap_works() else ["--no-sandbox"]))
    err = capsys.readouterr().err
    assert code == 2 and "so every student would get 0 points; nothing was graded" in err, err
    assert "No module named 'lab.teaching'" in err, err
    assert not (tmp_path / "out" / "summary.csv").exists() and not list((tmp_path / "out").glob("ada*"))


def test_cli_json_gradescope_and_exit_status(capsys):
    path = SOLUTION / "00_start.ipynb"
    assert grade.main([str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["score"] == data["max_score"] == 1 and data["tasks"][0]["cases"]
    assert grade.main([str(path), "--format", "gradescope"]) == 0
    gs = json.loads(capsys.readouterr().out)
    assert gs["score"] == 1 and gs["tests"][0]["name"] == "warmup (mean_curvature)"
    assert grade.main([str(EXERCISE / "00_start.ipynb")]) == 1
    assert "not implemented yet" in capsys.readouterr().out


def test_without_bubblewrap_the_report_names_the_missing_protections():
    result = grading.grade_notebook(SOLUTION / "00_start.ipynb", sandbox=False)
    assert result.score == 1
    assert any("network isolation" in m for m in result.missing_protections)
    assert "sandbox: missing" in result.text()


@pytest.mark.skipif(not bubblewrap.bwrap_works(), reason="bubblewrap cannot run here")
def test_with_bubblewrap_no_protection_is_missing_but_the_process_limit_where_cgroups_are_read_only():
    result = grading.grade_notebook(SOLUTION / "00_start.ipynb")
    assert all("process count" in m for m in result.missing_protections)
    if not any("memory" in m for m in result.missing_protections):  # the cgroup measured the whole submission
        assert 50 << 20 < result.peak_memory < 1 << 30, result.peak_memory  # a kernel and the checks: not 2 GiB
        assert not any("memory limit" in n for n in result.notes)
    assert grading.GradeResult.from_dict(result.to_dict()).peak_memory == result.peak_memory


def test_a_submission_at_its_memory_limit_is_told_so_in_its_language():
    from lab import i18n

    limit = bubblewrap.MEMORY
    assert grading._memory_notes(None, limit) == [] and grading._memory_notes(limit // 2, limit) == []
    assert grading._memory_notes(limit, limit) == [
        ("the submission used 2048 MiB of its 2048 MiB memory limit (all of it, for all its processes together): "
         "a kernel at the limit is killed or slowed down")]
    with i18n.using("de"):
        assert grading._memory_notes(limit - (1 << 20), limit)[0].startswith(
            "die Abgabe hat 2047 MiB ihres Speicherlimits von 2048 MiB belegt")


def test_a_v2_cgroup_gets_no_swap_where_the_host_has_swap(tmp_path):
    """On cgroup v2 the submission's memory limit also forbids swap (memory.swap.max = 0) where the file exists:
    a submission at its limit is killed, it does not page out to the disk."""
    from lab.teaching.sandbox import cgroups

    (tmp_path / "memory.swap.max").write_text("max\n")
    cgroups._no_swap(tmp_path)
    assert (tmp_path / "memory.swap.max").read_text().strip() == "0"
    cgroups._no_swap(tmp_path / "absent")  # no swap accounting: nothing to do, no error
    assert not (tmp_path / "absent").exists()


def test_a_corrupt_notebook_scores_zero_of_the_assignments_points(tmp_path):
    (tmp_path / "00_start.ipynb").write_text('{"cells": [ broken')
    result = grading.grade_notebook(tmp_path / "00_start.ipynb")
    assert result.error.startswith("cannot read the notebook") and (result.score, result.max_score) == (0, 1)
    assert result.assignment == "00_start" and result.tasks[0]["task"] == "warmup" and not result.passed
    result = grading.grade_notebook(tmp_path / "00_start.ipynb", assignment=EXERCISE / "01_curves_and_orientation.ipynb")
    assert (result.score, result.max_score) == (0, 2) and "cannot read the notebook" in result.tasks[0]["report"]


@pytest.mark.parametrize("body, message", [
    ("def mean_curvature(k1, k2)\n    return (k1 + k2) / 2", "has a syntax error (SyntaxError"),
    ("import os\nos._exit(1)\ndef mean_curvature(k1, k2):\n    return (k1 + k2) / 2", "the kernel died while cell"),
], ids=["syntax-error", "dead-kernel"])
def test_syntax_errors_and_dead_kernels_are_named_not_not_implemented(tmp_path, body, message):
    nb = nbformat.read(SOLUTION / "00_start.ipynb", as_version=4)
    cell = next(c for c in nb.cells if "def mean_curvature" in c.source)
    cell.source = body
    nbformat.write(nb, tmp_path / "00_start.ipynb")
    result = grading.grade_notebook(tmp_path / "00_start.ipynb", timeout=60)
    (task,) = result.tasks
    assert task["status"] == "error" and "not implemented" not in task["report"], result.text()
    assert "mean_curvature was never defined" in task["report"] and message in task["report"]
    assert f"cell {nb.cells.index(cell)}, which defines it" in task["report"]


def test_the_file_name_decides_the_assignment_and_a_claim_is_noted(tmp_path):
    nb = nbformat.read(SOLUTION / "00_start.ipynb", as_version=4)
    nb.metadata["lab"]["assignment"] = "09_dill_gallery"  # task-less: claiming it must not make a pass
    nbformat.write(nb, tmp_path / "00_start.ipynb")
    result = grading.grade_notebook(tmp_path / "00_start.ipynb")
    assert result.assignment == "00_start" and result.score == result.max_score == 1
    assert any("says it is assignment '09_dill_gallery', its file name says '00_start'" in n for n in result.notes)
    shutil.copy(tmp_path / "00_start.ipynb", tmp_path / "my_work.ipynb")  # no assignment by that name: the claim
    other = grading.grade_notebook(tmp_path / "my_work.ipynb")
    assert other.assignment == "09_dill_gallery" and other.tasks == [] and not other.passed
    assert "no graded tasks" in other.text()


def test_a_name_error_after_a_failed_defining_cell_says_which_cell_failed():
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("import lab"),
                                         nbformat.v4.new_code_cell("mine = make()\nmine.visualize_curvature(0, 0)"),
                                         nbformat.v4.new_code_cell("mine.show()"),
                                         nbformat.v4.new_code_cell("other.show()")])
    errors = [{"cell": 1, "kind": "timeout", "error": "stopped after 15 s (endless loop?)"},
              {"cell": 2, "kind": "error", "error": "NameError: name 'mine' is not defined"},
              {"cell": 3, "kind": "error", "error": "NameError: name 'other' is not defined"}]
    grading._explain_name_errors(grading._defining_cells(nb), errors)
    assert errors[1]["error"] == ("NameError: name 'mine' is not defined (cell 1, which defines mine, did not "
                                  "finish: stopped after 15 s (endless loop?))")
    assert errors[2]["error"] == "NameError: name 'other' is not defined"  # a typo stays a typo


def test_the_cells_that_define_names_are_found_in_one_linear_pass():
    """A cell of a million newlines: a regular expression with ``^\\s*`` over it took about 30 s per 80 000 lines
    (quadratic: hours for a million, per task); one pass over the lines takes a fraction of a second.  The alarm is
    1000 times what the pass needs here, and a thousandth of what the old search would."""
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("import lab"),
                                         nbformat.v4.new_code_cell("class Mine:\n    pass\n" + "\n" * 1_000_000),
                                         nbformat.v4.new_code_cell("\n" * 1_000_000 + "mine = Mine()\nx == 2")])
    signal.signal(signal.SIGALRM, lambda *_: pytest.fail("the search of a million-line cell did not end in 60 s"))
    signal.alarm(60)
    try:
        defined = grading._defining_cells(nb)
    finally:
        signal.alarm(0)
    assert defined == {"Mine": 1, "mine": 2}  # x == 2 defines nothing


def test_a_german_report_writes_decimal_commas_and_a_missing_student_by_name():
    task = {"task": "visualize_curvature", "object": "MyBezierPatches", "points": 10, "score": 4 / 18,
            "passed": False, "report": ""}
    result = grading.GradeResult("alice/05.ipynb", assignment="05_visualize_curvature", seed=1, lang="de",
                                 tasks=[task])
    assert result.text().startswith("alice/05.ipynb: 2,22 / 10 Punkte") and "2,22 / 10\n" in result.text() + "\n"
    missing = grading.GradeResult("", student="frank", assignment="05_visualize_curvature", tasks=[{**task, "score": 0}])
    assert missing.text().startswith("frank: 0 / 10 points")


def test_an_empty_task_shows_no_answer_it_never_gave():
    """The stub's text ("compute the chosen curvature …") is what to write, not what the code returned."""
    result = grading.grade_notebook(EXERCISE / "00_start.ipynb", seed=2)
    cases = result.tasks[0]["cases"]
    assert cases and all(c["status"] == "not implemented" and c["got"] == "" for c in cases), cases
    assert result.tasks[0]["message"] and cases[0]["hint"] == result.tasks[0]["message"]
