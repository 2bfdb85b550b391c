"""The check of notebook 10's task (lab.teaching.tasks.trimming): the signed area of a trimming loop."""

import numpy as np
import pytest
import sympy as sp

import lab
from lab import check
from lab.teaching.tasks import trimming


def shoelace(P):
    P = np.asarray(P, dtype=float)
    Q = np.roll(P, -1, axis=0)
    return 0.5 * float(np.sum(P[:, 0] * Q[:, 1] - Q[:, 0] * P[:, 1]))


def test_reference_solution_passes_public_and_graded():
    public, graded = check.signed_area(shoelace), check.signed_area(shoelace, graded=True)
    assert public.passed and graded.passed, str(public) + str(graded)
    assert len(graded.cases) > len(public.cases) >= 6
    assert check.TASKS["signed_area"].name == "signed_area"


def test_expected_areas_are_exact(rng):
    # the check's reference is the shoelace formula in rational arithmetic; sympy's polygon area is signed too
    for k in range(6):
        P = trimming._star(rng, 7, clockwise=bool(k % 2))
        exact = sp.Polygon(*[sp.Point(sp.Rational(str(u)), sp.Rational(str(v))) for u, v in P]).area
        assert trimming._exact_area(P) == float(exact)
        assert (exact < 0) == bool(k % 2)  # clockwise: negative
        assert not len(lab.trimming.loop_intersections(P, 1.0)[0])  # a simple polygon


@pytest.mark.parametrize(
    "mistake, hint",
    [
        (lambda P: -shoelace(P), "the sign: a counter-clockwise loop has positive area"),
        (lambda P: abs(shoelace(P)), "the area is signed: a clockwise loop (a hole) must give a negative area"),
        (lambda P: 2 * shoelace(P), "the factor ½ is missing"),
        (lambda P: 0.5 * float(np.sum(np.asarray(P)[:-1, 0] * np.asarray(P)[1:, 1]
                                      - np.asarray(P)[1:, 0] * np.asarray(P)[:-1, 1])),
         "the closing edge from the last point back to the first is missing"),
    ],
    ids=["sign", "abs", "no-half", "open"],
)
def test_each_mistake_gets_its_hint(mistake, hint):
    report = check.signed_area(mistake)
    assert not report.passed and hint in str(report), str(report)


def test_not_implemented_and_delegation():
    def stub(P):
        raise NotImplementedError("return the signed area of the loop")

    report = check.signed_area(stub)
    assert report.status == "not implemented" and "return the signed area" in str(report)
    report = check.signed_area(lambda P: lab.trimming.signed_area(P))
    assert report.status == "delegated" and "trimming.loops.signed_area" in report.message
    assert check.signed_area(lambda P: "big").status == "failed"
