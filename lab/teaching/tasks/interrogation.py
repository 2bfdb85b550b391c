"""The interrogation tasks (notebooks 06-08): focal points, reflection, Christoffel symbols, start velocity."""

import math

import numpy as np

from ...i18n import N_, _, decimal
from ..task import CaseSpec, Task, close, scalar_judge

__all__ = ["CHRISTOFFEL", "FOCAL_POINTS", "REFLECT", "START_VELOCITY"]


def _unit(v):
    return v / np.linalg.norm(v)


# -- focal points X + N / κ ------------------------------------------------------------------------------


def _focal_cases(rng, graded):
    cases = []
    for k in range(5 if graded else 3):
        X = rng.integers(-8, 9, 3) / 4
        N = _unit(rng.normal(size=3))
        k1, k2 = sorted(rng.choice([-2, -1, -0.5, 0.25, 0.5, 1.0, 2.0, 4.0], 2, replace=False))[::-1]
        name = _("random point {k} (k1 = {k1}, k2 = {k2})").format(k=k + 1, k1=decimal(f"{k1:g}"), k2=decimal(f"{k2:g}"))
        cases.append(CaseSpec(name, (X, N, float(k1), float(k2))))
    cases.append(CaseSpec(_("sphere of radius 2, outward normal (k1 = k2 = -1/2)"),
                          (np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 1.0]), -0.5, -0.5)))
    return cases


def _focal_hint(args, val, exp):
    X, N, k1, k2 = args
    if close(val, np.stack([X + k1 * N, X + k2 * N])):
        return _("the focal point lies at the radius of curvature 1/κ along N: F = X + N/κ, not X + κN.")
    if close(val, np.stack([X - N / k1, X - N / k2])):
        return _("the sign: F = X + N/κ with the practical's N; a negative κ puts F on the −N side by itself.")
    if close(val[::-1], exp):
        return _("return the sheets in the order (X + N/κ1, X + N/κ2).")
    return _("F_i = X + N / κ_i (Choi & Lee, section 4).")


FOCAL_POINTS = Task("focal_points", _focal_cases,
                    lambda c: np.stack([c.args[0] + c.args[1] / c.args[2], c.args[0] + c.args[1] / c.args[3]]),
                    scalar_judge(_focal_hint, N_("two points (F1, F2), an array of shape (2, 3)")),
                    blocked=("lab.interrogation.focal.focal_points", "lab.interrogation.focal.focal_sheet"),
                    summary=N_("two points (F1, F2), an array of shape (2, 3)"))


# -- reflection R = v - 2 (v.N) N -------------------------------------------------------------------------


def _reflect_cases(rng, graded):
    cases = [CaseSpec(_("straight down onto a horizontal plane"), (np.array([0.0, 0.0, -1.0]), np.array([0.0, 0.0, 1.0]))),
             CaseSpec(_("at 45 degrees"), (_unit(np.array([1.0, 0.0, -1.0])), np.array([0.0, 0.0, 1.0])))]
    for k in range(4 if graded else 2):
        cases.append(CaseSpec(_("random view and normal {k}").format(k=k + 1), (_unit(rng.normal(size=3)), _unit(rng.normal(size=3)))))
    return cases


def _reflect_hint(args, val, exp):
    v, N = args
    if close(val, v + 2 * np.dot(v, N) * N):
        return _("the sign: R = v − 2 (v·N) N; the part along N changes its sign, the tangential part stays.")
    if close(val, v - np.dot(v, N) * N):
        return _("that is the projection onto the tangent plane: the factor 2 is missing.")
    if close(val, -exp):
        return _("R points away from the surface: R = v − 2 (v·N) N, not its negative.")
    return _("R = v − 2 (v·N) N (Choi & Lee, section 3).")


REFLECT = Task("reflect", _reflect_cases, lambda c: c.args[0] - 2 * np.dot(c.args[0], c.args[1]) * c.args[1],
               scalar_judge(_reflect_hint, N_("a 3-vector")), blocked=("lab.interrogation.reflection.reflect",),
               summary=N_("a 3-vector"))


# -- Christoffel symbols -------------------------------------------------------------------------------------


def _random_first_form(rng):
    while True:
        E, G = rng.integers(1, 16, 2) / 4
        F = rng.integers(-6, 7) / 8
        if E * G - F * F > 0.1:
            return float(E), float(F), float(G)


def _christoffel_cases(rng, graded):
    cases = []
    for k in range(5 if graded else 3):
        derivs = tuple(float(x) for x in rng.integers(-12, 13, 6) / 4)
        cases.append(CaseSpec(_("random first form {k}").format(k=k + 1), _random_first_form(rng) + derivs))
    cases.append(CaseSpec(_("orthogonal parameters (F = 0)"), (1.0, 0.0, 4.0, 0.0, 0.5, 0.0, 0.0, 2.0, 0.0)))
    return cases


def _christoffel_expected(case):
    E, F, G, Eu, Ev, Fu, Fv, Gu, Gv = case.args
    D = 2 * (E * G - F * F)
    return np.array([
        (G * Eu - 2 * F * Fu + F * Ev) / D,
        (G * Ev - F * Gu) / D,
        (2 * G * Fv - G * Gu - F * Gv) / D,
        (2 * E * Fu - E * Ev - F * Eu) / D,
        (E * Gu - F * Ev) / D,
        (E * Gv - 2 * F * Fv + F * Gu) / D,
    ])


def _christoffel_hint(args, val, exp):
    if close(val, 2 * exp):
        return _("the denominator is 2(EG − F²), not EG − F².")
    if close(val, -exp):
        return _("every symbol has the wrong sign; compare with the formulas in the notebook.")
    if close(val[[3, 4, 5, 0, 1, 2]], exp):
        return _("Γ¹ and Γ² exchanged: return (Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂).")
    names = ("Γ¹₁₁", "Γ¹₁₂", "Γ¹₂₂", "Γ²₁₁", "Γ²₁₂", "Γ²₂₂")
    wrong = [names[i] for i in range(6) if not close(val[i], exp[i])]
    return _("{names} wrong; compare with the formulas in the notebook (Struik, chapter 4).").format(names=", ".join(wrong))


_SIX = N_("six numbers (Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂)")
CHRISTOFFEL = Task("christoffel", _christoffel_cases, _christoffel_expected, scalar_judge(_christoffel_hint, _SIX),
                   blocked=tuple(f"lab.interrogation.geodesics.problem.{name}" for name in (
                       "christoffel", "_christoffel_symbols", "_second_kind", "_second_kind_of")),
                   summary=_SIX)


# -- start velocity (u'(0), v'(0)) of angle α ----------------------------------------------------------------


def _start_cases(rng, graded):
    cases = []
    for k in range(5 if graded else 3):
        xu, xv = rng.integers(-8, 9, (2, 3)) / 4
        while np.linalg.norm(np.cross(xu, xv)) < 0.2:
            xu, xv = rng.integers(-8, 9, (2, 3)) / 4
        alpha = float(rng.uniform(0, 2 * np.pi))
        name = _("random tangent plane {k}, α = {alpha}°").format(k=k + 1, alpha=f"{np.degrees(alpha):.0f}")
        cases.append(CaseSpec(name, (xu, xv, alpha)))
    xu, xv = np.array([1.0, 0.0, 0.0]), np.array([0.5, 2.0, 0.0])
    cases.append(CaseSpec(_("α = 0: along x_v"), (xu, xv, 0.0)))
    cases.append(CaseSpec(_("α = 90°: along x_v⊥ = −G x_u + F x_v"), (xu, xv, np.pi / 2)))
    return cases


def _start_expected(case):
    xu, xv, alpha = case.args
    F, G = xu @ xv, xv @ xv
    perp = -G * xu + F * xv
    lv, lp = np.sqrt(G), np.linalg.norm(perp)
    return np.array([-np.sin(alpha) * G / lp, np.cos(alpha) / lv + F * np.sin(alpha) / lp])


def _start_hint(args, val, exp):
    xu, xv, _alpha = args
    E, F, G = xu @ xu, xu @ xv, xv @ xv
    speed = E * val[0] ** 2 + 2 * F * val[0] * val[1] + G * val[1] ** 2
    if close(val, exp[::-1]):
        return _("u' and v' exchanged: return (u'(0), v'(0)).")
    if close(val, -exp):
        return _("the direction is reversed: at α = 0 the path starts along +x_v.")
    if not math.isclose(speed, 1.0, rel_tol=1e-6):
        return _("the direction must have unit length on the surface: E u'² + 2F u'v' + G v'² = 1 "
                 "(yours gives {speed}; eq. 14).").format(speed=decimal(f"{speed:.4g}"))
    return _("α is measured from x_v towards x_v⊥ = −G x_u + F x_v (eqs. 9, 10, 15).")


START_VELOCITY = Task("start_velocity", _start_cases, _start_expected,
                      scalar_judge(_start_hint, N_("two numbers (u'(0), v'(0))")),
                      blocked=("lab.interrogation.geodesics.problem.start_direction",
                               "lab.interrogation.geodesics.problem._direction",
                               "lab.interrogation.geodesics.problem._frame"),
                      summary=N_("two numbers (u'(0), v'(0))"))
