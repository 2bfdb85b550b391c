"""Write deploy/constraints.txt: the versions of every package the lab needs, as installed where the tests ran.

    .venv/bin/python deploy/constraints.py        (after `make test`; tests/test_deploy.py fails when it is stale)

The closure of curvature-lab's own requirements with its extra "cad" (no test or benchmark extras) and nbgitpuller,
from the metadata of the installed distributions.
"""

import re
import sys
from importlib import metadata
from pathlib import Path

from packaging.requirements import Requirement

HERE = Path(__file__).resolve().parent
ROOTS = ("curvature-lab[cad]", "nbgitpuller")


def _name(requirement):
    return re.split(r"[ ;<>=!~\[(]", requirement.strip(), maxsplit=1)[0].lower().replace("_", "-")


def closure(roots=ROOTS):
    """``{name: version}`` of the installed distributions the roots need (requirements whose markers do not hold here, for another Python or an extra not asked for, left out)."""
    seen, todo = {}, [r.lower() for r in roots]
    while todo:
        root = todo.pop()
        name, _, extras = root.partition("[")
        extras = set(extras.rstrip("]").split(",")) - {""}
        if name in seen and not extras:
            continue
        try:
            dist = metadata.distribution(name)
        except metadata.PackageNotFoundError:
            continue
        seen[name] = dist.version
        for req in dist.requires or []:
            marker = Requirement(req).marker
            # a requirement for another Python (importlib-metadata before 3.10) or an extra not asked for is not needed
            if marker is not None and not any(marker.evaluate({"extra": e}) for e in extras | {""}):
                continue
            todo.append(_name(req))
    seen.pop("curvature-lab", None)
    return dict(sorted(seen.items()))


def text():
    lines = ["# Versions the tests ran with (deploy/constraints.py writes this file; tests/test_deploy.py checks it).",
             f"# Python {sys.version.split()[0]}; the image's Python may be newer: these versions have wheels for it."]
    return "\n".join(lines + [f"{n}=={v}" for n, v in closure().items()]) + "\n"


if __name__ == "__main__":
    (HERE / "constraints.txt").write_text(text())
