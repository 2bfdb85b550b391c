"""The gradebook on made-up report folders (issue 28, items 3 and 6): names are keys, quoted only in a cell, and
one student's data (a notebook claiming another assignment, an assignment in two folders, a damaged row) is that
student's note and zero, never an error for the class; the instructor's own mistakes stay errors."""

import csv
import io

import pytest

from lab.teaching import untrusted
from lab.teaching.course import files, gradebook, written
from tests.report_support import ID, report_folder, result, rows_of, text_file

OTHER = "09_dill_gallery"


def _table(path):
    """``{student: row}`` of a written gradebook, names read back through csv_value."""
    return {r["student"]: r for r in untrusted.csv_rows(io.StringIO(path.read_text()))}


def test_a_quoted_name_is_not_its_unquoted_twin(tmp_path):
    """A folder ``'bea`` and a folder ``bea`` are two students: the quote that keeps a formula out of a spreadsheet
    is not part of the name, so it is never stripped from one."""
    reports = report_folder(tmp_path / "r", result("'bea", score=0.3), result("bea", score=1.0),
                            result("=x", score=0.5))
    ids, _maxima, rows = gradebook.gradebook([reports])
    assert ids == [ID] and {r["student"]: r[ID] for r in rows} == {"'bea": 3.0, "bea": 10.0, "=x": 5.0}
    out = tmp_path / "g.csv"
    assert gradebook.main([str(reports), "-o", str(out)]) == 0
    cells = [line[0] for line in csv.reader(io.StringIO(out.read_text()))][2:]
    assert sorted(cells) == ["''bea", "'=x", "bea"]  # quoted in the cell, never a formula
    assert {s: float(r[ID]) for s, r in _table(out).items() if s != gradebook.MAX_ROW} == {"'bea": 3, "bea": 10,
                                                                                           "=x": 5}


def test_written_marks_of_a_quoted_name_count_for_that_name(tmp_path):
    """collect writes ``'bea`` as ``''bea`` into written-<id>.csv: the marks are 'bea's, not bea's."""
    marks = tmp_path / "marked.csv"
    marks.write_text("student,assignment,question,max_points,points\n"
                     f"''bea,{ID},q1,3,2\nbea,{ID},q1,3,1\n'=x,{ID},q1,3,3\n")
    assert written.read_written(marks) == {("'bea", ID): (2.0, 3.0), ("bea", ID): (1.0, 3.0), ("=x", ID): (3.0, 3.0)}
    reports = report_folder(tmp_path / "r", result("'bea", score=0.0), result("bea", score=0.0))
    _ids, _maxima, rows = gradebook.gradebook([reports], written=[marks])
    assert {r["student"]: r[ID] for r in rows} == {"'bea": 2.0, "bea": 1.0, "=x": 3.0}


def test_a_notebook_claiming_another_assignment_is_that_students_zero(tmp_path, capsys):
    """bob's flat SUBS/bob.ipynb says it is 09_dill_gallery: beside his real 09 in the 09 folder that is one
    assignment in two folders. Before, the gradebook refused for everyone; now bob's 09 is 0 with a note, and
    everybody else (bob's 05 too) is graded."""
    reports05 = report_folder(tmp_path / "reports" / "05", result("ada"), result("bob", score=1.0),
                              result("bob", OTHER, score=1.0, notebook="bob.ipynb"))
    reports09 = report_folder(tmp_path / "reports" / "09", result("ada", OTHER, score=0.5),
                              result("bob", OTHER, score=0.2))
    out = tmp_path / "g.csv"
    assert gradebook.main([str(reports05), str(reports09), "-o", str(out)]) == 0
    table = _table(out)
    assert float(table["ada"][ID]) == 7.5 and float(table["ada"][OTHER]) == 5 and table["ada"][f"{OTHER} note"] == ""
    assert float(table["bob"][ID]) == 10 and table["bob"][f"{ID} status"] == "submitted"
    note = (f"{OTHER} is in two report folders, {reports05} and {reports09}: 0 points here; pass only the folder "
            "that counts")
    assert float(table["bob"][OTHER]) == 0 and table["bob"][f"{OTHER} status"] == "refused"
    assert table["bob"][f"{OTHER} note"] == note and float(table["bob"]["total"]) == 10
    assert f"curvature-lab gradebook: bob: {note}\n" in capsys.readouterr().err
    canvas = tmp_path / "canvas.csv"  # no note column for an LMS: the note is said on stderr
    assert gradebook.main([str(reports05), str(reports09), "--format", "canvas", "-o", str(canvas)]) == 0
    assert ["bob", "", "", "bob", "", "10.0", "0.0"] in list(csv.reader(io.StringIO(canvas.read_text())))
    assert f"bob: {note}" in capsys.readouterr().err


def test_a_damaged_row_is_that_students_zero(tmp_path, capsys):
    reports = report_folder(tmp_path / "r", result("ada"), result("bob"), result("cy"),
                            summary={"bob": {"score": "lots"}, "cy": {"late_seconds": "soon"}})
    out = tmp_path / "g.csv"
    assert gradebook.main([str(reports), "--late-penalty", "10", "-o", str(out)]) == 0
    table = _table(out)
    assert float(table["ada"][ID]) == 7.5 and table["ada"][f"{ID} status"] == "submitted"
    assert float(table["bob"][ID]) == 0 and table["bob"][f"{ID} status"] == "refused"
    assert table["bob"][f"{ID} note"] == (f"score 'lots', max_score '10.0' or late_seconds '' in "
                                          f"{reports / 'summary.csv'} is not a number: 0 points here")
    assert float(table["cy"][ID]) == 0 and "late_seconds 'soon'" in table["cy"][f"{ID} note"]
    err = capsys.readouterr().err
    assert "curvature-lab gradebook: bob: score 'lots'" in err and "curvature-lab gradebook: cy: score" in err


def test_the_instructors_own_mistakes_stay_errors(tmp_path, capsys):
    reports = report_folder(tmp_path / "r", result("ada"))
    marks = tmp_path / "marked.csv"
    marks.write_text(f"student,assignment,question,max_points,points\nada,{OTHER},q1,3,2\n")
    assert gradebook.main([str(reports), "--written", str(marks), "-o", str(tmp_path / "g.csv")]) == 2
    assert f"written points of assignment {OTHER}, whose reports are not among the report folders" in \
        capsys.readouterr().err
    assert gradebook.main([str(reports), "--late-penalty", "-3", "-o", str(tmp_path / "g.csv")]) == 2
    assert "--late-penalty must be a number from 0 to 100; got -3.0" in capsys.readouterr().err
    assert gradebook.main([str(tmp_path), "-o", str(tmp_path / "g.csv")]) == 2
    assert "no summary.csv" in capsys.readouterr().err
    with pytest.raises(gradebook.GradebookError, match="name no assignment"):
        gradebook.gradebook([report_folder(tmp_path / "empty")])


def test_gradebook_csv_keeps_a_student_called_max(tmp_path):
    reports = tmp_path / "reports"
    reports.mkdir()
    with open(reports / "summary.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=files.SUMMARY_COLUMNS)
        w.writeheader()
        w.writerow({"student": "max", "notebook": f"max/{ID}.ipynb", "score": 4, "max_score": 10, "assignment": ID})
    out = tmp_path / "grades.csv"
    assert gradebook.main([str(reports), "-o", str(out)]) == 0
    table = {r["student"]: r for r in rows_of(out)}
    assert float(table["max"][ID]) == 4 and float(table[gradebook.MAX_ROW][ID]) == 10


def test_gradebook_refuses_written_points_without_their_reports(tmp_path, capsys):
    reports05 = report_folder(tmp_path / "reports" / "05", result("ada"))
    reports04 = report_folder(tmp_path / "reports" / "04", result("ada", assignment="04_color_maps", score=0.0))
    marks = text_file(tmp_path / "marked.csv", "student,assignment,question,max_points,points\n"
                                            "ada,04_color_maps,bfbc93a2,3,2.5\n")
    out = tmp_path / "grades.csv"
    assert gradebook.main([str(reports05), "--written", str(marks), "-o", str(out)]) == 2
    assert capsys.readouterr().err == (
        f"curvature-lab gradebook: error: {marks}: written points of assignment 04_color_maps, whose reports are not "
        f"among the report folders ({ID}): pass the folder graded for 04_color_maps too (its autograded points and "
        "lateness are part of the grade)\n")
    assert not out.exists()
    assert gradebook.main([str(reports05), str(reports04), "--written", str(marks), "-o", str(out)]) == 0
    table = {r["student"]: r for r in rows_of(out)}
    assert table["ada"]["04_color_maps"] == "2.5" and table["(max)"]["04_color_maps"] == "13.0"
    assert table["ada"]["total"] == "10.0"  # 7.5 + 2.5
    assert gradebook.main([str(reports05), str(reports04), "--written", str(marks), "--written", str(marks),
                           "-o", str(out)]) == 2
    assert f"ada's written points of 04_color_maps are in {marks} and in {marks}" in capsys.readouterr().err


def test_per_question_columns_for_an_item_analysis(tmp_path, capsys):
    """--per-question: a column per graded task (its points as graded) and per written question (the marked points,
    a spreadsheet's decimal comma too), with their maxima in the (max) row; refused for an LMS layout."""
    reports = report_folder(tmp_path / "r", result("ada", score=0.75), result("bob", score=1.0))
    marks = text_file(tmp_path / "written.csv", "student,assignment,question,title,max_points,points\n"
                                                f"ada,{ID},q1,Why the corners?,3,\"2,5\"\nbob,{ID},q1,Why the corners?,3,\n"
                                                f"ada,{ID},q2,=Which map,2,1\nbob,{ID},q2,=Which map,2,2\n")
    out = tmp_path / "g.csv"
    assert gradebook.main([str(reports), "--written", str(marks), "--per-question", "-o", str(out)]) == 0
    lines = list(csv.reader(io.StringIO(out.read_text())))
    head = lines[0]
    items = [f"{ID}: visualize_curvature", f"{ID}: Why the corners? (written)", f"{ID}: =Which map (written)"]
    assert head[5:8] == items  # after the assignment's four columns
    table = {r[0]: dict(zip(head, r)) for r in lines[1:]}
    assert [float(table[gradebook.MAX_ROW][c]) for c in items] == [10, 3, 2]
    assert [table["ada"][c] for c in items] == ["7.5", "2.5", "1.0"]
    assert [table["bob"][c] for c in items] == ["10.0", "", "2.0"]  # bob's first question not marked yet: empty
    assert float(table["ada"]["total"]) == 7.5 + 3.5 and float(table["ada"]["max"]) == 15
    with pytest.raises(SystemExit):
        gradebook.main([str(reports), "--per-question", "--format", "canvas", "-o", str(out)])
    assert "--per-question needs --format csv" in capsys.readouterr().err
