"""A Gradescope autograder for one assignment: ``curvature-lab gradescope ASSIGNMENT -o autograder.zip``.

Gradescope builds an image from an uploaded zip with ``setup.sh`` (run once, as root, on its Ubuntu base)
and runs ``run_autograder`` for every submission, which must write ``/autograder/results/results.json``
(https://gradescope-autograders.readthedocs.io/en/latest/specs/).  The zip holds:

* ``setup.sh``: the Debian/Ubuntu packages for offscreen rendering and bubblewrap, a virtual environment
  with the lab installed from the zip's ``curvature-lab/`` (this repository's library, with its references:
  they compute the answers, outside the student's sandbox), unpacked by Gradescope as
  ``/autograder/source/curvature-lab``;
* ``run_autograder``: finds the student's notebook in ``/autograder/submission`` (the assignment's file
  name, else the only notebook, else the one whose metadata names the assignment), copies it under the
  instructor's file name, and grades it with ``curvature-lab grade --format gradescope`` against the
  instructor's copies in ``/autograder/source/assignment/{en,de}``: fresh cases every run, one Gradescope test per task
  (its group of cases) with the same rounding as the score, the chosen ``--visibility``;
* ``assignment/``: the assignment's exercise in English and German; ``curvature-lab/``: the library.

Gradescope unpacks the zip into ``/autograder/source`` (and copies ``run_autograder`` to ``/autograder``), so
every path the scripts use is under ``$ROOT/source``.  To try the autograder here: unpack the zip into
``ROOT/source``, put a notebook into ``ROOT/submission`` and run ``AUTOGRADER_ROOT=ROOT LAB_PYTHON=.venv/bin/python
bash ROOT/source/run_autograder``.

Gradescope runs the autograder in a container that usually cannot create the namespaces bubblewrap needs;
``run_autograder`` then grades with ``--no-sandbox`` and says so in the results (the protections missing are
listed in the output).  ``AUTOGRADER_ROOT`` (default ``/autograder``) and ``LAB_PYTHON`` let the autograder be
tried outside Gradescope, as the tests do.
"""

import argparse
import sys
import zipfile
from pathlib import Path

from ... import repository
from ...i18n import _
from ..grader.assignments import DEFAULT_FOLDER, AssignmentError, load, reads_cad
from ..grader.notebook import VISIBILITY

__all__ = ["build", "main", "setup_script"]

ROOT = Path(repository())
#: What of the repository the autograder installs (the library and what pip needs to build it).
SOURCE = ("pyproject.toml", "README.md", "lab")

SETUP = """#!/usr/bin/env bash
# Gradescope runs this once, as root, to build the autograder's image.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends python3 python3-venv python3-pip libegl1 libgl1-mesa-dri bubblewrap git{apt}
python3 -m venv /autograder/venv
/autograder/venv/bin/python -m pip install -q --upgrade pip
/autograder/venv/bin/python -m pip install -q {package}
"""

def setup_script(notebook_text):
    """``setup.sh`` for an assignment whose instructor's notebook has the source ``notebook_text``: one on real parts
    (:func:`lab.teaching.grader.assignments.reads_cad`) needs OpenCASCADE (the extra ``cad``) and its sample parts (Debian's
    ``occt-misc``) in the autograder's image."""
    if reads_cad(notebook_text):
        return SETUP.format(apt=" occt-misc", package='"/autograder/source/curvature-lab[cad]"')
    return SETUP.format(apt="", package="/autograder/source/curvature-lab")

RUN = """#!/usr/bin/env bash
# Gradescope runs this for every submission; it writes $ROOT/results/results.json.
set -uo pipefail
ROOT="${{AUTOGRADER_ROOT:-/autograder}}"
PY="${{LAB_PYTHON:-$ROOT/venv/bin/python}}"
ID={assignment_id}
VISIBILITY={visibility}
mkdir -p "$ROOT/results"
cd "$ROOT/submission" || exit 1
shopt -s nullglob
found=("$ID.ipynb")
[ -f "$ID.ipynb" ] || found=(*.ipynb)
if [ "${{#found[@]}}" -gt 1 ]; then
  found=($(grep -l "\\"assignment\\": \\"$ID\\"" *.ipynb | head -n 1))
fi
if [ "${{#found[@]}}" -ne 1 ] || [ ! -f "${{found[0]}}" ]; then
  printf '{{"score": 0, "visibility": "%s", "output": "No notebook of %s found in the submission: upload your %s.ipynb (one notebook)."}}\\n' \\
    "$VISIBILITY" "$ID" "$ID" > "$ROOT/results/results.json"
  exit 0
fi
work="$(mktemp -d)"
cp -- "${{found[0]}}" "$work/$ID.ipynb"
sandbox=()
"$PY" -c "import sys; from lab.teaching.sandbox.bubblewrap import bwrap_works; sys.exit(0 if bwrap_works() else 1)" || sandbox=(--no-sandbox)
"$PY" -m lab.cli grade "$work/$ID.ipynb" --assignment "$ROOT/source/assignment" --format gradescope \\
  --visibility "$VISIBILITY" --out "$ROOT/results" "${{sandbox[@]}}"
status=$?
if [ ! -f "$ROOT/results/results.json" ]; then
  printf '{{"score": 0, "visibility": "%s", "output": "The grader failed (exit status %s); please tell your instructor."}}\\n' \\
    "$VISIBILITY" "$status" > "$ROOT/results/results.json"
fi
exit 0
"""


def build(assignment, output, *, visibility="visible", exercises=DEFAULT_FOLDER, source=ROOT):
    """Write the autograder zip for ``assignment`` (an id, or the path of an instructor's notebook)."""
    if visibility not in VISIBILITY:
        raise ValueError(f"visibility must be one of {', '.join(VISIBILITY)}; got {visibility!r}")
    path = Path(assignment)
    if not path.is_file():
        path = Path(exercises) / "en" / f"{assignment}.ipynb"
    if not path.is_file():
        raise AssignmentError(f"no assignment {assignment!r}: expected an instructor's notebook or an id in "
                              f"{exercises}/en")
    found = load(path)
    if not found.tasks:
        raise AssignmentError(f"assignment {found.id} has no graded tasks: nothing for Gradescope to grade")
    folder = path.parent.parent if path.parent.name in ("en", "de") else path.parent
    output = Path(output)
    with zipfile.ZipFile(output, "w", zipfile.ZIP_DEFLATED) as z:
        for name, text in (("setup.sh", setup_script(path.read_text())), ("run_autograder", RUN.format(assignment_id=found.id,
                                                                              visibility=visibility))):
            info = zipfile.ZipInfo(name)
            info.external_attr = 0o755 << 16
            z.writestr(info, text)
        for lang in ("en", "de"):
            copy = folder / lang / f"{found.id}.ipynb"
            if copy.is_file():
                z.write(copy, f"assignment/{lang}/{found.id}.ipynb")
        for item in SOURCE:
            base = Path(source) / item
            files = [base] if base.is_file() else sorted(p for p in base.rglob("*") if p.is_file()
                                                         and "__pycache__" not in p.parts and p.suffix != ".pyc")
            for f in files:
                z.write(f, f"curvature-lab/{f.relative_to(source)}")
    return output


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab gradescope",
        description=_("Build a Gradescope autograder (setup.sh, run_autograder, the lab, the assignment) for one "
                    "assignment; upload the zip as the assignment's autograder."))
    parser.add_argument("assignment", help=_("assignment id (e.g. 05_visualize_curvature) or the instructor's notebook"))
    parser.add_argument("-o", "--output", default="autograder.zip", help=_("the zip to write (default: autograder.zip)"))
    parser.add_argument("--visibility", choices=VISIBILITY, default="visible",
                        help=_("when students see the results (default: visible; e.g. after_due_date)"))
    parser.add_argument("--exercises", default=str(DEFAULT_FOLDER), help=_("the instructor's exercises (default: exercises/)"))
    args = parser.parse_args(argv)
    try:
        out = build(args.assignment, args.output, visibility=args.visibility, exercises=args.exercises)
    except (AssignmentError, OSError) as exc:
        print(f"curvature-lab gradescope: error: {exc}", file=sys.stderr)
        return 2
    print(_("wrote {file}").format(file=out))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
