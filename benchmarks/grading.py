"""Benchmark: the sandboxed grader, one notebook and a folder of submissions.

Prints, in one run:

* where the time of one graded notebook goes (notebook 05, the practical's task): building the cases,
  preparing the sandbox's copy of the library, the exact answers (sympy), the sandboxed run (kernel,
  cells, graded calls), judging;
* one notebook end to end with bubblewrap and without it (limits and a process group only): the
  sandbox's overhead;
* a folder of N submissions (half the reference solution, half the untouched exercise) with ``-j 1`` and
  ``-j 2``: wall time and submissions per minute.

Targets (issue 9): one notebook <= 15 s, a folder of 20 <= 3 min with -j 2, on this 2-core machine when
quiet.  The machine is shared: read the load average printed first.

Usage: python benchmarks/grading.py [--folder 20] [--repeat 3]
"""

import argparse
import json
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import nbformat

from lab.teaching import assignments, grading, sandbox

ROOT = Path(__file__).resolve().parent.parent
SOLUTION = ROOT / "solutions" / "en" / "05_visualize_curvature.ipynb"
EXERCISE = ROOT / "exercises" / "en" / "05_visualize_curvature.ipynb"


def phases(use_bwrap):
    """Seconds of each phase of grading the solution once."""
    nb = nbformat.read(str(SOLUTION), as_version=4)
    found, _ = assignments.for_submission(nb, SOLUTION)
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        prepared = grading.Prepared(found, 1, tmp)
        out["cases + the sandbox's copy of lab"] = time.perf_counter() - t
        t = time.perf_counter()
        expected = prepared.expected()
        out["exact answers (sympy; overlaps the run)"] = time.perf_counter() - t
        work = Path(tmp) / "work"
        (work / "out").mkdir(parents=True)
        box = sandbox.Sandbox(prepared.package, work, use_bwrap=use_bwrap)
        (work / "submission.ipynb").write_bytes(SOLUTION.read_bytes())
        spec = prepared.spec(box.inside / "submission.ipynb", box.inside / "out", 60, 10)
        (work / "spec.json").write_text(json.dumps(spec))
        t = time.perf_counter()
        box.run([sys.executable, "-m", "lab.teaching.child", str(box.inside / "spec.json")], 600)
        out["sandboxed run: kernel, cells, graded calls"] = time.perf_counter() - t
        t = time.perf_counter()
        task = grading.TASKS[found.tasks[0][0]]
        results = grading._read_results(work / "out" / "task-0.jsonl", len(prepared.cases[0]))
        for i, case in enumerate(prepared.cases[0]):
            grading.judge_outcome(task, case, results[i], lambda i=i: expected[0][i])
        out["reading and judging the results"] = time.perf_counter() - t
    return out


def one_notebook(use_bwrap, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        r = grading.grade_notebook(SOLUTION, sandbox=use_bwrap)
        times.append(time.perf_counter() - t)
        assert r.score == r.max_score, r.text()
    return statistics.median(times)


def folder(n, jobs):
    with tempfile.TemporaryDirectory() as tmp:
        subs = Path(tmp) / "subs"
        for k in range(n):
            (subs / f"s{k:02d}").mkdir(parents=True)
            shutil.copy(SOLUTION if k % 2 == 0 else EXERCISE, subs / f"s{k:02d}" / SOLUTION.name)
        t = time.perf_counter()
        results = grading.grade_folder(subs, Path(tmp) / "reports", jobs=jobs)
        wall = time.perf_counter() - t
    assert [r.score for r in results] == [10 if k % 2 == 0 else 0 for k in range(n)]
    return wall


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    bw = sandbox.bwrap_works()
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, bubblewrap {'works' if bw else 'unavailable'}")
    print("\nwhere the time of one graded notebook goes (05, reference solution, bubblewrap):")
    for name, secs in phases(bw).items():
        print(f"  {name:<52} {secs:6.2f} s")
    with_box = one_notebook(bw, args.repeat) if bw else float("nan")
    without = one_notebook(False, args.repeat)
    print(f"\n| one notebook (05), median of {args.repeat} | wall s |")
    print("|---|---:|")
    print(f"| bubblewrap sandbox | {with_box:.2f} |")
    print(f"| limits and a process group only | {without:.2f} |")
    print(f"| sandbox overhead | {with_box - without:+.2f} |")
    print(f"\n| folder of {args.folder} (half solved) | wall s | submissions / min |")
    print("|---|---:|---:|")
    for jobs in (1, 2):
        wall = folder(args.folder, jobs)
        print(f"| -j {jobs} | {wall:.1f} | {60 * args.folder / wall:.1f} |")
    print(f"\nload average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
