"""Benchmark: what a fresh Python process pays before it does anything (every CLI call, grading run, notebook).

Each row is a new interpreter (the venv's Python) running one command, repeated; wall time and CPU time
(user + system of the child) are medians.  ``import lab`` is lazy (PEP 562): it should cost about as much
as the interpreter itself and at most 3x ``import numpy``.

Usage: python benchmarks/startup.py [--repeat 5]
"""

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CLI = str(Path(sys.executable).with_name("curvature-lab"))


def commands(out):
    py = sys.executable
    return [
        ("python -c pass", [py, "-c", "pass"]),
        ("import numpy", [py, "-c", "import numpy"]),
        ("import lab", [py, "-c", "import lab"]),
        ("import lab; practical().curvature(1, 1)",
         [py, "-c", "import lab; lab.surfaces.practical().curvature(1, 1)"]),
        ("import lab; lab.CurvatureExplorer (pyvista, ipywidgets, trame)",
         [py, "-c", "import lab; lab.CurvatureExplorer"]),
        ("curvature-lab render practical -o x.png",
         [CLI, "render", "--surface", "practical", "--depth", "1", "--quiet", "-o", str(out)]),
    ]


def run(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=ROOT)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, medians of {args.repeat}")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, cmd in commands(Path(tmp) / "x.png"):
            run(cmd)  # warm the file cache
            times = [run(cmd) for _ in range(args.repeat)]
            rows.append((name, statistics.median(t[0] for t in times), statistics.median(t[1] for t in times)))
    numpy_cpu = rows[1][2]
    print(f"\n| {'command':<62} | wall s | CPU s | CPU / import numpy |")
    print(f"|{'-' * 64}|-------:|------:|-------------------:|")
    for name, wall, cpu in rows:
        print(f"| {name:<62} | {wall:6.3f} | {cpu:5.3f} | {cpu / numpy_cpu:18.2f} |")
    lab_cpu = rows[2][2]
    verdict = "meets" if lab_cpu <= 3 * numpy_cpu else "MISSES"
    print(f"\nimport lab: {lab_cpu:.3f} CPU s = {lab_cpu / numpy_cpu:.2f} x import numpy ({verdict} the target <= 3x)")


if __name__ == "__main__":
    main()
