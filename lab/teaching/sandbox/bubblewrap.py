"""The grader's sandbox: a submission runs with Debian's bubblewrap (``bwrap``), resource limits and a time limit.

Inside the sandbox the student's notebook sees:

* the operating system, Python and the virtual environment, read-only;
* a copy of the ``lab`` package in which the reference implementations of the graded tasks are withheld
  (their bodies replaced by an error, :func:`prepare_package`) and the teaching modules that hold cases,
  answers and hints are absent; it is mounted where the real package lives, so no import finds another;
* a private ``/tmp``, and as its only writable folder a fresh copy of the submission with the inputs;
* no network (a new network namespace with loopback only: nbclient and the kernel talk over it), its own
  process namespace (every process ends with the sandbox), no capabilities, nothing else of the course.

**Never the host's root inside.**  Two bubblewraps nest (:meth:`Sandbox.command`): the outer one, started by the
grader, builds what the submission sees (it can read any path the grader can) with the kernel's tunables
(``/proc/sys``, ``/proc/sysrq-trigger``, ``/proc/irq``, ``/proc/bus``) bound read-only; where the grader is root it
then drops to a **fresh unprivileged user id** (:data:`UID_BASE` + a random number, owned by no account, one per
submission: its own keyring, its own per-user quotas; :data:`DROP`).  The inner one makes a **user namespace**
(uid and gid :data:`INSIDE_ID` inside, that unprivileged id outside; where the grader is not root, the grader's own
id) and loads the **seccomp filter** of :mod:`lab.teaching.sandbox.seccomp` (no keyrings, no new namespaces, no mounts, no
``ptrace``, ``bpf``, ``perf_event_open``, modules, ``kexec`` …) before the submission's first instruction.  The
launcher (:mod:`lab.teaching.sandbox.launch`) gives the sandbox a fresh session keyring.  :func:`probe` checks each of these
from the inside before a folder is graded.

Limits apply to the submission as a whole where the cgroup file system is writable (:mod:`lab.teaching.sandbox.cgroups`:
memory including what it writes to tmpfs, processes and threads, an equal CPU weight beside every other
submission) and to every process in it (writable data, CPU time, file size, open files, processes of its user).
Its working folder is a tmpfs of :data:`DISK` bytes (root only) and its ``/tmp`` one of the same size; what it
writes to stderr reaches the grader through a pipe of which only the last :data:`STDERR_TAIL` bytes are kept.
Where ``bwrap`` cannot run, the submission runs in its own session and process group with the same limits.
:attr:`Sandbox.missing` names every protection that is missing; the grader shows them in each report, in
``summary.csv`` and on stderr, and refuses to grade a folder without them unless told to (``--no-sandbox``).
"""

import contextlib
import functools
import json
import os
import secrets
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

from ... import library
from ...i18n import N_, _
from . import cgroups, seccomp

__all__ = ["INSIDE_ID", "UID_BASE", "Sandbox", "bwrap_works", "probe"]

LAB_DIR = Path(library())
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
#: Where the grader is root, each submission runs as ``UID_BASE + k`` outside (k random below :data:`UID_SPAN`):
#: far above the ids of accounts and of the subordinate ranges that useradd hands out (100000 + 65536 per user).
UID_BASE = 2_000_000_000
UID_SPAN = 1 << 26
#: The submission's user and group id inside its user namespace.
INSIDE_ID = 1000
#: Run between the two bubblewraps where the grader is root: become the submission's user (``argv[1]``), with no
#: supplementary groups (the change of user clears the capabilities the outer bubblewrap kept for it), then the rest.
DROP = "import os, sys; u = int(sys.argv[1]); os.setgroups([]); os.setgid(u); os.setuid(u); os.execv(sys.argv[2], sys.argv[2:])"
#: The kernel's tunables and switches, bound read-only over the sandbox's /proc (bubblewrap skips its own cover
#: of /proc/sys when it runs as root).
KERNEL_TUNABLES = ("/proc/sys", "/proc/sysrq-trigger", "/proc/irq", "/proc/bus")
#: Bytes of a submission's stderr kept (the end); the rest is read and dropped.
STDERR_TAIL = 4000


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
                 N_("process isolation (a process that starts its own session can outlive the grading)"),
                 N_("a user namespace and a syscall filter (the submission runs as the grader's user)"))
#: Limits of a submission as a whole, and the missing protection each one's absence means.
MISSING = {"memory limit per submission": N_("memory limit per submission (including /tmp): each process has its own"),
           "process count limit": N_("process count limit (no writable pids cgroup; root ignores RLIMIT_NPROC)"),
           "equal CPU share": N_("equal CPU share (no writable cpu cgroup: a submission with many processes slows "
                                 "the others)"),
           "disk budget": N_("disk budget for the working folder (no tmpfs could be mounted: only the file size is "
                             "limited)"),
           "syscall filter": N_("syscall filter (libseccomp is missing: apt install libseccomp2, pip install "
                                "pyseccomp): the submission can use keyrings and create namespaces")}


def _ancestors(path):
    """The folders above ``path``, from the top (``/a/b/c`` → ``/a``, ``/a/b``)."""
    parts = Path(path).parts[1:-1]
    return [str(Path("/", *parts[:k])) for k in range(1, len(parts) + 1)]


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
    hide : sequence of str
        Folders and files of the host (installed packages, e.g. OpenCASCADE's ``OCP``) covered by an empty folder or
        file inside.
    """

    def __init__(self, package, workdir, *, memory=MEMORY, disk=DISK, use_bwrap=None, lang="en", hide=()):
        self.package = Path(package)
        self.lang = lang
        self.workdir = Path(workdir)
        self.memory = int(memory)
        self.disk = int(disk)
        self.hide = tuple(str(h) for h in hide)
        self.bwrap = bwrap_works() if use_bwrap is None else bool(use_bwrap)
        self.missing = [] if self.bwrap else [_(m) for m in WITHOUT_BWRAP]
        #: Whether the sandbox drops from the grader's root to :attr:`user` (outside its user namespace).
        self.drop = self.bwrap and os.geteuid() == 0
        #: The submission's user id outside its user namespace.
        self.user = UID_BASE + secrets.randbelow(UID_SPAN) if self.drop else os.getuid()
        self.filtered = self.bwrap and seccomp.available()
        if self.bwrap and not self.filtered:
            self._missing("syscall filter")
        self.cgroup = None
        self.peak_memory = None

    @property
    def inside(self):
        """Where the submission's folder appears to the code in the sandbox."""
        return Path("/grade") if self.bwrap else self.workdir

    @contextlib.contextmanager
    def workspace(self):
        """The working folder for the block, on a tmpfs of :attr:`disk` bytes where one can be mounted, owned by
        the submission's user."""
        self.workdir.mkdir(parents=True, exist_ok=True)
        with cgroups.mount_budget(self.workdir, self.disk, owner=self.user if self.drop else None) as mounted:
            if not mounted:
                self._missing("disk budget")
            yield self.workdir

    def hand_over(self):
        """Give everything in the working folder to the submission's user (the grader wrote it as root)."""
        if not self.drop:
            return
        os.chown(self.workdir, self.user, self.user)
        for here, dirs, files in os.walk(self.workdir):
            for name in dirs + files:
                os.chown(os.path.join(here, name), self.user, self.user, follow_symlinks=False)

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

    def _binds(self):
        """``(source, destination)`` of the read-only binds: the system, Python, the library copy."""
        binds = [(p, p) for p in SYSTEM_PATHS if os.path.exists(p)]
        binds += [(p, p) for p in sorted({sys.base_prefix, sys.prefix, str(Path(sys.executable).resolve().parent.parent)})]
        return binds + [(str(self.package), str(LAB_DIR))]

    def command(self, argv, seccomp_fd=None):
        """The command line that runs ``argv`` in the sandbox (``argv`` itself without bubblewrap).

        ``seccomp_fd``: an inherited descriptor from which the inner bubblewrap reads the compiled filter.
        """
        if not self.bwrap:
            return list(argv)
        bwrap = shutil.which("bwrap")
        outer = [bwrap, "--unshare-net", "--unshare-pid", "--unshare-ipc", "--unshare-uts", "--unshare-cgroup-try",
                 "--die-with-parent", "--new-session", "--cap-drop", "ALL"]
        if self.drop:  # kept only to become the submission's user below (DROP); the change of user clears them
            outer += ["--cap-add", "CAP_SETUID", "--cap-add", "CAP_SETGID"]
        outer += ["--proc", "/proc"]
        for p in KERNEL_TUNABLES:
            outer += ["--ro-bind-try", p, p]
        outer += ["--dev", "/dev"]
        binds = sorted(self._binds(), key=lambda b: (len(Path(b[1]).parts), b[1]))
        made = set()
        for source, dest in binds:
            # folders above a bind that no bind provides: made world-readable (bubblewrap makes them 0700, and
            # the submission's user must pass through /root/… or /home/… to reach Python)
            for folder in _ancestors(dest):
                if folder not in made and not any(folder == d or folder.startswith(d.rstrip("/") + "/")
                                                  for _source, d in binds):
                    outer += ["--perms", "0755", "--dir", folder]
                    made.add(folder)
            outer += ["--ro-bind", source, dest]
        for path in self.hide:  # an empty folder over a package, an empty file over a module or library
            outer += ["--tmpfs", path] if os.path.isdir(path) else ["--ro-bind", "/dev/null", path]
        outer += ["--bind", str(self.workdir), "/grade", "--dir", "/tmp"]
        drop = [sys.executable, "-I", "-S", "-c", DROP, str(self.user)] if self.drop else []
        inner = [bwrap, "--unshare-user", "--uid", str(INSIDE_ID), "--gid", str(INSIDE_ID), "--die-with-parent",
                 "--cap-drop", "ALL"]
        if seccomp_fd is not None:
            inner += ["--seccomp", str(seccomp_fd)]
        # the private /tmp (its size capped: it is host memory) and HOME in it, made by the submission's user
        inner += ["--ro-bind", "/", "/", "--bind", "/grade", "/grade", "--dev", "/dev",
                  "--size", str(self.disk), "--tmpfs", "/tmp", "--dir", "/tmp/home"]
        for _source, dest in binds:  # a course checked out under /tmp keeps its Python and its lab copy visible
            if dest.startswith("/tmp/"):
                inner += ["--ro-bind", dest, dest]
        inner += ["--chdir", "/grade", "--clearenv"]
        for k, v in self._env().items():
            inner += ["--setenv", k, v]
        return outer + drop + inner + list(argv)

    def _limits(self):
        """The launcher's limits (:mod:`lab.teaching.sandbox.launch`): per process, the submission's cgroups, and the
        number of the ``keyctl`` call that gives it a fresh session keyring."""
        rlimits = {"data": self.memory, "cpu": CPU_SECONDS, "fsize": FILE_SIZE, "nofile": OPEN_FILES, "core": 0}
        if os.getuid() != 0 or self.drop:  # counted per user: the grader's, or the submission's own
            rlimits["nproc"] = PROCESSES
        return {"rlimits": rlimits, "cgroups": [str(p) for p in self.cgroup.procs] if self.cgroup else [],
                "keyctl": seccomp.syscall_number("keyctl") if self.bwrap else None}

    def run(self, argv, timeout):
        """Run ``argv`` in the sandbox for at most ``timeout`` seconds; every process it started ends with it.

        Returns ``(returncode, timed_out, stderr_tail)``: the last :data:`STDERR_TAIL` bytes of stderr.
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
        with contextlib.ExitStack() as stack:
            stack.callback(os.unlink, fh.name)
            filt = None
            if self.filtered:
                filt = stack.enter_context(tempfile.TemporaryFile())
                filt.write(seccomp.bpf())
                filt.flush()
                filt.seek(0)
            read_end, write_end = os.pipe()
            tail = _Tail(read_end)
            try:
                proc = subprocess.Popen(launcher + self.command(argv, None if filt is None else filt.fileno()),
                                        stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=write_end,
                                        env=env, cwd=str(self.workdir), start_new_session=True,
                                        pass_fds=() if filt is None else (filt.fileno(),))
            finally:
                os.close(write_end)
            tail.start()
            timed_out = False
            try:
                proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                timed_out = True
            finally:
                self._kill(proc)
                text = tail.finish()
        return proc.returncode, timed_out, text

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


class _Tail(threading.Thread):
    """Reads a pipe to its end and keeps the last :data:`STDERR_TAIL` bytes (255 MiB written to stderr cost the
    grader neither memory nor disk)."""

    def __init__(self, fd):
        super().__init__(daemon=True)
        self.fd, self.kept, self.dropped = fd, bytearray(), 0

    def run(self):
        with contextlib.suppress(OSError):
            while chunk := os.read(self.fd, 1 << 16):
                self.kept += chunk
                if len(self.kept) > STDERR_TAIL:
                    self.dropped += len(self.kept) - STDERR_TAIL
                    del self.kept[:-STDERR_TAIL]

    def finish(self, wait=5.0):
        """The kept text, once the writers are gone (a process that escaped the kill holds the pipe: not waited
        for longer than ``wait`` seconds)."""
        self.join(wait)
        with contextlib.suppress(OSError):
            os.close(self.fd)
        return bytes(self.kept).decode("utf-8", "replace")


#: What :func:`probe` runs inside: each protection tried from the inside, the answers as JSON in probe.json.
PROBE = r"""
import ctypes, json, os, sys
libc, found = ctypes.CDLL(None, use_errno=True), {"uid": os.getuid(), "gid": os.getgid()}
def failed(result):
    return "allowed" if result >= 0 else os.strerror(ctypes.get_errno())
try:
    os.close(os.open("/proc/sys/kernel/core_pattern", os.O_WRONLY))  # opened, never written
    found["proc_sys"] = "writable"
except OSError as exc:
    found["proc_sys"] = exc.strerror
keyctl = json.loads(sys.argv[1])
found["keyring"] = failed(libc.syscall(keyctl, 0, -4, 0)) if keyctl else "not tried"  # the user keyring's id
found["unshare"] = failed(libc.unshare(0x10000000))  # a new user namespace
found["proc_sys_mount"] = next((l.split()[5].split(",")[0] for l in open("/proc/self/mountinfo")
                                if l.split()[4] == "/proc/sys"), "not mounted")
found["seccomp"] = next((l.split()[1] for l in open("/proc/self/status") if l.startswith("Seccomp:")), "?")
import lab.teaching.kernel.graded_run
with open("probe.json", "w") as fh:
    json.dump(found, fh)
"""


def _protections(found, owner):
    """What the probe's answers say is missing (English; the grader refuses to grade a folder then)."""
    missing = []
    if found.get("uid") == 0 or found.get("gid") == 0:
        missing.append("an unprivileged user inside (the submission is uid 0 in its sandbox)")
    if owner == 0:
        missing.append("an unprivileged user outside (what the submission writes belongs to the host's root)")
    if found.get("proc_sys") == "writable":
        missing.append("read-only kernel tunables (/proc/sys/kernel/core_pattern opens for writing)")
    elif found.get("proc_sys_mount") != "ro":
        missing.append("read-only kernel tunables (/proc/sys is not a read-only mount)")
    if found.get("keyring") == "allowed":
        missing.append("keyring isolation (keyctl reaches a keyring)")
    if found.get("unshare") == "allowed":
        missing.append("no new namespaces (unshare of a user namespace works)")
    if found.get("seccomp") != "2":
        missing.append("a syscall filter (seccomp is not in filter mode)")
    return missing


def probe(*, use_bwrap=None, timeout=300):
    """Whether a submission's kernel can start here, and which protections its sandbox lacks.

    Runs a script in a sandbox that imports the grader's child and tries, from the inside, what a hostile
    submission would: its user ids, opening ``/proc/sys/kernel/core_pattern`` for writing, reaching the user keyring,
    creating a user namespace, the seccomp mode; the grader checks who owns the file it wrote.

    Returns ``(error, missing)``: ``error`` is None or what went wrong (the end of its stderr); ``missing`` the
    protections the sandbox lacks (empty without bubblewrap, where the grader says so itself).  A folder run calls
    it first, so a broken installation stops the run instead of giving every student 0 points, and a sandbox that
    is not what this module promises stops it unless ``--no-sandbox``.
    """
    with tempfile.TemporaryDirectory(prefix="lab-probe-") as tmp:
        box = Sandbox(LAB_DIR, Path(tmp) / "work", use_bwrap=use_bwrap)
        with box.workspace() as work:
            box.hand_over()
            keyctl = seccomp.syscall_number("keyctl")
            code, timed_out, stderr = box.run([sys.executable, "-c", PROBE, json.dumps(keyctl)], timeout)
            report = work / "probe.json"
            found = json.loads(report.read_text()) if report.is_file() and not report.is_symlink() else None
            owner = report.stat().st_uid if found is not None else None
    if timed_out:
        return f"importing the lab in the sandbox took more than {timeout:g} s", []
    if code != 0 or found is None:
        return stderr.strip()[-1500:] or f"exit status {code}", []
    return None, _protections(found, owner) if box.bwrap else []
