"""The check of notebook 11's task (lab.teaching.tasks.models): which faces of a part are developable."""

import numpy as np
import pytest
import sympy as sp

from lab import check
from lab.teaching.tasks import models


def _size(s):
    P = s.control_points.reshape(-1, 3)
    return np.linalg.norm(P.max(axis=0) - P.min(axis=0))


def _max_K(s, n=41, which="K"):
    (u0, u1), (v0, v1) = s.domain
    c = s.curvature(np.linspace(u0, u1, n)[:, None], np.linspace(v0, v1, n)[None, :])
    return np.max(np.abs(getattr(c, which)))


def developable_faces(model):
    """The notebook's solution: max |K| s² on a 41 × 41 grid against 1e-6."""
    return [f.index for f in model.faces if _max_K(f.surface) * _size(f.surface) ** 2 <= 1e-6]


MISTAKES = {
    "H": (lambda m: [f.index for f in m.faces if _max_K(f.surface, which="H") * _size(f.surface) <= 1e-6],
          "is developable: K = κ1·κ2 = 0 although H ≠ 0"),
    "kind": (lambda m: [f.index for f in m.faces if f.kind in ("Plane", "Cylinder", "Cone")],
             "is a B-spline surface and still developable"),
    "ruled": (lambda m: [f.index for f in m.faces if 1 in f.surface.degree],
              "is made of straight lines (a twisted bilinear patch, a hyperbolic paraboloid) but not developable"),
    "corners": (lambda m: [f.index for f in m.faces if _max_K(f.surface, n=2) * _size(f.surface) ** 2 <= 1e-6],
                "is flat at its corners and along its border"),
    "absolute": (lambda m: [f.index for f in m.faces if _max_K(f.surface) <= 1e-6],
                 "Compare K·s² with 1e-6, not K"),
    "positions": (lambda m: [k for k, f in enumerate(m.faces) if f.index in developable_faces(m)],
                  "these are positions in model.faces, not file indices"),
    "complement": (lambda m: [f.index for f in m.faces if f.index not in developable_faces(m)],
                   "these are the faces that are NOT developable"),
}


def test_reference_solution_passes_public_and_graded():
    public, graded = check.developable_faces(developable_faces), check.developable_faces(developable_faces, graded=True)
    assert public.passed and graded.passed, str(public) + str(graded)
    assert len(graded.cases) > len(public.cases) >= 7


@pytest.mark.parametrize("mistake", sorted(MISTAKES))
def test_each_mistake_gets_its_hint(mistake):
    func, hint = MISTAKES[mistake]
    report = check.developable_faces(func)
    assert not report.passed and hint in report.message, str(report)


def test_the_truth_of_every_case_is_far_from_the_tolerance():
    """Developable faces: max |K| s² at rounding level; curved ones at least 1000 times the tolerance 1e-6, over
    40 seeds and every kind, at the scales the cases use."""
    rng = np.random.default_rng(11)
    worst_flat, least_curved = 0.0, np.inf
    for _ in range(40):
        for name in models._MAKERS:
            face = models._model(rng, [name], scale=float(10.0 ** rng.uniform(-4, 3)))[0]
            kn = models.relative_gaussian(models._surface(face))[0]
            if name in models.DEVELOPABLE:
                worst_flat = max(worst_flat, kn)
            else:
                least_curved = min(least_curved, kn)
    assert worst_flat < 1e-10, worst_flat
    assert least_curved > 1e-3, least_curved


def _bezier(P, u, v):
    m, n = P.shape[0] - 1, P.shape[1] - 1
    B = lambda k, d, t: sp.binomial(d, k) * t**k * (1 - t) ** (d - k)
    return sp.Matrix([sum(B(i, m, u) * B(j, n, v) * P[i, j, c] for i in range(m + 1) for j in range(n + 1))
                      for c in range(3)])


@pytest.mark.parametrize("name", ["plane", "tangent", "twisted"])
def test_developable_by_construction_with_sympy(name):
    """K's numerator det[x_uu, x_u, x_v] det[x_vv, x_u, x_v] - det[x_uv, x_u, x_v]^2 is the zero polynomial for
    the plane and the tangent surface (exact rational control points), and not for the twisted patch."""
    rng = np.random.default_rng(3)
    face = models._MAKERS[name](rng)
    P = np.vectorize(lambda x: sp.Rational(x).limit_denominator(10**6), otypes=[object])(np.round(face["P"], 6))
    if name == "tangent":  # rebuild the rows exactly from the curve: c + a e and c + b e
        c = np.vectorize(lambda x: sp.Rational(x).limit_denominator(10**6), otypes=[object])(
            np.round(face["P"][:, 0], 6))
        d = 3 * np.diff(c, axis=0)
        e = np.array([d[0], (d[0] + 2 * d[1]) / 3, (2 * d[1] + d[2]) / 3, d[2]], dtype=object)
        P = np.stack([c, c + sp.Rational(1, 2) * e], axis=1)
    u, v = sp.symbols("u v")
    x = _bezier(P, u, v)
    xu, xv = x.diff(u), x.diff(v)
    det = lambda a: sp.Matrix.hstack(a, xu, xv).det()
    numerator = sp.expand(det(x.diff(u, 2)) * det(x.diff(v, 2)) - det(x.diff(u).diff(v)) ** 2)
    assert (numerator == 0) == (name != "twisted"), numerator


def test_rational_faces_have_their_curvature():
    """The sphere band has K = 1/R^2 everywhere; the exact cylinder and cone K = 0 (to rounding)."""
    rng = np.random.default_rng(5)
    sphere = models._surface(models._sphere(rng))
    R = np.linalg.norm(sphere.evaluate(0.3, 0.6))  # centred at the origin before the model moves it
    c = sphere.curvature(np.linspace(0, 1, 9)[:, None], np.linspace(0, 1, 9)[None, :])
    assert np.allclose(c.K, 1 / R**2, rtol=1e-12) and np.allclose(c.k1, c.k2, rtol=1e-10)
    for name in ("cylinder", "cone"):
        s = models._surface(models._MAKERS[name](rng))
        assert _max_K(s) * _size(s) ** 2 < 1e-13 and _max_K(s, which="H") * _size(s) > 0.1


def test_answers_that_are_not_indices():
    def stub(model):
        raise NotImplementedError("return the file indices of the developable faces")

    assert check.developable_faces(stub).status == "not implemented"
    assert "return the file indices" in check.developable_faces(lambda m: True).message
    report = check.developable_faces(lambda m: [f.index for f in m.faces][:1] * 2)
    assert not report.passed
    report = check.developable_faces(lambda m: {f.index for f in m.faces if f.index in developable_faces(m)})
    assert report.passed, str(report)  # a set is an answer too
    report = check.developable_faces(lambda m: m.faces[0].surface.gaussian)
    assert report.status == "error" and "a face has .index, .kind and .surface" in str(report), str(report)
