"""The grader's sandbox: a submission runs with Debian's bubblewrap (``bwrap``), resource limits and a time limit.

Inside the sandbox the student's notebook sees:

* the operating system, Python and the virtual environment, read-only;
* a copy of the ``lab`` package in which the reference implementations of the graded tasks are withheld
  (their bodies replaced by an error, :func:`prepare_package`) and the teaching modules that hold cases,
  answers and hints are absent; it is mounted where the real package lives, so no import finds another;
* a private ``/tmp``, and as its only writable folder a fresh copy of the submission with the inputs;
* no network (a new network namespace with loopback only: nbclient and the kernel talk over it), its own
  process namespace (every process ends with the sandbox), no capabilities, nothing else of the course.

Limits apply to the submission as a whole where the cgroup file system is writable (:mod:`lab.teaching.cgroups`:
memory including what it writes to tmpfs, processes and threads, an equal CPU weight beside every other
submission) and to every process in it (writable data, CPU time, file size, open files).  Its working folder is
a tmpfs of :data:`DISK` bytes (root only) and its ``/tmp`` one of the same size.  Where ``bwrap`` cannot run, the
submission runs in its own session and process group with the same limits.  :attr:`Sandbox.missing` names
every protection that is missing; the grader shows them in each report, in ``summary.csv`` and on stderr,
and refuses to grade a folder without bubblewrap unless told to (``--no-sandbox``).
"""

import ast
import compileall
import contextlib
import functools
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

from ..i18n import N_, _
from . import cgroups
from .runner import stub_source

__all__ = ["Sandbox", "bwrap_works", "prepare_package", "probe"]

LAB_DIR = Path(__file__).resolve().parents[1]
#: Teaching modules the sandbox keeps: they call the student's code and hold no answers.
KEEP_TEACHING = ("__init__.py", "protocol.py", "harness.py", "child.py", "runner_client.py", "unfinished.py")
#: Read-only system folders and files (bound when present).
SYSTEM_PATHS = ("/usr", "/bin", "/sbin", "/lib", "/lib32", "/lib64", "/etc/alternatives", "/etc/ld.so.cache",
                "/etc/ld.so.conf", "/etc/ld.so.conf.d", "/etc/fonts", "/etc/passwd", "/etc/group",
                "/etc/nsswitch.conf", "/etc/localtime", "/etc/mime.types", "/usr/share/glvnd")
MEMORY = 2 << 30
#: Bytes a submission may write to its working folder, and to its /tmp.
DISK = 512 << 20
CPU_SECONDS = 900
FILE_SIZE = 256 << 20
OPEN_FILES = 1024
PROCESSES = 256  # processes and threads of a submission together (a kernel has about 10 threads)


def functions_named(tree, names, where):
    """``(qualified name within the module, node)`` of the functions and methods ``names`` in the module ``tree``;
    raises ``ValueError`` naming ``where`` when one is not there."""
    wanted, found = set(names), []

    def visit(body, prefix):
        for node in body:
            if isinstance(node, ast.ClassDef):
                visit(node.body, f"{prefix}{node.name}.")
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and f"{prefix}{node.name}" in wanted:
                found.append((f"{prefix}{node.name}", node))

    visit(tree.body, "")
    missing = wanted - {q for q, _ in found}
    if missing:
        raise ValueError(f"cannot withhold {sorted(missing)}: not found in {where}")
    return found


def strip_module(path, module, names):
    """Replace the bodies of the functions/methods ``names`` (dotted within ``module``) by the withheld stub,
    keeping their signatures and docstrings."""
    tree = ast.parse(path.read_text(), str(path))
    for qual, node in functions_named(tree, names, path):
        doc = [node.body[0]] if ast.get_docstring(node) else []
        node.body = doc + ast.parse(stub_source(f"{module}.{qual}")).body
    path.write_text(ast.unparse(tree) + "\n")


def _stub_check(task_names):
    lines = ['"""Checks are run by the grader, outside the notebook: in a graded run they do nothing."""', "",
             "TASKS = {}", "", "", "def _skip(name):", "    def check(*args, **kwargs):",
             "        print(f'check.{name}: checked by the grader')", "", "    return check", ""]
    lines += [f"{name} = TASKS[{name!r}] = _skip({name!r})" for name in task_names]
    return "\n".join(lines) + "\n"


def prepare_package(blocked, task_names, target):
    """A copy of the ``lab`` package at ``target/lab`` with ``blocked`` functions withheld; returns its path.

    ``blocked`` holds qualified names (``lab.geometry.curvature.from_derivatives``,
    ``lab.model.patches.BezierPatches.visualize_curvature``).  Of ``lab/teaching`` only the modules that
    call the student's code remain (no cases, answers or hints), and ``check`` is a stub whose functions
    print that the grader checks.
    """
    dest = Path(target) / "lab"
    shutil.copytree(LAB_DIR, dest, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    for f in (dest / "teaching").iterdir():
        if f.name not in KEEP_TEACHING:
            shutil.rmtree(f) if f.is_dir() else f.unlink()
    (dest / "teaching" / "check.py").write_text(_stub_check(task_names))
    for (file, module), names in by_module_file(blocked, dest).items():
        strip_module(file, module, names)
    compileall.compile_dir(str(dest), quiet=1, workers=1)
    return dest


def by_module_file(qualnames, package):
    """``{(file, module): [names within the module]}`` for qualified names of functions in the ``lab`` copy ``package``."""
    by_module = {}
    for qual in qualnames:
        parts = qual.split(".")
        for cut in range(len(parts) - 1, 1, -1):
            file = Path(package).joinpath(*parts[1:cut]).with_suffix(".py")
            if file.is_file():
                by_module.setdefault((file, ".".join(parts[:cut])), []).append(".".join(parts[cut:]))
                break
        else:
            raise ValueError(f"cannot withhold {qual!r}: no such module in lab")
    return by_module


@functools.lru_cache(maxsize=1)
def bwrap_works():
    """Whether ``bwrap`` exists and can create the namespaces the sandbox needs here."""
    exe = shutil.which("bwrap")
    if exe is None:
        return False
    try:
        done = subprocess.run([exe, "--unshare-net", "--unshare-pid", "--die-with-parent", "--ro-bind", "/", "/",
                               "--proc", "/proc", "--dev", "/dev", "true"], capture_output=True, timeout=30, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return done.returncode == 0


#: What a run without bubblewrap lacks (translated when shown).
WITHOUT_BWRAP = (N_("filesystem isolation (the course's files are readable)"), N_("network isolation"),
                 N_("process isolation (a process that starts its own session can outlive the grading)"))
#: Limits of a submission as a whole, and the missing protection each one's absence means.
MISSING = {"memory limit per submission": N_("memory limit per submission (including /tmp): each process has its own"),
           "process count limit": N_("process count limit (no writable pids cgroup; root ignores RLIMIT_NPROC)"),
           "equal CPU share": N_("equal CPU share (no writable cpu cgroup: a submission with many processes slows "
                                 "the others)"),
           "disk budget": N_("disk budget for the working folder (no tmpfs could be mounted: only the file size is "
                             "limited)")}


class Sandbox:
    """Runs a command for one submission with the protections available here; see the module docstring.

    Parameters
    ----------
    package : Path
        The prepared ``lab`` copy (:func:`prepare_package`).
    workdir : Path
        The submission's fresh folder (the only writable place); it appears as ``/grade`` inside.
    memory : int
        Memory of the whole submission, bytes: all its processes together and what they write to ``/tmp``
        and the working folder (a memory cgroup); also the limit of writable data per process.
    disk : int
        Bytes the submission may write into its working folder (a size-limited tmpfs) and into ``/tmp``.
    use_bwrap : bool or None
        None: use it when it works here.
    lang : str
        The language of the messages produced inside (``LAB_LANG``).
    """

    def __init__(self, package, workdir, *, memory=MEMORY, disk=DISK, use_bwrap=None, lang="en"):
        self.package = Path(package)
        self.lang = lang
        self.workdir = Path(workdir)
        self.memory = int(memory)
        self.disk = int(disk)
        self.bwrap = bwrap_works() if use_bwrap is None else bool(use_bwrap)
        self.missing = [] if self.bwrap else [_(m) for m in WITHOUT_BWRAP]
        self.cgroup = None
        self.peak_memory = None

    @property
    def inside(self):
        """Where the submission's folder appears to the code in the sandbox."""
        return Path("/grade") if self.bwrap else self.workdir

    @contextlib.contextmanager
    def workspace(self):
        """The working folder for the block, on a tmpfs of :attr:`disk` bytes where one can be mounted."""
        self.workdir.mkdir(parents=True, exist_ok=True)
        with cgroups.mount_budget(self.workdir, self.disk) as mounted:
            if not mounted:
                self._missing("disk budget")
            yield self.workdir

    def _missing(self, key):
        text = _(MISSING[key])
        if text not in self.missing:
            self.missing.append(text)

    def _env(self):
        home = "/tmp/home" if self.bwrap else str(self.workdir / ".home")
        env = {
            "PATH": f"{Path(sys.executable).parent}:/usr/local/bin:/usr/bin:/bin",
            "HOME": home, "LANG": "C.UTF-8", "LAB_LANG": self.lang, "LAB_GRADING": "1", "LAB_STATIC": "1",
            "PYVISTA_OFF_SCREEN": "true", "VTK_DEFAULT_OPENGL_WINDOW": "vtkEGLRenderWindow", "MPLBACKEND": "Agg",
            "MPLCONFIGDIR": f"{home}/mpl", "IPYTHONDIR": f"{home}/ipython", "JUPYTER_RUNTIME_DIR": f"{home}/runtime",
            "JUPYTER_DATA_DIR": f"{home}/data", "JUPYTER_CONFIG_DIR": f"{home}/config",
            "PYTHONDONTWRITEBYTECODE": "1", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
            "MKL_NUM_THREADS": "1", "PYTHONHASHSEED": "0", "LP_NUM_THREADS": "1",
        }
        # the copy is found first, whatever else the interpreter would find (an editable install's finder
        # points at a source tree the sandbox does not show)
        env["PYTHONPATH"] = str(LAB_DIR.parent if self.bwrap else self.package.parent)
        if not self.bwrap:
            env["TMPDIR"] = str(self.workdir / ".tmp")  # on the working folder's budget, not the host's /tmp
        return env

    def command(self, argv):
        if not self.bwrap:
            return list(argv)
        cmd = [shutil.which("bwrap"), "--unshare-net", "--unshare-pid", "--unshare-ipc", "--unshare-uts",
               "--unshare-cgroup-try", "--die-with-parent", "--new-session", "--cap-drop", "ALL",
               # the private /tmp first: the binds below go on top of it (a course checked out under /tmp
               # keeps its Python and its lab copy visible); its size is capped (it is host memory)
               "--size", str(self.disk), "--tmpfs", "/tmp", "--dir", "/tmp/home", "--proc", "/proc", "--dev", "/dev"]
        for p in SYSTEM_PATHS:
            cmd += ["--ro-bind-try", p, p]
        for p in sorted({sys.base_prefix, sys.prefix, str(Path(sys.executable).resolve().parent.parent)}):
            cmd += ["--ro-bind", p, p]
        cmd += ["--ro-bind", str(self.package), str(LAB_DIR),
                "--bind", str(self.workdir), "/grade", "--chdir", "/grade", "--clearenv"]
        for k, v in self._env().items():
            cmd += ["--setenv", k, v]
        return cmd + list(argv)

    def _limits(self):
        """The launcher's limits (:mod:`lab.teaching.launch`): per process, and the submission's cgroups."""
        rlimits = {"data": self.memory, "cpu": CPU_SECONDS, "fsize": FILE_SIZE, "nofile": OPEN_FILES, "core": 0}
        if os.getuid() != 0:
            rlimits["nproc"] = PROCESSES
        return {"rlimits": rlimits, "cgroups": [str(p) for p in self.cgroup.procs] if self.cgroup else []}

    def run(self, argv, timeout):
        """Run ``argv`` in the sandbox for at most ``timeout`` seconds; every process it started ends with it.

        Returns ``(returncode, timed_out, stderr_tail)``.
        """
        self.cgroup, missing = cgroups.create(self.memory, PROCESSES)
        for key in missing:
            if key != "process count limit" or os.getuid() == 0:  # RLIMIT_NPROC counts where not root
                self._missing(key)
        env = None if self.bwrap else {**self._env()}
        if not self.bwrap:
            Path(env["HOME"]).mkdir(exist_ok=True)
            Path(env["TMPDIR"]).mkdir(exist_ok=True)
        with tempfile.NamedTemporaryFile("w", suffix=".json", prefix="lab-limits-", delete=False) as fh:
            json.dump(self._limits(), fh)
        # the launcher as a script in isolated mode: it needs no lab, and the child's PYTHONPATH must not matter
        launcher = [sys.executable, "-I", str(Path(__file__).with_name("launch.py")), fh.name, "--"]
        with tempfile.TemporaryFile() as err:
            try:
                proc = subprocess.Popen(launcher + self.command(argv), stdin=subprocess.DEVNULL,
                                        stdout=subprocess.DEVNULL, stderr=err, env=env, cwd=str(self.workdir),
                                        start_new_session=True)
                timed_out = False
                try:
                    proc.wait(timeout=timeout)
                except subprocess.TimeoutExpired:
                    timed_out = True
                finally:
                    self._kill(proc)
            finally:
                os.unlink(fh.name)
            err.seek(0)
            tail = err.read()[-4000:].decode("utf-8", "replace")
        return proc.returncode, timed_out, tail

    def _kill(self, proc):
        """End the sandbox and everything in it: its process group, then any process left in its cgroup."""
        with contextlib.suppress(OSError):
            os.killpg(proc.pid, signal.SIGKILL)
        with contextlib.suppress(OSError):
            proc.kill()
        proc.wait()
        if self.cgroup is not None:
            self.peak_memory = self.cgroup.peak_memory()
            self.cgroup.remove()


def probe(*, use_bwrap=None, timeout=300):
    """Whether a submission's kernel can start here: import the grader's child in a sandbox with the library.

    Returns None, or what went wrong (the end of its stderr).  A folder run calls it first, so a broken
    installation (the sandbox cannot import ``lab``, no Python inside) stops the run instead of giving every
    student 0 points.
    """
    with tempfile.TemporaryDirectory(prefix="lab-probe-") as tmp:
        box = Sandbox(LAB_DIR, Path(tmp) / "work", use_bwrap=use_bwrap)
        with box.workspace():
            code, timed_out, stderr = box.run([sys.executable, "-c", "import lab.teaching.child"], timeout)
    if timed_out:
        return f"importing the lab in the sandbox took more than {timeout:g} s"
    if code != 0:
        return stderr.strip()[-1500:] or f"exit status {code}"
    return None
