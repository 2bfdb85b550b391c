"""The system calls a graded submission may not make: a seccomp filter in the manner of Docker's and Flatpak's
default profiles, compiled by libseccomp (through ``pyseccomp``, its ctypes bindings) for bubblewrap's
``--seccomp FD``.

Everything is allowed except what can reach beyond the submission's own sandbox or the limits it shares with
the host and the other submissions:

* **keyrings** (``keyctl``, ``add_key``, ``request_key``): a key planted by root on the host, or left by
  another submission, could be read or written (a channel between students);
* **namespaces** (``unshare``, ``setns``, ``clone`` with a ``CLONE_NEW*`` flag; ``clone3``, whose flags a filter
  cannot read, answers ``ENOSYS`` so that the C library falls back to ``clone``): thousands of namespaces use up
  the host's quota and a classmate's sandbox cannot start;
* **mounts and the root** (``mount``, ``umount2``, ``pivot_root``, ``chroot``, the new mount API), **tracing and
  other processes' memory** (``ptrace``, ``process_vm_readv``/``writev``, ``kcmp``), **the kernel's own
  facilities** (``bpf``, ``perf_event_open``, ``userfaultfd``, ``io_uring_*``, module loading, ``kexec``,
  ``reboot``, swap, clocks, ``syslog``, ``acct``, ``quotactl``, file handles, NUMA policy,
  ``ioperm``/``iopl``);
* **per-user quotas shared with the grader's user** where the grader is not root (``inotify_init``,
  ``mq_open``, ``fanotify_init``).

A denied call fails with ``EPERM`` (``clone3``: ``ENOSYS``); calls of other architectures (32-bit calls from a
64-bit process) kill the thread, libseccomp's default for a foreign architecture.
"""

import errno
import functools

__all__ = ["DENIED", "NAMESPACE_FLAGS", "available", "bpf", "syscall_number"]

#: System calls that fail with EPERM inside the sandbox.
DENIED = (
    # keyrings
    "keyctl", "add_key", "request_key",
    # namespaces
    "unshare", "setns",
    # mounts, the root, the new mount API
    "mount", "umount", "umount2", "pivot_root", "chroot", "open_tree", "move_mount", "fsopen", "fsconfig",
    "fsmount", "fspick", "mount_setattr",
    # other processes
    "ptrace", "process_vm_readv", "process_vm_writev", "kcmp", "pidfd_getfd",
    # the kernel's own facilities
    "bpf", "perf_event_open", "userfaultfd", "io_uring_setup", "io_uring_enter", "io_uring_register",
    "init_module", "finit_module", "delete_module", "create_module", "query_module", "get_kernel_syms",
    "kexec_load", "kexec_file_load", "reboot", "swapon", "swapoff", "settimeofday", "clock_settime",
    "clock_adjtime", "adjtimex", "stime", "syslog", "acct", "quotactl", "quotactl_fd", "nfsservctl",
    "lookup_dcookie", "name_to_handle_at", "open_by_handle_at", "uselib", "ustat", "sysfs",
    "_sysctl", "vhangup", "ioperm", "iopl", "vm86", "vm86old", "mbind", "set_mempolicy", "migrate_pages",
    "move_pages",
    # per-user quotas
    "inotify_init", "inotify_init1", "mq_open", "fanotify_init",
)

#: ``clone`` flags that make a namespace (CLONE_NEWNS … CLONE_NEWTIME).
NAMESPACE_FLAGS = {"CLONE_NEWTIME": 0x80, "CLONE_NEWNS": 0x20000, "CLONE_NEWCGROUP": 0x02000000,
                   "CLONE_NEWUTS": 0x04000000, "CLONE_NEWIPC": 0x08000000, "CLONE_NEWUSER": 0x10000000,
                   "CLONE_NEWPID": 0x20000000, "CLONE_NEWNET": 0x40000000}


def _seccomp():
    try:
        import pyseccomp
    except ImportError:
        return None
    try:
        pyseccomp.resolve_syscall(pyseccomp.Arch.NATIVE, "read")
    except Exception:  # noqa: BLE001 - pyseccomp without a loadable libseccomp raises on first use
        return None
    return pyseccomp


def available():
    """Whether libseccomp and its bindings can compile the filter here (Linux with libseccomp2 and pyseccomp)."""
    return _seccomp() is not None


def syscall_number(name):
    """The number of the system call ``name`` on this machine, or None (no libseccomp, or no such call here)."""
    S = _seccomp()
    number = S.resolve_syscall(S.Arch.NATIVE, name) if S is not None else -1
    return number if number >= 0 else None


@functools.lru_cache(maxsize=1)
def bpf():
    """The compiled filter (BPF program, bytes) for this machine's architecture; raises ``RuntimeError`` naming
    what to install when libseccomp is missing."""
    S = _seccomp()
    if S is None:
        raise RuntimeError("the grader's syscall filter needs libseccomp: install it (Debian: apt install "
                           "libseccomp2; Python: pip install pyseccomp)")
    f = S.SyscallFilter(S.ALLOW)
    for name in DENIED:
        if S.resolve_syscall(S.Arch.NATIVE, name) < 0:  # not a call of this architecture
            continue
        f.add_rule(S.ERRNO(errno.EPERM), name)
    for flag in NAMESPACE_FLAGS.values():
        f.add_rule(S.ERRNO(errno.EPERM), "clone", S.Arg(0, S.MASKED_EQ, flag, flag))
    f.add_rule(S.ERRNO(errno.ENOSYS), "clone3")
    import tempfile

    with tempfile.TemporaryFile() as fh:
        f.export_bpf(fh)
        fh.seek(0)
        return fh.read()
