"""The per-student task of notebook 05: the numbers of the student's own surface (``own_surface``).

The student computes, with their ``visualize_curvature``, the Gaussian and the mean curvature at the corners of the
patches of their surface (``lab.my_surface("05_visualize_curvature")``) refined once, and reports the smallest and
the largest of each, ``answer = (K min, K max, H min, H max)``, written as numbers.  The grader reads them as written
(protocol ``"reported"``: no code of the student runs for this task) and compares them with the exact values of that
student's variant: the extremes are found among the corners in floating point, and the corners that come within
10⁻⁹ of an extreme are evaluated in exact rational arithmetic (:func:`lab.geometry.analytic.bezier_curvature_exact`).

Numbers are right when each is within 10⁻⁸ of its exact value, relative (ten significant digits, as the notebook
prints them).  The variants' numbers differ from each other's by far more (``tests/test_per_student.py``), so numbers
that are right for a classmate's variant and wrong for one's own are recognised (the grader notes it).
"""

import functools

import numpy as np

from ...geometry import analytic
from ...i18n import N_, _
from ..kernel.variants import PRACTICAL, resolve
from ..task import CaseSpec, Hint, Task, close, fmt

__all__ = ["OWN_SURFACE", "REL_TOL", "corner_extremes"]

#: Relative tolerance of each reported number (ten significant digits).
REL_TOL = 1e-8
#: The depth the question asks for (the practical refines once).
DEPTH = 1
_FIELDS = ("K", "H")
_SUMMARY = N_("four numbers (K min, K max, H min, H max), written as numbers")


def _key(params):
    return None if params is None else tuple(sorted(params.items()))


@functools.lru_cache(maxsize=4096)
def _extremes(key, exact, depth):
    params = None if key is None else dict(key)
    patches = PRACTICAL.surface(params).to_bezier_patches().refine(depth)
    curvature = patches.corner_curvature()
    nets, out = patches.control_points, []
    for name in _FIELDS:
        values = np.asarray(getattr(curvature, name), dtype=float)
        scale = float(np.max(np.abs(values)))
        for pick in (np.min, np.max):
            x = float(pick(values))
            if exact:
                near = np.argwhere(np.abs(values - x) <= 1e-9 * scale)
                x = float(pick([getattr(analytic.to_float(analytic.bezier_curvature_exact(nets[p], a, b)), name)
                                for p, a, b in near]))
            out.append(x)
    return tuple(out)


def corner_extremes(params=None, *, exact=True, depth=DEPTH):
    """``(K min, K max, H min, H max)`` over the corners of the patches of the variant ``params`` (None: the
    common surface) refined ``depth`` times: exact (rational arithmetic at the extremes) or floating point."""
    return np.array(_extremes(_key(params), bool(exact), int(depth)))


def _cases_for(student, params, exact=True, status=None, show=True):
    """The one case of a variant: ``show`` whether a failure shows the right numbers (the grader's report does, the
    notebook's check does not: it would hand out the answer)."""
    if params is not None:
        name = _("your surface (the variant of {student}): K and H at the corners, depth 1").format(student=student)
    elif status == "not on roster":
        name = _("the common surface ({student} is not on the roster): K and H at the corners, depth 1").format(
            student=student)
    else:
        name = _("the common surface: K and H at the corners, depth 1")
    return [CaseSpec(name, (), info={"student": student, "params": params, "exact": exact, "show": show})]


def _cases(rng, graded):
    variant = resolve(PRACTICAL.assignment)
    return _cases_for(variant.student, variant.params, status=variant.status, show=False)


def _expected(case):
    return corner_extremes(case.info["params"], exact=case.info.get("exact", True))


def matches(value, exp):
    """Whether reported numbers ``value`` are ``exp``'s, each within :data:`REL_TOL` relative."""
    value, exp = np.asarray(value, dtype=float), np.asarray(exp, dtype=float)
    if value.shape != exp.shape or not np.all(np.isfinite(value)):
        return False
    return bool(np.all(np.abs(value - exp) <= REL_TOL * np.abs(exp) + 1e-12 * np.max(np.abs(exp))))


def _hint(case, value, exp):
    params = case.info["params"]
    if params is not None and matches(value, corner_extremes(None, exact=False)):
        return Hint(_("these are the numbers of the common surface lab.surfaces.practical(), not of yours: compute "
                      "them on lab.my_surface(\"05_visualize_curvature\")."), "common_surface")
    if matches(value, corner_extremes(params, exact=False, depth=0)):
        return Hint(_("these are the corners of the patches before refining: refine once (depth 1), as asked."),
                    "depth")
    if matches(value, exp[[2, 3, 0, 1]]):
        return Hint(_("K and H are swapped: the order is (K min, K max, H min, H max)."), "order")
    if matches(value, exp[[1, 0, 3, 2]]):
        return Hint(_("smallest and largest are swapped: the order is (K min, K max, H min, H max)."), "order")
    if matches(value, np.array([exp[0], exp[1], -exp[3], -exp[2]])):
        return Hint(_("H has the opposite sign: take the net as the surface gives it (u along y), so that "
                      "N = b_u × b_v points down, as in the practical."), "orientation")
    if close(value, exp, rtol=1e-4):
        return Hint(_("close, but not to ten significant digits: write the numbers as your cell prints them."),
                    "digits")
    return _("compare with the values your visualize_curvature stores for your surface at depth 1.")


def _judge(case, value, exp):
    exp = np.asarray(exp, dtype=float)
    shown = fmt(exp, 10) if case.info.get("show", True) else _("the four numbers of your surface (the check does not "
                                                                 "show them: compute them)")
    if not isinstance(value, np.ndarray) or value.size != 4:
        got = fmt(value) if isinstance(value, np.ndarray) else repr(value)[:200]
        return False, shown, got, _("write four numbers: answer = (K min, K max, H min, H max).")
    value = value.reshape(4)
    if matches(value, exp):
        return True, shown, fmt(value, 10), ""
    return False, shown, fmt(value, 10), _hint(case, value, exp)


def _error_hint(case, message):
    """The one error an answer of numbers has: it is code (:func:`lab.teaching.untrusted.reported_outcome`)."""
    return Hint(_("the grader reads your numbers as you wrote them and runs no code for them: copy the four numbers "
                  "your cell printed into answer = (…)."), "code")


OWN_SURFACE = Task("own_surface", _cases, _expected, _judge, protocol="reported", error_hint=_error_hint,
                   summary=_SUMMARY, variant=PRACTICAL.assignment, variant_cases=_cases_for)
