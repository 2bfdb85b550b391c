"""Benchmark: the memory a student's kernel holds after each notebook, explorers included (for sizing a hub).

Every solution notebook runs top to bottom in a fresh kernel (nbclient), with ``LAB_INTERACTIVE=1`` so that
the explorers start their live views (trame servers) as in JupyterLab; a last cell reads the kernel's
resident memory now (VmRSS) and at its peak (VmHWM), and the CPU seconds it used.  The table gives what
``deploy/values.yaml`` sizes from: a student with two notebooks open holds about the sum of two rows.

Usage: python benchmarks/kernel_memory.py [--lang en] [notebooks ...]
"""

import argparse
import json
import os
import sys
import time
from pathlib import Path

import nbformat

from lab.teaching.kernel.notebook_client import NotebookRunner

ROOT = Path(__file__).resolve().parent.parent
PROBE = """import json, os, resource
status = dict(line.split(":", 1) for line in open("/proc/self/status") if ":" in line)
usage = resource.getrusage(resource.RUSAGE_SELF)
print("@@MEM@@" + json.dumps({"rss": int(status["VmRSS"].split()[0]) / 1024, "peak": int(status["VmHWM"].split()[0]) / 1024,
                             "cpu": usage.ru_utime + usage.ru_stime}))
"""


def measure(path):
    nb = nbformat.read(str(path), as_version=4)
    nb.cells.append(nbformat.v4.new_code_cell(PROBE))
    os.environ["LAB_INTERACTIVE"] = "1"
    client = NotebookRunner(nb, timeout=600, kernel_name="python3", allow_errors=True,
                            resources={"metadata": {"path": str(path.parent)}},
                            extra_arguments=["--IPKernelApp.log_level=ERROR"])
    start = time.perf_counter()
    client.execute()
    wall = time.perf_counter() - start
    text = "".join(o.get("text", "") for o in nb.cells[-1].outputs if o.get("output_type") == "stream")
    data = json.loads(text.split("@@MEM@@", 1)[1].splitlines()[0])
    explorers = sum(c.source.count("Explorer") for c in nb.cells if c.cell_type == "code")
    return data, wall, explorers


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("notebooks", nargs="*")
    parser.add_argument("--lang", default="en")
    args = parser.parse_args(argv)
    folder = ROOT / "solutions" / args.lang
    if not folder.is_dir():
        folder = ROOT / "solutions"
    paths = [Path(p) for p in args.notebooks] or sorted(folder.glob("[0-9][0-9]_*.ipynb"))
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, {sys.executable}")
    print("\n| notebook | explorers | kernel RSS MiB | peak MiB | kernel CPU s | wall s |")
    print("|---|---:|---:|---:|---:|---:|")
    rows = []
    for path in paths:
        data, wall, explorers = measure(path)
        rows.append(data)
        print(f"| {path.stem} | {explorers} | {data['rss']:.0f} | {data['peak']:.0f} | {data['cpu']:.1f} | {wall:.1f} |")
    rss = sorted(r["rss"] for r in rows)
    print(f"\nlargest kernel {rss[-1]:.0f} MiB, median {rss[len(rss) // 2]:.0f} MiB; two largest together "
          f"{sum(rss[-2:]):.0f} MiB")


if __name__ == "__main__":
    main()
