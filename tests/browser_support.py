"""Drive a real JupyterLab in headless Chromium (Playwright), as the developers' guide describes (docs/developers/runtime.md)."""

import contextlib
import io
import os
import secrets
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
PANEL = ".jp-NotebookPanel:not(.lm-mod-hidden)"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_for_port(proc, port, what, log_name, *, timeout, poll=0.3):
    """Wait until ``proc`` (``what``, logging to ``log_name``) accepts connections on 127.0.0.1:``port``."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        with contextlib.suppress(OSError):
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            return
        if proc.poll() is not None:
            raise RuntimeError(f"{what} exited; see {log_name}")
        time.sleep(poll)
    raise RuntimeError(f"{what} did not start within {timeout:g} s; see {log_name}")


@contextlib.contextmanager
def serving(args, port, what, log_path, *, env, cwd, timeout, stop_timeout, poll=0.3, own_group=False):
    """Run the server ``args`` (logging to ``log_path``) until it accepts connections on ``port``; yield the process.

    On exit it is terminated (killed after ``stop_timeout`` s); with ``own_group`` it runs in its own process
    group, which is killed too (the children it started, e.g. a hub's proxy and single-user servers).
    """
    with open(log_path, "w") as log:
        proc = subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, env=env, cwd=cwd,
                                start_new_session=own_group)
        try:
            wait_for_port(proc, port, what, log.name, timeout=timeout, poll=poll)
            yield proc
        finally:
            proc.terminate()
            try:
                proc.wait(timeout=stop_timeout)
            except subprocess.TimeoutExpired:
                proc.kill()
            if own_group:
                with contextlib.suppress(ProcessLookupError):
                    os.killpg(proc.pid, 9)


@contextlib.contextmanager
def jupyterlab(root, *, overrides=True, log=None):
    """Start ``jupyter lab`` on 127.0.0.1 with a token; ``overrides=False`` runs without the project's settings override."""
    port, token = free_port(), secrets.token_hex(12)
    # Test-only user settings: render every cell (no windowing), so explorers below the fold are in the page.
    user = Path(root) / ".user-settings" / "@jupyterlab" / "notebook-extension"
    user.mkdir(parents=True, exist_ok=True)
    (user / "tracker.jupyterlab-settings").write_text('{"windowingMode": "none", "recordTiming": true}')
    args = [sys.executable, "-m", "jupyter", "lab", "--no-browser", "--ip=127.0.0.1", f"--port={port}",
            f"--ServerApp.token={token}", f"--ServerApp.root_dir={root}", "--allow-root",
            f"--LabApp.user_settings_dir={Path(root) / '.user-settings'}", "--LabApp.expose_app_in_browser=True"]
    if not overrides:
        empty = Path(root) / ".no-settings-overrides"
        empty.mkdir(exist_ok=True)
        args.append(f"--LabApp.app_settings_dir={empty}")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "PYTEST_XDIST_WORKER")}
    with serving(args, port, "jupyter lab", log or Path(root) / "jupyterlab.log", env=env, cwd=root, timeout=90,
                 stop_timeout=20):
        yield f"http://127.0.0.1:{port}", token


def image(png_bytes):
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png_bytes)).convert("RGB")).astype(int)


def coverage(img, skip_top=56):
    """Fraction of non-white pixels below the trame toolbar (a dead kernel still shows the toolbar icons)."""
    body = img[skip_top:]
    return float(np.mean(np.any(np.abs(body - 255) > 20, axis=-1)))


class Notebook:
    """One notebook open in JupyterLab."""

    def __init__(self, page, url, token, name, shots):
        self.page, self.shots, self.name = page, Path(shots), name
        self.shots.mkdir(parents=True, exist_ok=True)
        page.goto(f"{url}/lab/tree/{name}?reset&token={token}")
        page.wait_for_selector(f'{PANEL} .jp-Notebook-ExecutionIndicator[data-status="idle"]', timeout=180_000)

    def shot(self, name):
        path = self.shots / f"{name}.png"
        self.page.screenshot(path=str(path), full_page=False)
        return path

    def code_cells(self):
        return self.page.locator(f"{PANEL} .jp-CodeCell")

    def run_all(self, timeout=300):
        """Run every cell (Run > Run All Cells) and wait until all code cells have run and the kernel is idle.

        The command acts on the current notebook, so the panel is activated and its kernel session awaited
        first; if nothing has started after a while (a slow start under load), the command is sent again.
        """
        for attempt in range(3):
            self.page.evaluate(
                """async (name) => {
                    const app = window.jupyterapp;
                    let panel = null;
                    for (const w of app.shell.widgets('main')) {
                        if (w.context && w.context.path === name) panel = w;
                    }
                    await panel.context.ready;
                    await panel.sessionContext.ready;
                    app.shell.activateById(panel.id);
                    await app.commands.execute('notebook:run-all-cells');
                }""",
                self.name,
            )
            deadline = time.time() + 30
            while time.time() < deadline:
                st = self.state()
                if st["pending"] < st["code"] or st["status"] == "busy":
                    return self.wait_idle(timeout)
                time.sleep(0.5)
        raise TimeoutError(f"Run All Cells did not start the cells; screenshot {self.shot('run-all')}")

    def state(self):
        """Code cells not yet run and the kernel status, read from JupyterLab's notebook model."""
        return self.page.evaluate(
            """() => {
                const nb = window.jupyterapp.shell.currentWidget;
                const cells = nb.content.model.cells;
                let pending = 0, code = 0;
                for (let i = 0; i < cells.length; i++) {
                    const c = cells.get(i);
                    if (c.type === 'code') { code++; if (c.executionCount === null) pending++; }
                }
                const kernel = nb.sessionContext.session && nb.sessionContext.session.kernel;
                return {pending: pending, code: code, status: kernel ? kernel.status : 'none'};
            }"""
        )

    def wait_idle(self, timeout=300):
        deadline = time.time() + timeout
        while time.time() < deadline:
            st = self.state()
            if st["status"] == "dead":
                raise RuntimeError(f"the kernel is {st['status']}; screenshot {self.shot('kernel-' + st['status'])}")
            if st["pending"] == 0 and st["status"] == "idle":
                return st
            time.sleep(0.5)
        raise TimeoutError(f"cells still running after {timeout} s ({self.state()}); screenshot {self.shot('timeout')}")

    def explorers(self):
        return self.page.locator(f"{PANEL} .lab-explorer")

    def view_image(self, explorer):
        frame = explorer.locator("iframe.pyvista")
        frame.scroll_into_view_if_needed()
        return image(frame.screenshot())

    def wait_for_picture(self, explorer, timeout=60, min_coverage=0.03):
        """Wait until the explorer's 3D view shows something below its toolbar; return the picture."""
        deadline = time.time() + timeout
        img = None
        while time.time() < deadline:
            img = self.view_image(explorer)
            if coverage(img) > min_coverage:
                return img
            time.sleep(1)
        return img

    def wait_for_change(self, explorer, before, timeout=60, threshold=1.0, min_coverage=0.03):
        """Wait until the view differs from ``before`` and has settled (the same picture twice, not blank).

        Frames in between (an image half pushed, a plain surface before the colours arrive) are skipped.
        """
        deadline = time.time() + timeout
        img, last, changed = before, None, False
        while time.time() < deadline:
            time.sleep(1)
            img = self.view_image(explorer)
            changed = changed or (img.shape == before.shape and np.mean(np.abs(img - before)) > threshold)
            settled = last is not None and img.shape == last.shape and np.mean(np.abs(img - last)) < 0.05
            if changed and settled and coverage(img) > min_coverage:
                return img, True
            last = img
        return img, changed

    def run_cell(self, source, expect, timeout=120):
        """Append a cell with ``source``, run it and wait for ``expect`` in its output; return the output text."""
        page = self.page
        page.evaluate(
            """(src) => {
                const nb = window.jupyterapp.shell.currentWidget;
                nb.content.activeCellIndex = nb.content.widgets.length - 1;
                return window.jupyterapp.commands.execute('notebook:insert-cell-below').then(() => {
                    nb.content.activeCell.model.sharedModel.setSource(src);
                    return window.jupyterapp.commands.execute('notebook:run-cell');
                });
            }""",
            source,
        )
        deadline = time.time() + timeout
        while time.time() < deadline:
            out = page.locator(f"{PANEL} .jp-OutputArea-output").all_inner_texts()
            hits = [o for o in out if expect in o]
            if hits:
                return hits[-1]
            st = self.state()
            if st["status"] == "dead":
                raise RuntimeError(f"the kernel is {st['status']}; screenshot {self.shot('kernel-' + st['status'])}")
            time.sleep(0.5)
        raise TimeoutError(f"no output containing {expect!r}; screenshot {self.shot('no-output')}")


# ----------------------------------------------------------------------------- helpers for timing and inspection

#: Injected into every frame (``context.add_init_script``): records when a picture was drawn.  In a view that renders
#: in the browser (vtk.js, WebGL) a frame is an animation frame in which something was drawn; in a view that shows
#: images streamed from the kernel it is the arrival of an image.  Times are absolute (ms since the epoch).
FRAME_COUNTER_JS = """
(() => {
  if (window.__labFrames) return;
  const frames = [];
  window.__labFrames = frames;
  const stamp = () => performance.timeOrigin + performance.now();
  let pending = false;
  const mark = () => {
    if (pending) return;
    pending = true;
    requestAnimationFrame(() => { pending = false; frames.push(stamp()); });
  };
  const protos = [window.WebGLRenderingContext, window.WebGL2RenderingContext].filter(Boolean).map(c => c.prototype);
  for (const proto of protos) {
    for (const name of ['drawArrays', 'drawElements', 'drawArraysInstanced', 'drawElementsInstanced',
                        'drawRangeElements']) {
      const original = proto[name];
      if (!original) continue;
      proto[name] = function (...args) { mark(); return original.apply(this, args); };
    }
  }
  const create = URL.createObjectURL;
  URL.createObjectURL = function (object) {
    const url = create.call(URL, object);
    if (object && object.type && object.type.startsWith('image/')) frames.push(stamp());
    return url;
  };
})();
"""


def write_notebook(path, cells):
    """Write a notebook with these code cells (and a Python 3 kernelspec, so JupyterLab does not ask)."""
    import nbformat

    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3 (ipykernel)", "language": "python"}
    nb.cells = [nbformat.v4.new_code_cell(source) for source in cells]
    nbformat.write(nb, str(path))
    return path


def now_ms(page_or_frame):
    """The browser's clock (ms since the epoch, sub-millisecond)."""
    return page_or_frame.evaluate("() => performance.timeOrigin + performance.now()")


def view_frame(explorer):
    """The Playwright frame inside an explorer's live view (the trame page; cross-origin is fine)."""
    handle = explorer.locator("iframe.pyvista").element_handle(timeout=120_000)
    return handle.content_frame()


def choose(explorer, value, at=None):
    """Choose ``value`` in the explorer's primary dropdown from page script; returns the browser time of the change.

    With ``at`` (a browser time, ms since the epoch) the page makes the change then and this returns None at once;
    :func:`chosen_at` reads the time of the change afterwards (several pages can change at the same moment).
    """
    return explorer.locator(".lab-primary-control select").evaluate(
        """(sel, [value, at]) => {
            const i = Array.from(sel.options).findIndex(o => o.value === value);
            if (i < 0) throw new Error(`no option ${value}`);
            const change = () => {
                sel.selectedIndex = i;
                const t0 = performance.timeOrigin + performance.now();
                sel.dispatchEvent(new Event('change', {bubbles: true}));
                window.__labChosenAt = t0;
                return t0;
            };
            if (at === null) return change();
            window.__labChosenAt = null;
            setTimeout(change, Math.max(0, at - (performance.timeOrigin + performance.now())));
            return null;
        }""", [value, at])


def chosen_at(explorer, timeout=60.0):
    """The browser time of the change that :func:`choose` scheduled with ``at`` (waits until it happened)."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        t0 = explorer.page.evaluate("() => window.__labChosenAt")
        if t0 is not None:
            return t0
        time.sleep(0.05)
    raise TimeoutError("the scheduled change did not happen")


def frames_after(frame, t0):
    """Times (ms) of the pictures drawn in ``frame`` after ``t0``."""
    return frame.evaluate("(t0) => (window.__labFrames || []).filter(t => t > t0)", t0)


def settle_time(frame, t0, *, quiet=1.5, timeout=60.0):
    """Wait until no new picture has been drawn for ``quiet`` seconds; return (last picture - t0) in ms, or None."""
    deadline = time.time() + timeout
    last, seen_at = None, time.time()
    while time.time() < deadline:
        times = frames_after(frame, t0)
        latest = max(times) if times else None
        if latest != last:
            last, seen_at = latest, time.time()
        elif last is not None and time.time() - seen_at >= quiet:
            return last - t0
        time.sleep(0.1)
    return None if last is None else last - t0


def wait_quiet(frame, quiet=1.0, timeout=60.0):
    """Wait until the view has drawn nothing for ``quiet`` seconds."""
    settle_time(frame, now_ms(frame) - 10 * 60 * 1000, quiet=quiet, timeout=timeout)


def click_when_still(locator, timeout=30.0):
    """Click ``locator`` once it has stopped moving (JupyterLab scrolls the notebook after a cell runs; a click
    during that scroll lands where the element was)."""
    locator.scroll_into_view_if_needed()
    deadline = time.time() + timeout
    box = None
    while time.time() < deadline:
        time.sleep(0.25)
        new = locator.bounding_box()
        if new is not None and new == box:
            break
        box = new
    locator.click()


def kernel_value(nb, expression, timeout=180):
    """Evaluate ``expression`` in the notebook's kernel (through a new cell) and return the printed text."""
    marker = f"value-{secrets.token_hex(4)}"
    out = nb.run_cell(f"print({marker!r}, repr(({expression})))", marker, timeout=timeout)
    return out.split(marker, 1)[1].strip()


def process_cpu_seconds(pid):
    """User + system CPU time of a process (all its threads), from /proc."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    ticks = os.sysconf("SC_CLK_TCK")
    return (int(fields[11]) + int(fields[12])) / ticks


def process_rss_mb(pid):
    """Resident memory of a process in MB."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def rerun_cell(nb, index, timeout=300):
    """Run the notebook's code cell number ``index`` again (as Shift+Enter on it would) and wait until idle."""
    nb.page.evaluate(
        """(index) => {
            const nb = window.jupyterapp.shell.currentWidget;
            let k = -1;
            nb.content.widgets.forEach((cell, i) => { if (cell.model.type === 'code' && ++k === index) nb.content.activeCellIndex = i; });
            return window.jupyterapp.commands.execute('notebook:run-cell');
        }""",
        index,
    )
    time.sleep(0.5)
    return nb.wait_idle(timeout)


def restart_kernel(nb, timeout=300):
    """Restart the notebook's kernel (no dialog) and wait until it is idle again."""
    nb.page.evaluate("async () => { await window.jupyterapp.shell.currentWidget.sessionContext.restartKernel(); }")
    time.sleep(1.0)
    deadline = time.time() + timeout
    while time.time() < deadline:
        if nb.state()["status"] == "idle":
            return
        time.sleep(0.5)
    raise TimeoutError(f"the kernel did not come back within {timeout} s")


#: Geometry of an explorer in the page: its view and output area, clipped texts, labels outside their boxes.
LAYOUT_JS = """
(explorer) => {
  const rect = (el) => { const r = el.getBoundingClientRect(); return {x: r.x, y: r.y, w: r.width, h: r.height}; };
  const output = explorer.closest('.jp-OutputArea-output') || explorer.parentElement;
  const view = explorer.querySelector('iframe.pyvista, .lab-static-view');
  const clipped = [];
  for (const el of explorer.querySelectorAll('.lab-controls *, .lab-legend-view *')) {
    const text = Array.from(el.childNodes).filter(n => n.nodeType === 3).map(n => n.textContent).join('').trim();
    const input = el.tagName === 'INPUT' && el.type === 'text';
    if (!text && !input) continue;
    const style = getComputedStyle(el);
    if (style.display === 'none' || style.visibility === 'hidden' || el.clientWidth === 0) continue;
    if (el.scrollWidth > el.clientWidth + 1 && style.overflowX !== 'visible')
      clipped.push(`${el.tagName.toLowerCase()}.${el.className} "${(text || el.value).slice(0, 40)}" needs ${el.scrollWidth} px, has ${el.clientWidth}`);
  }
  // a dropdown cuts off an option the select is too narrow for (its arrow takes the right padding)
  const ctx = document.createElement('canvas').getContext('2d');
  for (const sel of explorer.querySelectorAll('.lab-controls select')) {
    const style = getComputedStyle(sel);
    if (style.display === 'none' || sel.clientWidth === 0) continue;
    ctx.font = style.font;
    const room = sel.clientWidth - parseFloat(style.paddingLeft) - parseFloat(style.paddingRight);
    for (const option of sel.options) {
      const need = ctx.measureText(option.text).width;
      if (need > room + 1) clipped.push(`select option "${option.text.slice(0, 40)}" needs ${Math.ceil(need)} px, has ${Math.floor(room)}`);
    }
  }
  const box = rect(explorer), out = rect(output);
  const outside = [];
  for (const el of explorer.querySelectorAll('.lab-colorbar-label, .lab-legend-item, .lab-controls .widget-inline-hbox, .lab-controls button')) {
    const r = rect(el);
    if (r.w === 0) continue;
    if (r.x < Math.max(box.x, out.x) - 1 || r.x + r.w > Math.min(box.x + box.w, out.x + out.w) + 1)
      outside.push(`${el.className} "${el.textContent.trim().slice(0, 30)}" at ${Math.round(r.x)}..${Math.round(r.x + r.w)}, box ${Math.round(box.x)}..${Math.round(box.x + box.w)}`);
  }
  // texts meant to span the controls' grid (.lab-full-row) that sit in one column instead
  const grid = explorer.querySelector('.lab-controls');
  const narrow = grid ? Array.from(grid.querySelectorAll(':scope > .lab-full-row'))
    .filter(el => el.textContent.trim() && el.getBoundingClientRect().width < 0.9 * grid.getBoundingClientRect().width)
    .map(el => `"${el.textContent.trim().slice(0, 30)}" ${Math.round(el.getBoundingClientRect().width)} px of ${Math.round(grid.getBoundingClientRect().width)}`) : [];
  return {view: view ? rect(view) : null, output: out, explorer: box, clipped, outside, narrow,
          labels: explorer.querySelectorAll('.lab-colorbar-label, .lab-legend-item').length};
}
"""


def layout_of(explorer):
    return explorer.evaluate(LAYOUT_JS)
