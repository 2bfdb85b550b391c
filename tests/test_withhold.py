"""What does a task's work is withheld in the grading sandbox: for every task, the library functions that compute
its answer (or its core) are listed here, and each is shown to raise the withheld marker in the sandbox's copy
of the library, called on anything.  The list is the reviewer's: a helper that computes an answer and is
missing from a task's ``blocked`` makes this test fail once it is added here."""

import json
import subprocess
import sys

import pytest

from lab.teaching.kernel import protocol
from lab.teaching.sandbox import withhold
from lab.teaching.tasks import TASKS

SURFACE = "lab.model.surface.Surface"
#: task -> the library functions that compute its answer, or the core of it, from the task's inputs
ANSWERS = {
    "warmup": [],
    "curve_curvature": [],
    "fundamental_forms": ["lab.geometry.curvature.fundamental_forms", "lab.geometry.curvature.unit_normal",
                          "lab.geometry.curvature.from_derivatives", "lab.geometry.analytic.curvature_from_derivatives",
                          f"{SURFACE}.fundamental_forms", f"{SURFACE}.normal", f"{SURFACE}.curvature"],
    "curvatures": ["lab.geometry.curvature.principal_curvatures", "lab.geometry.curvature.from_derivatives",
                   "lab.geometry.curvature.shape_operator", "lab.geometry.directions.from_derivatives",
                   "lab.geometry.directions.eigen", f"{SURFACE}._directions",
                   "lab.geometry.analytic.curvature_from_derivatives", f"{SURFACE}.curvature",
                   f"{SURFACE}.curvature_grid"],
    "derivative_nets": ["lab.geometry.bezier.derivative_net", "lab.geometry.bezier.derivatives",
                        "lab.geometry.bezier._corner_stencil", "lab.geometry.bezier._both_corners",
                        "lab.geometry.bezier._evaluate_nets", "lab.geometry.analytic._bernstein_exact",
                        "lab.geometry.analytic.bezier_derivatives_exact", "lab.geometry.bspline.basis_derivatives",
                        "lab.geometry.tensor.point_derivatives", f"{SURFACE}.derivatives"],
    "corner_derivatives": ["lab.geometry.bezier.corner_derivatives", "lab.geometry.bezier._corner_values",
                           "lab.geometry.bezier._corner_stencil", "lab.geometry.bezier._both_corners",
                           "lab.model.patches.BezierPatches.corner_derivatives", "lab.geometry.analytic._bernstein_exact"],
    "h": ["lab.geometry.colormaps.h", "lab.geometry.colormaps.apply", "lab.geometry.colormaps.colors_for"],
    "f1": ["lab.geometry.colormaps.f1", "lab.geometry.colormaps.apply"],
    "f2": ["lab.geometry.colormaps.f2", "lab.geometry.colormaps.symmetric", "lab.geometry.colormaps.colors_for"],
    "f3": ["lab.geometry.colormaps.f3", "lab.geometry.colormaps.apply"],
    "visualize_curvature": ["lab.model.patches.BezierPatches.visualize_curvature",
                            "lab.model.patches.BezierPatches.corner_curvature",
                            "lab.model.patches.BezierPatches.corner_derivatives",
                            "lab.model.patches.BezierPatches.curvature_at", "lab.geometry.curvature.from_derivatives",
                            "lab.geometry.curvature.curvature_values", "lab.geometry.colormaps.colors_for",
                            "lab.geometry.colormaps.apply", "lab.geometry.bezier._corner_values",
                            "lab.geometry.analytic.bezier_corner_curvature_exact"],
    "focal_points": ["lab.interrogation.focal.focal_points", "lab.interrogation.focal.focal_sheet"],
    "reflect": ["lab.interrogation.reflection.reflect"],
    "christoffel": ["lab.interrogation.geodesics.problem.christoffel",
                    "lab.interrogation.geodesics.problem._christoffel_symbols",
                    "lab.interrogation.geodesics.problem._second_kind",
                    "lab.interrogation.geodesics.problem._second_kind_of"],
    "start_velocity": ["lab.interrogation.geodesics.problem.start_direction",
                       "lab.interrogation.geodesics.problem._direction", "lab.interrogation.geodesics.problem._frame"],
    "principal_directions": ["lab.geometry.directions.from_derivatives", "lab.geometry.directions.eigen",
                             "lab.geometry.curvature.shape_operator", "lab.geometry.curvature.from_derivatives",
                             f"{SURFACE}.curvature", f"{SURFACE}._directions", "lab.interrogation.umbilics.traceless"],
    # the lab's exact curvature is the tool this task teaches to use on a real part; the judgement is the student's
    "developable_faces": [],
    # numbers the student reports, read from the notebook as written: no code of theirs runs for them
    "own_surface": [],
    "signed_area": ["lab.interrogation.trimming.loops.signed_area",
                    "lab.interrogation.trimming.surface.TrimmedSurface.area_uv"],
    "deficit_curvature": ["lab.geometry.discrete.angle_deficit", "lab.geometry.discrete.mixed_areas",
                          "lab.geometry.discrete.gaussian_curvature", "lab.geometry.discrete.corner_angles",
                          "lab.geometry.discrete.boundary_vertices", "lab.interrogation.estimators.estimate"],
}

PROBE = r"""
import importlib, inspect, json, sys
out = {}
for name in json.loads(sys.argv[1]):
    parts = name.split(".")
    for cut in range(len(parts) - 1, 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
            break
        except ImportError:
            continue
    for part in parts[cut:]:
        obj = getattr(obj, part)
    func = obj.fget if isinstance(obj, property) else obj
    args = [None] * sum(p.default is p.empty and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
                        for p in inspect.signature(func).parameters.values())
    try:
        func(*args)
        out[name] = "returned"
    except BaseException as exc:
        out[name] = f"{type(exc).__name__}: {exc}"
print(json.dumps(out))
"""


def test_every_task_is_listed():
    assert set(ANSWERS) == set(TASKS)


@pytest.mark.parametrize("task", [t for t in ANSWERS if ANSWERS[t]])
def test_what_computes_the_answer_is_withheld_in_the_sandbox(task, tmp_path):
    blocked = withhold.withheld([task])
    assert set(ANSWERS[task]) <= set(blocked), sorted(set(ANSWERS[task]) - set(blocked))
    package = withhold.prepare_package(blocked, list(TASKS), tmp_path)
    probe = subprocess.run([sys.executable, "-c", PROBE, json.dumps(ANSWERS[task])], capture_output=True, text=True,
                           env={"PYTHONPATH": str(package.parent), "PATH": "/usr/bin:/bin"}, cwd=tmp_path,
                           timeout=600, check=True)
    found = json.loads(probe.stdout.strip().splitlines()[-1])
    assert {k: v for k, v in found.items() if protocol.MARKER not in v} == {}
    # and the package in use is the stripped copy, not the repository's library
    where = subprocess.run([sys.executable, "-c", "import lab; print(lab.__file__)"], capture_output=True, text=True,
                           env={"PYTHONPATH": str(package.parent), "PATH": "/usr/bin:/bin"}, cwd=tmp_path,
                           check=True).stdout
    assert where.strip().startswith(str(package))
