"""Start a graded submission's process with its limits: ``python -I launch.py LIMITS.json -- COMMAND…``.

Runs outside the sandbox, between the grader and ``bwrap`` (or the child itself where bubblewrap is
missing): it dies with the grader (``PR_SET_PDEATHSIG``), sets the per-process resource limits, joins the
submission's control groups (:mod:`lab.teaching.sandbox.cgroups`), joins a fresh, empty session keyring (nothing the
grader's session holds is inherited; the sandbox's syscall filter then denies every keyring call) and then
becomes the command (``exec``), so every process the submission starts inherits all of them.  A launcher instead of ``preexec_fn``: the
grader forks from several threads at once, where ``preexec_fn`` is not safe.
"""

import contextlib
import ctypes
import json
import os
import resource
import signal
import sys

#: Resource limits by name (values in the LIMITS file).
RLIMITS = {"data": resource.RLIMIT_DATA, "cpu": resource.RLIMIT_CPU, "fsize": resource.RLIMIT_FSIZE,
           "nofile": resource.RLIMIT_NOFILE, "core": resource.RLIMIT_CORE, "nproc": resource.RLIMIT_NPROC}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) < 3 or argv[1] != "--":
        print("usage: python -I launch.py LIMITS.json -- COMMAND …", file=sys.stderr)
        return 2
    with open(argv[0]) as fh:
        limits = json.load(fh)
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    if os.getppid() == 1:  # the grader died before the line above
        return 1
    for name, value in limits.get("rlimits", {}).items():
        resource.setrlimit(RLIMITS[name], (value, value))
    for procs in limits.get("cgroups", []):
        with open(procs, "w") as fh:
            fh.write(str(os.getpid()))
    if limits.get("keyctl") is not None:  # KEYCTL_JOIN_SESSION_KEYRING with no name: a new anonymous keyring
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.syscall(limits["keyctl"], 1, None) < 0:
            print(f"launch: cannot join a fresh session keyring ({os.strerror(ctypes.get_errno())})", file=sys.stderr)
            return 1
    command = argv[2:]
    os.execvp(command[0], command)
    return 1  # pragma: no cover


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
