"""Limits for a whole submission, not per process: Linux control groups (v1 or v2) and a size-capped folder.

One :class:`Cgroup` per graded submission, created below the grader's own control groups:

* **memory** (v1 ``memory.limit_in_bytes`` and ``memory.memsw.limit_in_bytes``, v2 ``memory.max`` and
  ``memory.swap.max = 0`` where the host has swap): every process of the submission together,
  including the pages it writes to a tmpfs (its private ``/tmp`` and its working folder), so six processes
  of 400 MiB or 1.5 GiB written to ``/tmp`` meet one limit;
* **pids** (``pids.max``): processes and threads together, so a fork bomb stops at the cap;
* **cpu** (v1 ``cpu.shares``, v2 ``cpu.weight``): every submission has the same weight whatever the number of
  its processes, so 48 busy processes share one submission's part of the CPU, not 48 parts.

Where the cgroup file system is not writable (no root, a read-only container) :func:`create` returns None
and the names of the missing protections; the sandbox then falls back to per-process limits and says so.

:func:`mount_budget` mounts a size-limited tmpfs on the submission's working folder (root only), so the
files a submission writes cannot fill the host's disk.
"""

import contextlib
import os
import signal
import subprocess
import time
import uuid
from pathlib import Path

__all__ = ["Cgroup", "create", "mount_budget"]

ROOT = Path("/sys/fs/cgroup")
#: v1 controllers used, and the v2 files that do the same.
V1 = ("memory", "pids", "cpu")


def _own_paths():
    """``{controller: path}`` of this process's cgroups (v1), and ``""`` for the v2 hierarchy."""
    paths = {}
    with contextlib.suppress(OSError):
        for line in Path("/proc/self/cgroup").read_text().splitlines():
            _, controllers, path = line.split(":", 2)
            for c in controllers.split(",") if controllers else [""]:
                paths[c] = path
    return paths


def _write(path, value):
    path.write_text(str(value))


class Cgroup:
    """The control groups of one submission (see the module docstring).  ``dirs``: one folder per controller."""

    def __init__(self, dirs, version):
        self.dirs, self.version = dirs, version

    @property
    def procs(self):
        """The ``cgroup.procs`` files a new process is added to (one per v1 hierarchy)."""
        return [d / "cgroup.procs" for d in self.dirs.values()]

    def attach(self, pid=None):
        """Put ``pid`` (default: this process; used right after fork) into every group."""
        pid = os.getpid() if pid is None else pid
        for procs in self.procs:
            with open(procs, "w") as fh:
                fh.write(str(pid))

    def pids(self):
        found = set()
        for procs in self.procs:
            with contextlib.suppress(OSError, ValueError):
                found |= {int(p) for p in procs.read_text().split()}
        return found

    def peak_memory(self):
        """Largest memory use of the submission so far (bytes), or None."""
        d = self.dirs.get("memory")
        for name in ("memory.max_usage_in_bytes", "memory.peak"):
            with contextlib.suppress(OSError, ValueError):
                return int((d / name).read_text())
        return None

    def kill(self):
        """SIGKILL every process in the groups, until none is left (at most about 5 s)."""
        for _attempt in range(100):
            pids = self.pids()
            if not pids:
                return
            for pid in pids:
                with contextlib.suppress(OSError):
                    os.kill(pid, signal.SIGKILL)
            time.sleep(0.05)

    def remove(self):
        self.kill()
        for d in self.dirs.values():
            for _attempt in range(20):
                try:
                    d.rmdir()
                    break
                except FileNotFoundError:
                    break
                except OSError:
                    time.sleep(0.05)


def _no_swap(d):
    """v2 on a host with swap: a submission at its memory limit is killed instead of paging out to the disk
    (which slows every other submission); nothing where the kernel has no swap accounting."""
    if (d / "memory.swap.max").exists():
        with contextlib.suppress(OSError):
            _write(d / "memory.swap.max", 0)


def create(memory, processes, *, root=ROOT):
    """A fresh :class:`Cgroup` limiting a submission to ``memory`` bytes and ``processes`` tasks with the same
    CPU weight as every other submission; returns ``(cgroup or None, [names of missing limits])``."""
    own = _own_paths()
    name = f"lab-grade-{uuid.uuid4().hex[:12]}"
    dirs, missing = {}, []
    v2 = root / "cgroup.controllers"
    if v2.is_file():  # a pure v2 system: one folder, the controllers that the parent delegates
        base = root / own.get("", "/").lstrip("/")
        d = base / name
        try:
            d.mkdir()
        except OSError:
            return None, ["memory limit per submission", "process count limit", "equal CPU share"]
        dirs["unified"] = d
        for file, value, what in (("memory.max", memory, "memory limit per submission"),
                                  ("pids.max", processes, "process count limit"),
                                  ("cpu.weight", 100, "equal CPU share")):
            try:
                _write(d / file, value)
            except OSError:
                missing.append(what)
        _no_swap(d)
        return Cgroup(dirs, 2), missing
    for controller, settings, what in (
            ("memory", (("memory.limit_in_bytes", memory), ("memory.memsw.limit_in_bytes", memory)),
             "memory limit per submission"),
            ("pids", (("pids.max", processes),), "process count limit"),
            ("cpu", (("cpu.shares", 1024),), "equal CPU share")):
        base = root / controller / own.get(controller, "/").lstrip("/")
        d = base / name
        try:
            d.mkdir()
        except OSError:
            missing.append(what)
            continue
        try:
            for file, value in settings:
                if (d / file).exists() or file == settings[0][0]:
                    _write(d / file, value)
        except OSError:
            with contextlib.suppress(OSError):
                d.rmdir()
            missing.append(what)
            continue
        dirs[controller] = d
    return (Cgroup(dirs, 1) if dirs else None), missing


@contextlib.contextmanager
def mount_budget(folder, size, owner=None):
    """Mount a tmpfs of ``size`` bytes on ``folder`` for the block (root only), owned by the user and group id
    ``owner`` (default: root); yields whether it worked."""
    folder = Path(folder)
    mounted = False
    if os.geteuid() == 0:
        ids = f",uid={int(owner)},gid={int(owner)}" if owner is not None else ""
        done = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={int(size)},mode=0700,nosuid,nodev{ids}",
                               "lab-grade", str(folder)], capture_output=True, check=False)
        mounted = done.returncode == 0
    try:
        yield mounted
    finally:
        if mounted:
            for _attempt in range(20):
                if subprocess.run(["umount", str(folder)], capture_output=True, check=False).returncode == 0:
                    break
                time.sleep(0.1)
            else:
                subprocess.run(["umount", "-l", str(folder)], capture_output=True, check=False)
