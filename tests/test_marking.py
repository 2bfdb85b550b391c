"""Marking written answers (``lab.teaching.course.marking`` and the panel of ``lab.teaching.course.mark``): a small
class collected with ``curvature-lab collect``, marked through the panel's own handlers, two markers at once, the
sheet that ``gradebook --written`` reads, collecting again without losing a mark.  (tests/test_mark_browser.py marks
the same kind of class with the keyboard in JupyterLab.)"""

import base64
import datetime
import io

import nbformat
import pytest

from lab.teaching.course import collect, gradebook, mark, marking, written
from lab.teaching.grader.assignments import DEFAULT_FOLDER

ID = "04_color_maps"
QUESTION = "bfbc93a2"
#: notebook 04's second written question (colour for every student), not marked here
OTHER = "c0107a07"
PAST = datetime.datetime(2025, 12, 15, 23, 59, tzinfo=datetime.timezone.utc)
#: A 1×1 PNG, a student's figure.
PNG = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg==")
ANSWERS = {
    "ada": ("en", "f1 compares surfaces; $f_2$ shows the shape."),
    "bea": ("en", "f1   compares surfaces; $f_2$ shows the SHAPE."),  # the same as ada's up to space and case
    "cy": ("de", "**f1** ist absolut, $f_2 = \\frac{1}{2}$ relativ."),
    "dan": ("en", "<img src=x onerror=alert(1)> <script>alert(2)</script> plain"),
    "eli": ("en", ""),  # no answer
    "fay": ("en", "A picture says it."),
}


def _home(homes, student, lang, answer):
    nb = nbformat.read(DEFAULT_FOLDER / lang / f"{ID}.ipynb", as_version=4)
    cell = next(c for c in nb.cells if c.get("id") == QUESTION)
    if answer:
        cell.source = answer
    if student == "fay":  # a figure in the code cell before the question
        code = [c for c in nb.cells[: nb.cells.index(cell)] if c.cell_type == "code"][-1]
        code.outputs = [nbformat.v4.new_output("display_data", data={"image/png": base64.b64encode(PNG).decode()})]
    path = homes / student / f"{ID}.ipynb"
    path.parent.mkdir(parents=True)
    nbformat.write(nb, path)


@pytest.fixture(scope="module")
def subs(tmp_path_factory):
    root = tmp_path_factory.mktemp("marking")
    homes = root / "homes"
    for student, (lang, answer) in ANSWERS.items():
        _home(homes, student, lang, answer)
    collect.collect(homes, ID, PAST + datetime.timedelta(days=3650), root / "subs", log=io.StringIO())
    return root


@pytest.fixture()
def folder(subs, tmp_path):
    """A fresh copy of the collected folder for each test (marks written by one test never reach another)."""
    import shutil

    shutil.copytree(subs / "subs", tmp_path / "subs")
    return tmp_path / "subs"


def test_the_sheet_has_every_answer_as_written_with_sample_answer_and_points(folder):
    sheet = marking.load(folder, lang="en")
    assert sheet.assignment == ID and [q.cell for q in sheet.questions] == [QUESTION, OTHER]
    assert sheet.max_points == {QUESTION: 3.0, OTHER: 2.0}
    answers = {a.student: a.text for a in sheet.answers[QUESTION]}
    assert answers == {s: text for s, (_lang, text) in ANSWERS.items()}  # line breaks and markup as written
    assert sheet.samples[QUESTION].startswith("**$f_1$ (cut)** is absolute")
    assert "BEGIN SOLUTION" not in sheet.samples[QUESTION]
    assert marking.figures(sheet.notebooks["fay"], QUESTION) == [PNG]
    assert marking.figures(sheet.notebooks["ada"], QUESTION) == []
    german = marking.load(folder, lang="de")
    assert german.samples[QUESTION] != sheet.samples[QUESTION] and "absolut" in german.samples[QUESTION]


def test_equal_answers_form_one_group_that_can_be_split(folder):
    sheet = marking.load(folder, lang="en")
    groups = marking.groups(sheet.answers[QUESTION])
    assert [[a.student for a in g] for g in groups] == [["ada", "bea"], ["cy"], ["dan"], ["eli"], ["fay"]]
    split = marking.groups(sheet.answers[QUESTION], split={marking._key(ANSWERS["ada"][1])})
    assert [[a.student for a in g] for g in split][:2] == [["ada"], ["bea"]]


def test_points_are_checked_with_the_reason(folder):
    assert marking.check_points("2,5", 3) == 2.5 and marking.check_points(" 3 ", 3) == 3.0
    assert marking.check_points("", 3) is None
    with pytest.raises(ValueError, match=r"^3.5 points: expected 0 to 3 in steps of 0.5$"):
        marking.check_points("3.5", 3)
    with pytest.raises(ValueError, match=r"^1.2 points: expected 0 to 3 in steps of 0.5$"):
        marking.check_points("1.2", 3)
    with pytest.raises(ValueError, match=r"^'zwei' is not a number; expected points from 0 to 3$"):
        marking.check_points("zwei", 3)


def test_pseudonyms_are_stable_and_unrelated_to_the_names():
    a = marking.pseudonym(ID, "ada")
    assert a == marking.pseudonym(ID, "ada") and a.startswith("S-") and len(a) == 8 and "ADA" not in a
    assert a != marking.pseudonym("05_visualize_curvature", "ada")  # not linkable across assignments
    assert len({marking.pseudonym(ID, f"s{k:03d}") for k in range(200)}) == 200


def test_marking_through_the_panel_saves_at_once_and_resumes(folder):
    panel = mark.mark(folder, marker="ta1", lang="en")
    shown = panel.w_who.value
    assert "S-" in shown and not any(f">{s}" in shown or f" {s}," in shown for s in ANSWERS)  # blind: pseudonyms
    panel.w_names.value = True
    assert any(s in panel.w_who.value for s in ANSWERS) and "S-" not in panel.w_who.value
    panel.w_names.value = False
    seen = []
    for points in ("3", "2", "1,5", "0", "2"):  # typed and Enter: saved, then the next unmarked answer
        seen.append(tuple(a.student for a in panel.current()))
        panel.w_points.value = points
    assert sorted(seen) == sorted([("ada", "bea"), ("cy",), ("dan",), ("eli",), ("fay",)])
    marks = {(r["student"]): r["points"] for r in written.read_rows(folder / f"written-{ID}.csv")[1] if r["question"] == QUESTION}
    given = dict(zip(seen, ("3", "2", "1.5", "0", "2")))
    assert marks == {s: p for group, p in given.items() for s in group}  # the group's mark went to both
    assert "every answer of this question is marked" in panel.w_message.value
    assert panel.sheet.progress() == (6, 12)  # notebook 04's second question not marked yet
    # a comment with markup is kept as text; an answer's HTML is shown escaped
    panel._go(next(k for k, g in enumerate(panel._ordered()) if g[0].student == "dan"))
    assert "&lt;img src=x onerror=alert(1)&gt;" in panel.w_answer.value and "<img" not in panel.w_answer.value
    assert "&lt;script&gt;" in panel.w_answer.value
    panel.w_comment.value = "see <b>2.1</b>\nand $K$"
    row = next(r for r in written.read_rows(folder / f"written-{ID}.csv")[1] if r["student"] == "dan" and r["question"] == QUESTION)
    assert row["comment"] == "see <b>2.1</b> and $K$"  # one line in the sheet, the markup as text
    # out of range: refused with the reason, nothing saved
    panel.w_points.value = "4"
    assert "4 points: expected 0 to 3 in steps of 0.5" in panel.w_message.value
    assert next(r for r in written.read_rows(folder / f"written-{ID}.csv")[1] if r["student"] == "dan" and r["question"] == QUESTION)["points"] == "0"
    # reopening resumes at the same answer, for the same marker
    where = panel.current()[0].student
    again = mark.mark(folder, marker="ta1", lang="en")
    assert again.current()[0].student == where and again.sheet.progress() == (6, 12)
    # the gradebook reads the sheet the panel wrote
    assert written.read_written(folder / f"written-{ID}.csv")[("bea", ID)] == (3.0, 5.0)  # of 3 + 2 points


def test_a_second_markers_change_is_never_overwritten(folder):
    one = mark.mark(folder, marker="ana", lang="en")
    two = mark.mark(folder, marker="ben", lang="de")
    target = one.current()
    students = [a.student for a in target]
    k = next(i for i, g in enumerate(two._ordered()) if g[0].student == students[0])
    two._go(k)
    two.w_points.value = "1"  # ben marks first
    one.w_points.value = "3"  # ana's panel read the sheet before: her mark is refused, ben's kept and shown
    assert "changed by another marker since you read it, and kept" in one.w_message.value
    rows = {r["student"]: r["points"] for r in written.read_rows(folder / f"written-{ID}.csv")[1] if r["question"] == QUESTION}
    assert all(rows[s] == "1" for s in students)
    assert one.w_points.value == "1"  # she now sees ben's mark, and can change it knowingly
    one.w_points.value = "2"
    rows = {r["student"]: r["points"] for r in written.read_rows(folder / f"written-{ID}.csv")[1] if r["question"] == QUESTION}
    assert all(rows[s] == "2" for s in students)


def test_collecting_again_keeps_the_marks_of_unchanged_answers(subs, tmp_path):
    import shutil

    folder, homes = tmp_path / "subs", tmp_path / "homes"
    shutil.copytree(subs / "subs", folder)
    shutil.copytree(subs / "homes", homes)
    sheet = marking.load(folder, lang="en")
    for student in ("ada", "bea", "cy"):
        assert marking.save(sheet, [student], QUESTION, 2, f"fine, {student}") == []
    # cy changes the answer, then the instructor collects again
    nb = nbformat.read(homes / "cy" / f"{ID}.ipynb", as_version=4)
    next(c for c in nb.cells if c.get("id") == QUESTION).source = "a new answer"
    nbformat.write(nb, homes / "cy" / f"{ID}.ipynb")
    log = io.StringIO()
    collect.collect(homes, ID, PAST + datetime.timedelta(days=3650), folder, log=log)
    rows = {r["student"]: r for r in written.read_rows(folder / f"written-{ID}.csv")[1] if r["question"] == QUESTION}
    assert (rows["ada"]["points"], rows["ada"]["comment"]) == ("2", "fine, ada")
    assert (rows["bea"]["points"], rows["cy"]["points"], rows["cy"]["answer"]) == ("2", "", "a new answer")
    kept = sorted(folder.glob(f"written-{ID}.marked-*.csv"))
    assert len(kept) == 1 and "1 marked written answers changed since they were marked" in log.getvalue()
    assert "cy (" in log.getvalue() and {r["student"]: r["points"] for r in written.read_rows(kept[0])[1] if r["question"] == QUESTION}["cy"] == "2"


def test_the_command_writes_the_marking_notebook_once(folder, capsys):
    assert mark.main([str(folder)]) == 0
    path = folder / f"marking-{ID}.ipynb"
    nb = nbformat.read(path, as_version=4)
    assert f"lab.mark({str(folder.resolve())!r}, {ID!r})" in nb.cells[1].source
    assert f"{path}: open it in JupyterLab and run its cell (0 of 12 answers marked)" in capsys.readouterr().out
    path.write_text(path.read_text().replace("Run the cell", "Run my cell"))  # the instructor's edit is kept
    assert mark.main([str(folder)]) == 0 and "Run my cell" in path.read_text()
    assert "is there already (kept)" in capsys.readouterr().out
    assert mark.main([str(folder / "nothing")]) == 2
    assert "is not a folder of collected submissions" in capsys.readouterr().err
    (folder / "written-other.csv").write_text((folder / f"written-{ID}.csv").read_text())
    assert mark.main([str(folder)]) == 2
    assert "expected one written-<id>.csv of curvature-lab collect; found 2" in capsys.readouterr().err


def test_gradebook_reads_the_marks_of_the_panel(folder):
    sheet = marking.load(folder, lang="en")
    marking.save(sheet, ["ada"], QUESTION, 2.5, "")
    assert written.read_written(folder / f"written-{ID}.csv")[("ada", ID)] == (2.5, 5.0)  # of 3 + 2 points
    assert gradebook.read_written is written.read_written


def test_a_markers_share_of_the_class(folder, capsys):
    """Three assistants split the class by students: each panel shows only its share, and the command writes one
    notebook per share (``--students``), named after the roster file."""
    share = folder.parent / "ta1.txt"
    share.write_text("# the first assistant\nada\ncy\n")
    panel = mark.mark(folder, marker="ta1", lang="en", students=share)
    assert {a.student for answers in panel.sheet.answers.values() for a in answers} == {"ada", "cy"}
    assert panel.sheet.progress() == (0, 2 * len(panel.sheet.questions))
    assert mark.main([str(folder), "--students", str(share)]) == 0
    nb = nbformat.read(folder / f"marking-{ID}-ta1.ipynb", as_version=4)
    assert f"students={str(share.resolve())!r}" in nb.cells[1].source
    capsys.readouterr()
    nobody = folder.parent / "nobody.txt"
    nobody.write_text("zed\n")
    assert mark.main([str(folder), "--students", str(nobody)]) == 2
    assert "none of the 1 students given has an answer here" in capsys.readouterr().err
