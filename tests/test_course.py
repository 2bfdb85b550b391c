"""A course from hand-out to gradebook, without the hub (tests/test_hub.py runs it through JupyterHub):
release, collect, grading a mixed English/German folder (resumed after a crash), feedback, written answers,
gradebook (Canvas, Moodle, CSV, late penalty), the Gradescope autograder.

One folder run is graded once for the module (``graded``); the other tests read its reports."""

import csv
import dataclasses
import datetime
import json
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import nbformat
import pytest

from lab.teaching.course import collect, feedback, grade, gradebook, gradescope, late, written
from tests import students
from tests.report_support import report_folder, result, rows_of

ROOT = Path(__file__).resolve().parent.parent
ID = "05_visualize_curvature"
SOLUTION = {lang: ROOT / "solutions" / lang / f"{ID}.ipynb" for lang in ("en", "de")}
EXERCISE = {lang: ROOT / "exercises" / lang / f"{ID}.ipynb" for lang in ("en", "de")}
# in the past: a hand-in time is never after the kernel's status-change time of the file (the time the test wrote
# it), so a late hand-in needs a deadline before that; on-time ones are seen by a collect "at the deadline" (course)
DEADLINE = datetime.datetime(2025, 12, 15, 23, 59, tzinfo=datetime.timezone.utc)

pytestmark = pytest.mark.xdist_group("course")  # one graded folder for the module


def _save(src, dst, when, rename=None):
    dst.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(src, dst)
    os.utime(dst, (when.timestamp(), when.timestamp()))
    return dst


def lines_of(path):
    with open(path, newline="") as fh:
        return list(csv.reader(fh))


def _snapshot(root):
    return {p.relative_to(root): (p.read_bytes(), p.stat().st_mtime) for p in sorted(Path(root).rglob("*"))
            if p.is_file() and not p.is_symlink()}


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    """Homes of six students: ada (English, right, on time), bea (German, right, 2.5 days late, the notebook
    renamed), cy (English, not done), dan (a link to ada's notebook), eli (no notebook), gus (English, b_u and b_v
    without their degree factors); then collect and grade.  Collected twice, as an instructor would: 3 hours before
    the deadline (the collector's clock set back: the first sight of each notebook's bytes is the on-time record)
    and again after bea's hand-in, 2.5 days late."""
    root = tmp_path_factory.mktemp("course")
    homes = root / "home"
    on_time, late = DEADLINE - datetime.timedelta(hours=3), DEADLINE + datetime.timedelta(days=2, hours=12)
    _save(SOLUTION["en"], homes / "ada" / "curvature-lab" / "exercises" / "en" / f"{ID}.ipynb", on_time)
    nb = nbformat.read(SOLUTION["de"], as_version=4)
    answer = next(c for c in nb.cells if c.cell_type == "markdown")
    _save(EXERCISE["en"], homes / "cy" / f"{ID}.ipynb", on_time)
    (homes / "bea" / "work").mkdir(parents=True)  # her notebook comes after the deadline
    (homes / "dan").mkdir()
    (homes / "dan" / f"{ID}.ipynb").symlink_to(homes / "ada" / "curvature-lab" / "exercises" / "en" / f"{ID}.ipynb")
    (homes / "eli" / "notes").mkdir(parents=True)
    # gus forgot m and n in b_u and b_v (K comes out 81 times too large): his report must name that mistake
    mine = nbformat.read(SOLUTION["en"], as_version=4)
    next(c for c in mine.cells if "class MyBezierPatches" in c.source).source = students.source("bu_bv_without_m_n")
    (homes / "gus").mkdir()
    nbformat.write(mine, homes / "gus" / f"{ID}.ipynb")
    os.utime(homes / "gus" / f"{ID}.ipynb", (on_time.timestamp(),) * 2)
    # written answers of 04 for ada and bea
    ex04 = nbformat.read(ROOT / "exercises" / "en" / "04_color_maps.ipynb", as_version=4)
    q = written.questions_of(ex04)[0]
    for student, text in (("ada", "f1 is absolute; f2 uses the whole ramp."), ("bea", "=cmd|' /C calc'!A0")):
        mine = nbformat.read(ROOT / "exercises" / "en" / "04_color_maps.ipynb", as_version=4)
        next(c for c in mine.cells if c.get("id") == q.cell).source = text
        path = homes / student / "04_color_maps.ipynb"
        nbformat.write(mine, path)
        os.utime(path, (on_time.timestamp(),) * 2)
    del nb, answer
    subs, roster = root / "subs", ["ada", "bea", "cy", "dan", "eli", "fay", "gus"]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(collect, "_clock", lambda: on_time)
        collect.collect(homes, ID, DEADLINE.isoformat(), subs, roster=roster)
        rows04 = collect.collect(homes, "04_color_maps", DEADLINE.isoformat(), root / "subs04")
        _save(SOLUTION["de"], homes / "bea" / "work" / "meine_abgabe.ipynb", late)  # found by its metadata id
        before = _snapshot(homes)
        mp.setattr(collect, "_clock", lambda: late)
        rows = collect.collect(homes, ID, DEADLINE.isoformat(), subs, roster=roster)
    reports = root / "reports"
    results = grade.grade_folder(subs, reports, jobs=2, seed=777, timeout=120)
    return {"root": root, "homes": homes, "subs": subs, "reports": reports, "rows": rows, "rows04": rows04,
            "results": {r.student: r for r in results}, "before": before}


def test_the_report_of_a_common_mistake_names_it(course):
    """Graded through the folder (sandbox, child process), a wrong submission's report names its mistake once:
    the headline is the first failing case's diagnosis (tests/test_hints.py tries every mutant through lab.check)."""
    res = course["results"]["gus"]
    text = (course["reports"] / f"gus__{ID}.txt").read_text()
    assert res.score == 0 and res.max_score == 10, text  # every case needs K, H or κ from b_u and b_v
    for words in ("b_u has the factor 1 = 1 instead of m = 3", "b_v has the factor 1 = 1 instead of n = 3",
                  "81 times the right ones"):
        assert words in text, text
    assert text.count("81 times the right ones") == 1 and "with the same hint" in text, text  # grouped


def test_collect_finds_each_notebook_and_records_lateness(course):
    rows = {r["student"]: r for r in course["rows"]}
    assert rows["ada"]["status"] == "collected" and rows["ada"]["late"] is False
    assert rows["bea"]["status"] == "collected" and rows["bea"]["file"] == "work/meine_abgabe.ipynb"
    assert rows["bea"]["late"] is True and rows["bea"]["late_seconds"] == 2.5 * 86400
    late = DEADLINE + datetime.timedelta(days=2.5)  # bea's hand-in: first seen then, her file's time says the same
    assert rows["bea"]["submitted"] == rows["bea"]["first_seen"] == rows["bea"]["modified"] == late.isoformat()
    on_time = (DEADLINE - datetime.timedelta(hours=3)).isoformat()  # ada's: first seen by the collect at the deadline
    assert rows["ada"]["submitted"] == rows["ada"]["first_seen"] == on_time < rows["ada"]["changed"]
    assert rows["dan"]["status"] == "refused" and "symbolic link" in rows["dan"]["note"]
    assert rows["eli"]["status"] == "missing" and rows["fay"]["note"] == "no home"
    copy = course["subs"] / "bea" / f"{ID}.ipynb"
    assert copy.read_bytes() == SOLUTION["de"].read_bytes()  # copied under the instructor's file name
    written_csv = rows_of(course["subs"] / "collected.csv")
    assert {r["student"] for r in written_csv} == {"ada", "bea", "cy", "dan", "eli", "fay", "gus"}


def test_collect_never_changes_a_home(course):
    assert _snapshot(course["homes"]) == course["before"]


def test_collect_refuses_to_overwrite_a_changed_copy(course, tmp_path):
    subs = tmp_path / "subs"
    collect.collect(course["homes"], ID, DEADLINE.isoformat(), subs)
    (subs / "ada" / f"{ID}.ipynb").write_text("{}")  # an instructor's correction
    with pytest.raises(collect.CollectError, match="was changed since it was collected"):
        collect.collect(course["homes"], ID, DEADLINE.isoformat(), subs)
    with pytest.raises(collect.CollectError, match="ISO 8601"):
        collect.collect(course["homes"], ID, "next friday", tmp_path / "x")


def test_the_written_answers_are_collected_per_question(course):
    page = (course["root"] / "subs04" / "written-04_color_maps.html").read_text()
    assert "f1 is absolute" in page and "=cmd|" in page and "<script" not in page
    rows = rows_of(course["root"] / "subs04" / "written-04_color_maps.csv")
    assert {r["student"] for r in rows} == {"ada", "bea"} and all(r["points"] == "" for r in rows)
    assert next(r for r in rows if r["student"] == "bea")["answer"].startswith("'=")  # never a formula
    assert float(rows[0]["max_points"]) == 3
    assert rows[0]["question"] == "bfbc93a2" and rows[0]["title"] == "Question: advantages and disadvantages"


def test_a_mixed_english_and_german_folder_is_graded(course):
    res = course["results"]
    assert res["ada"].score == res["bea"].score == 10 and res["ada"].lang == "en" and res["bea"].lang == "de"
    assert "Punkte" in (course["reports"] / f"bea__{ID}.txt").read_text()
    assert res["cy"].score == 0 and res["cy"].max_score == 10
    assert res["eli"].score == 0 and res["eli"].max_score == 10 and "no submission" in res["eli"].error
    rows = {r["student"]: r for r in rows_of(course["reports"] / "summary.csv")}
    assert rows["bea"]["late"] == "True" and rows["bea"]["late_seconds"] == str(int(2.5 * 86400))
    assert rows["ada"]["missing_protections"] == ""  # bubblewrap, cgroups and the tmpfs budget are all there


def test_resume_grades_only_what_is_missing(course):
    reports = course["reports"]
    kept = {p.name: p.stat().st_mtime_ns for p in reports.glob("*.json")}
    (reports / f"cy__{ID}.json").unlink()
    results = grade.grade_folder(course["subs"], reports, jobs=2, resume=True, timeout=120)
    after = {p.name: p.stat().st_mtime_ns for p in reports.glob("*.json")}
    assert after[f"ada__{ID}.json"] == kept[f"ada__{ID}.json"]  # not graded again
    assert f"cy__{ID}.json" in after and {r.student: r.score for r in results}["cy"] == 0
    assert json.loads((reports / "run.json").read_text())["seed"] == 777
    with pytest.raises(grade.GradingError, match="graded with seed 777, not 5"):
        grade.grade_folder(course["subs"], reports, resume=True, seed=5)


def test_folder_grading_refuses_without_bubblewrap(course, monkeypatch, tmp_path):
    monkeypatch.setattr(grade, "bwrap_works", lambda: False)
    with pytest.raises(grade.GradingError, match="bubblewrap .* cannot run here.*--no-sandbox"):
        grade.grade_folder(course["subs"], tmp_path / "r")
    with pytest.raises(grade.GradingError, match="no notebooks"):
        (tmp_path / "empty").mkdir()
        grade.grade_folder(tmp_path / "empty", tmp_path / "r", sandbox=False)


def test_feedback_in_each_home_in_the_students_language(course):
    homes = course["homes"]
    (homes / "cy" / "feedback").mkdir()
    (homes / "cy" / "feedback" / f"{ID}.html").write_text("my own notes")  # not ours: kept
    (homes / "dan" / "feedback").symlink_to("/etc")  # a trap for an instructor running as root
    feedback.feedback([course["reports"]], homes)
    ada = (homes / "ada" / "feedback" / f"{ID}.html").read_text()
    bea = (homes / "bea" / "feedback" / f"{ID}.html").read_text()
    assert "10 of 10 points" in ada and "visualize_curvature" in ada
    assert "10 von 10 Punkten" in bea and "Rückmeldung" in bea
    cy = (homes / "cy" / "feedback" / f"{ID}.2.html").read_text()
    assert "0 of 10 points" in cy and "not implemented" in cy
    # an empty task: what to write, once, above the cases; no "got:" that would show it as the code's answer
    assert "got:" not in cy and cy.count("compute the chosen curvature") == 1, cy
    assert "<th></th>" not in cy and "<th>status</th></tr>" in cy  # no empty third column: no case has a detail
    assert (homes / "cy" / "feedback" / f"{ID}.html").read_text() == "my own notes"
    assert not (Path("/etc") / f"{ID}.html").exists()
    for student in ("ada", "bea"):  # their work is untouched
        for path, (data, mtime) in course["before"].items():
            if path.parts[0] == student:
                assert (homes / path).read_bytes() == data


def test_gradebook_totals_late_penalty_and_lms_layouts(course, tmp_path):
    marks = tmp_path / "written.csv"
    rows = rows_of(course["root"] / "subs04" / "written-04_color_maps.csv")
    for r in rows:
        r["points"] = "2" if r["student"] == "ada" else "1"
    with open(marks, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    reports04 = tmp_path / "reports04"
    grade.grade_folder(course["root"] / "subs04", reports04, jobs=2, seed=3, timeout=120)
    out = tmp_path / "grades.csv"
    assert gradebook.main([str(course["reports"]), str(reports04), "--written", str(marks), "--late-penalty", "10",
                           "--late-cap", "25", "--format", "csv", "-o", str(out)]) == 0
    table = {r["student"]: r for r in rows_of(out)}
    assert float(table["ada"][ID]) == 10 and float(table["bea"][ID]) == 7.5  # 3 started days late: 30 %, capped 25 %
    assert table["bea"][f"{ID} late days"] == "3"
    assert float(table["(max)"][ID]) == 10 and float(table["(max)"]["04_color_maps"]) == 7 + 3 + 2  # two questions
    assert float(table["ada"]["total"]) == 10 + float(table["ada"]["04_color_maps"])
    assert float(table["ada"]["04_color_maps"]) == 0 + 2 + 2  # the exercise untouched (0 autograded) + 2 per question
    canvas = tmp_path / "canvas.csv"
    gradebook.main([str(course["reports"]), "--format", "canvas", "-o", str(canvas), "--late-penalty", "10"])
    lines = lines_of(canvas)
    assert lines[0] == ["Student", "ID", "SIS User ID", "SIS Login ID", "Section", ID]
    assert lines[1][0] == "Points Possible" and float(lines[1][5]) == 10
    assert ["bea", "", "", "bea", "", "7.0"] in lines
    moodle = tmp_path / "moodle.csv"
    gradebook.main([str(course["reports"]), "--format", "moodle", "-o", str(moodle)])
    lines = lines_of(moodle)
    assert lines[0] == ["Username", "ID number", "Email address", ID] and ["ada", "", "", "10.0"] in lines
    bad = tmp_path / "bad.csv"
    bad.write_text("student,assignment,question,max_points,points\nada,04_color_maps,x,3,5\n")
    assert gradebook.main([str(reports04), "--written", str(bad), "-o", str(tmp_path / "g.csv")]) == 2


def test_gradebook_csv_tells_a_missing_submission_from_an_empty_one(course, tmp_path):
    """cy handed in the untouched exercise, eli nothing: both score 0, the status column tells them apart; the
    (max) row holds the points possible in every points column, total and max alike."""
    out = tmp_path / "grades.csv"
    assert gradebook.main([str(course["reports"]), "-o", str(out)]) == 0
    lines = {line[0]: line for line in lines_of(out)}
    assert lines["student"] == ["student", ID, f"{ID} late days", f"{ID} status", f"{ID} note", "total", "max"]
    assert lines["(max)"] == ["(max)", "10.0", "", "", "", "10.0", "10.0"]
    assert lines["cy"] == ["cy", "0.0", "0", "submitted", "", "0.0", "10.0"]
    assert lines["eli"] == ["eli", "0.0", "0", "missing", "", "0.0", "10.0"]
    assert lines["fay"][3] == "missing" and lines["dan"][3] == "missing"  # no home; a link collect refused


def test_feedback_tells_a_late_student_the_lateness_and_the_penalty(course, tmp_path):
    """bea handed in 2.5 days late: her (German) page says so, and with the gradebook's penalty what it takes."""
    homes = tmp_path / "home"
    for student in ("ada", "bea"):
        (homes / student).mkdir(parents=True)
    assert feedback.main([str(course["reports"]), str(homes)]) == 0
    bea = (homes / "bea" / "feedback" / f"{ID}.html").read_text()
    assert "<p class='late'>Abgegeben 2 Tg. 12 Std. 0 Min. nach Ablauf der Frist.</p>" in bea
    assert feedback.main([str(course["reports"]), str(homes), "--late-penalty", "10", "--late-cap", "25"]) == 0
    bea = (homes / "bea" / "feedback" / f"{ID}.html").read_text()
    assert ("<p class='late'>Abgegeben 2 Tg. 12 Std. 0 Min. nach Ablauf der Frist. Verspätungsabzug: 25 Prozent der "
            "Punkte (angefangene Tage Verspätung: 3); von den Punkten oben (10) zählen 7,5.</p>") in bea
    assert "class='late'" not in (homes / "ada" / "feedback" / f"{ID}.html").read_text()  # on time
    page = feedback.render(dataclasses.replace(course["results"]["bea"], lang="en"), 3600 * 5 + 1,
                           late.LatePolicy(10, grace=360))
    assert "<p class='late'>Handed in 0 d 5 h 1 min after the deadline. No late penalty.</p>" in page  # grace


def test_gradescope_autograder_runs_and_rounds_alike(course, tmp_path):
    zpath = gradescope.build(ID, tmp_path / "autograder.zip", visibility="after_due_date")
    root = tmp_path / "autograder"
    with zipfile.ZipFile(zpath) as z:
        names = z.namelist()
        z.extractall(root / "source")
    assert {"setup.sh", "run_autograder", f"assignment/en/{ID}.ipynb", f"assignment/de/{ID}.ipynb",
            "curvature-lab/pyproject.toml", "curvature-lab/lab/teaching/grader/notebook.py"} <= set(names)
    for script in ("setup.sh", "run_autograder"):
        assert subprocess.run(["bash", "-n", str(root / "source" / script)], check=False).returncode == 0
    # Gradescope's layout: the zip unpacked as it is into /autograder/source, the upload in /autograder/submission;
    # what setup.sh installs is there, unmoved
    installed = re.search(r"pip install -q (/autograder/\S+)\s*$", (root / "source" / "setup.sh").read_text()).group(1)
    assert (root / Path(installed).relative_to("/autograder") / "pyproject.toml").is_file()
    (root / "submission").mkdir()
    shutil.copy(SOLUTION["de"], root / "submission" / "abgabe (1).ipynb")
    env = {**os.environ, "AUTOGRADER_ROOT": str(root), "LAB_PYTHON": sys.executable}
    subprocess.run(["bash", str(root / "source" / "run_autograder")], env=env, check=True, timeout=1200,
                   capture_output=True)
    results = json.loads((root / "results" / "results.json").read_text())
    assert results["score"] == 10 and results["visibility"] == "after_due_date"
    assert sum(t["score"] for t in results["tests"]) == results["score"]
    assert all(t["visibility"] == "after_due_date" for t in results["tests"])
    with pytest.raises(Exception, match="no graded tasks"):
        gradescope.build("09_dill_gallery", tmp_path / "x.zip")
    # notebook 11 reads CAD files: its image gets OpenCASCADE (the extra cad) and the sample parts (occt-misc)
    with zipfile.ZipFile(gradescope.build("11_real_part", tmp_path / "parts.zip")) as z:
        setup = z.read("setup.sh").decode()
    assert " occt-misc" in setup and 'pip install -q "/autograder/source/curvature-lab[cad]"' in setup
    assert "occt-misc" not in (root / "source" / "setup.sh").read_text()


# -- the hand-out ----------------------------------------------------------------------------------------------





















# -- what an instructor reads on the way (no grading needed) ---------------------------------------------------









@pytest.mark.parametrize("verb", ["release", "collect", "grade", "feedback", "gradebook", "gradescope"])
def test_course_commands_help_in_the_instructors_language(verb, capsys):
    import importlib

    from lab import cli, i18n

    main = importlib.import_module(f"lab.teaching.course.{verb}").main
    texts = {}
    for lang in ("en", "de"):
        with i18n.using(lang), pytest.raises(SystemExit):
            main(["--help"])
        texts[lang] = capsys.readouterr().out
    # the description and every option's help are translated (argparse's own "usage:", "options:" stay English)
    assert texts["de"] != texts["en"]
    assert " (default" not in texts["de"] and "Vorgabe" in texts["de"] + ("Vorgabe" if verb == "feedback" else "")
    with i18n.using("de"), pytest.raises(SystemExit):
        cli.main(["--help"])
    assert "Aufgabenblatt" in capsys.readouterr().out


# -- feedback and gradebook on made-up reports (no grading needed) -------------------------------------------------





def test_feedback_and_gradebook_make_one_assignment_in_two_folders_that_students_zero(tmp_path, capsys):
    """ada's assignment in two report folders: no order of the folders decides her grade, and she alone pays for it
    (0 points and a note in the gradebook, no page and a line on stderr from feedback); bob is graded and gets his
    page. (Before issue 28 both commands refused for the whole class.)"""
    late = report_folder(tmp_path / "reports" / "05late", result("ada", score=1.0), late={"ada": 3600})
    on_time = report_folder(tmp_path / "reports" / "05", result("ada"), result("bob"))
    for student in ("ada", "bob"):
        (tmp_path / "home" / student).mkdir(parents=True)
    assert feedback.main([str(late), str(on_time), str(tmp_path / "home")]) == 0
    assert capsys.readouterr().err == (
        f"curvature-lab feedback: ada has assignment {ID} in two report folders, {late} and {on_time}: no page "
        "written; pass only the folder that counts\nfeedback for 1 of 2 reports\n")
    assert not (tmp_path / "home" / "ada" / "feedback").exists()
    assert "7.5 of 10 points" in (tmp_path / "home" / "bob" / "feedback" / f"{ID}.html").read_text()
    note = f"{ID} is in two report folders, {late} and {on_time}: 0 points here; pass only the folder that counts"
    assert gradebook.main([str(late), str(on_time), "-o", str(tmp_path / "g.csv")]) == 0
    assert f"curvature-lab gradebook: ada: {note}\n" in capsys.readouterr().err
    table = {r["student"]: r for r in rows_of(tmp_path / "g.csv")}
    assert table["ada"][ID] == "0.0" and table["ada"][f"{ID} status"] == "refused" and table["ada"][f"{ID} note"] == note
    assert table["bob"][ID] == "7.5" and table["bob"][f"{ID} note"] == ""
    assert gradebook.main([str(on_time), str(on_time), "-o", str(tmp_path / "g.csv")]) == 0  # the same folder twice
    assert {r["student"]: r[ID] for r in rows_of(tmp_path / "g.csv")}["ada"] == "7.5"








