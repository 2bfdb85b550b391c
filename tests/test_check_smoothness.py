"""The check of notebook 12's task (lab.teaching.tasks.smoothness): principal directions at a patch corner."""

import numpy as np
import pytest

import lab
from lab import check
from lab.teaching.tasks import smoothness


def weingarten(bu, bv, buu, buv, bvv, *, mistake=None):
    N = np.cross(bu, bv)
    N = N / np.linalg.norm(N)
    G = np.array([[bu @ bu, bu @ bv], [bu @ bv, bv @ bv]])
    H = np.array([[N @ buu, N @ buv], [N @ buv, N @ bvv]])
    S = H if mistake == "H" else H @ np.linalg.inv(G) if mistake == "transposed" else np.linalg.solve(G, H)
    k, w = np.linalg.eig(S)
    order = {"swap": np.argsort(k.real), "unsorted": np.arange(2)}.get(mistake, np.argsort(-k.real))
    w = w.real[:, order]
    if mistake == "flat":
        return np.array([[w[0, 0], w[1, 0], 0.0], [w[0, 1], w[1, 1], 0.0]])
    if mistake == "rows":  # the rows of the eigenvector matrix instead of its columns
        w = w.T
    d = np.stack([w[0, i] * bu + w[1, i] * bv for i in range(2)])
    return 3 * d if mistake == "unnormalised" else d / np.linalg.norm(d, axis=1, keepdims=True)


def test_reference_solution_passes_public_and_graded():
    public, graded = check.principal_directions(weingarten), check.principal_directions(weingarten, graded=True)
    assert public.passed and graded.passed, str(public) + str(graded)
    assert len(graded.cases) > len(public.cases) >= 5


def test_expected_agrees_with_the_library(rng):
    # the exact (sympy) answer against curvature(..., directions=True) of the patch itself
    for _ in range(3):
        P, d = smoothness._net(rng)
        c = lab.BezierSurface(P).curvature(0.0, 0.0, directions=True)
        e = smoothness.exact(*d)
        assert abs(abs(e[0] @ c.d1) - 1) <= 1e-13 and abs(abs(e[1] @ c.d2) - 1) <= 1e-13


@pytest.mark.parametrize(
    "mistake, hint",
    [
        ("swap", "d1 and d2 are swapped"),
        ("unnormalised", "not unit vectors"),
        ("H", "eigenvectors of the second fundamental form H alone"),
        ("transposed", "the transpose of the Weingarten map"),
        ("flat", "not orthogonal in space"),
        ("unsorted", "d1 and d2 are swapped"),  # numpy's order: the public case z = x²/4 + y² has κ1 second
        ("rows", "the rows of the eigenvector matrix"),
    ],
)
def test_each_mistake_gets_its_hint(mistake, hint):
    report = check.principal_directions(lambda *d: weingarten(*d, mistake=mistake))
    assert not report.passed and hint in str(report), str(report)


def test_shapes_stub_and_delegation():
    report = check.principal_directions(lambda *d: np.zeros((2, 2)))
    assert not report.passed and "these are 2-vectors" in str(report)

    def stub(*d):
        raise NotImplementedError("return d1 and d2")

    assert check.principal_directions(stub).status == "not implemented"

    def library(bu, bv, buu, buv, bvv):
        from lab.geometry import directions
        from lab.geometry.derivatives import Derivatives

        c = directions.from_derivatives(Derivatives(bu, bu, bv, buu, buv, bvv))
        return np.stack([c.d1, c.d2])

    report = check.principal_directions(library)
    assert report.status == "delegated" and "directions.from_derivatives" in report.message
