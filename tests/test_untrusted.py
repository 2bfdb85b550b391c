"""What a submission or a sandbox leaves behind is read as hostile input (lab.teaching.untrusted, lab.teaching.results)."""

import json
import os
import threading

import pytest

from lab.teaching import results, untrusted


@pytest.fixture
def out(tmp_path):
    folder = tmp_path / "out"
    folder.mkdir()
    fd = results.open_folder(folder)
    yield folder, fd
    os.close(fd)


def test_a_fifo_never_blocks_the_reader(out):
    folder, fd = out
    os.mkfifo(folder / "cells.json")
    done = {}
    reader = threading.Thread(target=lambda: done.setdefault("error", pytest.raises(results.InvalidResults,
                                                                                     results.read_cells, fd)))
    reader.start()
    reader.join(timeout=120)  # generous: only a blocked read would take it
    assert not reader.is_alive()
    assert "not a regular file (a FIFO)" in str(done["error"].value)


@pytest.mark.parametrize("target", ["/dev/zero", "/etc/passwd"])
def test_a_symbolic_link_is_not_followed(out, target):
    folder, fd = out
    (folder / "cells.json").symlink_to(target)
    with pytest.raises(results.InvalidResults, match="symbolic link"):
        results.read_cells(fd)
    (folder / "task-0.jsonl").symlink_to(target)
    with pytest.raises(results.InvalidResults, match="symbolic link"):
        results.read_outcomes(fd, "task-0.jsonl", 3)


def test_a_replaced_output_folder_is_refused(tmp_path):
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "out").symlink_to(tmp_path / "elsewhere")
    with pytest.raises(results.InvalidResults, match="output folder cannot be opened"):
        results.open_folder(tmp_path / "out")


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
    with pytest.raises(results.InvalidResults, match=match):
        results.read_outcomes(fd, "task-0.jsonl", 3)


def test_well_formed_results_are_read_and_a_cut_off_last_line_is_ignored(out):
    folder, fd = out
    lines = [{"index": 0, "status": "ok", "value": {"kind": "array", "shape": [2], "data": [1.0, float("nan")]}},
             {"index": 1, "status": "error", "message": "boom \x1b[2J"},
             {"index": 0, "status": "timeout", "message": "late"}]
    (folder / "task-0.jsonl").write_text("".join(json.dumps(x) + "\n" for x in lines) + '{"index": 2, "sta')
    found = results.read_outcomes(fd, "task-0.jsonl", 3)
    assert sorted(found) == [0, 1] and found[0]["status"] == "timeout"  # the last line per index counts
    assert found[1]["message"] == "boom \\x1b[2J"


def test_an_infinite_shape_is_refused_when_decoded():
    from lab.teaching import protocol

    for shape in ([float("inf")], [True], [-1], [2.0], [10**9]):
        with pytest.raises(ValueError, match="malformed array shape"):
            protocol.decode({"kind": "array", "shape": shape, "data": []})


def test_cells_json_is_validated_and_capped(out):
    folder, fd = out
    (folder / "cells.json").write_text(json.dumps({"cell_errors": [{"error": "x", "kind": "error"}]}))
    with pytest.raises(results.InvalidResults, match="cell error 0 is malformed"):
        results.read_cells(fd)
    (folder / "cells.json").write_text(json.dumps({"cell_errors": [{"cell": 1, "error": "y" * (1 << 20),
                                                                   "kind": "error"}] * 2}))
    with pytest.raises(results.InvalidResults, match="at most 1048576 are read"):
        results.read_cells(fd)
    (folder / "cells.json").write_text(json.dumps({"cell_errors": [{"cell": 3, "error": "z" * 900, "kind": "syntax"}],
                                                   "restarts": 1}))
    errors, restarts, complete = results.read_cells(fd)
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
    with pytest.raises(results.InvalidResults, match="not what the harness writes"):
        results.read_outcomes(fd, "task-0.jsonl", 3)
