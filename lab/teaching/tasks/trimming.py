"""The trimming task (notebook 10): the signed area of a trimming loop decides its orientation."""

from fractions import Fraction

import numpy as np

from ...i18n import N_, _
from ...interrogation.trimming import loops as _loops
from ..task import CaseSpec, Task, close, scalar_judge

__all__ = ["SIGNED_AREA"]


def _exact_area(P):
    """Shoelace formula in exact rational arithmetic (the coordinates are multiples of 1/8)."""
    pts = [(Fraction(float(u)), Fraction(float(v))) for u, v in P]
    twice = sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(pts, pts[1:] + pts[:1]))
    return float(twice / 2)


def _star(rng, k, clockwise):
    """A star-shaped simple polygon with ``k`` vertices, coordinates on a 1/8 grid, around (1/2, 1/2)."""
    while True:
        angles = np.sort(rng.uniform(0, 2 * np.pi, k))
        r = rng.uniform(0.15, 0.45, k)
        P = np.round(8 * (0.5 + np.column_stack([r * np.cos(angles), r * np.sin(angles)]))) / 8
        if len(np.unique(P, axis=0)) == k and abs(_exact_area(P)) > 0.02 and len(_loops.loop_intersections(P, 1.0)[0]) == 0:
            return P[::-1] if clockwise else P


def _cases(rng, graded):
    """Unit and shifted squares both ways round, a triangle far from the origin, random star-shaped polygons of
    either orientation, and a loop whose first point is repeated at the end (the area must not change)."""
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    cases = [
        CaseSpec(_("unit square, counter-clockwise (area +1)"), (square,)),
        CaseSpec(_("unit square, clockwise (area -1)"), (square[::-1].copy(),)),
        CaseSpec(_("triangle (0, 0), (4, 0), (0, 3), far from the origin: shifted by (100, -50)"),
                 (np.array([[100.0, -50.0], [104.0, -50.0], [100.0, -47.0]]),)),
    ]
    for k in range(4 if graded else 2):
        clockwise = bool(k % 2)
        P = _star(rng, int(rng.integers(5, 10)), clockwise)
        name = (_("random {k}-gon, clockwise") if clockwise else _("random {k}-gon, counter-clockwise")).format(k=len(P))
        cases.append(CaseSpec(name, (P,)))
    P = _star(rng, 6, False)
    cases.append(CaseSpec(_("closed explicitly: the first point repeated at the end"), (np.vstack([P, P[:1]]),)))
    return cases


def _hint(args, val, exp):
    (P,) = args
    Q = np.roll(P, -1, axis=0)
    open_sum = 0.5 * float(np.sum(P[:-1, 0] * Q[:-1, 1] - Q[:-1, 0] * P[:-1, 1]))
    if close(val, -exp) and exp < 0:
        return _("the area is signed: a clockwise loop (a hole) must give a negative area, so no abs().")
    if close(val, -exp):
        return _("the sign: a counter-clockwise loop has positive area, A = ½ Σ (u_i v_(i+1) − u_(i+1) v_i).")
    if close(val, 2 * exp):
        return _("the factor ½ is missing: A = ½ Σ (u_i v_(i+1) − u_(i+1) v_i).")
    if close(val, open_sum):
        return _("the closing edge from the last point back to the first is missing (np.roll(P, -1, axis=0)).")
    return _("the shoelace formula: A = ½ Σ_i (u_i v_(i+1) − u_(i+1) v_i), indices modulo k.")


#: ``func(loop)``: the signed (shoelace) area of a closed polyline, positive when counter-clockwise.
#: Choi & Lee, §2.1: the outer trimming loop runs counter-clockwise (positive area) and holes run clockwise
#: (negative), so the trimmed region lies to the left of every loop.
SIGNED_AREA = Task("signed_area", _cases, lambda c: _exact_area(c.args[0]),
                   scalar_judge(_hint, N_("one number (the signed area)")),
                   blocked=("lab.interrogation.trimming.loops.signed_area",
                            "lab.interrogation.trimming.surface.TrimmedSurface.area_uv"),
                   summary=N_("one number (the signed area)"))
