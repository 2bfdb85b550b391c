"""The registry of tasks: name -> :class:`~lab.teaching.spec.Task` (used by the checks and the grader).

A task's module is imported when the task is first looked up, so ``from lab import check`` in a notebook does not
load the cases of every other notebook's tasks (the trimming and geodesic tasks pull in their own libraries).
"""

import collections.abc
import importlib

__all__ = ["TASKS"]

#: Every task of the lab, by name, in the order of the course, and the module that defines it.
MODULES = {"warmup": "tasks_curvature", "curve_curvature": "tasks_curvature", "fundamental_forms": "tasks_curvature",
           "curvatures": "tasks_curvature", "derivative_nets": "tasks_curvature",
           "corner_derivatives": "tasks_curvature", "h": "tasks_colors", "f1": "tasks_colors", "f2": "tasks_colors",
           "f3": "tasks_colors", "visualize_curvature": "tasks_colors", "focal_points": "tasks_interrogation",
           "reflect": "tasks_interrogation", "christoffel": "tasks_interrogation",
           "start_velocity": "tasks_interrogation", "signed_area": "tasks_trimming",
           "developable_faces": "tasks_models", "principal_directions": "tasks_smoothness"}


class _Registry(collections.abc.Mapping):
    """``{name: Task}``; a task's module is imported on the first lookup of one of its tasks."""

    def __init__(self, modules):
        self._modules, self._tasks = dict(modules), {}

    def __getitem__(self, name):
        if name not in self._tasks:
            module = importlib.import_module(f"{__package__}.{self._modules[name]}")  # KeyError for unknown names
            from .spec import Task

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
