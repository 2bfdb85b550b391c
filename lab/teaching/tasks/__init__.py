"""The graded tasks: their cases, exact answers, hints and mutants, one module per group of notebooks; this registry
(name -> :class:`~lab.teaching.task.Task`) is what the checks and the grader import.  Withheld whole from the hand-out
(:mod:`lab.teaching.sandbox.withhold`); its modules import only the task model and each other.

A task's module is imported when the task is first looked up, so ``from lab import check`` in a notebook does not
load the cases of every other notebook's tasks (the trimming and geodesic tasks pull in their own libraries).
"""

import collections.abc
import importlib

__all__ = ["ANALYTIC_BLOCK", "TASKS"]

#: Every task of the lab, by name, in the order of the course, and the module that defines it.
MODULES = {"warmup": "curvature", "curve_curvature": "curvature", "fundamental_forms": "curvature",
           "curvatures": "curvature", "derivative_nets": "curvature", "corner_derivatives": "curvature",
           "h": "colors", "f1": "colors", "f2": "colors", "f3": "colors", "visualize_curvature": "colors",
           "own_surface": "variants",
           "focal_points": "interrogation", "reflect": "interrogation", "christoffel": "interrogation",
           "start_velocity": "interrogation", "signed_area": "trimming", "developable_faces": "models",
           "principal_directions": "smoothness", "deficit_curvature": "meshes"}
#: What every graded sandbox and the hand-out withhold whatever the task: the sympy-exact references of the
#: curvature (they give every curvature task's answer).
ANALYTIC_BLOCK = tuple(f"lab.geometry.analytic.{name}" for name in (
    "curvature_from_derivatives", "curvature_exprs", "exact_curvature", "bezier_derivatives_exact",
    "bezier_curvature_exact", "bezier_corner_curvature_exact", "_bernstein_exact"))


class _Registry(collections.abc.Mapping):
    """``{name: Task}``; a task's module is imported on the first lookup of one of its tasks."""

    def __init__(self, modules):
        self._modules, self._tasks = dict(modules), {}

    def __getitem__(self, name):
        if name not in self._tasks:
            module = importlib.import_module(f"{__package__}.{self._modules[name]}")  # KeyError for unknown names
            from ..task import Task

            for value in vars(module).values():
                if isinstance(value, Task) and value.name in self._modules:
                    self._tasks.setdefault(value.name, value)
        return self._tasks[name]

    def __iter__(self):
        return iter(self._modules)

    def __len__(self):
        return len(self._modules)

    def __contains__(self, name):
        return name in self._modules

    def __repr__(self):
        return f"TASKS({', '.join(self._modules)})"


TASKS = _Registry(MODULES)
