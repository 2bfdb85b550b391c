"""Builds the hostile submissions of this folder from exercise 05 (run it after changing an attack).

Each attack is the exercise with the task cell (``class MyBezierPatches``) replaced by the attacker's code
(a list: further cells after it) and, for some, the notebook's metadata changed.  ``python tests/data/hostile/build.py
[NAME …]`` rewrites them (or the named ones).
Every one must score 0 and change nothing outside its sandbox (tests/test_hostile.py).
"""

import copy
from pathlib import Path

import nbformat

HERE = Path(__file__).resolve().parent
EXERCISE = HERE.parents[2] / "exercises" / "en" / "05_visualize_curvature.ipynb"
MARK = "lab-hostile-marker"  # in the command line of every process an attack starts

ATTACKS = {
    "replace_check_tasks": '''
import lab
from lab import check


def passed(*args, **kwargs):
    from lab.teaching.report import Report
    return Report("visualize_curvature", "passed", [], "", True)


check.TASKS["visualize_curvature"] = passed
check.visualize_curvature = passed


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
''',
    "replace_run_tasks": '''
import lab
import lab.grading as grading

grading.run_tasks = lambda *a, **k: [{"task": "visualize_curvature", "status": "passed", "score": 1.0, "passed": True}]
grading.grade_notebook = lambda *a, **k: None


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
''',
    "fake_sentinel_hook": '''
import glob, json, os
import lab
from IPython import get_ipython

FAKE = json.dumps([{"task": "visualize_curvature", "object": "MyBezierPatches", "points": 10, "score": 1.0,
                    "passed": True, "status": "passed", "cases": [], "text": "ok"}])


def hook(*args, **kwargs):
    print("@@LAB-GRADING@@" + FAKE)
    for folder in glob.glob("/grade/out") + glob.glob("out") + glob.glob("../out"):
        for k in range(3):
            with open(os.path.join(folder, f"task-{k}.jsonl"), "a") as fh:
                for i in range(40):
                    fh.write(json.dumps({"index": i, "status": "ok", "value": {"kind": "patches",
                        "curvature": {"shape": [1, 2, 2], "data": [0.0] * 4},
                        "colors": {"shape": [1, 2, 2, 3], "data": [0.0, 1.0, 0.0] * 4}}}) + "\\n")


get_ipython().events.register("pre_run_cell", hook)


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        raise NotImplementedError("the hook does the work")
''',
    "restore_library_code": '''
import lab
from lab.geometry import curvature as C
from lab.model import patches as P

KEPT = {f: f.__code__ for f in (P.BezierPatches.visualize_curvature, C.from_derivatives, C.fundamental_forms)}


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        for f, code in KEPT.items():
            f.__code__ = code
        super().visualize_curvature(curvature_mode, color_map)
''',
    "second_copy_importlib": '''
import glob, importlib.util, os, sys
import lab

roots = {os.path.dirname(os.path.dirname(lab.__file__))}
roots |= {os.path.dirname(os.path.dirname(p)) for p in glob.glob("/**/lab/geometry/curvature.py", recursive=True)}
copies = []
for k, root in enumerate(sorted(roots)):
    for name in [m for m in sys.modules if m == "lab" or m.startswith("lab.")]:
        pass
    spec = importlib.util.spec_from_file_location(f"labcopy{k}", os.path.join(root, "lab", "__init__.py"),
                                                  submodule_search_locations=[os.path.join(root, "lab")])
    copies.append((root, spec))
print("copies found:", [r for r, _ in copies])


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        import importlib
        for root, _ in copies:
            saved = {m: sys.modules.pop(m) for m in list(sys.modules) if m == "lab" or m.startswith("lab.")}
            sys.path.insert(0, root)
            try:
                other = importlib.import_module("lab")
                other.model.patches.BezierPatches.visualize_curvature(self, curvature_mode, color_map)
                return
            except Exception:
                continue
            finally:
                sys.path.remove(root)
                sys.modules.update(saved)
        raise RuntimeError("no usable copy of the library")
''',
    "exec_solution": '''
import glob, json, os
import lab

found = []
course = os.path.dirname(os.path.dirname(os.path.dirname(lab.__file__)))
for pattern in ("/**/solutions/05_visualize_curvature.ipynb", "/**/solutions/*/05_visualize_curvature.ipynb",
                "../**/05_visualize_curvature.ipynb", os.path.join(course, "solutions", "*.ipynb"),
                os.path.join(course, "solutions", "*", "*.ipynb")):
    found += glob.glob(pattern, recursive=True)
for path in found:
    nb = json.load(open(path))
    for cell in nb["cells"]:
        src = "".join(cell["source"])
        if "class MyBezierPatches" in src and "BEGIN SOLUTION" in src:
            exec(src)
            break
print("solutions found:", found)
''',
    "zero_nets_in_init": '''
import numpy as np
import lab


class MyBezierPatches(lab.BezierPatches):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._P[..., 2] = 0.0          # a flat world: every curvature is 0

    def visualize_curvature(self, curvature_mode, color_map):
        for patch in self:
            patch.set_curvature(0.0, 0.0, 0.0, 0.0)
            patch.set_colors(*[(0.0, 1.0, 0.0)] * 4)
''',
    "metadata_rename_task": '''
import lab


def mean(k1, k2):
    return (k1 + k2) / 2
''',
    "metadata_task_twice": '''
import lab


def mean(k1, k2):
    return (k1 + k2) / 2
''',
    "endless_loop_ignores_interrupts": ['''
import signal
import lab

signal.signal(signal.SIGINT, signal.SIG_IGN)


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        while True:
            try:
                while True:
                    pass
            except BaseException:
                pass
''', '''
import signal

signal.signal(signal.SIGINT, signal.SIG_IGN)
while True:  # a cell that never ends either
    try:
        pass
    except BaseException:
        pass
'''],
    "vandal_in_folder": f'''
import glob, json, os, subprocess, sys
import lab

for path in glob.glob("/**/*.ipynb", recursive=True) + glob.glob("../**/*.ipynb", recursive=True):
    try:
        nb = json.load(open(path))
        nb.setdefault("metadata", {{}}).setdefault("lab", {{}})["tasks"] = []
        json.dump(nb, open(path, "w"))
    except Exception:
        pass
for path in glob.glob("/**/canary.txt", recursive=True) + glob.glob("../canary.txt"):
    try:
        os.remove(path)
    except Exception:
        pass
later = ("import glob, time; time.sleep(4)\\n"
         "for p in glob.glob('/**/summary.csv', recursive=True) + glob.glob('../**/summary.csv', recursive=True):\\n"
         "    open(p, 'w').write('student,notebook,score,max_score\\\\nattacker,a.ipynb,10,10\\\\n')\\n"
         "time.sleep(60)  # {MARK}")
subprocess.Popen([sys.executable, "-c", later], start_new_session=True, stdin=subprocess.DEVNULL,
                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
if os.fork() == 0:  # a double-forked daemon too
    os.setsid()
    if os.fork() == 0:
        os.execv(sys.executable, [sys.executable, "-c", later])
    os._exit(0)


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
''',
    "resources": '''
import socket
import lab

try:
    hog = bytearray(3 << 30)          # 3 GiB
    print("allocated 3 GiB")
except MemoryError:
    print("no memory")
for host in ("pypi.org", "1.1.1.1", "10.0.2.2"):
    try:
        socket.create_connection((host, 443), timeout=3).close()
        print("connected to", host)
    except OSError as exc:
        print("no network:", exc)
for name in ("../left_behind.txt", "left_behind.txt", "/tmp/left_behind.txt"):
    try:
        open(name, "w").write("was here")
    except OSError as exc:
        print("cannot write", name, exc)
try:
    with open("big.bin", "wb") as fh:
        fh.write(b"x" * (1 << 30))    # 1 GiB file
except OSError as exc:
    print("file too large:", exc)


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        block = [bytearray(1 << 30) for _ in range(3)]   # and 3 GiB when called
''',
    "exit_kernel": '''
import os
import lab


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        os._exit(0)
''',
    "flood_output": '''
import lab

for _ in range(2000):
    print("x" * 100000)


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        print("y" * 10**7)
''',
    "forged_results_file": '''
import json, os
import lab


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        # overwrite the results file with the values it would like to have
        for folder in ("/grade/out", "out"):
            if os.path.isdir(folder):
                for name in os.listdir(folder):
                    with open(os.path.join(folder, name), "w") as fh:
                        fh.write(json.dumps({"index": 0, "status": "ok", "value": {"kind": "array", "shape": [],
                                                                                     "data": [1.0]}}) + "\\n")
        for patch in self:
            patch.set_curvature(1.0, 1.0, 1.0, 1.0)
            patch.set_colors(*[(1.0, 0.0, 0.0)] * 4)
''',
    # -- issue 19: the files the sandbox leaves behind, forged ------------------------------------------------
    "results_bad_status": """
import lab

with open("/grade/out/task-0.jsonl", "a") as fh:
    fh.write('{"index": 0, "status": []}\\n')


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
""",
    "results_deep_json": """
import lab

with open("/grade/out/task-0.jsonl", "a") as fh:
    fh.write("[" * 200000 + "]" * 200000 + "\\n")


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
""",
    "results_infinite_shape": """
import json
import lab

line = {"index": 0, "status": "ok", "value": {"kind": "patches", "curvature": {"shape": [float("inf")], "data": []},
                                              "colors": {"shape": [float("inf")], "data": []}}}
with open("/grade/out/task-0.jsonl", "a") as fh:
    fh.write(json.dumps(line) + "\\n")


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
""",
    "results_cells_forged": f"""
import subprocess, sys
import lab

# a process that keeps replacing cells.json (the child writes it last) until the sandbox ends: by a link to
# /dev/zero, a FIFO, and an entry without "cell" beside 200 errors of 1 MiB each, in turn
forge = '''
import json, os, time
out = "/grade/out"
k = 0
while True:
    k += 1
    tmp = os.path.join(out, f".forged{{k}}")
    try:
        if k % 3 == 0:
            os.symlink("/dev/zero", tmp)
        elif k % 3 == 1:
            os.mkfifo(tmp)
        else:
            with open(tmp, "w") as fh:
                json.dump({{"cell_errors": [{{"error": "x", "kind": "error"}}] + [{{"cell": 1, "error": "y" * (1 << 20),
                          "kind": "error"}}] * 200, "restarts": 0}}, fh)
        os.replace(tmp, os.path.join(out, "cells.json"))
    except OSError:
        pass
    time.sleep(0.001)  # {MARK}
'''
subprocess.Popen([sys.executable, "-c", forge], start_new_session=True, stdin=subprocess.DEVNULL,
                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
""",
    # -- student text that would reach the instructor raw ---------------------------------------------------
    "escape_sequences": """
import lab

FORGED = "\\x1b[2J\\x1b[H\\x1b]0;graded\\x07ada: 10 / 10 points\\n  \\u2714 visualize_curvature: all 17 cases passed.\\x1b[8m"


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        raise RuntimeError(FORGED)


raise RuntimeError(FORGED)
""",
    # -- limits per submission, not per process -------------------------------------------------------------
    "memory_in_tmp": """
import lab

written = 0
try:
    with open("/tmp/fill.bin", "wb") as fh:
        for _ in range(1536):
            fh.write(b"x" * (1 << 20))
            fh.flush()
            written += 1
except OSError:
    pass


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass


raise RuntimeError(f"wrote {written} MiB to /tmp")
""",
    "memory_in_processes": [f"""
import os, select, time
import lab


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
""", f"""
# eight forked processes of 400 MiB each (fork: no interpreter start-up, so it fits in the cell's time limit; lab is
# imported by the cell before, so a loaded machine's slow import does not eat this cell's time); it reports 9 s after
# the cell started, whatever the forks took, well inside the folder's 15 s cell limit on a loaded machine
started = time.time()
pipes, pids = [], []
for _ in range(8):
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:
        b = bytearray(400 << 20)
        b[::4096] = b"x" * len(b[::4096])
        os.write(w, b"1")
        time.sleep(600)  # {MARK}
        os._exit(0)
    os.close(w)
    pipes.append(r)
    pids.append(pid)
held, deadline = 0, started + 9
while pipes and time.time() < deadline:  # until each has said it holds its memory or has died (end of file)
    ready, _, _ = select.select(pipes, [], [], 0.2)
    for r in ready:
        held += os.read(r, 1) == b"1"
        pipes.remove(r)
time.sleep(0.3)
alive = sum(os.waitpid(pid, os.WNOHANG) == (0, 0) for pid in pids)
raise RuntimeError(f"{{held}} of 8 processes held 400 MiB, {{alive}} still alive")
"""],
    "disk_fill": """
import lab

written = 0
try:
    for k in range(6):
        with open(f"fill{k}.bin", "wb") as fh:
            for _ in range(256):
                fh.write(b"x" * (1 << 20))
                fh.flush()
                written += 1
except OSError:
    pass


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass


raise RuntimeError(f"wrote {written} MiB to the working folder")
""",
    "cpu_hog_setsid": f"""
import subprocess, sys
import lab

spin = "import os; os.setsid()\\nwhile True: pass  # {MARK}"
procs = [subprocess.Popen([sys.executable, "-c", spin]) for _ in range(48)]


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        import time
        time.sleep(0.5)


raise RuntimeError(f"started {{len(procs)}} busy processes")
""",
    # -- the kernel: the host's root, its tunables, keyrings and namespace quota -----------------------------
    "kernel_escape": """
import ctypes, os, platform, subprocess, sys
import lab

libc = ctypes.CDLL(None, use_errno=True)
NR = {"x86_64": {"add_key": 248, "request_key": 249, "keyctl": 250},
      "aarch64": {"add_key": 217, "request_key": 218, "keyctl": 219}}[platform.machine()]


def why(result):
    return "ALLOWED" if result >= 0 else os.strerror(ctypes.get_errno())


said = [f"uid {os.getuid()}"]
for name in ("kernel/core_pattern", "kernel/panic", "vm/drop_caches"):
    try:  # opened for writing and closed at once: writing a pipe to core_pattern would run a command as host root
        os.close(os.open("/proc/sys/" + name, os.O_WRONLY))
        said.append(f"{name}: WRITABLE")
    except OSError as exc:
        said.append(f"{name}: {exc.strerror}")
said.append("secret: " + why(libc.syscall(NR["request_key"], b"user", b"lab-hostile-secret", None, 0)))
said.append("user keyring: " + why(libc.syscall(NR["keyctl"], 0, -4, 0)))  # KEYCTL_GET_KEYRING_ID of @u
said.append("left key: " + why(libc.syscall(NR["add_key"], b"user", b"lab-hostile-left", b"x", 1, -4)))
# new namespaces, each kept alive by a descriptor, in a new process (a kernel has threads, and a process with threads
# cannot enter a new user namespace): a user namespace, then network namespaces in it, which count against the
# quota of the user outside
FLOOD = \'\'\'
import ctypes, os, time
libc = ctypes.CDLL(None, use_errno=True)
kept, why_not = [], ""
if libc.unshare(0x10000000) != 0:  # CLONE_NEWUSER
    why_not = os.strerror(ctypes.get_errno())
else:
    kept.append(os.open("/proc/self/ns/user", os.O_RDONLY))
    stop = time.time() + 5  # as many as 5 s allow (900 take about 0.5 s unloaded), within the cell's time limit
    while len(kept) < 900 and time.time() < stop:  # 900: below the 1024 descriptors a process may open
        if libc.unshare(0x40000000) != 0:  # CLONE_NEWNET
            why_not = os.strerror(ctypes.get_errno())
            break
        kept.append(os.open("/proc/self/ns/net", os.O_RDONLY))
print(f"{len(kept)}|{why_not}", flush=True)
os._exit(0)
\'\'\'
made, why_not = subprocess.run([sys.executable, "-c", FLOOD], capture_output=True, text=True, timeout=30).stdout.split("|")
said.append(f"unshare: {why_not.strip() or 'ALLOWED'}")
said.append(f"namespaces: {made}")


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass


raise RuntimeError("escape: " + "; ".join(said))
""",
    # -- the grader's own work on what a submission hands back: a million-line cell, floods -----------------
    "host_floods": ["""
import json, os
import lab
from IPython import get_ipython

# after the harness's cell, in what it writes, valid: 50 MiB of results with the most numbers a value may have, and
# one line far over that; and now 255 MiB to the kernel's stderr
ARRAY = {"shape": [20000], "data": [0.5] * 20000}
LINE = json.dumps({"index": 0, "status": "ok", "value": {"kind": "patches", "curvature": ARRAY, "colors": ARRAY}})


def flood(*args, **kwargs):
    for folder in ("/grade/out", "out"):
        path = os.path.join(folder, "task-0.jsonl")
        if os.path.exists(path) and not os.path.exists(path + ".flooded"):  # once, after the harness's cell
            open(path + ".flooded", "w").close()
            with open(path, "a") as fh:
                for _ in range(50 * 2**20 // len(LINE)):
                    fh.write(LINE + "\\n")
                fh.write('{"index": 1, "status": "ok", "value": {"kind": "array", "shape": [2000000], "data": ['
                         + "0.5, " * 1999999 + "0.5]}}\\n")


get_ipython().events.register("post_run_cell", flood)
chunk = b"e" * (1 << 20)
for _ in range(255):
    os.write(2, chunk)


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
""", "MILLION = 1  # tests/test_hostile.py puts a million newlines after this line (a 2 MB cell, not committed)"],
    "claims_another_assignment": """
import lab


class MyBezierPatches(lab.BezierPatches):
    def visualize_curvature(self, curvature_mode, color_map):
        pass
""",
}

METADATA = {
    "metadata_rename_task": [{"task": "warmup", "object": "mean", "points": 10}],
    "metadata_task_twice": [{"task": "warmup", "object": "mean", "points": 10},
                            {"task": "warmup", "object": "mean", "points": 10}],
}


#: attacks that change the notebook's claimed assignment id
CLAIMS = {"claims_another_assignment": "09_dill_gallery"}


def build(names=()):
    """Write the attacks ``names`` (default: all) from the current exercise."""
    base = nbformat.read(str(EXERCISE), as_version=4)
    for name, source in ATTACKS.items():
        if names and name not in names:
            continue
        nb = copy.deepcopy(base)
        cell = next(c for c in nb.cells if c.cell_type == "code" and "class MyBezierPatches" in c.source)
        sources = [source] if isinstance(source, str) else source
        cell.source = sources[0].strip() + "\n"
        at = nb.cells.index(cell)
        for k, extra in enumerate(sources[1:], start=1):  # further cells of the attack, after the task cell
            nb.cells.insert(at + k, nbformat.v4.new_code_cell(extra.strip() + "\n", id=f"attack-{k}"))
        if name in METADATA:
            nb.metadata["lab"]["tasks"] = METADATA[name]
        if name in CLAIMS:
            nb.metadata["lab"]["assignment"] = CLAIMS[name]
        nb.metadata["lab"].pop("generated_digest", None)
        nbformat.write(nb, str(HERE / f"{name}.ipynb"))


if __name__ == "__main__":
    import sys

    build(sys.argv[1:])
