"""lab.teaching.kernel.protocol's time limit on every platform (issue 30, item 3).

Windows has no SIGALRM and no setitimer; there the limit is a watchdog thread.  These tests take the signal
functions away on Linux (``monkeypatch.delattr``, the way Windows lacks them) and compare the portable path with
the signal path: the same status and message for an endless loop, the same reports on correct code for every task.
"""

import json
import os
import select
import signal
import threading
import time

import numpy as np
import pytest

from lab import check
from lab.teaching.kernel import protocol
from lab.teaching.kernel.protocol import TimeUp, outcome, time_limit
from lab.teaching.self_check import DEFAULT_TIMEOUT, run_task
from lab.teaching.tasks import TASKS
from lab.teaching.tasks.references import NET_NAMES
from tests.students import student_class

TIMEOUT_MESSAGE = "stopped after 0.5 s. Is there an endless loop?"


def without_signals(monkeypatch):
    """Windows, emulated: no SIGALRM, no setitimer, no ITIMER_REAL."""
    for name in ("SIGALRM", "setitimer", "ITIMER_REAL"):
        monkeypatch.delattr(signal, name)


@pytest.fixture
def windows(monkeypatch):
    without_signals(monkeypatch)
    assert not hasattr(signal, "SIGALRM")


def forever(*args):
    while True:
        pass


def test_the_emulation_takes_the_signal_path_away(windows):
    assert not protocol._has_alarm()
    assert isinstance(time_limit(1.0), protocol._WatchdogLimit)


def test_the_signal_path_is_kept_where_it_exists():
    assert protocol._has_alarm()
    assert not isinstance(time_limit(1.0), protocol._WatchdogLimit)  # SIGALRM in the main thread


def test_an_endless_loop_stops_with_the_same_outcome_on_both_paths(monkeypatch):
    with_signals = outcome("function", forever, [1.0, 2.0], 0.5)
    without_signals(monkeypatch)
    portable = outcome("function", forever, [1.0, 2.0], 0.5)
    assert with_signals == portable == {"status": "timeout", "message": TIMEOUT_MESSAGE}


def test_code_that_returns_in_time_is_unaffected(windows):
    assert outcome("function", lambda k1, k2: (k1 + k2) / 2, [1.0, 2.0], 0.5) == {
        "status": "ok", "value": {"kind": "array", "shape": [], "data": [1.5]}}
    # the stop that was not needed does not come later: a loop after the block runs past the limit untouched
    with time_limit(0.2):
        pass
    assert protocol._the_watchdog()._limits == set()  # disarmed with the block
    deadline = time.monotonic() + 0.5
    ran = 0
    while time.monotonic() < deadline:
        ran += 1
    assert ran > 0


def test_except_exception_does_not_hide_the_stop(windows):
    def swallow(k1, k2):
        try:
            forever()
        except Exception:  # noqa: BLE001, S110 - the student's code under test swallows everything on purpose
            pass

    assert outcome("function", swallow, [1.0, 2.0], 0.5) == {"status": "timeout", "message": TIMEOUT_MESSAGE}


def test_the_students_own_errors_are_reported_as_before(windows):
    def wrong(k1, k2):
        return {"k1": k1}["K"]

    out = outcome("function", wrong, [1.0, 2.0], 0.5)
    assert out["status"] == "error" and out["message"].startswith("KeyError: 'K'")
    assert 'return {"k1": k1}["K"]' in out["message"]


def test_a_stop_that_fires_as_the_block_ends_never_escapes_it(windows):
    """The race: the limit is reached just as the block ends.  Whatever the timing, TimeUp is raised inside the
    block or not at all; never after it.  Blocks of 0 to 8 ms under a limit of 1 ms (the stop lands up to a
    thread switch, 5 ms, late), and every tenth block an endless loop, which must stop."""
    escaped, finished, stopped, loops_stopped = 0, 0, 0, 0
    for k in range(200):
        try:
            try:
                with time_limit(0.001):
                    if k % 10 == 9:
                        forever()
                    deadline = time.perf_counter() + 0.001 * (k % 9)
                    while time.perf_counter() < deadline:
                        pass
                finished += 1
            except TimeUp:
                stopped += 1
                loops_stopped += k % 10 == 9
            for _ in range(20_000):  # bytecodes after the block: a late stop would be delivered here
                pass
        except TimeUp:
            escaped += 1
    assert escaped == 0
    assert finished + stopped == 200
    assert loops_stopped == 20


def test_the_limit_also_holds_off_the_main_thread():
    """No signal reaches another thread; the watchdog does, on every platform."""
    result = {}

    def run():
        result["out"] = outcome("function", forever, [1.0, 2.0], 0.5)

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    worker.join(120)
    assert not worker.is_alive()
    assert result["out"] == {"status": "timeout", "message": TIMEOUT_MESSAGE}


def test_no_limit_for_none(windows):
    assert outcome("function", lambda: 2.0, [], None) == {
        "status": "ok", "value": {"kind": "array", "shape": [], "data": [2.0]}}


# -- every task's public cases: the same reports on both paths ----------------------------------------------------


def correct_answer(task, seed):
    """A correct student object for ``task``: the task's own exact answers, computed before the check (the check
    blocks the library functions they come from), handed out one per case in the check's order;
    visualize_curvature's is a class written the way a student writes it (tests/students.py)."""
    if task.protocol == "patches":
        return student_class()
    if task.protocol == "reported":  # the numbers themselves (notebook 05's own surface)
        return task.expected(task.make_cases(np.random.default_rng(seed), False)[0])
    answers = iter([task.expected(case) for case in task.make_cases(np.random.default_rng(seed), False)])

    def answer(*args):
        value = next(answers)
        return tuple(value[k] for k in NET_NAMES) if isinstance(value, dict) else value

    return answer


def report_of(task, make, seed, timeout=DEFAULT_TIMEOUT):
    report = run_task(task, make(task, seed), seed=seed, timeout=timeout)
    return str(report), json.dumps(report.to_dict(), sort_keys=True, default=str)


@pytest.mark.parametrize("name", list(TASKS))
def test_every_task_gives_the_same_report_on_both_paths(name, monkeypatch):
    task = TASKS[name]
    with_signals = report_of(task, correct_answer, seed=5)
    without_signals(monkeypatch)
    portable = report_of(task, correct_answer, seed=5)
    assert portable == with_signals
    assert run_task(task, correct_answer(task, 5), seed=5).passed, portable[0]


@pytest.mark.parametrize("name", ["warmup", "visualize_curvature", "developable_faces"])  # the three protocols
def test_a_loop_in_a_case_gives_the_same_report_on_both_paths(name, monkeypatch):
    """The second case loops: it stops with the timeout message, the rest are not run, the first passed."""
    task = TASKS[name]

    def looping(task, seed):
        right, calls = correct_answer(task, seed), []
        if task.protocol == "patches":
            class Looping(right):
                def visualize_curvature(self, curvature_mode, color_map):
                    calls.append(1)
                    if len(calls) == 2:
                        forever()
                    super().visualize_curvature(curvature_mode, color_map)

            return Looping

        def answer(*args):
            calls.append(1)
            value = right(*args)
            if len(calls) == 2:
                forever()
            return value

        return answer

    with_signals = report_of(task, looping, seed=5, timeout=0.5)
    without_signals(monkeypatch)
    portable = report_of(task, looping, seed=5, timeout=0.5)
    assert portable == with_signals
    report = run_task(task, looping(task, 5), seed=5, timeout=0.5)
    assert [c.status for c in report.cases] == ["passed", "timeout"] + ["not run"] * (len(report.cases) - 2)
    assert report.status == "timeout" and TIMEOUT_MESSAGE in report.cases[1].got


def test_notebook_00s_check_passes_a_correct_answer(windows):
    """solutions/00_start.ipynb: ``check.warmup(mean_curvature)``."""

    def mean_curvature(k1, k2):
        """Mean curvature H from the principal curvatures k1, k2."""
        return (k1 + k2) / 2

    report = check.warmup(mean_curvature)
    assert report.passed and report.score == 1.0
    assert "AttributeError" not in str(report)
    assert str(report).startswith("✔ warmup")


@pytest.mark.skipif(not hasattr(os, "fork"), reason="no fork here")
def test_a_forked_child_gets_its_own_watchdog(windows):
    """The watchdog's thread does not survive a fork; the child starts its own on its first limit."""
    assert outcome("function", lambda: 1.0, [], 0.5)["status"] == "ok"  # the parent's watchdog is running
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: report the outcome and leave at once, whatever happens
        try:
            os.write(write, json.dumps(outcome("function", forever, [], 0.5)).encode())
        finally:
            os._exit(0)
    os.close(write)
    answered = select.select([read], [], [], 120)[0]  # a generous bound: a child without a watchdog loops forever
    if not answered:
        os.kill(pid, signal.SIGKILL)
    with os.fdopen(read) as fh:
        text = fh.read() if answered else ""
    os.waitpid(pid, 0)
    assert text and json.loads(text) == {"status": "timeout", "message": TIMEOUT_MESSAGE}
