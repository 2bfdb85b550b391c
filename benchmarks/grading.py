"""Benchmark: the sandboxed grader, one notebook and a folder of submissions.

Prints, in one run:

* where the time of one graded notebook goes (notebook 05, the practical's task): building the cases,
  preparing the sandbox's copy of the library, the exact answers (sympy), the sandboxed run (kernel,
  cells, graded calls), judging;
* one notebook end to end with bubblewrap and without it (limits and a process group only): the
  sandbox's overhead;
* a folder of N submissions (half the reference solution, half the untouched exercise) with ``-j 1`` and
  ``-j 2``: wall time and submissions per minute;
* a class of ``--class`` mixed English and German submissions (solutions and untouched exercises, in both
  languages) at ``-j 2``: wall time, load, the estimate for 200 students;
* a crash half way: ``curvature-lab grade`` killed once half the reports are written, then ``--resume``: what
  was lost and what was graded again;
* fairness: a correct classmate graded alone, and beside the submission with 48 busy ``setsid()`` processes.

Targets (issue 9): one notebook <= 15 s, a folder of 20 <= 3 min with -j 2, on this 2-core machine when
quiet.  The machine is shared: read the load average printed first.

Usage: python benchmarks/grading.py [--folder 20] [--repeat 3] [--class 40] [--only phases,one,folder,class,crash,fair]
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

from lab.teaching.course import files, grade
from lab.teaching.grader import assignments, notebook, sandbox_output
from lab.teaching.sandbox import bubblewrap

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
        prepared = notebook.Prepared(found, 1, notebook.Prepared.package_for(found, tmp))
        out["cases + the sandbox's copy of lab"] = time.perf_counter() - t
        t = time.perf_counter()
        expected = prepared.expected()
        out["exact answers (sympy; overlaps the run)"] = time.perf_counter() - t
        work = Path(tmp) / "work"
        (work / "out").mkdir(parents=True)
        box = bubblewrap.Sandbox(prepared.package, work, use_bwrap=use_bwrap)
        (work / "submission.ipynb").write_bytes(SOLUTION.read_bytes())
        spec = prepared.spec(box.inside / "submission.ipynb", box.inside / "out", 60, 10)
        (work / "spec.json").write_text(json.dumps(spec))
        t = time.perf_counter()
        box.run([sys.executable, "-m", "lab.teaching.kernel.graded_run", str(box.inside / "spec.json")], 600)
        out["sandboxed run: kernel, cells, graded calls"] = time.perf_counter() - t
        t = time.perf_counter()
        task = notebook.TASKS[found.tasks[0][0]]
        fd = sandbox_output.open_folder(work / "out")
        found_results = sandbox_output.read_outcomes(fd, "task-0.jsonl", len(prepared.cases[0]))
        os.close(fd)
        for i, case in enumerate(prepared.cases[0]):
            notebook.judge_outcome(task, case, found_results[i], lambda i=i: expected[0][i])
        out["reading and judging the results"] = time.perf_counter() - t
    return out


def one_notebook(use_bwrap, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        r = notebook.grade_notebook(SOLUTION, sandbox=use_bwrap)
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
        graded = grade.grade_folder(subs, Path(tmp) / "reports", jobs=jobs)
        wall = time.perf_counter() - t
    assert [r.score for r in graded] == [10 if k % 2 == 0 else 0 for k in range(n)]
    return wall


def mixed_class(subs, n):
    """``n`` submissions: the English and German solutions and untouched exercises of 05, in turn."""
    kinds = [(ROOT / "solutions" / "en"), (ROOT / "solutions" / "de"), (ROOT / "exercises" / "en"),
             (ROOT / "exercises" / "de")]
    for k in range(n):
        (subs / f"s{k:03d}").mkdir(parents=True)
        shutil.copy(kinds[k % 4] / SOLUTION.name, subs / f"s{k:03d}" / SOLUTION.name)
    return [10 if k % 4 < 2 else 0 for k in range(n)]


def whole_class(n):
    with tempfile.TemporaryDirectory() as tmp:
        subs = Path(tmp) / "subs"
        expected = mixed_class(subs, n)
        load0, t, cpu0 = os.getloadavg()[0], time.perf_counter(), machine_busy()
        graded = grade.grade_folder(subs, Path(tmp) / "reports", jobs=2)
        wall, cpu = time.perf_counter() - t, machine_busy() - cpu0
        assert [r.score for r in graded] == expected, [r.score for r in graded]
        assert {r.lang for r in graded} == {"en", "de"}
    return wall, load0, os.getloadavg()[0], cpu


def machine_busy():
    """CPU seconds the whole machine has been busy (all cores, /proc/stat): the sandboxes' share is not separable
    from the rest, so it is an upper bound of the grading's CPU time."""
    fields = [int(x) for x in Path("/proc/stat").read_text().split("\n")[0].split()[1:]]
    return (sum(fields) - fields[3] - fields[4]) / os.sysconf("SC_CLK_TCK")


def crash_and_resume(n):
    """Kill a folder run once half the reports exist, then resume: (reports before the kill, regraded, wall)."""
    import signal
    import subprocess

    with tempfile.TemporaryDirectory() as tmp:
        subs, out = Path(tmp) / "subs", Path(tmp) / "reports"
        expected = mixed_class(subs, n)
        cmd = [sys.executable, "-m", "lab.cli", "grade", str(subs), "--out", str(out), "-j", "2"]
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        while proc.poll() is None and len(list(out.glob("s*.json"))) < n // 2:
            time.sleep(0.5)
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        before = {p.name: p.stat().st_mtime_ns for p in out.glob("s*.json")}
        t = time.perf_counter()
        subprocess.run(cmd + ["--resume"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        wall = time.perf_counter() - t
        after = {p.name: p.stat().st_mtime_ns for p in out.glob("s*.json")}
        kept = sum(after.get(name) == mtime for name, mtime in before.items())
        rows = files.read_summary(out / "summary.csv")
        assert [float(r["score"]) for r in sorted(rows, key=lambda r: r["student"])] == expected
    return len(before), kept, len(after) - kept, wall


def fairness():
    """Seconds the classmate's grading took alone, and beside 48 busy processes of another submission."""
    hog = ROOT / "tests" / "data" / "hostile" / "cpu_hog_setsid.ipynb"
    out = {}
    for label, others in (("alone", []), ("beside the CPU attack", [hog])):
        with tempfile.TemporaryDirectory() as tmp:
            subs = Path(tmp) / "subs"
            (subs / "classmate").mkdir(parents=True)
            shutil.copy(SOLUTION, subs / "classmate" / SOLUTION.name)
            for k, path in enumerate(others):
                (subs / f"attacker{k}").mkdir()
                shutil.copy(path, subs / f"attacker{k}" / SOLUTION.name)
            graded = {r.student: r for r in grade.grade_folder(subs, Path(tmp) / "reports", jobs=2,
                                                                 assignment=EXERCISE)}
            assert graded["classmate"].score == 10, graded["classmate"].text()
            out[label] = graded["classmate"].seconds
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--class", dest="size", type=int, default=40, help="submissions of the mixed class")
    parser.add_argument("--only", default="phases,one,folder,class,crash,fair")
    args = parser.parse_args(argv)
    only = set(args.only.split(","))
    bw = bubblewrap.bwrap_works()
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, bubblewrap {'works' if bw else 'unavailable'}")
    if "phases" in only:
        print("\nwhere the time of one graded notebook goes (05, reference solution, bubblewrap):")
        for name, secs in phases(bw).items():
            print(f"  {name:<52} {secs:6.2f} s")
    if "one" in only:
        with_box = one_notebook(bw, args.repeat) if bw else float("nan")
        without = one_notebook(False, args.repeat)
        print(f"\n| one notebook (05), median of {args.repeat} | wall s |")
        print("|---|---:|")
        print(f"| bubblewrap sandbox | {with_box:.2f} |")
        print(f"| limits and a process group only | {without:.2f} |")
        print(f"| sandbox overhead | {with_box - without:+.2f} |")
    if "folder" in only:
        print(f"\n| folder of {args.folder} (half solved) | wall s | submissions / min |")
        print("|---|---:|---:|")
        for jobs in (1, 2):
            wall = folder(args.folder, jobs)
            print(f"| -j {jobs} | {wall:.1f} | {60 * args.folder / wall:.1f} |")
    if "class" in only:
        wall, load0, load1, cpu = whole_class(args.size)
        per = wall / args.size
        print(f"\n| a class of {args.size}, English and German mixed, -j 2 | value |")
        print("|---|---:|")
        print(f"| wall time | {wall:.0f} s ({per:.1f} s per submission) |")
        print(f"| CPU time of the machine meanwhile (all cores) | {cpu:.0f} s ({cpu / args.size:.1f} s per submission) |")
        print(f"| load average, start / end | {load0:.1f} / {load1:.1f} |")
        print(f"| estimate for 200 students at -j 2 on 2 cores | {200 * per / 60:.0f} min |")
        print(f"| estimate for 200 students at -j 8 on 8 cores | {200 * cpu / args.size / 8 / 60:.1f} min (CPU time / cores) |")
    if "crash" in only:
        done, kept, regraded, wall = crash_and_resume(args.size)
        print(f"\n| a crash half way ({args.size} submissions, killed with SIGKILL) | value |")
        print("|---|---:|")
        print(f"| reports written before the kill | {done} |")
        print(f"| of them kept by --resume (not graded again) | {kept} |")
        print(f"| graded by --resume | {regraded} |")
        print(f"| --resume wall time | {wall:.0f} s |")
    if "fair" in only:
        times = fairness()
        print("\n| a classmate's 05, -j 2 | seconds |")
        print("|---|---:|")
        for label, secs in times.items():
            print(f"| {label} | {secs:.1f} |")
        print(f"| ratio | {times['beside the CPU attack'] / times['alone']:.2f} (goal <= 1.5) |")
    print(f"\nload average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
