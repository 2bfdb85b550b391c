"""Feedback on made-up report folders (issue 28, items 3 and 6): a page is written only inside a home that is a
user name's, and one student's report (a name that is a path, an assignment in two folders, a damaged or oversized
report) is a line on stderr for that student, never an error that stops the pages of the class."""

import json

import pytest

from lab.teaching.course import feedback
from tests.report_support import ID, report_folder, result


@pytest.fixture
def homes(tmp_path):
    homes = tmp_path / "homes"
    for student in ("ada", "bob"):
        (homes / student).mkdir(parents=True)
    return homes


def _pages(homes):
    return sorted(str(p.relative_to(homes)) for p in homes.rglob("*.html"))


def test_a_report_whose_student_is_a_path_writes_nothing_outside_the_homes(tmp_path, homes, capsys):
    """A report of a student ``..`` (a flat file ``...ipynb`` graded before the names were checked) would put
    its page into the folder above the homes; ``ad\\u200ba`` looks like ada."""
    reports = report_folder(tmp_path / "reports", result("ada"), result(".."), result("ad\u200ba"),
                            result("x\ny"), result("bob/../ada"))
    before = sorted(p.name for p in tmp_path.iterdir())
    assert feedback.main([str(reports), str(homes)]) == 0
    assert _pages(homes) == [f"ada/feedback/{ID}.html"]  # ada's page only, and once
    assert sorted(p.name for p in tmp_path.iterdir()) == before and not (tmp_path / "feedback").exists()
    err = capsys.readouterr().err
    assert "curvature-lab feedback: the report of '..' skipped: '..' is a path, not a user name\n" in err
    assert ("curvature-lab feedback: the report of 'ad\\u200ba' skipped: the user name 'ad\\u200ba' has an "
            "invisible character (U+200B)\n") in err
    assert "the user name 'x\\ny' has a line break (U+000A)" in err and "has a path separator (/)" in err
    assert "feedback for 1 of 5 reports" in err


def test_one_assignment_in_two_folders_is_that_students_note(tmp_path, homes, capsys):
    """Before, the whole command refused before any page; now ada, in both folders, gets no page and a line on
    stderr saying why, and bob his page."""
    late = report_folder(tmp_path / "reports" / "05late", result("ada", score=1.0), late={"ada": 3600})
    on_time = report_folder(tmp_path / "reports" / "05", result("ada"), result("bob"))
    assert feedback.main([str(late), str(on_time), str(homes)]) == 0
    assert _pages(homes) == [f"bob/feedback/{ID}.html"]
    err = capsys.readouterr().err
    assert (f"curvature-lab feedback: ada has assignment {ID} in two report folders, {late} and {on_time}: no page "
            "written; pass only the folder that counts\n") in err
    assert "feedback for 1 of 2 reports" in err


def test_a_damaged_or_oversized_report_is_skipped_alone(tmp_path, homes, capsys, monkeypatch):
    reports = report_folder(tmp_path / "reports", result("ada"), result("bob"), result("cy"), late={"bob": "soon"})
    (tmp_path / "homes" / "cy").mkdir()
    (reports / "r2.json").write_text(json.dumps(result("cy").to_dict()) + " " * 5000)  # over the limit below
    (reports / "broken.json").write_text('{"student": "eve", "tasks": [')
    (reports / "odd.json").write_text(json.dumps({"student": "fay", "tasks": [], "colour": "blue"}))
    (reports / "bad_points.json").write_text(json.dumps({**result("gus").to_dict(), "tasks": [{"task": "x"}]}))
    (tmp_path / "homes" / "gus").mkdir()
    monkeypatch.setattr(feedback, "MAX_REPORT", 4000)
    assert feedback.main([str(reports), str(homes)]) == 0
    assert _pages(homes) == [f"ada/feedback/{ID}.html"]
    err = capsys.readouterr().err
    assert f"curvature-lab feedback: {reports / 'broken.json'}: not a report of curvature-lab grade (not a JSON " \
           "document (JSONDecodeError)): skipped\n" in err
    assert f"{reports / 'r2.json'}: not a report of curvature-lab grade (r2.json has " in err
    assert "at most 4000 are read" in err
    assert f"{reports / 'odd.json'}: not a report of curvature-lab grade (" in err
    assert "curvature-lab feedback: bob: the page could not be made: ValueError" in err  # late_seconds 'soon'
    assert f"{reports / 'bad_points.json'}: not a report of curvature-lab grade (KeyError: 'points')" in err


def test_a_home_that_is_a_link_or_a_file_is_skipped(tmp_path, homes, capsys):
    (tmp_path / "elsewhere").mkdir()
    (homes / "cy").symlink_to(tmp_path / "elsewhere")
    (homes / "dan").write_text("not a folder")
    reports = report_folder(tmp_path / "reports", result("ada"), result("cy"), result("dan"), result("eve"))
    assert feedback.main([str(reports), str(homes)]) == 0
    assert _pages(homes) == [f"ada/feedback/{ID}.html"] and list((tmp_path / "elsewhere").iterdir()) == []
    err = capsys.readouterr().err
    assert all(f"curvature-lab feedback: no home for {s}: skipped\n" in err for s in ("cy", "dan", "eve")), err


def test_a_page_name_is_one_file_name(tmp_path, homes):
    with pytest.raises(feedback.FeedbackError, match="is not a single file name"):
        feedback.write_into_home(homes / "ada", "../../outside", "<p>x</p>")
    assert not (tmp_path / "outside.html").exists() and not (homes / "outside.html").exists()
    path = feedback.write_into_home(homes / "ada", "..", "<p>x</p>")  # "...html": one name, inside
    assert path == homes / "ada" / "feedback" / "...html" and path.is_file()


def test_no_report_at_all_is_still_an_error(tmp_path, homes, capsys):
    (tmp_path / "reports").mkdir()
    assert feedback.main([str(tmp_path / "reports"), str(homes)]) == 2
    assert "no reports (<name>.json written by curvature-lab grade)" in capsys.readouterr().err
    assert feedback.main([str(tmp_path / "reports"), str(tmp_path / "nowhere")]) == 2
    assert "is not a folder of homes" in capsys.readouterr().err


def test_feedback_usage_names_the_homes(capsys):
    with pytest.raises(SystemExit):
        feedback.main(["reports/05"])
    err = capsys.readouterr().err
    assert "REPORTS [REPORTS ...] HOMES" in err and "required: HOMES" in err


def test_feedback_keeps_a_page_the_student_edited(tmp_path):
    """Only a page whose bytes are exactly what feedback wrote is replaced: a page the student added notes to stays,
    and the new page is numbered (and replaced on the next run, being the command's own)."""
    reports = report_folder(tmp_path / "reports", result("ada"))
    (tmp_path / "home" / "ada").mkdir(parents=True)
    pages = tmp_path / "home" / "ada" / "feedback"
    feedback.feedback([reports], tmp_path / "home")
    first = (pages / f"{ID}.html").read_bytes()
    assert "7.5 of 10 points" in first.decode()
    feedback.feedback([reports], tmp_path / "home")  # unchanged: replaced in place, nothing numbered
    assert (pages / f"{ID}.html").read_bytes() == first and sorted(p.name for p in pages.iterdir()) == [f"{ID}.html"]
    with open(pages / f"{ID}.html", "a") as fh:
        fh.write("<p>MY NOTES</p>\n")
    feedback.feedback([reports], tmp_path / "home")
    assert (pages / f"{ID}.html").read_bytes() == first + b"<p>MY NOTES</p>\n"  # the student's edit is kept
    assert (pages / f"{ID}.2.html").read_bytes() == first
    (pages / f"{ID}.2.html").write_bytes(first.replace(b"7.5 of 10", b"10 of 10"))  # edited inside, stamp kept
    feedback.feedback([reports], tmp_path / "home")
    assert b"10 of 10" in (pages / f"{ID}.2.html").read_bytes() and (pages / f"{ID}.3.html").read_bytes() == first
    assert not list(pages.glob(".*"))  # no temporary file left behind


def test_a_german_feedback_page_writes_decimal_commas():
    from lab.teaching.grader.notebook import GradeResult

    task = {"task": "visualize_curvature", "object": "MyBezierPatches", "points": 10, "score": 4 / 18,
            "passed": False, "report": "", "message": "", "cases": []}
    page = feedback.render(GradeResult("bea/05.ipynb", assignment=ID, lang="de", tasks=[task]))
    assert "2,22 von 10 Punkten" in page and "(MyBezierPatches): 2,22 / 10</h2>" in page, page


def test_written_marks_and_comments_on_the_page_in_the_students_language(tmp_path, homes, capsys):
    """feedback --written: each written answer's points and the marker's comment (markup shown as text), under the
    question's title in the student's language; an answer not marked yet says so."""
    aid = "04_color_maps"
    german = result("bob", assignment=aid, score=1.0)
    german.lang = "de"
    reports = report_folder(tmp_path / "reports", result("ada", assignment=aid, score=1.0), german)
    marks = tmp_path / f"written-{aid}.csv"
    marks.write_text("student,assignment,question,title,max_points,points,comment,answer\n"
                     f"ada,{aid},bfbc93a2,Question: advantages and disadvantages,3,\"2,5\",<b>good</b> but f3?,x\n"
                     f"bob,{aid},bfbc93a2,Question: advantages and disadvantages,3,,,y\n")
    assert feedback.main([str(reports), str(homes), "--written", str(marks)]) == 0
    ada = (homes / "ada" / "feedback" / f"{aid}.html").read_text()
    assert "<h2>Written answers: 2.5 of 3 points</h2>" in ada
    assert "<h3>Question: advantages and disadvantages: 2.5 / 3</h3>" in ada
    assert "&lt;b&gt;good&lt;/b&gt; but f3?" in ada and "<b>good</b>" not in ada
    bob = (homes / "bob" / "feedback" / f"{aid}.html").read_text()
    assert "<h2>Schriftliche Antworten: 0 von 3 Punkten</h2>" in bob
    assert "<h3>Frage: Vor- und Nachteile: noch nicht bewertet</h3>" in bob
    bad = tmp_path / "bad.csv"
    bad.write_text(f"student,assignment,question,title,max_points,points\nada,{aid},q,T,3,4\n")
    assert feedback.main([str(reports), str(homes), "--written", str(bad)]) == 2
    assert f"{bad}, line 2: 4 points for question q of ada; expected 0 … 3" in capsys.readouterr().err
