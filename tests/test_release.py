"""The students' hand-out (``curvature-lab release``): no solution and no course file in it, the answers withheld
from its library (the tasks' modules compiled only), ``make lab`` works in it, the self-study hand-out keeps the
references."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from lab.teaching.course import release

ROOT = Path(__file__).resolve().parent.parent

pytestmark = pytest.mark.xdist_group("release")  # one hand-out for the module


@pytest.fixture(scope="module")
def handout(tmp_path_factory):
    out = tmp_path_factory.mktemp("handout") / "student"
    release.release(out, git=True)
    return out


def test_the_handout_holds_no_solution_and_no_course_file(handout):
    assert release.solution_lines_in(handout) == []
    assert len(release.solution_lines()) > 100  # the search has something to look for
    names = {p.relative_to(handout).parts[0] for p in handout.iterdir()}
    assert names == {".git", ".gitignore", release.MARK, "Makefile", "README.md", "exercises", "jupyter", "lab",
                     "pyproject.toml"}
    assert sorted(p.name for p in (handout / "exercises" / "de").glob("*.ipynb")) == \
        sorted(p.name for p in (ROOT / "exercises" / "de").glob("*.ipynb"))
    source = (handout / "lab" / "model" / "patches.py").read_text()
    assert "withheld in this hand-out" in source and "corner_curvature_chunks()" not in source.split(
        "def visualize_curvature")[1].split("\n    def ")[0]
    assert "make lab" in (handout / "README.md").read_text()


def test_the_handout_search_finds_a_solution_line(handout, tmp_path):
    """The check itself can fail: a solution line pasted into a file of the hand-out is found."""
    copy = tmp_path / "copy"
    shutil.copytree(handout / "lab" / "geometry", copy)
    (copy / "x.py").write_text("    return np.linalg.norm(np.cross(d1, d2)) / np.linalg.norm(d1) ** 3\n")
    hits = release.solution_lines_in(copy)
    assert [(p.name, nb) for p, nb, _ in hits] == [("x.py", "01_curves_and_orientation.ipynb")]


def _run(handout, code, env_extra=None):
    env = {"PYTHONPATH": str(handout), "PATH": os.environ["PATH"], "HOME": str(handout), **(env_extra or {})}
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=handout,
                          check=False, timeout=600)


def test_the_handouts_library_works_and_shows_no_answer(handout):
    done = _run(handout, """
import inspect, lab, numpy as np
from lab import check, colormaps
assert lab.__file__.startswith("HANDOUT"), lab.__file__
print(colormaps.h(np.array([0.0, 0.5, 1.0])).tolist())
print("withheld" in inspect.getsource(colormaps.h), "np.where" in inspect.getsource(colormaps.h))
p = lab.surfaces.practical().to_bezier_patches().refine(1)
p.visualize_curvature(p.CURVATURE_GAUSSIAN, p.COLOR_MAP_LINEAR)
print(round(float(p.curvature.max()), 6), p.to_mesh().n_points)
print(check.h(lambda x: (0.0, 4 * x, 1.0) if x <= 0.25 else (0.0, 1.0, 2 - 4 * x) if x <= 0.5 else
      (4 * x - 2, 1.0, 0.0) if x <= 0.75 else (1.0, 4 - 4 * x, 0.0)).status)
""".replace("HANDOUT", str(handout)))
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == "[[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]"
    assert lines[1] == "True False"  # the source says withheld; the code runs
    reference = lab_practical_max()
    assert abs(float(lines[2].split()[0]) - reference) < 1e-6 and int(lines[2].split()[1]) > 100
    assert lines[3] == "passed"  # the in-notebook check works: it has its cases and answers


def lab_practical_max():
    import lab

    p = lab.surfaces.practical().to_bezier_patches().refine(1)
    p.visualize_curvature(p.CURVATURE_GAUSSIAN, p.COLOR_MAP_LINEAR)
    return round(float(p.curvature.max()), 6)


def test_a_python_without_the_compiled_code_is_told(handout, tmp_path):
    copy = tmp_path / "other-python"
    shutil.copytree(handout, copy, ignore=shutil.ignore_patterns("__pycache__", ".git"))
    done = _run(copy, "import numpy as np\nfrom lab import colormaps\ncolormaps.h(np.zeros(1))")
    assert "withheld in this hand-out" in done.stderr and "ask for a hand-out built for cpython" in done.stderr
    done = _run(copy, "import lab.teaching.tasks.colors")
    assert "ImportError: lab.teaching.tasks is withheld in this hand-out" in done.stderr  # the registry: first


def test_make_lab_works_in_the_handout(handout, tmp_path):
    """`make setup` in the hand-out: its venv takes the packages of the test venv (no download), installs the
    hand-out's library, and a kernel there runs exercise 05 with its pictures."""
    if shutil.which("make") is None:
        pytest.skip("make is missing")
    venv = handout / ".venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    site = next(venv.glob("lib/python*/site-packages"))
    (site / "test-venv.pth").write_text(next(p for p in sys.path if p.endswith("site-packages")) + "\n")
    done = subprocess.run(["make", "-C", str(handout), "setup"], capture_output=True, text=True, timeout=900,
                          check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    where = subprocess.run([str(venv / "bin" / "python"), "-c", "import lab; print(lab.__file__)"],
                           capture_output=True, text=True, check=True, cwd=tmp_path).stdout
    assert where.strip() == str(handout / "lab" / "__init__.py")
    assert "make lab" in subprocess.run(["make", "-C", str(handout), "-n", "lab"], capture_output=True, text=True,
                                        check=True).stdout.replace("jupyter lab", "make lab")
    shutil.rmtree(venv)


def test_release_refuses_a_foreign_folder_and_self_study_keeps_references(tmp_path):
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "thesis.tex").write_text("x")
    with pytest.raises(release.ReleaseError, match="not empty and not an earlier release"):
        release.release(tmp_path / "mine", check=False)
    out = release.release(tmp_path / "self", self_study=True, check=False)
    assert "np.where" in (out / "lab" / "geometry" / "colormaps.py").read_text()
    assert not (out / "solutions").exists() and not (out / "tests").exists()
    readme = (out / "README.md").read_text()  # it says what it holds, and only that
    assert "are included and readable" in readme and "withheld" not in readme
