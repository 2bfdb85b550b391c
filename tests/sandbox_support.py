"""What the sandbox tests and the hostile folder run share: the keyring of this process, and the report of the
attack ``tests/data/hostile/kernel_escape.ipynb`` read back."""

import ctypes

from lab.teaching.sandbox import bubblewrap, seccomp


def escape_report(result):
    """What the attack said it could do: ``{"uid": …, "kernel/core_pattern": …, "secret": …, …}``."""
    text = next(e["error"] for e in result["cell_errors"] if "escape: " in e["error"])
    said = text.split("escape: ", 1)[1]
    return dict(part.split(": ", 1) if ": " in part else ("uid", part.split()[1]) for part in said.split("; "))


def assert_contained(said):
    assert said["uid"] == str(bubblewrap.INSIDE_ID), said
    for name in ("kernel/core_pattern", "kernel/panic", "vm/drop_caches"):
        assert said[name] in ("Read-only file system", "Permission denied"), said
    for what in ("secret", "user keyring", "left key", "unshare"):
        assert said[what] == "Operation not permitted", said
    assert said["namespaces"] == "0", said


class Keyring:
    """The user keyring of this process (root's in CI): a secret planted before, what a submission left after."""

    def __init__(self):
        self.libc = ctypes.CDLL(None, use_errno=True)
        self.add_key, self.keyctl = seccomp.syscall_number("add_key"), seccomp.syscall_number("keyctl")

    def plant(self, description, payload):
        return self.libc.syscall(self.add_key, b"user", description.encode(), payload, len(payload), -4)

    def find(self, description):
        """The key's serial in the user keyring (KEYCTL_SEARCH), or -1."""
        return self.libc.syscall(self.keyctl, 10, -4, b"user", description.encode(), 0)

    def remove(self, serial):
        self.libc.syscall(self.keyctl, 9, serial, -4)  # KEYCTL_UNLINK from the user keyring
