"""The wheel carries the course's exercises: ``exercises/{en,de}/*.ipynb`` become ``lab/exercises/{en,de}/`` (what
``curvature-lab start`` copies for a self-learner).  Everything else is in pyproject.toml; never the solutions."""

import shutil
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent


class BuildWithExercises(build_py):
    """build_py, then the exercise notebooks of both languages into the built package."""

    def run(self):
        super().run()
        if self.editable_mode:  # an editable install reads them from the checkout (lab.repository())
            return
        for lang in ("en", "de"):
            source = HERE / "exercises" / lang
            target = Path(self.build_lib) / "lab" / "exercises" / lang
            target.mkdir(parents=True, exist_ok=True)
            for notebook in sorted(source.glob("[0-9][0-9]_*.ipynb")):
                shutil.copy2(notebook, target / notebook.name)


setup(cmdclass={"build_py": BuildWithExercises})
