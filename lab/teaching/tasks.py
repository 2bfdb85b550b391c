"""The registry of tasks: name -> :class:`~lab.teaching.spec.Task` (used by the checks and the grader)."""

from .tasks_colors import F1, F2, F3, VISUALIZE_CURVATURE, H
from .tasks_curvature import CORNER_DERIVATIVES, CURVATURES, CURVE_CURVATURE, DERIVATIVE_NETS, FUNDAMENTAL_FORMS, WARMUP
from .tasks_interrogation import CHRISTOFFEL, FOCAL_POINTS, REFLECT, START_VELOCITY
from .tasks_smoothness import PRINCIPAL_DIRECTIONS
from .tasks_trimming import SIGNED_AREA

__all__ = ["TASKS"]

#: Every task of the lab, by name.
TASKS = {t.name: t for t in (WARMUP, CURVE_CURVATURE, FUNDAMENTAL_FORMS, CURVATURES, DERIVATIVE_NETS,
                             CORNER_DERIVATIVES, H, F1, F2, F3, VISUALIZE_CURVATURE, FOCAL_POINTS, REFLECT,
                             CHRISTOFFEL, START_VELOCITY, SIGNED_AREA, PRINCIPAL_DIRECTIONS)}
