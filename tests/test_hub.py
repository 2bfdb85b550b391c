"""The classroom: JupyterHub serves the lab to two students; explorers go through the hub's proxy only.

A real JupyterHub (pip ``jupyterhub``; ``configurable-http-proxy`` from npm, installed by ``make test``)
on 127.0.0.1 with the dummy authenticator and the simple local process spawner.  Headless Chromium logs
two students in through the hub's URL, opens notebook 05 in each, runs it, and checks that each
student's explorer view is live (served under ``/user/NAME/proxy/PORT/`` by jupyter-server-proxy),
changes with its control, and that the two students' views and kernels are independent.  Every request
the browser makes goes to the hub's port.
"""

import os
import shutil
import subprocess
import time
from pathlib import Path
from urllib.parse import urlsplit

import pytest

from tests.browser_support import CHROMIUM, CHROMIUM_ARGS, Notebook, coverage
from tests.hub_support import PROXY, ROOT, jupyterhub, login

NOTEBOOK = "05_visualize_curvature.ipynb"
STUDENTS = ("ada", "bob")

pytestmark = [
    pytest.mark.xdist_group("hub"),  # one hub for all its tests, on one worker
    pytest.mark.skipif(os.environ.get("LAB_SKIP_BROWSER") == "1", reason="LAB_SKIP_BROWSER=1"),
    pytest.mark.skipif(not PROXY.exists(), reason="configurable-http-proxy is not installed (make test installs it)"),
]


def settled(nb, explorer, timeout=60):
    """The explorer's picture once two frames a second apart agree (a view still loading is not compared)."""
    last = nb.view_image(explorer)
    deadline = time.time() + timeout
    while time.time() < deadline:
        time.sleep(1)
        img = nb.view_image(explorer)
        if img.shape == last.shape and abs(img - last).mean() < 0.05:
            return img
        last = img
    return last


@pytest.fixture(scope="module")
def hub(tmp_path_factory):
    root = tmp_path_factory.mktemp("hub")
    with jupyterhub(root, STUDENTS, [ROOT / "solutions" / "en" / NOTEBOOK]) as (url, _process):
        yield url, root


def test_two_students_through_the_hub(hub, tmp_path):
    from playwright.sync_api import sync_playwright

    url, _root = hub
    origin = urlsplit(url).netloc
    foreign = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        views = {}
        for user in STUDENTS:
            context = browser.new_context(viewport={"width": 1500, "height": 1100})
            context.on("request", lambda r: foreign.append(r.url) if urlsplit(r.url).netloc not in (origin, "")
                       and not r.url.startswith(("data:", "blob:", "about:")) else None)
            page = login(context, url, user)
            nb = Notebook(page, f"{url}/user/{user}", "", NOTEBOOK, tmp_path / user)
            nb.run_all(timeout=400)
            explorer = nb.explorers().first
            frame = explorer.locator("iframe.pyvista")
            src = frame.get_attribute("src")
            assert src and f"/user/{user}/proxy/" in src, src
            assert urlsplit(src).netloc in ("", origin), src  # the view is served through the hub
            before = nb.wait_for_picture(explorer)
            assert coverage(before) > 0.03, f"{user}: blank view; see {nb.shot('blank')}"
            views[user] = (nb, explorer, before, src)
        # a control change in ada's explorer changes ada's view, not bob's
        nb_a, ex_a, before_a, src_a = views["ada"]
        nb_b, ex_b, _, src_b = views["bob"]
        assert src_a != src_b
        before_b = settled(nb_b, ex_b)
        select = ex_a.locator(".lab-primary-control select")
        options = select.locator("option").all_inner_texts()
        current = select.evaluate("s => s.options[s.selectedIndex].text")
        select.select_option(label=next(o for o in options if o != current))
        _after_a, changed = nb_a.wait_for_change(ex_a, before_a)
        assert changed, f"ada's view did not change; see {nb_a.shot('ada-unchanged')}"
        after_b = settled(nb_b, ex_b)
        assert after_b.shape == before_b.shape and abs(after_b - before_b).mean() < 1.0, "bob's view changed too"
        # separate kernels: a variable set in ada's kernel does not exist in bob's
        nb_a.run_cell("secret = 'ada-only'; print('set', secret)", "set ada-only")
        out = nb_b.run_cell("print('bob sees', globals().get('secret'))", "bob sees")
        assert "bob sees None" in out
        pid_a = nb_a.run_cell("import os; print('pid', os.getpid(), os.environ.get('JUPYTERHUB_USER'))", "pid")
        pid_b = nb_b.run_cell("import os; print('pid', os.getpid(), os.environ.get('JUPYTERHUB_USER'))", "pid")
        assert pid_a.split()[1] != pid_b.split()[1] and pid_a.split()[2] == "ada" and pid_b.split()[2] == "bob"
        browser.close()
    assert foreign == [], f"the browser addressed other origins than the hub's: {foreign[:5]}"


def _git(cwd, *args):
    subprocess.run(["git", "-c", "user.email=instructor@example.org", "-c", "user.name=instructor", *args], cwd=cwd,
                   check=True, capture_output=True)


@pytest.mark.skipif(shutil.which("git") is None, reason="git is missing")
def test_exercises_handed_out_with_nbgitpuller_never_overwrite_edits(hub, tmp_path):
    """The nbgitpuller link of the instructors' guide (docs/instructors/handout.md): the first click clones, a later one pulls the instructor's
    new commits, and a notebook the student edited keeps the student's version."""
    from playwright.sync_api import sync_playwright

    url, root = hub
    course = tmp_path / "course"
    (course / "exercises").mkdir(parents=True)
    exercise = ROOT / "exercises" / "en" / "00_start.ipynb"
    shutil.copy(exercise, course / "exercises" / "00_start.ipynb")
    _git(course, "init", "-q", "-b", "main")
    _git(course, "add", ".")
    _git(course, "commit", "-q", "-m", "exercises")
    user = "cyd"
    (root / "home" / user).mkdir(parents=True, exist_ok=True)
    link = (f"{url}/hub/user-redirect/git-pull?repo=file://{course}&branch=main"
            f"&urlpath=lab/tree/course/exercises/00_start.ipynb")
    mine = root / "home" / user / "course" / "exercises" / "00_start.ipynb"
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = login(browser.new_context(), url, user)
        page.goto(link)
        page.wait_for_url("**/lab/tree/course/exercises/00_start.ipynb**", timeout=240_000)
        assert mine.exists()
        # the student edits the notebook; the instructor fixes a typo in it and adds a notebook
        edited = mine.read_text().replace('"cells": [', '"cells": [{"cell_type": "markdown", "id": "mine00", '
                                          '"metadata": {}, "source": ["my own notes"]}, ', 1)
        mine.write_text(edited)
        text = (course / "exercises" / "00_start.ipynb").read_text()
        (course / "exercises" / "00_start.ipynb").write_text(text.replace("How the lab works", "How this lab works", 1))
        shutil.copy(exercise, course / "exercises" / "01_new.ipynb")
        _git(course, "add", ".")
        _git(course, "commit", "-q", "-m", "a typo and a new notebook")
        page.goto(link)
        page.wait_for_url("**/lab/tree/course/exercises/00_start.ipynb**", timeout=240_000)
        browser.close()
    assert (root / "home" / user / "course" / "exercises" / "01_new.ipynb").exists()  # the new notebook arrived
    after = mine.read_text()
    assert "my own notes" in after  # the student's edit is kept
    import json

    json.loads(after)  # and the notebook is still valid JSON


def _save_as(src, dst, when):
    """What a student's save does: the notebook's new content, at the time ``when``."""
    dst.write_bytes(Path(src).read_bytes())
    os.utime(dst, (when.timestamp(), when.timestamp()))


@pytest.mark.skipif(shutil.which("git") is None, reason="git is missing")
def test_a_course_from_handout_to_gradebook(hub, tmp_path, monkeypatch):
    """The hand-out reaches two students through nbgitpuller (one German), with no solution in either home; one
    hands in a correct 05, the other a wrong one after the deadline; collect, grade the mixed folder, feedback (each
    student's JupyterLab shows it), gradebook with totals and the late penalty."""
    import csv
    import datetime

    import nbformat
    from playwright.sync_api import sync_playwright

    from lab.teaching.course import collect, feedback, grade, gradebook, release

    url, root = hub
    handout = release.release(tmp_path / "curvature-lab-student", git=True)
    students = {"uli": "de", "vic": "en"}
    homes = root / "home"
    nb_path = {u: homes / u / "curvature-lab-student" / "exercises" / lang / NOTEBOOK for u, lang in students.items()}
    # in the past: a hand-in time is never after the status-change time of the file (when the test wrote it)
    deadline = datetime.datetime(2025, 12, 15, 23, 59, tzinfo=datetime.timezone.utc)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        pages = {}
        for user, lang in students.items():
            (homes / user).mkdir(parents=True, exist_ok=True)
            page = login(browser.new_context(viewport={"width": 1300, "height": 900}), url, user)
            link = (f"{url}/hub/user-redirect/git-pull?repo=file://{handout}&branch=main"
                    f"&urlpath=lab/tree/curvature-lab-student/exercises/{lang}/{NOTEBOOK}")
            page.goto(link)
            page.wait_for_url(f"**/lab/tree/curvature-lab-student/exercises/{lang}/{NOTEBOOK}**", timeout=240_000)
            pages[user] = page
            assert nb_path[user].exists()
            assert release.solution_lines_in(homes / user) == [], f"a solution line in {user}'s home"
        # uli hands in the German solution on time; vic a wrong one (degree factors left out) two days late
        _save_as(ROOT / "solutions" / "de" / NOTEBOOK, nb_path["uli"], deadline - datetime.timedelta(hours=1))
        subs, reports = tmp_path / "subs", tmp_path / "reports"
        # collected at the deadline (the collector's clock set back): its first sight of uli's bytes is on time
        monkeypatch.setattr(collect, "_clock", lambda: deadline - datetime.timedelta(minutes=1))
        collect.collect(homes, "05_visualize_curvature", deadline.isoformat(), subs, roster=list(students))
        wrong = nbformat.read(ROOT / "solutions" / "en" / NOTEBOOK, as_version=4)
        cell = next(c for c in wrong.cells if "class MyBezierPatches" in c.source)
        cell.source = (cell.source.replace("bu = m * (", "bu = (").replace("bv = n * (", "bv = (")
                       .replace("buu = m * (m - 1) * (", "buu = (").replace("buv = m * n * (", "buv = (")
                       .replace("bvv = n * (n - 1) * (", "bvv = ("))
        nbformat.write(wrong, nb_path["vic"])
        late = deadline + datetime.timedelta(days=1, hours=2)
        os.utime(nb_path["vic"], (late.timestamp(), late.timestamp()))
        monkeypatch.setattr(collect, "_clock", lambda: late)  # and again when vic has handed in
        rows = {r["student"]: r for r in collect.collect(homes, "05_visualize_curvature", deadline.isoformat(), subs,
                                                         roster=list(students))}
        assert rows["uli"]["late"] is False and rows["vic"]["late"] is True
        results = {r.student: r for r in grade.grade_folder(subs, reports, jobs=2, timeout=120)
                   if r.student in students}
        assert results["uli"].score == 10 and results["uli"].lang == "de"
        assert results["vic"].score < 10 and results["vic"].lang == "en"
        feedback.feedback([reports], homes)
        for user, text in (("uli", "10 von 10 Punkten"), ("vic", "degree factor")):
            page = pages[user]
            page.goto(f"{url}/user/{user}/lab/tree/feedback/05_visualize_curvature.html")
            frame = page.frame_locator(".jp-HTMLViewer iframe").first
            frame.locator("body").wait_for(timeout=120_000)
            shown = frame.locator("body").inner_text(timeout=120_000)
            assert text in shown, f"{user}'s JupyterLab shows: {shown[:300]}"
            page.screenshot(path=str(tmp_path / f"feedback-{user}.png"))
        browser.close()
    out = tmp_path / "grades.csv"
    assert gradebook.main([str(reports), "--late-penalty", "20", "--format", "csv", "-o", str(out)]) == 0
    with open(out, newline="") as fh:
        table = {r["student"]: r for r in csv.DictReader(fh)}
    assert float(table["uli"]["total"]) == 10
    assert float(table["vic"]["total"]) == round(results["vic"].score * 0.6, 2)  # 2 started days late: 40 % off
    assert table["vic"]["05_visualize_curvature late days"] == "2"
