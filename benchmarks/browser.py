"""Benchmark: the explorers end to end in a real JupyterLab in headless Chromium, per rendering mode.

Measured from the control change in the browser to the settled picture in
the view (the last picture drawn after the change, once nothing more has been
drawn for 1.5 s), on the practical's surface, median of ``--repeat`` runs:

* colour change: the colour map dropdown, h∘f2 linear ↔ signed log, at depth 2;
* depth → 5: the depth slider dragged from 2 to 5 and released; "first" drops
  the explorer's cached mesh of depth 5 before each run, "cached" keeps it;
* 40 geodesics: the geodesic explorer's start u0 dragged to a new place (40
  paths of length 4.5 and 9 isodistance curves recomputed);
* after a restart: the kernel restarted, Run All, until both views show a
  picture again (printed under the table, with the first Run All);
* camera drag: a 2 s mouse drag over the view at the explorer's default
  depth 2 (784 patches), and again at depth 5 (50 176 patches); pictures
  per second while dragging, and the lag from releasing the mouse to the
  last picture.

A "picture" is counted in the page: in a view that renders in the browser
(vtk.js) an animation frame in which WebGL drew something, in a view that
shows streamed images the arrival of an image.  The rendering modes:

* ``client``: PyVista's client backend, vtk.js renders in the browser (the default);
* ``server``: trame's remote view, the kernel renders offscreen and streams images;
* ``trame``: trame's hybrid view, remote by default (PyVista's ``trame`` backend, the lab's old default).

The server-side table (``benchmarks/widgets.py``: computation + scene update +
offscreen render, without the browser) is printed beside it.  Uses Debian's
chromium at /usr/bin/chromium through Playwright (never ``playwright install``).

From a student's seat (``--seat``, issue 20): the course's own notebooks 05–08
(solutions/en, the tasks done) each opened in a fresh kernel: Run All until
every explorer of the notebook shows its picture, then every explorer's primary
control changed (the next option of its menu, or the geodesic explorer's start
dragged), from the change to the settled picture, median of ``--repeat``.
Targets on a quiet 2-core machine: Run All of 05 ≤ 10 s, every update ≤ 1 s.

Usage: python benchmarks/browser.py [--repeat 10] [--backends client,server,trame] [--no-server-side]
       python benchmarks/browser.py --seat [--repeat 5] [--notebooks 05,06,07,08]
"""

import argparse
import math
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.browser_support import (
    CHROMIUM,
    CHROMIUM_ARGS,
    FRAME_COUNTER_JS,
    Notebook,
    choose,
    frames_after,
    jupyterlab,
    kernel_value,
    now_ms,
    restart_kernel,
    settle_time,
    view_frame,
    wait_quiet,
    write_notebook,
)

TARGETS = {"colour change": ("≤", 250.0), "depth → 5 (first)": ("≤", 800.0), "depth → 5 (cached)": ("≤", 250.0),
           "40 geodesics": ("≤", 1000.0), "camera drag": ("≥", 15.0)}
UNITS = {"camera drag": "frames/s", "camera drag, depth 5": "frames/s"}


def _drag_slider(page, explorer, selector, fraction):
    """Drag a slider's handle to ``fraction`` of its track and release; returns the browser time of the release."""
    track = explorer.locator(f"{selector} .noUi-target").first
    handle = track.locator(".noUi-handle").first
    handle.scroll_into_view_if_needed()
    hb, tb = handle.bounding_box(), track.bounding_box()
    page.mouse.move(hb["x"] + hb["width"] / 2, hb["y"] + hb["height"] / 2)
    page.mouse.down()
    x = tb["x"] + fraction * tb["width"]
    page.mouse.move(x, hb["y"] + hb["height"] / 2, steps=5)
    t0 = now_ms(page)
    page.mouse.up()
    return t0


def _camera_drag(page, explorer, frame, seconds=2.0):
    """Drag across the view for ``seconds``; returns (pictures per second while dragging, lag after release in ms)."""
    iframe = explorer.locator("iframe.pyvista")
    iframe.scroll_into_view_if_needed()
    box = iframe.bounding_box()
    viewport = page.viewport_size
    top, bottom = max(box["y"], 0), min(box["y"] + box["height"], viewport["height"])
    cx, cy = box["x"] + box["width"] * 0.5, (top + bottom) / 2
    wait_quiet(frame)
    page.mouse.move(cx, cy)
    t_down = now_ms(page)
    page.mouse.down()
    start = time.perf_counter()
    k = 0
    while time.perf_counter() - start < seconds:
        k += 1
        page.mouse.move(cx + 120 * math.sin(k / 12), cy + 40 * math.cos(k / 17))
        time.sleep(1 / 120)
    t_up = now_ms(page)
    page.mouse.up()
    lag = settle_time(frame, t_up, quiet=1.5, timeout=30)
    times = [t for t in frame.evaluate("() => window.__labFrames") if t_down < t <= t_up]
    fps = len(times) / ((t_up - t_down) / 1000)
    return fps, (lag if lag is not None else 0.0)


def measure(browser, backend, repeat, workdir):
    """One JupyterLab session, one notebook with a curvature and a geodesic explorer in ``backend``."""
    name = f"bench_{backend}.ipynb"
    write_notebook(workdir / name, [
        "import lab\nfrom lab import surfaces",
        f"e = lab.CurvatureExplorer(surfaces.practical(), depth=2, backend={backend!r})\ne",
        (f"g = lab.GeodesicExplorer(surfaces.practical(), start=(4.9, 2.1), n_angles=40, step=0.5, n_curves=9, "
         f"backend={backend!r})\ng"),
    ])
    rows = {}
    with jupyterlab(workdir) as (url, token):
        context = browser.new_context(viewport={"width": 1400, "height": 900})
        context.add_init_script(FRAME_COUNTER_JS)
        page = context.new_page()
        nb = Notebook(page, url, token, name, workdir / "shots")
        start = time.time()
        nb.run_all()
        explorers = nb.explorers()
        curv, geo = explorers.nth(0), explorers.nth(1)
        for ex in (curv, geo):
            nb.wait_for_picture(ex, timeout=120)
        first_view = time.time() - start
        fc, fg = view_frame(curv), view_frame(geo)
        curv.scroll_into_view_if_needed()

        def timed(label, action, frame, check=None):
            values = []
            for k in range(repeat):
                wait_quiet(frame)
                t0 = action(k)
                lat = settle_time(frame, t0, quiet=1.5, timeout=60)
                values.append(float("nan") if lat is None else lat)
            rows[label] = values

        drags = [_camera_drag(page, curv, fc) for _ in range(max(3, repeat // 3))]
        rows["camera drag"] = [d[0] for d in drags]
        rows["drag lag"] = [d[1] for d in drags]
        maps = ["signed log", "h∘f2 linear (min/max)"]
        timed("colour change", lambda k: choose(curv, maps[k % 2]), fc)
        kernel_value(nb, "e.depth.value")

        def depth_first(k):
            kernel_value(nb, "e._meshes.pop(5, None) is not None, e.depth.value")
            if kernel_value(nb, "e.depth.value") != "2":
                _drag_slider(page, curv, ".lab-depth", 2 / 6)
                wait_quiet(fc)
            return _drag_slider(page, curv, ".lab-depth", 5 / 6)

        def depth_cached(k):
            if kernel_value(nb, "e.depth.value") != "2":
                _drag_slider(page, curv, ".lab-depth", 2 / 6)
                wait_quiet(fc)
            return _drag_slider(page, curv, ".lab-depth", 5 / 6)

        timed("depth → 5 (first)", depth_first, fc)
        timed("depth → 5 (cached)", depth_cached, fc)
        geo.scroll_into_view_if_needed()
        spots = [0.62, 0.72]
        timed("40 geodesics", lambda k: _drag_slider(page, geo, ".lab-primary-control", spots[k % 2]), fg)
        paths = kernel_value(nb, "len(g.fan), g.status.value")
        curv.scroll_into_view_if_needed()
        if kernel_value(nb, "e.depth.value") != "5":
            _drag_slider(page, curv, ".lab-depth", 5 / 6)
        wait_quiet(fc, 2)
        drags = [_camera_drag(page, curv, fc) for _ in range(max(3, repeat // 3))]
        rows["camera drag, depth 5"] = [d[0] for d in drags]
        rows["drag lag, depth 5"] = [d[1] for d in drags]
        counts = kernel_value(nb, "dict(e.counts), dict(g.counts)")
        restart_kernel(nb)
        start = time.time()
        nb.run_all()
        for k in range(nb.explorers().count()):
            nb.wait_for_picture(nb.explorers().nth(k), timeout=120)
        back = time.time() - start
        context.close()
    return rows, {"first view (s)": first_view, "geodesic fan": paths, "actions run": counts,
                  "after a restart (s)": back}


SEAT_NOTEBOOKS = ("05", "06", "07", "08")
SEAT_TARGETS = {"run all": 10.0, "update": 1.0}  # s, on a quiet 2-core machine


def _next_option(explorer):
    """The value of the option after the chosen one in the explorer's primary menu (wrapping round)."""
    return explorer.locator(".lab-primary-control select").evaluate(
        "sel => sel.options[(sel.selectedIndex + 1) % sel.options.length].value")


def measure_seat(browser, workdir, numbers, repeat):
    """The course's notebooks from a student's seat: Run All to the last picture, then each explorer's updates."""
    rows = []
    with jupyterlab(workdir) as (url, token):
        for number in numbers:
            source = next((ROOT / "solutions" / "en").glob(f"{number}_*.ipynb"))
            shutil.copy(source, workdir / source.name)
            context = browser.new_context(viewport={"width": 1400, "height": 900})
            context.add_init_script(FRAME_COUNTER_JS)
            page = context.new_page()
            nb = Notebook(page, url, token, source.name, workdir / "shots")
            t_start = now_ms(page)
            nb.run_all(timeout=600)
            cells_done = (now_ms(page) - t_start) / 1000
            explorers = nb.explorers()
            firsts = []  # the browser time of each view's first picture (its frame counter), not a polled screenshot
            for k in range(explorers.count()):
                nb.wait_for_picture(explorers.nth(k), timeout=300)
                times = frames_after(view_frame(explorers.nth(k)), t_start)
                firsts.append(min(times) if times else now_ms(page))
            pictures = (max(firsts) - t_start) / 1000
            slowest = page.evaluate("""() => {
                const cells = window.jupyterapp.shell.currentWidget.content.model.cells, out = [];
                for (let i = 0; i < cells.length; i++) {
                    const t = cells.get(i).getMetadata('execution');
                    if (t && t['iopub.execute_input'] && t['shell.execute_reply'])
                        out.push([i, (Date.parse(t['shell.execute_reply']) - Date.parse(t['iopub.execute_input'])) / 1000]);
                }
                return out.sort((a, b) => b[1] - a[1]).slice(0, 4);
            }""")
            print(f"  {source.stem}: slowest cells " + ", ".join(f"{i}: {d:.1f} s" for i, d in slowest),
                  file=sys.stderr, flush=True)
            updates = []
            for k in range(explorers.count()):
                ex = explorers.nth(k)
                ex.scroll_into_view_if_needed()
                frame = view_frame(ex)
                is_menu = ex.locator(".lab-primary-control select").count() > 0
                values = []
                for r in range(repeat):
                    wait_quiet(frame)
                    if is_menu:
                        t0 = choose(ex, _next_option(ex))
                    else:
                        t0 = _drag_slider(page, ex, ".lab-primary-control", (0.55, 0.7)[r % 2])
                    lat = settle_time(frame, t0, quiet=1.5, timeout=60)
                    values.append(float("nan") if lat is None else lat / 1000)
                title = ex.locator("b").first.inner_text() if ex.locator("b").count() \
                    else f"explorer {k}"
                updates.append((title.strip()[:28], statistics.median(values), max(values)))
            rows.append((source.stem, cells_done, pictures, updates))
            context.close()
    return rows


def print_seat(rows, repeat, load_before, load_after):
    head = f"{'notebook':24s}{'cells run':>11s}{'last picture':>14s}   explorer updates (median / worst of {repeat}, s)"
    print(head)
    print("-" * (len(head) + 10))
    ok = True
    for name, cells, pictures, updates in rows:
        text = "; ".join(f"{t} {m:.2f} / {w:.2f}" for t, m, w in updates) or "–"
        print(f"{name:24s}{cells:10.1f}s{pictures:13.1f}s   {text}")
        ok &= all(m <= SEAT_TARGETS["update"] for _, m, _ in updates)
        if name.startswith("05"):
            ok &= pictures <= SEAT_TARGETS["run all"]
    print(f"targets: 05 Run All to the last picture ≤ {SEAT_TARGETS['run all']:g} s, every update ≤ "
          f"{SEAT_TARGETS['update']:g} s (quiet 2-core machine)")
    print(f"load average before {load_before[0]:.2f} / after {load_after[0]:.2f} (1 min), "
          f"{os.cpu_count()} CPUs; {time.strftime('%Y-%m-%d %H:%M')}")
    return 0 if ok else 1


def _fmt(label, values):
    if not values:
        return "–"
    med = statistics.median(values)
    return f"{med:.1f}" if label.startswith("camera drag") else f"{med:.0f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=10)
    parser.add_argument("--backends", default="client,server,trame")
    parser.add_argument("--no-server-side", action="store_true", help="skip the server-side table")
    parser.add_argument("--seat", action="store_true", help="the course's notebooks 05–08 from a student's seat")
    parser.add_argument("--notebooks", default=",".join(SEAT_NOTEBOOKS), help="with --seat: which notebooks")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    if args.seat:
        load_before = os.getloadavg()
        workdir = Path(tempfile.mkdtemp(prefix="lab-seat-bench-"))
        try:
            with sync_playwright() as p:
                browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
                rows = measure_seat(browser, workdir, [n.strip() for n in args.notebooks.split(",")], args.repeat)
                browser.close()
        finally:
            shutil.rmtree(workdir, ignore_errors=True)
        return print_seat(rows, args.repeat, load_before, os.getloadavg())

    backends = [b.strip() for b in args.backends.split(",") if b.strip()]
    load_before = os.getloadavg()
    results, extra = {}, {}
    workdir = Path(tempfile.mkdtemp(prefix="lab-browser-bench-"))
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            for backend in backends:
                sub = workdir / backend
                sub.mkdir()
                print(f"measuring {backend} …", file=sys.stderr, flush=True)
                results[backend], extra[backend] = measure(browser, backend, args.repeat, sub)
            browser.close()
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
    load_after = os.getloadavg()

    server = {}
    if not args.no_server_side:
        sys.path.insert(0, str(ROOT / "benchmarks"))
        import widgets as server_side

        for name, ours, base, what in server_side.measure(max(3, args.repeat // 2)):
            server[name] = (ours, base, what)

    labels = list(TARGETS) + ["drag lag", "camera drag, depth 5", "drag lag, depth 5"]
    head = f"{'in the browser, median of ' + str(args.repeat):34s}" + "".join(f"{b:>10s}" for b in backends)
    head += f"{'target':>12s}"
    print(head)
    print("-" * len(head))
    for label in labels:
        unit = UNITS.get(label, "ms")
        line = f"{label + ' (' + unit + ')':34s}" + "".join(f"{_fmt(label, results[b].get(label, [])):>10s}"
                                                            for b in backends)
        if label in TARGETS:
            op, value = TARGETS[label]
            line += f"{op + ' ' + format(value, 'g'):>12s}"
        print(line)
    for b in backends:
        print(f"  {b}: both views {extra[b]['first view (s)']:.1f} s after Run All, "
              f"{extra[b]['after a restart (s)']:.1f} s after a kernel restart and Run All; "
              f"fan {extra[b]['geodesic fan']}; actions run {extra[b]['actions run']}")
    print(f"load average before {load_before[0]:.2f} / after {load_after[0]:.2f} (1 min), "
          f"{os.cpu_count()} CPUs; {time.strftime('%Y-%m-%d %H:%M')}")
    if server:
        print()
        print(f"{'server side (benchmarks/widgets.py)':34s}{'median':>10s}{'best':>10s}   baseline")
        print("-" * 72)
        for name, (ours, base, what) in server.items():
            print(f"{name:34s}{1000 * statistics.median(ours):8.0f}ms{1000 * min(ours):8.0f}ms   "
                  f"{1000 * statistics.median(base):.0f} ms {what}")
    ok = all((statistics.median(results[backends[0]][k]) <= v if op == "≤" else statistics.median(results[backends[0]][k]) >= v)
             for k, (op, v) in TARGETS.items() if results[backends[0]].get(k))
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
