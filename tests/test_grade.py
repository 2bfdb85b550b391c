"""``curvature-lab grade`` on a folder: names are data, not paths (a student's folder or file name is checked as a
user name, kept raw as a key, escaped where it is shown and quoted in a spreadsheet cell; no report takes a name the
folder run needs for itself, ``run.json``, ``summary.csv`` …, and no file is written outside the report folder), the
run record, the options.

Where the grading itself is not the point it is replaced by a stand-in (a full score for every notebook it is given),
so these tests run in seconds; tests/test_grader.py grades for real."""

import csv
import hashlib
import io
import json
from pathlib import Path

import nbformat
import pytest

from lab.teaching.course import files, grade
from lab.teaching.grader import notebook
from lab.teaching.sandbox import bubblewrap

ROOT = Path(__file__).resolve().parent.parent
ID = "05_visualize_curvature"
SOLUTION = {lang: ROOT / "solutions" / lang / f"{ID}.ipynb" for lang in ("en", "de")}
FORGED = "x\nada: 10 \u2215 10 points"  # a folder name whose newline forges a line of ada's (U+2215 looks like /)


def _task(score=1.0):
    return {"task": "visualize_curvature", "object": "MyBezierPatches", "points": 10, "score": score,
            "passed": score == 1.0, "report": "", "message": "", "cases": []}


@pytest.fixture
def fake_grading(monkeypatch):
    """Every notebook scores 10 of 10, without a sandbox; the paths it was given are recorded."""
    graded = []

    def grade_notebook(path, *, seed=None, **_kwargs):
        graded.append(Path(path))
        return notebook.GradeResult(str(path), assignment=ID, seed=seed, tasks=[_task()],
                                   sha256=hashlib.sha256(Path(path).read_bytes()).hexdigest())

    monkeypatch.setattr(grade, "grade_notebook", grade_notebook)
    monkeypatch.setattr(grade._assignments, "for_submission", lambda *_args: (None, []))  # nothing to prepare
    monkeypatch.setattr(grade, "probe", lambda **_kwargs: (None, []))
    monkeypatch.setattr(grade, "bwrap_works", lambda: True)
    return graded


def _subs(root, *paths):
    """A folder of submissions: each path an empty notebook."""
    subs = root / "subs"
    for rel in paths:
        (subs / rel).parent.mkdir(parents=True, exist_ok=True)
        nbformat.write(nbformat.v4.new_notebook(), subs / rel)
    return subs


def _summary(out):
    return list(csv.DictReader(io.StringIO((out / "summary.csv").read_text())))


def test_report_names_never_take_a_reserved_name(tmp_path):
    """``run.ipynb`` would overwrite run.json (and --resume would refuse); ``x.results.ipynb`` would be taken for the
    Gradescope file of a student x (and skipped by feedback); no report begins with a dot."""
    flat = ["run", "RUN", "summary", "collected", "written-05", "bob.results", "bob", "_x"]
    paths = [tmp_path / f"{stem}.ipynb" for stem in flat] + [tmp_path / "run" / f"{ID}.ipynb"]
    names = grade.report_names(tmp_path, paths)
    stems = {p.relative_to(tmp_path).as_posix(): stem for p, (stem, _note) in names.items()}
    assert stems == {"run.ipynb": "run~2", "RUN.ipynb": "RUN~3", "summary.ipynb": "summary~2",
                     "collected.ipynb": "collected~2", "written-05.ipynb": "written-05~2",
                     "bob.results.ipynb": "bob.results~2", "bob.ipynb": "bob", "_x.ipynb": "_x",
                     f"run/{ID}.ipynb": f"run__{ID}"}
    assert names[tmp_path / "run.ipynb"][1] == ("its report name 'run' is reserved for the files of the folder run "
                                                "(run.json, summary.csv): 'run~2'")
    assert names[tmp_path / "bob.ipynb"][1] == ""
    assert grade.report_names(tmp_path, [tmp_path / ".ipynb"]) == {tmp_path / ".ipynb": ("_ipynb", "")}


def test_a_long_name_makes_a_report_name_the_file_system_takes(tmp_path):
    path = tmp_path / ("ü" * 90) / ("ö" * 120 + ".ipynb")  # 540 bytes in UTF-8: over the 255 of a file name
    stem, _note = grade.report_names(tmp_path, [path])[path]
    assert len(stem.encode()) <= 150 and stem.startswith("ü" * 75)


def test_a_flat_notebook_called_run_leaves_run_json_alone_and_resume_works(tmp_path, fake_grading):
    subs = _subs(tmp_path, "run.ipynb", f"ada/{ID}.ipynb")
    out = tmp_path / "reports"
    results = grade.grade_folder(subs, out, seed=5, sandbox=False)
    assert json.loads((out / "run.json").read_text()) == {"seed": 5, "assignment": None}
    assert json.loads((out / "run~2.json").read_text())["student"] == "run"
    run = next(r for r in results if r.student == "run")
    assert run.score == 10 and any("reserved" in n for n in run.notes)
    fake_grading.clear()
    again = grade.grade_folder(subs, out, resume=True, sandbox=False)  # no "graded with seed …" refusal
    assert fake_grading == [] and sorted(r.student for r in again) == ["ada", "run"]


def test_a_name_that_is_a_path_is_refused_and_nothing_is_written_outside(tmp_path, fake_grading):
    """``...ipynb`` is a student called ``..``; a folder ``.hidden`` or one with a newline is no user name either: each
    is refused like a symbolic link (its own row, 0 points, the name escaped), never graded, never part of a path."""
    subs = _subs(tmp_path, f"ada/{ID}.ipynb", "...ipynb", f".hidden/{ID}.ipynb", f"{FORGED}/{ID}.ipynb",
                 f"ad\u200ba/{ID}.ipynb")
    out = tmp_path / "reports"
    out.mkdir()
    before = sorted(p.name for p in tmp_path.iterdir())
    results = grade.grade_folder(subs, out, seed=5, sandbox=False)
    assert fake_grading == [subs / "ada" / f"{ID}.ipynb"]  # only ada's notebook was graded
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # no "...json" next to the reports
    by_student = {r.student: r for r in results}
    assert set(by_student) == {"ada", "..", ".hidden", "x\\nada: 10 \u2215 10 points", "ad\\u200ba"}
    assert by_student[".."].error == ("refused: '..' is a path, not a user name; a submission is "
                                      "SUBS/<user name>/<notebook>.ipynb or SUBS/<user name>.ipynb")
    assert "begins with a dot" in by_student[".hidden"].error
    assert "has a line break (U+000A)" in by_student["x\\nada: 10 \u2215 10 points"].error
    assert "has an invisible character (U+200B)" in by_student["ad\\u200ba"].error
    assert all(r.score == 0 for s, r in by_student.items() if s != "ada")
    rows = {r["student"]: r for r in _summary(out)}
    shown = "x\\nada: 10 \u2215 10 points"
    assert set(rows) == set(by_student) and rows[shown]["notebook"] == f"{shown}/{ID}.ipynb"
    assert float(rows["ada"]["score"]) == 10 and float(rows[".."]["score"]) == 0


def test_a_newline_in_a_name_forges_no_line_of_a_report_or_of_the_output(tmp_path, fake_grading):
    """A notebook's file name may hold a newline (its folder, the user name, may not): the report's first line and
    the line ``grade`` prints stay one line each."""
    subs = _subs(tmp_path, f"bob/{FORGED}.ipynb")
    out = tmp_path / "reports"
    (res,) = grade.grade_folder(subs, out, seed=5, sandbox=False)
    assert res.student == "bob" and res.notebook == f"bob/{FORGED}.ipynb"  # kept raw as data
    assert grade.result_line(res) == "bob/x\\nada: 10 \u2215 10 points.ipynb: 10 / 10"
    text = res.text()
    assert text.splitlines()[0] == f"bob/x\\nada: 10 \u2215 10 points.ipynb: 10 / 10 points  (assignment {ID}, seed 5)"
    assert not any(line.startswith("ada") for line in text.splitlines())
    (report,) = out.glob("*.txt")
    assert report.read_text().splitlines()[0] == text.splitlines()[0]
    error = notebook.GradeResult("a.ipynb", error="line one\nada: 10 / 10 points")
    assert error.text().splitlines()[1:] == ["  error: line one", "    ada: 10 / 10 points"]  # indented under it


def test_a_quoted_name_is_not_its_unquoted_twin(tmp_path, fake_grading):
    """``'bea`` and ``bea`` are two students: two rows, two cells that read back as the two names."""
    subs = _subs(tmp_path, f"'bea/{ID}.ipynb", f"bea/{ID}.ipynb", f"=cmd/{ID}.ipynb")
    out = tmp_path / "reports"
    grade.grade_folder(subs, out, seed=5, sandbox=False)
    cells = sorted(r["student"] for r in _summary(out))
    assert cells == ["''bea", "'=cmd", "bea"]  # as a spreadsheet sees them: quoted, never a formula
    assert sorted(r["student"] for r in files.read_summary(out / "summary.csv")) == ["'bea", "=cmd", "bea"]


def test_collected_csv_is_read_through_the_same_quoting(tmp_path, fake_grading):
    """collect writes collected.csv with quoted cells: a student ``'bea`` listed missing there is not ``bea``."""
    subs = _subs(tmp_path, f"bea/{ID}.ipynb")
    (subs / "collected.csv").write_text("student,assignment,status,late,late_seconds,note\n"
                                        f"bea,{ID},collected,False,0,\n''bea,{ID},missing,,,\n")
    results = grade.grade_folder(subs, tmp_path / "reports", seed=5, sandbox=False)
    assert sorted((r.student, r.score) for r in results) == [("'bea", 0), ("bea", 10)]
    assert "no submission (missing)" in next(r for r in results if r.student == "'bea").error


@pytest.mark.skipif(not bubblewrap.bwrap_works(), reason="bubblewrap cannot run here")
def test_grade_cli_rejects_bad_options(capsys):
    for args, message in ((["--timeout", "-5"], "expected a positive number"), (["--memory", "0"], "positive"),
                          (["--memory", "100"], "at least 256")):
        with pytest.raises(SystemExit):
            grade.main([str(SOLUTION["en"]), *args])
        assert message in capsys.readouterr().err


def test_run_record_writes_null_for_the_default_assignment_and_resumes_an_old_one(tmp_path):
    seed = grade._run_record(tmp_path, 7, None, resume=False)
    assert seed == 7 and json.loads((tmp_path / "run.json").read_text()) == {"seed": 7, "assignment": None}
    (tmp_path / "run.json").write_text(json.dumps({"seed": 9, "assignment": "None"}))  # written before the fix
    assert grade._run_record(tmp_path, None, None, resume=True) == 9
    with pytest.raises(grade.GradingError, match="graded against None, not elsewhere"):
        grade._run_record(tmp_path, None, "elsewhere", resume=True)


def test_a_student_without_a_submission_is_named_and_a_missing_seed_is_no_none():
    from lab.teaching.grader.notebook import GradeResult

    res = GradeResult(notebook="", assignment=ID, student="hans", error="no submission (missing: no home)",
                      tasks=[{"task": "visualize_curvature", "object": "MyBezierPatches", "points": 10, "score": 0.0,
                             "passed": False, "report": ""}])
    assert grade.result_line(res) == "hans: 0 / 10  (no submission (missing: no home))"
    assert "seed –" in res.text() and "None" not in res.text()
