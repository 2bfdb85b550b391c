"""Binder (mybinder.org): the files in binder/ agree with the project and repo2docker accepts them.

There is no Docker engine here to build the image; ``jupyter-repo2docker --no-build --debug`` writes the Dockerfile it
would build, which is read back: the Debian packages, the pinned requirements installed from the whole repository,
postBuild and the start script in their places.
"""

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BINDER = ROOT / "binder"


def test_the_requirements_are_the_lab_at_the_versions_the_tests_ran():
    lines = [line.strip() for line in (BINDER / "requirements.txt").read_text().splitlines()
             if line.strip() and not line.startswith("#")]
    assert lines == ["-c ../deploy/constraints.txt", ".[cad]"]  # the constraints, read relative to this file
    assert (BINDER / "../deploy/constraints.txt").resolve().is_file()


def test_the_python_is_the_one_the_tests_ran_and_the_project_allows():
    version = (BINDER / "runtime.txt").read_text().strip()
    assert version == f"python-{sys.version_info.major}.{sys.version_info.minor}"
    floor = re.search(r'^requires-python = "(.*)"$', (ROOT / "pyproject.toml").read_text(), re.MULTILINE).group(1)
    assert floor == ">=3.10" and tuple(map(int, version.split("-")[1].split("."))) >= (3, 10)


def test_the_debian_packages_are_those_make_lab_installs():
    apt = {line.strip() for line in (BINDER / "apt.txt").read_text().splitlines()
           if line.strip() and not line.startswith("#")}
    setup = (ROOT / "jupyter" / "setup.mk").read_text()
    make = set(re.search(r"^APT_PACKAGES := (.*)$", setup, re.MULTILINE).group(1).split())
    assert apt == make == {"libegl1", "libgl1-mesa-dri", "occt-misc"}


def test_post_build_writes_the_settings_and_start_sets_the_language():
    post = (BINDER / "postBuild").read_text()
    assert 'python jupyter/settings.py en "${NB_PYTHON_PREFIX}/share/jupyter/lab/settings/overrides.json"' in post
    start = (BINDER / "start").read_text()
    assert 'export LAB_LANG="${LAB_LANG:-en}"' in start and start.rstrip().endswith('exec "$@"')
    for script in ("postBuild", "start"):
        assert (BINDER / script).stat().st_mode & 0o111, f"binder/{script} is not executable"


def test_the_readme_has_the_badge_and_the_german_link():
    readme = (ROOT / "README.md").read_text()
    badge = re.search(r"https://mybinder\.org/v2/gh/[^)\s]+", readme)
    assert badge and "urlpath=lab/tree/exercises/en/00_start.ipynb" in badge.group(0)
    assert "urlpath=lab/tree/exercises/de/00_start.ipynb" in readme


def test_repo2docker_accepts_the_repository():
    exe = shutil.which("jupyter-repo2docker", path=str(Path(sys.executable).parent)) or shutil.which(
        "jupyter-repo2docker")
    if exe is None:
        pytest.skip("jupyter-repo2docker is not installed (the test extra has it)")
    done = subprocess.run([exe, "--no-build", "--debug", "--no-run", str(ROOT)], capture_output=True, text=True,
                          timeout=600, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    dockerfile = done.stdout
    assert re.search(r"apt-get install --yes --no-install-recommends libegl1 libgl1-mesa-dri occt-misc", dockerfile)
    copy = dockerfile.index("COPY --chown=0:0 src/ ${REPO_DIR}/")
    pip = dockerfile.index('pip install --no-cache-dir -r "binder/requirements.txt"')
    assert copy < pip  # a local requirement: installed from the whole repository, not a copy of the file alone
    assert "RUN ./binder/postBuild" in dockerfile and 'ENV R2D_ENTRYPOINT="${REPO_DIR}/binder/start"' in dockerfile
    assert "environment.py-3.11" in dockerfile.replace("-2e", ".").replace("-2d", "-")
