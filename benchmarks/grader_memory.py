"""Benchmark: the grader's own memory and time against the largest output the limits allow, at ``-j N``.

Each of N submissions is ``tests/data/hostile/host_floods.ipynb`` with its cell of a million newlines: after the
graded calls it appends 50 MiB of valid results (the most numbers a value may have, 20 000, in every line) and a line
of 2 million numbers, and writes 255 MiB to stderr.  One reference solution is graded beside them.  The grader's
resident memory is sampled every 0.1 s (``VmRSS``; ``VmHWM`` at the end) while ``grade_folder`` runs ``-j N``.

Prints the grader's resident memory before the run, its peak, the peak above the start per submission, the wall
time and what each submission scored (the solution must have full marks).  The bound (see the developers' notes on
the sandbox): per submission the grader holds the decoded values of its cases (at most 20 000 numbers of 8 bytes per
case, the last line per case) and one line of at most ``results.MAX_LINE`` bytes while it is parsed.

Usage: python benchmarks/grader_memory.py [--jobs 8] [--submissions 8]
"""

import argparse
import os
import shutil
import tempfile
import threading
import time
from pathlib import Path

import nbformat

from lab.teaching.course import grade
from lab.teaching.grader import sandbox_output

ROOT = Path(__file__).resolve().parent.parent
ATTACK = ROOT / "tests" / "data" / "hostile" / "host_floods.ipynb"
SOLUTION = ROOT / "solutions" / "en" / "05_visualize_curvature.ipynb"
ASSIGNMENT = ROOT / "exercises" / "en" / "05_visualize_curvature.ipynb"


def rss(field="VmRSS"):
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) << 10
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--jobs", type=int, default=8)
    parser.add_argument("--submissions", type=int, default=8)
    parser.add_argument("--no-million", action="store_true",
                        help="leave out the million-line cell (for a grader whose search of it is quadratic)")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory(prefix="lab-bench-memory-") as tmp:
        subs = Path(tmp) / "subs"
        nb = nbformat.read(ATTACK, as_version=4)
        cell = next(c for c in nb.cells if c.source.startswith("MILLION = 1"))
        if not args.no_million:
            cell.source = "MILLION = 1\n" + "\n" * 1_000_000 + "MILLION = 2\n"
        for k in range(args.submissions):
            (subs / f"flood{k:02d}").mkdir(parents=True)
            nbformat.write(nb, subs / f"flood{k:02d}" / ASSIGNMENT.name)
        (subs / "ada").mkdir()
        shutil.copy(SOLUTION, subs / "ada" / ASSIGNMENT.name)
        start_rss, peak, done = rss(), [0], threading.Event()

        def sample():
            while not done.is_set():
                peak[0] = max(peak[0], rss())
                time.sleep(0.1)

        sampler = threading.Thread(target=sample, daemon=True)
        sampler.start()
        t = time.perf_counter()
        res = grade.grade_folder(subs, Path(tmp) / "reports", jobs=args.jobs, seed=1, assignment=ASSIGNMENT,
                                 timeout=60, check_timeout=2, total_timeout=600)
        wall = time.perf_counter() - t
        done.set()
        sampler.join()
        peak[0] = max(peak[0], rss("VmHWM"))
    mib = 1 << 20
    print(f"{args.submissions} flooding submissions + 1 solution, -j {args.jobs}: {wall:.0f} s")
    print("| grader memory | MiB |")
    print("|---|---:|")
    print(f"| resident at the start | {start_rss / mib:.0f} |")
    print(f"| peak while grading | {peak[0] / mib:.0f} |")
    print(f"| peak above the start, per flooding submission | {(peak[0] - start_rss) / mib / args.submissions:.1f} |")
    if hasattr(sandbox_output, "MAX_LINE"):
        print(f"| bound per submission: one line being parsed (MAX_LINE) | {sandbox_output.MAX_LINE / mib:.1f} |")
    scores = {r.student: f"{r.score:g}/{r.max_score:g}" for r in res}
    print("scores:", ", ".join(f"{k} {v}" for k, v in sorted(scores.items())))


if __name__ == "__main__":
    main()
