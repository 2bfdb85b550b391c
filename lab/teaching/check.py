"""In-notebook checks with hints: one call per task, e.g. ``check.visualize_curvature(MyBezierPatches)``.

Every check builds fresh random test cases (control nets with rational
coordinates, so the ground truth is computed exactly with sympy and no answer
can be hard-coded), runs the student's code under a time limit and with the
library's reference implementations blocked, and returns a :class:`Report`:
which cases passed, and for the first failing case what was expected, what
came out and a hint.  Hints come from comparing the output with deliberately
wrong variants of the computation (degree factors missing, m and n swapped,
unnormalised normal, H without ½, corners in the wrong order, ...).

``graded=True`` (used by :mod:`lab.grading`) adds further cases.
"""


from .report import Case, Report, _Stop
from .runner import ALLOWED_HELPERS, DEFAULT_TIMEOUT
from .tasks_colors import f1, f2, f3, h, visualize_curvature
from .tasks_curvature import corner_derivatives, curvatures, curve_curvature, derivative_nets, fundamental_forms, warmup
from .tasks_interrogation import christoffel, focal_points, reflect, start_velocity
from .tasks_trimming import signed_area

__all__ = [
    "ALLOWED_HELPERS",
    "DEFAULT_TIMEOUT",
    "Report",
    "Case",
    "TASKS",
    "run",
    "warmup",
    "curve_curvature",
    "fundamental_forms",
    "curvatures",
    "derivative_nets",
    "corner_derivatives",
    "h",
    "f1",
    "f2",
    "f3",
    "visualize_curvature",
    "focal_points",
    "reflect",
    "christoffel",
    "start_velocity",
]

#: Seconds a student function may run in one check before it is stopped.

#: The tasks the autograder knows: name -> check function.
TASKS = {
    "warmup": warmup,
    "curve_curvature": curve_curvature,
    "fundamental_forms": fundamental_forms,
    "curvatures": curvatures,
    "derivative_nets": derivative_nets,
    "corner_derivatives": corner_derivatives,
    "h": h,
    "f1": f1,
    "f2": f2,
    "f3": f3,
    "visualize_curvature": visualize_curvature,
    "focal_points": focal_points,
    "reflect": reflect,
    "christoffel": christoffel,
    "start_velocity": start_velocity,
    "signed_area": signed_area,
}


def run(task, obj, **kwargs):
    """Run the check called ``task`` on ``obj``; never raises for problems in ``obj``."""
    if task not in TASKS:
        raise ValueError(f"unknown task {task!r}; expected one of {', '.join(TASKS)}")
    try:
        return TASKS[task](obj, **kwargs)
    except _Stop as stop:  # pragma: no cover - tasks convert their own stops
        return Report(task, stop.status, [], stop.message, kwargs.get("graded", False))
