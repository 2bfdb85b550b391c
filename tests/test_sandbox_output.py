"""What a graded run leaves behind costs the grader a bounded amount of work (lab.teaching.grader.sandbox_output): task files read
one line at a time, values kept decoded and only the last per case, an over-long line its case's bad output."""

import json
import os
import tracemalloc

import numpy as np
import pytest

from lab.teaching.grader import sandbox_output
from lab.teaching.kernel import protocol
from lab.teaching.task import judge_outcome
from lab.teaching.tasks import TASKS

#: A result with the most numbers a value may have, as the harness writes it.
BIG = {"shape": [protocol.MAX_VALUES], "data": [0.5] * protocol.MAX_VALUES}


@pytest.fixture
def out(tmp_path):
    folder = tmp_path / "out"
    folder.mkdir()
    fd = sandbox_output.open_folder(folder)
    yield folder, fd
    os.close(fd)


def test_fifty_mib_of_valid_results_cost_a_few_mib(out):
    """The red team's 58 MiB of valid results took the grader from 117 to 804 MiB (the whole file as text, split into
    lines, every value kept as Python lists): now one line at a time, each value decoded (8 bytes a number), only the
    last per case."""
    folder, fd = out
    n = 18
    with open(folder / "task-0.jsonl", "w") as fh:
        written = 0
        k = 0
        while written < 50 << 20:
            line = json.dumps({"index": k % n, "status": "ok",
                               "value": {"kind": "patches", "curvature": BIG, "colors": BIG}}) + "\n"
            fh.write(line)
            written, k = written + len(line), k + 1
    tracemalloc.start()
    found = sandbox_output.read_outcomes(fd, "task-0.jsonl", n)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert sorted(found) == list(range(n))
    assert isinstance(found[0]["value"]["curvature"], np.ndarray) and found[0]["value"]["curvature"].size == 20000
    kept = n * 2 * protocol.MAX_VALUES * 8  # 18 cases × two arrays of 20 000 numbers: 5.5 MiB
    assert peak < kept + (8 << 20), peak >> 20  # and one line being parsed; not the file's 50 MiB, nor its lists


def test_a_line_over_the_limit_is_its_cases_bad_output_never_parsed(out):
    folder, fd = out
    huge = '{"index": 1, "status": "ok", "value": {"kind": "array", "shape": [2000000], "data": [' + \
        "0.5, " * 1999999 + "0.5]}}"
    good = json.dumps({"index": 0, "status": "ok", "value": {"kind": "array", "shape": [], "data": [2.0]}})
    (folder / "task-0.jsonl").write_text(good + "\n" + huge + "\n")
    tracemalloc.start()
    found = sandbox_output.read_outcomes(fd, "task-0.jsonl", 3)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert found[0]["status"] == "ok" and float(found[0]["value"]) == 2.0
    assert found[1] == {"index": 1, "status": "bad output", "message":
                        f"a result with far more numbers than the task asks for (more than {protocol.MAX_VALUES} are "
                        "not read)"}
    assert peak < 4 * sandbox_output.MAX_LINE, peak  # the 10 MB line was never held
    # judged like any bad output: the case fails with that message
    task = TASKS["visualize_curvature"]
    case = task.make_cases(np.random.default_rng(0), True)[0]
    judged = judge_outcome(task, case, found[1], lambda: None)
    assert judged.status == "failed" and "far more numbers" in judged.got


def test_an_over_long_line_that_is_no_cases_result_makes_the_results_invalid(out):
    folder, fd = out
    (folder / "task-0.jsonl").write_text("x" * (sandbox_output.MAX_LINE + 10) + "\n")
    with pytest.raises(sandbox_output.InvalidResults, match="a line of more than .* bytes that is not a case's result"):
        sandbox_output.read_outcomes(fd, "task-0.jsonl", 3)
    (folder / "task-0.jsonl").write_text('{"index": 9, ' + " " * (sandbox_output.MAX_LINE + 10) + "}\n")
    with pytest.raises(sandbox_output.InvalidResults, match="not a case's result"):
        sandbox_output.read_outcomes(fd, "task-0.jsonl", 3)


def test_a_value_over_the_limit_is_refused_by_the_harness_with_a_message():
    """The student's own code returning too many numbers: a bad output that says so, in the notebook and graded."""
    out = protocol.outcome("function", lambda: np.zeros(protocol.MAX_VALUES + 1), [], 10)
    assert out == {"status": "bad output", "message": f"{protocol.MAX_VALUES + 1} values; at most "
                                                      f"{protocol.MAX_VALUES} are read"}


def test_the_largest_answer_of_a_graded_case_is_far_below_the_limit():
    """The limit leaves room: every graded case's exact answer has at most a few hundred numbers."""
    largest = 0
    for task in TASKS.values():
        for case in task.make_cases(np.random.default_rng(1), True):
            answer = task.expected(case)
            parts = answer.values() if isinstance(answer, dict) else answer if isinstance(answer, (list, tuple)) \
                else [answer]
            largest = max(largest, sum(np.size(a) for a in parts if isinstance(a, (np.ndarray, float, int))))
    assert 100 < largest <= protocol.MAX_VALUES // 20, largest
