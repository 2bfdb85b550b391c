"""The grader's sandbox from the inside: never the host's root, read-only kernel tunables, no keyring, no namespaces,
bounded stderr; and its probe, which names what is missing before a folder is graded.

The attack ``tests/data/hostile/kernel_escape.ipynb`` is graded once as root (this process, as in CI) and once by an
ordinary user (``setpriv`` to an unprivileged id; where Python lives under a folder others cannot enter, such as
``/root/.pyenv``, a private mount namespace shows that one folder to it), and reports what it could do.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import tracemalloc
from pathlib import Path

import pytest

from lab.teaching.course import grade
from lab.teaching.grader import notebook
from lab.teaching.sandbox import bubblewrap, seccomp
from tests.sandbox_support import assert_contained, escape_report

ROOT = Path(__file__).resolve().parent.parent
ATTACK = ROOT / "tests" / "data" / "hostile" / "kernel_escape.ipynb"
ASSIGNMENT = ROOT / "exercises" / "en" / "05_visualize_curvature.ipynb"
#: The ordinary user that grades in the second run (no account needed).
ORDINARY = 54321

needs_bwrap = pytest.mark.skipif(not bubblewrap.bwrap_works(), reason="bubblewrap cannot run here")
needs_root = pytest.mark.skipif(os.geteuid() != 0, reason="the grader runs as root here only in CI and as root")


@needs_bwrap
def test_the_probe_finds_every_protection():
    broken, missing = bubblewrap.probe()
    assert broken is None and missing == []


@needs_bwrap
def test_without_the_syscall_filter_the_probe_names_it_and_a_folder_is_not_graded(tmp_path, monkeypatch):
    """The filter is what keeps keyrings and namespaces out of reach: without libseccomp the probe finds both open,
    and a folder run stops before it grades anyone (unless --no-sandbox)."""
    monkeypatch.setattr(seccomp, "available", lambda: False)
    broken, missing = bubblewrap.probe()
    assert broken is None
    assert "no new namespaces (unshare of a user namespace works)" in missing
    assert "a syscall filter (seccomp is not in filter mode)" in missing
    (tmp_path / "subs" / "ada").mkdir(parents=True)
    shutil.copy(ASSIGNMENT, tmp_path / "subs" / "ada" / ASSIGNMENT.name)
    with pytest.raises(grade.GradingError, match=r"the sandbox lacks protections .*a syscall filter .* --no-sandbox"):
        grade.grade_folder(tmp_path / "subs", tmp_path / "out")
    assert not (tmp_path / "out" / "summary.csv").exists()


@needs_bwrap
@needs_root
def test_a_sandbox_that_would_stay_root_does_not_start(monkeypatch):
    """Were the submission's user to stay the host's root (here: the drop made to go to uid 0), the inner bubblewrap
    could not even make its user namespace: the probe says the kernel cannot start, and a folder is not graded."""
    monkeypatch.setattr(bubblewrap, "UID_BASE", 0)
    monkeypatch.setattr(bubblewrap, "UID_SPAN", 1)
    broken, missing = bubblewrap.probe()
    assert broken == "bwrap: setting up uid map: Operation not permitted" and missing == []


def test_the_probe_reads_each_protection_from_the_answers_inside():
    """Each answer of the script run inside maps to the protection it proves missing (English, for the refusal)."""
    contained = {"uid": 1000, "gid": 1000, "proc_sys": "Permission denied", "proc_sys_mount": "ro",
                 "keyring": "Operation not permitted", "unshare": "Operation not permitted", "seccomp": "2"}
    assert bubblewrap._protections(contained, 2_000_123_456) == []
    assert bubblewrap._protections({**contained, "proc_sys_mount": "rw"}, 2_000_123_456) == [
        "read-only kernel tunables (/proc/sys is not a read-only mount)"]
    found = bubblewrap._protections({**contained, "uid": 0, "proc_sys": "writable", "keyring": "allowed",
                                  "unshare": "allowed", "seccomp": "0"}, 0)
    assert found == ["an unprivileged user inside (the submission is uid 0 in its sandbox)",
                     "an unprivileged user outside (what the submission writes belongs to the host's root)",
                     "read-only kernel tunables (/proc/sys/kernel/core_pattern opens for writing)",
                     "keyring isolation (keyctl reaches a keyring)",
                     "no new namespaces (unshare of a user namespace works)",
                     "a syscall filter (seccomp is not in filter mode)"]


@needs_bwrap
@needs_root
def test_graded_as_root_a_notebook_is_not_the_hosts_root(keyring):
    result = notebook.grade_notebook(ATTACK, assignment=ASSIGNMENT, seed=1, timeout=60, check_timeout=2).to_dict()
    assert result["score"] == 0 and result["max_score"] == 10
    assert_contained(escape_report(result))
    assert "the-planted-secret" not in json.dumps(result)
    assert keyring.find("lab-hostile-left") == -1  # nothing left in root's keyring for a classmate to read


def _ordinary_grader(tmp_path):
    """A command prefix that runs as the user :data:`ORDINARY`, with this Python reachable."""
    prefix = [shutil.which("setpriv"), f"--reuid={ORDINARY}", f"--regid={ORDINARY}", "--clear-groups", "--"]
    base = Path(sys.base_prefix).resolve()
    closed = next((p for p in reversed(base.parents) if p != Path("/") and not os.stat(p).st_mode & 0o001), None)
    if closed is None:
        return prefix
    # a private mount namespace: ``closed`` (e.g. /root) becomes an empty world-readable folder with only Python in it
    hold = tmp_path / "hold"
    hold.mkdir()
    script = (f"mount --bind {base} {hold} && mount -t tmpfs -o mode=0755 tmpfs {closed} && mkdir -p {base} && "
              f"mount --move {hold} {base} && exec \"$@\"")
    return [shutil.which("unshare"), "--mount", "--propagation", "private", "sh", "-c", script, "sh"] + prefix


@needs_bwrap
@needs_root
def test_graded_by_an_ordinary_user_a_notebook_is_contained(keyring):
    tmp_path = Path(tempfile.mkdtemp(prefix="lab-ordinary-"))  # pytest's own folders are root's alone
    os.chmod(tmp_path, 0o755)
    work = tmp_path / "work"
    work.mkdir()
    shutil.copy(ATTACK, work / ASSIGNMENT.name)
    os.chown(work, ORDINARY, ORDINARY)
    os.chown(work / ASSIGNMENT.name, ORDINARY, ORDINARY)
    try:
        _grade_as_ordinary_user(tmp_path, work, keyring)
    finally:
        shutil.rmtree(tmp_path, ignore_errors=True)


def _grade_as_ordinary_user(tmp_path, work, keyring):
    env = {"PATH": os.environ["PATH"], "HOME": str(work), "TMPDIR": str(work), "LANG": "C.UTF-8"}
    done = subprocess.run(_ordinary_grader(tmp_path) + [
        sys.executable, "-m", "lab.cli", "grade", str(work / ASSIGNMENT.name), "--json", "--assignment",
        str(ASSIGNMENT), "--seed", "1", "--timeout", "60", "--check-timeout", "2"],
        capture_output=True, text=True, env=env, cwd=ROOT, timeout=900, check=False)
    assert done.returncode == 1, (done.returncode, done.stderr[-3000:])  # graded, not passed
    result = json.loads(done.stdout)
    assert result["score"] == 0 and result["max_score"] == 10
    assert_contained(escape_report(result))
    # the grader could not create cgroups or mount a tmpfs (not root): said so, not hidden
    assert any("disk budget" in m for m in result["missing_protections"]), result["missing_protections"]
    assert not any("syscall filter" in m or "user id" in m for m in result["missing_protections"])
    assert keyring.find("lab-hostile-left") == -1


@needs_bwrap
def test_stderr_is_read_through_a_pipe_and_only_its_end_kept(tmp_path):
    """255 MiB written to stderr landed on the host's disk and in the grader's memory: now a pipe, of which the
    grader keeps the last 4000 bytes while the rest passes."""
    box = bubblewrap.Sandbox(bubblewrap.LAB_DIR, tmp_path / "work")
    code = ("import os\nchunk = b'e' * (1 << 20)\nfor _ in range(64):\n    os.write(2, chunk)\n"
            "os.write(2, b'the end')\n")
    tracemalloc.start()
    with box.workspace():
        box.hand_over()
        status, timed_out, tail = box.run([sys.executable, "-c", code], 120)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert (status, timed_out) == (0, False)
    assert len(tail) == bubblewrap.STDERR_TAIL and tail.endswith("the end") and set(tail[:-7]) == {"e"}
    assert peak < 1 << 20, peak  # not 64 MiB


def test_the_filter_denies_the_calls_of_docker_and_flatpak_profiles():
    """The list itself, against the calls those profiles deny that matter here."""
    for call in ("keyctl", "add_key", "request_key", "unshare", "setns", "mount", "ptrace", "bpf", "perf_event_open",
                 "init_module", "finit_module", "kexec_load", "userfaultfd", "io_uring_setup", "open_by_handle_at"):
        assert call in seccomp.DENIED
    if seccomp.available():
        assert len(seccomp.bpf()) % 8 == 0 and len(seccomp.bpf()) > 8 * len(seccomp.NAMESPACE_FLAGS)
