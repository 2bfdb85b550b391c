"""What a submission or a sandbox leaves behind is read as hostile input (lab.teaching.untrusted, lab.teaching.grader.sandbox_output)."""

import json
import os
import re
import threading

import pytest

from lab.teaching import untrusted
from lab.teaching.grader import sandbox_output


@pytest.fixture
def out(tmp_path):
    folder = tmp_path / "out"
    folder.mkdir()
    fd = sandbox_output.open_folder(folder)
    yield folder, fd
    os.close(fd)


def test_a_fifo_never_blocks_the_reader(out):
    folder, fd = out
    os.mkfifo(folder / "cells.json")
    done = {}
    reader = threading.Thread(target=lambda: done.setdefault("error", pytest.raises(sandbox_output.InvalidResults,
                                                                                     sandbox_output.read_cells, fd)))
    reader.start()
    reader.join(timeout=120)  # generous: only a blocked read would take it
    assert not reader.is_alive()
    assert "not a regular file (a FIFO)" in str(done["error"].value)


@pytest.mark.parametrize("target", ["/dev/zero", "/etc/passwd"])
def test_a_symbolic_link_is_not_followed(out, target):
    folder, fd = out
    (folder / "cells.json").symlink_to(target)
    with pytest.raises(sandbox_output.InvalidResults, match="symbolic link"):
        sandbox_output.read_cells(fd)
    (folder / "task-0.jsonl").symlink_to(target)
    with pytest.raises(sandbox_output.InvalidResults, match="symbolic link"):
        sandbox_output.read_outcomes(fd, "task-0.jsonl", 3)


def test_a_replaced_output_folder_is_refused(tmp_path):
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "out").symlink_to(tmp_path / "elsewhere")
    with pytest.raises(sandbox_output.InvalidResults, match="output folder cannot be opened"):
        sandbox_output.open_folder(tmp_path / "out")


@pytest.mark.parametrize("line, match", [
    ('{"index": 0, "status": []}', "unknown status"),
    ('{"index": true, "status": "ok", "value": 1}', "case index True"),
    ('{"index": 7, "status": "error"}', "case index 7 is not one of 0 … 2"),
    ('{"index": 0, "status": "error", "message": {"a": 1}}', "message is not text"),
    ('{"index": 0, "status": "error", "value": 1}', "value belongs to status 'ok'"),
    ('[' * 200000 + ']' * 200000, "nested deeper than 32"),
    ('{"index": 0, "status": "ok"', "not a JSON document"),
    ('"just text"', "not an object"),
])
def test_malformed_result_lines_make_the_results_invalid(out, line, match):
    folder, fd = out
    good = json.dumps({"index": 1, "status": "ok", "value": {"kind": "array", "shape": [], "data": [1.0]}})
    (folder / "task-0.jsonl").write_text(good + "\n" + line + "\n")
    with pytest.raises(sandbox_output.InvalidResults, match=match):
        sandbox_output.read_outcomes(fd, "task-0.jsonl", 3)


def test_well_formed_results_are_read_and_a_cut_off_last_line_is_ignored(out):
    folder, fd = out
    lines = [{"index": 0, "status": "ok", "value": {"kind": "array", "shape": [2], "data": [1.0, float("nan")]}},
             {"index": 1, "status": "error", "message": "boom \x1b[2J"},
             {"index": 0, "status": "timeout", "message": "late"}]
    (folder / "task-0.jsonl").write_text("".join(json.dumps(x) + "\n" for x in lines) + '{"index": 2, "sta')
    found = sandbox_output.read_outcomes(fd, "task-0.jsonl", 3)
    assert sorted(found) == [0, 1] and found[0]["status"] == "timeout"  # the last line per index counts
    assert found[1]["message"] == "boom \\x1b[2J"


def test_an_infinite_shape_is_refused_when_decoded():
    from lab.teaching.kernel import protocol

    for shape in ([float("inf")], [True], [-1], [2.0], [10**9]):
        with pytest.raises(ValueError, match="malformed array shape"):
            protocol.decode({"kind": "array", "shape": shape, "data": []})


def test_cells_json_is_validated_and_capped(out):
    folder, fd = out
    (folder / "cells.json").write_text(json.dumps({"cell_errors": [{"error": "x", "kind": "error"}]}))
    with pytest.raises(sandbox_output.InvalidResults, match="cell error 0 is malformed"):
        sandbox_output.read_cells(fd)
    (folder / "cells.json").write_text(json.dumps({"cell_errors": [{"cell": 1, "error": "y" * (1 << 20),
                                                                   "kind": "error"}] * 2}))
    with pytest.raises(sandbox_output.InvalidResults, match="at most 1048576 are read"):
        sandbox_output.read_cells(fd)
    (folder / "cells.json").write_text(json.dumps({"cell_errors": [{"cell": 3, "error": "z" * 900, "kind": "syntax"}],
                                                   "restarts": 1}))
    errors, restarts, complete = sandbox_output.read_cells(fd)
    assert restarts == 1 and complete and errors[0]["kind"] == "syntax" and len(errors[0]["error"]) < 560


def test_clean_shows_control_characters_and_cuts_long_text():
    assert untrusted.clean("a\x1b[2Jb\x07\u202ec\r\n") == "a\\x1b[2Jb\\x07\\u202ec\\r\n"
    assert untrusted.clean("\x9b31m") == "\\x9b31m"
    text = untrusted.clean("x" * 5000, 100)
    assert text.startswith("x" * 100) and text.endswith("(4900 more characters)")


@pytest.mark.parametrize("value, cell", [("=HYPERLINK(\"a\")", "'=HYPERLINK(\"a\")"), ("+1", "'+1"), ("-2+3", "'-2+3"),
                                         ("@SUM(A1)", "'@SUM(A1)"), ("ada", "ada"), (10.0, 10.0), ("a\nb", "a b")])
def test_csv_cells_are_never_formulas(value, cell):
    assert untrusted.csv_cell(value) == cell


def test_plain_files_only(tmp_path):
    (tmp_path / "a.ipynb").write_text("{}")
    (tmp_path / "link.ipynb").symlink_to(tmp_path / "a.ipynb")
    os.link(tmp_path / "a.ipynb", tmp_path / "hard.ipynb")
    (tmp_path / "real").mkdir()
    (tmp_path / "real" / "b.ipynb").write_text("{}")
    (tmp_path / "dirlink").symlink_to(tmp_path / "real")
    os.mkfifo(tmp_path / "fifo.ipynb")
    assert untrusted.plain_file(tmp_path / "real" / "b.ipynb", tmp_path) is None
    assert untrusted.plain_file(tmp_path / "link.ipynb", tmp_path) == "a symbolic link"
    assert "hard link" in untrusted.plain_file(tmp_path / "hard.ipynb", tmp_path)
    assert untrusted.plain_file(tmp_path / "dirlink" / "b.ipynb", tmp_path) == "inside a symbolic link (dirlink)"
    assert untrusted.plain_file(tmp_path / "fifo.ipynb", tmp_path) == "a FIFO"
    with pytest.raises(untrusted.UntrustedError, match="has 12 bytes; at most 5"):
        (tmp_path / "c.ipynb").write_text("x" * 12)
        untrusted.read_file(tmp_path / "c.ipynb", 5)


def test_a_forged_value_makes_the_results_invalid(out):
    folder, fd = out
    line = {"index": 0, "status": "ok", "value": {"kind": "patches", "curvature": {"shape": [float("inf")], "data": []},
                                                 "colors": {"shape": [1], "data": [0.0]}}}
    (folder / "task-0.jsonl").write_text(json.dumps(line) + "\n")
    with pytest.raises(sandbox_output.InvalidResults, match="not what the harness writes"):
        sandbox_output.read_outcomes(fd, "task-0.jsonl", 3)


# -- names, spreadsheet cells and invisible characters (issue 28, items 3 and 7) --------------------------------------

INVISIBLE = {"\u2028": "\\u2028", "\u2029": "\\u2029", "\u200e": "\\u200e", "\u200f": "\\u200f", "\u061c": "\\u061c",
             **{chr(c): f"\\u{c:04x}" for c in range(0x202A, 0x202F)},
             **{chr(c): f"\\u{c:04x}" for c in range(0x2066, 0x206A)},
             "\u200b": "\\u200b", "\u200c": "\\u200c", "\u200d": "\\u200d", "\u2060": "\\u2060", "\ufeff": "\\ufeff"}


@pytest.mark.parametrize("char, shown", sorted(INVISIBLE.items()))
def test_clean_shows_separators_bidi_marks_zero_width_characters_and_boms(char, shown):
    assert untrusted.clean(f"a{char}b") == f"a{shown}b"
    assert untrusted.clean(f"a{char}b", keep_newlines=False) == f"a{shown}b"


def test_clean_keeps_every_legitimate_character():
    text = ("Grüße aus Köln: Öl, Äpfel, ß, ẞ; ∂κ/∂u ≤ ∞, ∇·n = 2H, 90°, a — b – c, π≈3,14, “quoted” «guillemets» "
            "曲率 😀 ½ € №\tx")
    assert untrusted.clean(text) == text.replace("\t", "\\t")
    assert untrusted.clean("line one\nline two") == "line one\nline two"
    assert untrusted.clean("line one\nline two", keep_newlines=False) == "line one\\nline two"
    assert untrusted.clean("\U000e0001tag\udc80") == "\\U000e0001tag\\udc80"  # a tag character, a lone surrogate


@pytest.mark.parametrize("value", ["'bea", "''bea", "'", "=1+1", "bea", "-2", "@x", "+", "", "a'b", "' =x"])
def test_a_cell_reads_back_as_the_text_it_was_written_from(value):
    """csv_cell quotes, csv_value unquotes exactly once: two names never share a cell ('bea is not bea)."""
    cell = untrusted.csv_cell(value)
    assert untrusted.csv_value(cell) == value
    assert not cell[:1] in ("=", "+", "-", "@")


def test_a_leading_quote_is_quoted_too():
    assert untrusted.csv_cell("'bea") == "''bea" and untrusted.csv_cell("bea") == "bea"
    assert untrusted.csv_value("''bea") == "'bea" and untrusted.csv_value("'=1") == "=1"
    assert untrusted.csv_value("bea") == "bea" and untrusted.csv_value(None) == ""


@pytest.mark.parametrize("name", ["ada", "bea.m", "o'neil", "'bea", "Jürgen", "ß-2", "a b", "user_1@uni", "x" * 100,
                                  '=HYPERLINK("http:__example.org","10")', "x...", "a..b"])
def test_a_user_name_is_an_id(name):
    assert untrusted.student_id(name) == name


@pytest.mark.parametrize("name, message", [
    ("", "an empty user name"),
    (".", "'.' is a path, not a user name"),
    ("..", "'..' is a path, not a user name"),
    (".bob", "'.bob' begins with a dot"),
    ("a/b", "'a/b' has a path separator (/)"),
    ("a\\b", "'a\\b' has a path separator (\\)"),
    ("a\nb", "'a\\nb' has a line break (U+000A)"),
    ("a\rb", "'a\\rb' has a line break (U+000D)"),
    ("a\u2028b", "'a\\u2028b' has a line break (U+2028)"),
    ("a\u2029b", "'a\\u2029b' has a line break (U+2029)"),
    ("a\x00b", "'a\\x00b' has a control character (U+0000)"),
    ("a\x1b[2Jb", "'a\\x1b[2Jb' has a control character (U+001B)"),
    ("ad\u200ba", "'ad\\u200ba' has an invisible character (U+200B)"),
    ("ada\u202e", "'ada\\u202e' has an invisible character (U+202E)"),
    ("\ufeffada", "'\\ufeffada' has an invisible character (U+FEFF)"),
    ("x" * 101, "has 101 characters; at most 100"),
    (7, "a user name must be text; got int"),
])
def test_a_name_that_is_a_path_or_hides_characters_is_refused(name, message):
    with pytest.raises(untrusted.UntrustedError, match=re.escape(message)):
        untrusted.student_id(name)


def test_a_file_is_written_inside_its_folder_only(tmp_path):
    folder = tmp_path / "reports"
    folder.mkdir()
    (tmp_path / "outside.json").write_text("theirs")
    (folder / "link.json").symlink_to(tmp_path / "outside.json")
    fd = untrusted.open_folder(folder)
    try:
        untrusted.write_at(fd, "ada.json", "ours\n")
        assert (folder / "ada.json").read_text() == "ours\n"
        untrusted.write_at(fd, "link.json", "replaced")  # the link itself is replaced, its target untouched
        assert (tmp_path / "outside.json").read_text() == "theirs" and not (folder / "link.json").is_symlink()
        for bad, message in (("../outside.json", "not a single file name"), ("..", "not a single file name"),
                             ("a/b.json", "not a single file name"), ("", "not a single file name"),
                             ("a\x00.json", "not a single file name"), ("x" * 240, "longer than")):
            with pytest.raises(untrusted.UntrustedError, match=message):
                untrusted.write_at(fd, bad, "x")
        assert (tmp_path / "outside.json").read_text() == "theirs"
        assert sorted(p.name for p in folder.iterdir()) == ["ada.json", "link.json"]  # no temporary file left
    finally:
        os.close(fd)
    (tmp_path / "swapped").symlink_to(folder)
    with pytest.raises(untrusted.UntrustedError, match="cannot be opened as a folder"):
        untrusted.open_folder(tmp_path / "swapped")


def test_a_notebook_is_validated_once_and_refused_by_its_size_before_that(monkeypatch):
    """nbformat's validator takes about 0.25 ms a cell and much more on an invalid one, and ``nbformat.reads``
    validated a second time: a 60 000-cell notebook with one malformed cell took 29 s (90 s under load)."""
    import nbformat

    calls = []
    validate = nbformat.validate
    monkeypatch.setattr(nbformat, "validate", lambda nb, *a, **k: calls.append(1) or validate(nb, *a, **k))
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(["x = 1\n", "y = 2"])])
    raw = json.dumps(nb).encode()
    calls.clear()  # building it validated its cells
    assert untrusted.read_notebook(raw).cells[0].source == "x = 1\ny = 2" and calls == [1]  # as nbformat reads it
    many = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("x = 1", id=f"c{k}")
                                           for k in range(untrusted.MAX_CELLS + 1)])
    lines = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(["\n"] * (untrusted.MAX_TEXTS + 10))])
    bad = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("x")])
    bad.cells[0]["outputs"] = [{"output_type": "bogus"}]
    calls.clear()
    with pytest.raises(ValueError, match=f"a notebook of {untrusted.MAX_CELLS + 1} cells; at most 2000 are read"):
        untrusted.read_notebook(json.dumps(many).encode())
    with pytest.raises(ValueError, match="a notebook of about 1200.* texts .*; at most 1200000 are read"):
        untrusted.read_notebook(json.dumps(lines).encode())
    assert calls == []  # neither was validated
    with pytest.raises(ValueError, match="NotebookValidationError"):
        untrusted.read_notebook(json.dumps(bad).encode())
    assert calls == [1]


@pytest.mark.parametrize("source, names", [
    ("class MyBezierPatches(lab.BezierPatches):\n    def visualize_curvature(self, m, c):\n        k = 1",
     ["MyBezierPatches", "visualize_curvature", "k"]),
    ("mine=3\nmine == 4\nmine2 = 1\n# def hidden\ndef\tf(x): pass\nx.y = 2", ["mine", "mine2", "f"]),
])
def test_definitions_are_read_line_by_line(source, names):
    assert list(untrusted.definitions(source)) == names
    assert untrusted.defines(source, names[0]) and not untrusted.defines(source, "hidden")
