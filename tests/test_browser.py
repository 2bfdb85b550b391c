"""The explorers in a real JupyterLab, driven by headless Chromium (Playwright).

For each notebook with explorers: run all cells, check that every 3D view
shows the surface (below the trame toolbar: a dead kernel still shows the
toolbar icons), change a control, check that the picture changed, and
check that the kernel is still alive.  Screenshots are kept in the test's
temporary folder; their paths are in the failure messages.
"""

import os
import shutil
from pathlib import Path

import pytest

from .browser_support import CHROMIUM, CHROMIUM_ARGS, Notebook, coverage, jupyterlab

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = [p.name for p in sorted((ROOT / "solutions").glob("*.ipynb")) if "Explorer(" in p.read_text()]

pytestmark = pytest.mark.skipif(os.environ.get("LAB_SKIP_BROWSER") == "1", reason="LAB_SKIP_BROWSER=1")


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    assert Path(CHROMIUM).exists(), f"Debian's chromium is needed at {CHROMIUM} (make test installs it)"
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


def _workdir(tmp_path, names):
    root = tmp_path / "nb"
    root.mkdir()
    for name in names:
        shutil.copy(ROOT / "solutions" / name, root / name)
    return root


def _change_control(page, explorer):
    """Change the explorer's primary control (a dropdown: another option; a slider: 25 arrow-key steps)."""
    control = explorer.locator(".lab-primary-control")
    select = control.locator("select")
    if select.count():
        options = select.locator("option").all_inner_texts()
        current = select.evaluate("s => s.options[s.selectedIndex].text")
        target = next(o for o in options if o != current)
        select.select_option(label=target)
        return f"dropdown {current!r} -> {target!r}"
    handle = control.locator(".noUi-handle")
    handle.focus()
    for _ in range(25):
        page.keyboard.press("ArrowRight")
    return "slider moved 25 steps"


def _move_slider(page, explorer, steps=1):
    """Move the explorer's last enabled slider with the keyboard (as a user would with the arrow keys)."""
    handle = explorer.locator(".noUi-target:not([disabled]) .noUi-handle").last
    handle.focus()
    for _ in range(steps):
        page.keyboard.press("ArrowRight")


def _exercise_explorers(nb, tag):
    explorers = nb.explorers()
    n = explorers.count()
    assert n > 0, f"no explorer found; screenshot {nb.shot(tag + '-none')}"
    for k in range(n):
        ex = explorers.nth(k)
        before = nb.wait_for_picture(ex)
        path = nb.shots / f"{tag}-explorer{k}-before.png"
        ex.locator("iframe.pyvista").screenshot(path=str(path))
        assert coverage(before) > 0.03, f"explorer {k}: the 3D view is blank below the toolbar; see {path}"
        what = _change_control(nb.page, ex)
        after, changed = nb.wait_for_change(ex, before)
        path2 = nb.shots / f"{tag}-explorer{k}-after.png"
        ex.locator("iframe.pyvista").screenshot(path=str(path2))
        assert changed, f"explorer {k}: picture did not change after {what}; see {path} and {path2}"
        assert coverage(after) > 0.03, f"explorer {k}: blank after {what}; see {path2}"
    return n


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_explorers_live_in_jupyterlab(browser, tmp_path, name):
    root = _workdir(tmp_path, [name])
    with jupyterlab(root) as (url, token):
        page = browser.new_page(viewport={"width": 1500, "height": 1100})
        nb = Notebook(page, url, token, name, tmp_path / "shots")
        nb.run_all()
        nb.shot("after-run-all")
        n = _exercise_explorers(nb, Path(name).stem)
        out = nb.run_cell("print('kernel-alive', 6 * 7, lab.widgets.callback_threads())", "kernel-alive 42")
        assert "MainThread" in out or "Thread" in out, out
        nb.shot("end")
        page.close()
    assert n >= 1


def test_kernel_survives_with_default_comm_settings(browser, tmp_path):
    """Without the settings override, callbacks may arrive on a comm subshell thread: the main-thread hop must hold."""
    name = "05_visualize_curvature.ipynb"
    root = _workdir(tmp_path, [name])
    with jupyterlab(root, overrides=False) as (url, token):
        page = browser.new_page(viewport={"width": 1500, "height": 1100})
        nb = Notebook(page, url, token, name, tmp_path / "shots")
        nb.run_all()
        _exercise_explorers(nb, "default-settings")
        explorer = nb.explorers().first
        _move_slider(nb.page, explorer)  # depth 2 -> 3: a recomputation, rendered from a callback
        out = nb.run_cell(
            "import time; time.sleep(3); e = [x for x in lab.view.explorers.base._INSTANCES if getattr(x, 'student', 1) is None][0]\n"
            "print('kernel-alive', 6 * 7, e.depth.value, repr(e.status.value), lab.widgets.callback_threads())",
            "kernel-alive 42")
        assert "kernel-alive 42 3 ''" in out, f"depth slider did not reach the kernel or reported an error: {out}"
        print("callbacks arrived on:", out)
        page.close()
