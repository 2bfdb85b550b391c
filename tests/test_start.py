"""Self-study after ``pip install``: the wheel carries the exercises (never a solution), ``curvature-lab start`` copies
them and opens JupyterLab in the student's language, never overwriting a notebook the student edited, and the course's
commands say plainly that they need a course repository.

The wheel is built here (``python -m build``) and installed into a fresh virtual environment (its dependencies at the
versions the tests ran, from pip's cache where it has them), and every command runs from a folder outside the
checkout, as a self-learner's would.
"""

import json
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
import zipfile
from pathlib import Path

import pytest

from lab.teaching.course import start

ROOT = Path(__file__).resolve().parent.parent
EXERCISES = sorted(p.name for p in (ROOT / "exercises" / "en").glob("[0-9][0-9]_*.ipynb"))

pytestmark = pytest.mark.xdist_group("start")  # one wheel and one fresh environment for the module


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("dist")
    done = subprocess.run([sys.executable, "-m", "build", "--wheel", "--outdir", str(out), str(ROOT)],
                          capture_output=True, text=True, timeout=900, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    (found,) = out.glob("curvature_lab-*.whl")
    return found


@pytest.fixture(scope="module")
def installed(wheel, tmp_path_factory):
    """A fresh virtual environment with the wheel installed; ``(bin folder, a folder outside the checkout)``."""
    venv = tmp_path_factory.mktemp("venv") / "env"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    done = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "-q", "-c",
                           str(ROOT / "deploy" / "constraints.txt"), str(wheel)],
                          capture_output=True, text=True, timeout=1800, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    return venv / "bin", tmp_path_factory.mktemp("home")


def _env(home, **extra):
    return {"PATH": f"{os.environ['PATH']}", "HOME": str(home), "LANG": "C.UTF-8", **extra}


def test_the_wheel_carries_the_exercises_in_both_languages_and_no_solution(wheel):
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        notebooks = {n: z.read(n).decode() for n in names if n.endswith(".ipynb")}
    assert sorted(notebooks) == sorted(f"lab/exercises/{lang}/{name}" for lang in ("en", "de") for name in EXERCISES)
    assert not [n for n in names if "solutions" in n or n.startswith(("tests/", "deploy/"))]
    for name, text in notebooks.items():  # the exercises as generated, no solution in any
        assert "BEGIN SOLUTION" not in text, name
        assert text.encode() == (ROOT / "exercises" / name.split("/")[2] / name.split("/")[3]).read_bytes(), name
    assert "lab/teaching/tasks/references.py" in names  # the self-learner's library: the references readable
    assert "lab/i18n/locale/de/LC_MESSAGES/lab.mo" in names


def test_copying_never_overwrites_a_notebook_the_student_edited(tmp_path):
    source = tmp_path / "shipped"
    source.mkdir()
    for name in EXERCISES[:3]:
        (source / name).write_bytes((ROOT / "exercises" / "en" / name).read_bytes())
    folder = tmp_path / "mine"
    assert set(start.copy_exercises(source, folder).values()) == {"new"}
    first, second, third = (folder / name for name in EXERCISES[:3])
    first.write_text(first.read_text().replace("NotImplementedError", "NotImplementedError  # my notes"))
    for name in EXERCISES[:2]:  # a new version of the lab changes two notebooks
        (source / name).write_text((source / name).read_text() + " ")
    done = start.copy_exercises(source, folder)
    beside = first.with_name(first.stem + ".2.ipynb")
    assert done == {first.name: f"kept: new version in {beside.name}", second.name: "updated",
                    third.name: "unchanged"}
    assert "# my notes" in first.read_text() and beside.read_bytes() == (source / first.name).read_bytes()
    assert second.read_bytes() == (source / second.name).read_bytes()
    assert start.copy_exercises(source, folder)[first.name] == "kept"  # the new version is beside it already
    assert not first.with_name(first.stem + ".3.ipynb").exists()


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("lang, locale", [("en", "en"), ("de", "de_DE")])
def test_start_opens_jupyterlab_on_the_exercises_in_the_language(installed, lang, locale):
    bin_folder, home = installed
    port, folder = _free_port(), home / f"lab-{lang}"
    began = time.perf_counter()
    proc = subprocess.Popen([str(bin_folder / "curvature-lab"), "start", str(folder), "--lang", lang, "--no-browser",
                             "--port", str(port)], cwd=home, env=_env(home), stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        url, log = None, []
        deadline = time.monotonic() + 600
        while url is None and time.monotonic() < deadline:
            line = proc.stdout.readline()
            if not line:
                break
            log.append(line)
            if f"http://127.0.0.1:{port}/lab?token=" in line and not line.rstrip().endswith("token=..."):
                url = line.strip().split()[-1]  # the full address (the log's own lines hide the token)
        assert url, "".join(log)[-3000:]
        token = url.split("token=")[1]
        base = f"http://127.0.0.1:{port}"
        listing = _get(f"{base}/api/contents?token={token}")
        assert sorted(c["name"] for c in listing["content"] if c["name"].endswith(".ipynb")) == EXERCISES
        assert (folder / "00_start.ipynb").read_bytes() == (ROOT / "exercises" / lang / "00_start.ipynb").read_bytes()
        plugin = _get(f"{base}/lab/api/settings/@jupyterlab/translation-extension:plugin?token={token}")
        assert plugin["schema"]["properties"]["locale"]["default"] == locale
        kernels = _get(f"{base}/lab/api/settings/@jupyterlab/apputils-extension:kernels-settings?token={token}")
        assert kernels["schema"]["properties"]["commsOverSubshells"]["default"] == "disabled"
        server = next(p for p in Path("/proc").iterdir() if p.name.isdigit() and _child_of(p, proc.pid))
        assert f"LAB_LANG={lang}".encode() in (server / "environ").read_bytes().split(b"\0")
        print(f"start {lang}: JupyterLab answered {time.perf_counter() - began:.1f} s after the command")
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=60)


def _get(url):
    """JSON from the server; it prints its address a moment before it accepts connections: asked again meanwhile."""
    for _attempt in range(600):
        try:
            return json.load(urllib.request.urlopen(url, timeout=60))
        except urllib.error.URLError as exc:
            if not isinstance(exc.reason, ConnectionRefusedError):
                raise
            time.sleep(0.1)
    raise AssertionError(f"the server never accepted a connection: {url}")


def _child_of(proc_dir, parent):
    try:
        return int((proc_dir / "stat").read_text().rsplit(")", 1)[1].split()[1]) == parent
    except (OSError, ValueError, IndexError):
        return False


@pytest.mark.parametrize("argv", [["exercises", "--check"], ["release", "--self-study", "handout"]])
def test_course_commands_outside_a_checkout_say_they_need_one(installed, argv):
    """``exercises --check`` printed nothing and exited 0 (a false "all fine"), ``release`` failed on a missing
    pyproject.toml in site-packages."""
    bin_folder, home = installed
    done = subprocess.run([str(bin_folder / "curvature-lab"), *argv], cwd=home, env=_env(home), capture_output=True,
                          text=True, timeout=600, check=False)
    assert done.returncode == 2, (done.returncode, done.stdout, done.stderr)
    assert (f"curvature-lab {argv[0]} works in a course repository (a checkout of curvature-lab, with solutions/ and "
            "pyproject.toml)") in done.stderr
    assert "run curvature-lab start" in done.stderr and not (home / "handout").exists()
