"""Benchmark: how many students with a live explorer one machine holds behind JupyterHub.

A real JupyterHub on 127.0.0.1 (``tests/hub_support.py``: dummy authenticator, simple local process
spawner, configurable-http-proxy), and one headless Chromium with one browser context per student
(separate cookies).  Students log in through the hub's URL, open notebook 05
(``solutions/en/05_visualize_curvature.ipynb``, copied to their homes) and run it; the class grows in
steps (1, 2, 4, 6, 8 … up to ``--max``).  With every student's explorers live, each step measures the
colour change of the first ``CurvatureExplorer`` (colour map h∘f2 linear ↔ signed log, depth 2), from
the change in the browser to the last picture drawn in the view once nothing more is drawn for 1.5 s
(``FRAME_COUNTER_JS`` of ``tests/browser_support.py``, as in ``benchmarks/browser.py``):

* all at once: every student changes the colour map at the same moment (``--repeats`` rounds; each
  page is told to change at the same time on the browser's clock, "changes within" says how close the
  changes came), the worst case of a class that clicks together;
* one at a time: one student changes it while the others' explorers sit live and idle.

It stops after the step whose median colour change (all at once) exceeds 1 s, or when the machine's
available memory runs short.  Memory is the resident memory (VmRSS, from /proc) of all kernels and of
all single-user servers started by the hub; Chromium's is its proportional set size (PSS).  The CPU
time (from /proc) that the all-at-once rounds cost, per colour change, is split into the kernels, the
hub's side (hub, configurable-http-proxy, single-user servers with jupyter-server-proxy) and Chromium;
it includes what runs anyway during the rounds (JupyterLab's polling, this script's polling of the pages).

Everything runs on this one machine: the students' browsers (software WebGL) run here and take CPU from
the kernels; on a real hub they run on the students' own computers, so the latencies here are pessimistic.

Usage: python benchmarks/hub_load.py [--max 12] [--repeats 10] [--min-free 3] [--keep DIR]
"""

import argparse
import math
import os
import shutil
import statistics
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.browser_support import (
    CHROMIUM,
    CHROMIUM_ARGS,
    FRAME_COUNTER_JS,
    Notebook,
    choose,
    chosen_at,
    frames_after,
    now_ms,
    process_cpu_seconds,
    process_rss_mb,
    view_frame,
    wait_quiet,
)
from tests.hub_support import PROXY, descendants, hub_processes, jupyterhub, login

NOTEBOOK = ROOT / "solutions" / "en" / "05_visualize_curvature.ipynb"
MAPS = ("signed log", "h∘f2 linear (min/max)")
LIMIT_MS = 1000.0
QUIET_S = 1.5
#: every student has a browser of their own in the foreground: no throttling of pages in the background
BROWSER_ARGS = CHROMIUM_ARGS + ["--disable-renderer-backgrounding", "--disable-background-timer-throttling",
                                "--disable-backgrounding-occluded-windows"]


@dataclass
class Student:
    name: str
    nb: Notebook
    explorer: object
    frame: object

    def change(self, at=None):
        """Switch the colour map to the other of ``MAPS`` (now, or at browser time ``at``: see ``choose``)."""
        current = self.explorer.locator(".lab-primary-control select").evaluate("s => s.value")
        return choose(self.explorer, MAPS[1] if current == MAPS[0] else MAPS[0], at)


def say(text):
    print(f"[{time.strftime('%H:%M:%S')}] {text}", file=sys.stderr, flush=True)


def class_sizes(largest):
    sizes, n = [], 1
    while n < largest:
        sizes.append(n)
        n = 2 if n == 1 else n + 2
    return sizes + [largest]


def available_mib():
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemAvailable:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def join(browser, url, name, shots):
    """Log ``name`` in, open notebook 05, run it and wait for the curvature explorer's picture."""
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    context.add_init_script(FRAME_COUNTER_JS)
    page = login(context, url, name)
    nb = Notebook(page, f"{url}/user/{name}", "", NOTEBOOK.name, shots / name)
    nb.run_all(timeout=600)
    explorer = nb.explorers().first
    explorer.scroll_into_view_if_needed()
    nb.wait_for_picture(explorer, timeout=180)
    src = explorer.locator("iframe.pyvista").get_attribute("src") or ""
    if f"/user/{name}/proxy/" not in src:
        raise RuntimeError(f"{name}: the view does not go through the hub's proxy: {src!r}")
    return Student(name, nb, explorer, view_frame(explorer))


def settle_all(students, starts, timeout=60.0):
    """Latency (ms) of each student's change: last picture after its start, once its view is quiet for 1.5 s.

    All views are watched together (a view that settled early does not wait for the others).
    """
    last = {s.name: None for s in students}
    seen = {s.name: time.time() for s in students}
    done = {}
    deadline = time.time() + timeout
    while len(done) < len(students) and time.time() < deadline:
        for s, t0 in zip(students, starts):
            if s.name in done:
                continue
            times = frames_after(s.frame, t0)
            latest = max(times) if times else None
            if latest != last[s.name]:
                last[s.name], seen[s.name] = latest, time.time()
            elif latest is not None and time.time() - seen[s.name] >= QUIET_S:
                done[s.name] = latest - t0
        time.sleep(0.05)
    return [done.get(s.name, math.nan) for s in students]


def all_at_once(students, repeats):
    """Latencies of every student's change, and how far apart the first and last change of each round were (ms)."""
    values, spreads = [], []
    for _ in range(repeats):
        # every page is told to change at the same browser time, far enough ahead for all of them to hear it
        at = now_ms(students[0].nb.page) + 500 + 300 * len(students)
        for s in students:
            s.change(at)
        starts = [chosen_at(s.explorer) for s in students]
        spreads.append(max(starts) - min(starts))
        values += settle_all(students, starts)
    return values, spreads


def one_at_a_time(students, repeats):
    values = []
    for k in range(max(repeats, len(students))):
        s = students[k % len(students)]
        values += settle_all([s], [s.change()])
    return values


def memory(hub, browser_root):
    procs = hub_processes(hub)
    chromium = [pid for pid in descendants(browser_root) if _is_chromium(pid)]
    return (len(procs["kernels"]), sum(process_rss_mb(p) for p in procs["kernels"]),
            sum(process_rss_mb(p) for p in procs["servers"]), sum(_pss_mib(p) for p in chromium))


def cpu_seconds(hub, browser_root):
    """CPU seconds used so far by the kernels, the hub's side (hub, proxy, single-user servers) and Chromium."""
    kernels = set(hub_processes(hub)["kernels"])
    groups = {"kernels": 0.0, "hub side": 0.0, "browser": 0.0}
    for pid in [hub.pid] + descendants(hub.pid) + [p for p in descendants(browser_root) if _is_chromium(p)]:
        try:
            used = process_cpu_seconds(pid)
        except (OSError, IndexError, ValueError):
            continue
        group = "kernels" if pid in kernels else "browser" if _is_chromium(pid) else "hub side"
        groups[group] += used
    return groups


def _pss_mib(pid):
    """Proportional set size (MiB): Chromium's many processes share much of their memory, RSS would count it again."""
    try:
        for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
            if line.startswith("Pss:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


def _is_chromium(pid):
    try:
        return "chromium" in Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0")[0].decode(errors="replace")
    except OSError:
        return False


def median(values):
    values = [v for v in values if not math.isnan(v)]
    return statistics.median(values) if values else math.nan


def percentile(values, q):
    values = sorted(v for v in values if not math.isnan(v))
    if not values:
        return math.nan
    return values[min(len(values) - 1, max(0, math.ceil(q * len(values)) - 1))]


HEAD = ("| students | all at once: median ms | p90 ms | changes within ms | one at a time: median ms "
        "| CPU ms per change: kernel / hub side / browser | kernels | kernel RSS MiB | servers RSS MiB "
        "| Chromium PSS MiB | load 1 / 5 min |")


def _row(row):
    size, med, p90, spread, single, cpu, kernels, kmib, smib, cmib, load = row
    return (f"| {size} | {med:.0f} | {p90:.0f} | {spread:.0f} | {single:.0f} | {' / '.join(f'{c:.0f}' for c in cpu)} "
            f"| {kernels} | {kmib:.0f} | {smib:.0f} | {cmib:.0f} | {load[0]:.1f} / {load[1]:.1f} |")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max", type=int, default=12, help="largest class (default 12)")
    parser.add_argument("--repeats", type=int, default=10, help="rounds of colour changes per class size (default 10)")
    parser.add_argument("--min-free", type=float, default=3.0, help="stop when less memory is available (GiB)")
    parser.add_argument("--keep", help="keep the hub's folder (logs, homes) here")
    args = parser.parse_args(argv)
    if not PROXY.exists():
        raise SystemExit("configurable-http-proxy is missing (make test installs it into .venv/node)")
    from playwright.sync_api import sync_playwright

    names = [f"s{k:02d}" for k in range(1, args.max + 1)]
    root = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="lab-hub-load-"))
    rows, stopped, began = [], "", time.time()
    say(f"hub in {root}; {os.cpu_count()} cores, {available_mib() / 1024:.1f} GiB available")
    try:
        with jupyterhub(root, names, [NOTEBOOK]) as (url, hub), sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=BROWSER_ARGS)
            students = []
            for size in class_sizes(args.max):
                while len(students) < size:
                    if available_mib() < args.min_free * 1024:
                        stopped = f"stopped: {available_mib() / 1024:.1f} GiB available, less than {args.min_free} GiB"
                        break
                    start = time.time()
                    students.append(join(browser, url, names[len(students)], root / "shots"))
                    say(f"{students[-1].name} joined in {time.time() - start:.0f} s")
                if stopped:
                    break
                for s in students:
                    wait_quiet(s.frame)
                say(f"{size} students: measuring")
                before = cpu_seconds(hub, os.getpid())
                together, spreads = all_at_once(students, args.repeats)
                after = cpu_seconds(hub, os.getpid())
                changes = args.repeats * size
                cpu = [1000 * (after[g] - before[g]) / changes for g in ("kernels", "hub side", "browser")]
                single = one_at_a_time(students, args.repeats)
                kernels, kernel_mib, server_mib, chromium_mib = memory(hub, os.getpid())
                load = os.getloadavg()
                missed = sum(math.isnan(v) for v in together + single)
                if missed:
                    say(f"{missed} colour changes never settled within 60 s (left out); see {root / 'shots'}")
                row = (size, median(together), percentile(together, 0.9), median(spreads), median(single), cpu,
                       kernels, kernel_mib, server_mib, chromium_mib, load)
                rows.append(row)
                say(_row(row))
                if row[1] > LIMIT_MS:
                    stopped = f"stopped: the median colour change of {size} students exceeds {LIMIT_MS:.0f} ms"
                    break
            browser.close()
    finally:
        if not args.keep:
            shutil.rmtree(root, ignore_errors=True)
    print(f"\nJupyterHub on one machine: {os.cpu_count()} cores, local process spawner, headless Chromium; "
          f"{time.strftime('%Y-%m-%d %H:%M')}, {(time.time() - began) / 60:.0f} min; colour change of notebook 05's "
          f"CurvatureExplorer (depth 2), {args.repeats} rounds\n")
    print(HEAD)
    print("|---:" * HEAD.count(" | ") + "|---:|")
    for row in rows:
        print(_row(row))
    if rows:
        size, kmib, smib = rows[-1][0], rows[-1][7], rows[-1][8]
        print(f"\nper student: kernel {kmib / size:.0f} MiB, single-user server {smib / size:.0f} MiB "
              f"(largest class measured: {size})")
    if stopped:
        print(stopped)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
