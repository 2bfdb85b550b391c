"""The marking panel in JupyterLab in headless Chromium: a class of 40 (English and German) marked with the keyboard
only, a teaching assistant's concurrent mark that survives, the page reloaded and every mark found again, and the
gradebook reading the sheet.  (tests/test_marking.py tests the same rules without a browser.)"""

import datetime
import io
import os
import subprocess
import sys
import time

import pytest

from lab.teaching.course import collect, marking, written
from tests.browser_support import CHROMIUM, CHROMIUM_ARGS, PANEL, Notebook, jupyterlab
from tests.test_marking import ID, OTHER, PAST, QUESTION, _home

pytestmark = [pytest.mark.skipif(os.environ.get("LAB_SKIP_BROWSER") == "1", reason="LAB_SKIP_BROWSER=1"),
              pytest.mark.xdist_group("browser")]  # one JupyterLab and one Chromium, on one worker
CLASS = 40


def _answer(k):
    if k in (7, 8):  # two students with the same answer: one group
        return "The cut map $f_1$ compares surfaces."
    return f"Answer {k}: $f_{1 + k % 3}$ is {'absolute' if k % 2 else 'relative'} (student {k})."


@pytest.fixture(scope="module")
def marked(tmp_path_factory):
    """A class of 40 collected, then marked in the browser with the keyboard; what the test saw, for the tests."""
    from playwright.sync_api import sync_playwright

    root = tmp_path_factory.mktemp("mark")
    homes = root / "homes"
    for k in range(CLASS):
        _home(homes, f"s{k:02d}", "de" if k % 4 == 0 else "en", _answer(k))
    collect.collect(homes, ID, PAST + datetime.timedelta(days=3650), root / "subs", log=io.StringIO())
    done = subprocess.run([sys.executable, "-m", "lab.cli", "mark", str(root / "subs")], capture_output=True, text=True,
                          check=True, env={"LAB_LANG": "en", "PATH": "/usr/bin:/bin", "HOME": str(root),
                                           "JUPYTERHUB_USER": "prof"})
    assert f"marking-{ID}.ipynb: open it in JupyterLab" in done.stdout
    seen = {"typed": {}, "order": []}
    with jupyterlab(root) as (url, token), sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1300, "height": 1000})
        nb = Notebook(page, url, token, f"subs/marking-{ID}.ipynb", root / "shots")
        nb.run_all()
        panel = page.locator(f"{PANEL} .lab-mark")
        panel.wait_for(timeout=120_000)
        who = panel.locator(".lab-mark-who b")
        points = panel.locator(".lab-mark-points input")
        students = {marking.pseudonym(ID, f"s{k:02d}"): f"s{k:02d}" for k in range(CLASS)}
        points.click()
        t0 = time.perf_counter()
        conflicts = 0
        for step in range(60):
            name = who.inner_text()
            if "every answer of this question is marked" in panel.inner_text():
                break
            value = "2,5" if step % 5 == 0 else str(step % 4)
            if step == 6:  # a teaching assistant marks the answer on the screen from another process, just before
                sheet = marking.load(root / "subs", lang="de")
                seen["ta"] = [students[n.strip()] for n in name.split(",")]
                assert marking.save(sheet, seen["ta"], QUESTION, 1, "TA: partly") == []
            points.fill(value)
            points.press("Enter")
            deadline = time.time() + 30
            while (time.time() < deadline and who.inner_text() == name
                   and not any(m in panel.inner_text() for m in ("another marker", "every answer of this question"))):
                time.sleep(0.05)
            if "another marker" in panel.inner_text():
                conflicts += 1
                seen["conflict_text"] = panel.inner_text()
                seen["conflict_value"] = points.input_value()
                panel.locator("button", has_text="Next unmarked").press("Enter")  # Tab to it and Enter, as a marker
                deadline = time.time() + 30
                while time.time() < deadline and who.inner_text() == name:
                    time.sleep(0.05)
                points.click()
                continue
            assert who.inner_text() != name or "every answer of this question is marked" in panel.inner_text(), \
                f"the panel did not move on from {name} within 30 s of Enter"
            seen["typed"][name] = value
            seen["order"].append(name)
        seen["seconds"] = time.perf_counter() - t0
        seen["conflicts"] = conflicts
        seen["final"] = panel.inner_text()
        nb.shot("marked")
        # the page reloaded: the notebook opened again and its cell run, every mark is found
        page.reload()
        nb = Notebook(page, url, token, f"subs/marking-{ID}.ipynb", root / "shots")
        nb.run_all()
        panel = page.locator(f"{PANEL} .lab-mark")
        panel.wait_for(timeout=120_000)
        seen["reloaded"] = panel.inner_text()
        (root / "reloaded.txt").write_text(seen["reloaded"])
        seen["reloaded_points"] = panel.locator(".lab-mark-points input").input_value()
        nb.shot("reloaded")
        browser.close()
    seen["root"] = root
    return seen


def _rows(marked, question=QUESTION):
    """The sheet's rows of one question (notebook 04 asks two; the panel marks the first here)."""
    return [r for r in written.read_rows(marked["root"] / "subs" / f"written-{ID}.csv")[1] if r["question"] == question]


def test_forty_answers_are_marked_with_the_keyboard_and_saved_at_once(marked):
    rows = _rows(marked)
    assert len(rows) == CLASS and all(r["points"] for r in rows), [r["student"] for r in rows if not r["points"]]
    # 39 items (a group of two counts once), one of them the teaching assistant's: 38 typed, blind
    assert len(marked["order"]) == CLASS - 2 and all(name.startswith("S-") for name in marked["order"])
    by_pseudonym = {marking.pseudonym(ID, r["student"]): r for r in rows}
    for shown, value in marked["typed"].items():
        first = shown.split(",")[0].strip()
        assert by_pseudonym[first]["points"] == value.replace(",", "."), shown
    group = [r for r in rows if r["student"] in ("s07", "s08")]
    assert group[0]["points"] == group[1]["points"]  # one mark for the group
    print(f"\n{len(marked['order'])} answers of one question marked with the keyboard in {marked['seconds']:.1f} s "
          f"({marked['seconds'] / len(marked['order']):.2f} s per answer, the browser's own waiting included)")


def test_the_assistants_concurrent_mark_survives(marked):
    rows = {r["student"]: r for r in _rows(marked)}
    assert marked["ta"] and all((rows[s]["points"], rows[s]["comment"]) == ("1", "TA: partly") for s in marked["ta"])
    assert marked["conflicts"] == 1 and "changed by another marker since you read it, and kept" in marked["conflict_text"]
    assert marked["conflict_value"] == "1"  # the panel then shows the assistant's mark


def test_after_a_reload_every_mark_is_found(marked):
    assert "this question: 40 of 40 marked" in marked["reloaded"]
    assert marked["reloaded_points"] != ""  # the answer the marker stopped at, with its mark
    assert "Sample answer" in marked["reloaded"] and "3 points" in marked["reloaded"], marked["reloaded"]
    assert len(_rows(marked, OTHER)) == CLASS and not any(r["points"] for r in _rows(marked, OTHER))  # not marked yet
    total = written.read_written(marked["root"] / "subs" / f"written-{ID}.csv")
    marks = {r["student"]: float(r["points"]) for r in _rows(marked)}
    # each student's total is out of both questions' points (3 + 2) and holds the one marked so far
    assert len(total) == CLASS and all(top == 5.0 and got == marks[s] for (s, _a), (got, top) in total.items()), total
