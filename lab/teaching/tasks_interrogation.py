"""Checks of the interrogation tasks (notebooks 06-08): focal points, reflection, Christoffel symbols, start velocity."""

import math

import numpy as np

from .hints import _close
from .runner import DEFAULT_TIMEOUT, _rng
from .tasks_colors import _numeric_task

__all__ = ["focal_points", "reflect", "christoffel", "start_velocity"]


# -- the interrogation tasks (notebooks 06-08) ------------------------------------------------------


def _unit(v):
    return v / np.linalg.norm(v)


def focal_points(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(X, N, k1, k2)`` returns the points ``X + N/k1`` and ``X + N/k2`` of the classical focal sheets."""
    rng = _rng(seed)
    samples = []
    for k in range(5 if graded else 3):
        X = rng.integers(-8, 9, 3) / 4
        N = _unit(rng.normal(size=3))
        k1, k2 = sorted(rng.choice([-2, -1, -0.5, 0.25, 0.5, 1.0, 2.0, 4.0], 2, replace=False))[::-1]
        samples.append((f"random point {k + 1} (k1 = {k1:g}, k2 = {k2:g})", (X, N, float(k1), float(k2))))
    samples.append(("sphere of radius 2, outward normal (k1 = k2 = -1/2)", (np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 1.0]), -0.5, -0.5)))

    def expected(X, N, k1, k2):
        return np.stack([X + N / k1, X + N / k2])

    def diagnose(args, val, exp):
        X, N, k1, k2 = args
        if _close(val, np.stack([X + k1 * N, X + k2 * N])):
            return "the focal point lies at the radius of curvature 1/κ along N: F = X + N/κ, not X + κN."
        if _close(val, np.stack([X - N / k1, X - N / k2])):
            return "the sign: F = X + N/κ with the practical's N; a negative κ puts F on the −N side by itself."
        if _close(val[::-1], exp):
            return "return the sheets in the order (X + N/κ1, X + N/κ2)."
        return "F_i = X + N / κ_i (seeds/002, section 4)."

    return _numeric_task("focal_points", func, samples, expected, diagnose, graded=graded, timeout=timeout,
                         shape_text="two points (F1, F2), an array of shape (2, 3)")


def reflect(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(v, N)``: the view vector ``v`` reflected about the unit normal ``N``, R = v − 2 (v·N) N."""
    rng = _rng(seed)
    samples = [("straight down onto a horizontal plane", (np.array([0.0, 0.0, -1.0]), np.array([0.0, 0.0, 1.0]))),
               ("at 45 degrees", (_unit(np.array([1.0, 0.0, -1.0])), np.array([0.0, 0.0, 1.0])))]
    for k in range(4 if graded else 2):
        samples.append((f"random view and normal {k + 1}", (_unit(rng.normal(size=3)), _unit(rng.normal(size=3)))))

    def expected(v, N):
        return v - 2 * np.dot(v, N) * N

    def diagnose(args, val, exp):
        v, N = args
        if _close(val, v + 2 * np.dot(v, N) * N):
            return "the sign: R = v − 2 (v·N) N; the part along N changes its sign, the tangential part stays."
        if _close(val, v - np.dot(v, N) * N):
            return "that is the projection onto the tangent plane: the factor 2 is missing."
        if _close(val, -exp):
            return "R points away from the surface: R = v − 2 (v·N) N, not its negative."
        return "R = v − 2 (v·N) N (seeds/002, section 3)."

    return _numeric_task("reflect", func, samples, expected, diagnose, graded=graded, timeout=timeout,
                         shape_text="a 3-vector")


def _random_first_form(rng):
    while True:
        E, G = rng.integers(1, 16, 2) / 4
        F = rng.integers(-6, 7) / 8
        if E * G - F * F > 0.1:
            return float(E), float(F), float(G)


def christoffel(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(E, F, G, Eu, Ev, Fu, Fv, Gu, Gv)`` returns (Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂)."""
    rng = _rng(seed)
    samples = []
    for k in range(5 if graded else 3):
        E, F, G = _random_first_form(rng)
        derivs = tuple(float(x) for x in rng.integers(-12, 13, 6) / 4)
        samples.append((f"random first form {k + 1}", (E, F, G) + derivs))
    samples.append(("orthogonal parameters (F = 0)", (1.0, 0.0, 4.0, 0.0, 0.5, 0.0, 0.0, 2.0, 0.0)))

    def expected(E, F, G, Eu, Ev, Fu, Fv, Gu, Gv):
        D = 2 * (E * G - F * F)
        return np.array([
            (G * Eu - 2 * F * Fu + F * Ev) / D,
            (G * Ev - F * Gu) / D,
            (2 * G * Fv - G * Gu - F * Gv) / D,
            (2 * E * Fu - E * Ev - F * Eu) / D,
            (E * Gu - F * Ev) / D,
            (E * Gv - 2 * F * Fv + F * Gu) / D,
        ])

    def diagnose(args, val, exp):
        if _close(val, 2 * exp):
            return "the denominator is 2(EG − F²), not EG − F²."
        if _close(val, -exp):
            return "every symbol has the wrong sign; compare with the formulas in the notebook."
        if _close(val[[3, 4, 5, 0, 1, 2]], exp):
            return "Γ¹ and Γ² exchanged: return (Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂)."
        names = ("Γ¹₁₁", "Γ¹₁₂", "Γ¹₂₂", "Γ²₁₁", "Γ²₁₂", "Γ²₂₂")
        wrong = [names[i] for i in range(6) if not _close(val[i], exp[i])]
        return f"{', '.join(wrong)} wrong; compare with the formulas in the notebook (Struik, chapter 4)."

    return _numeric_task("christoffel", func, samples, expected, diagnose, graded=graded, timeout=timeout,
                         shape_text="six numbers (Γ¹₁₁, Γ¹₁₂, Γ¹₂₂, Γ²₁₁, Γ²₁₂, Γ²₂₂)")


def start_velocity(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(xu, xv, alpha)`` returns (u'(0), v'(0)) of the unit direction at angle α from x_v (seeds/003 eqs. 9–16)."""
    rng = _rng(seed)
    samples = []
    for k in range(5 if graded else 3):
        xu, xv = rng.integers(-8, 9, (2, 3)) / 4
        while np.linalg.norm(np.cross(xu, xv)) < 0.2:
            xu, xv = rng.integers(-8, 9, (2, 3)) / 4
        alpha = float(rng.uniform(0, 2 * np.pi))
        samples.append((f"random tangent plane {k + 1}, α = {np.degrees(alpha):.0f}°", (xu, xv, alpha)))
    samples.append(("α = 0: along x_v", (np.array([1.0, 0.0, 0.0]), np.array([0.5, 2.0, 0.0]), 0.0)))
    samples.append(("α = 90°: along x_v⊥ = −G x_u + F x_v", (np.array([1.0, 0.0, 0.0]), np.array([0.5, 2.0, 0.0]), np.pi / 2)))

    def expected(xu, xv, alpha):
        E, F, G = xu @ xu, xu @ xv, xv @ xv
        perp = -G * xu + F * xv
        lv, lp = np.sqrt(G), np.linalg.norm(perp)
        return np.array([-np.sin(alpha) * G / lp, np.cos(alpha) / lv + F * np.sin(alpha) / lp])

    def diagnose(args, val, exp):
        xu, xv, alpha = args
        E, F, G = xu @ xu, xu @ xv, xv @ xv
        speed = E * val[0] ** 2 + 2 * F * val[0] * val[1] + G * val[1] ** 2
        if _close(val, exp[::-1]):
            return "u' and v' exchanged: return (u'(0), v'(0))."
        if _close(val, -exp):
            return "the direction is reversed: at α = 0 the path starts along +x_v."
        if not math.isclose(speed, 1.0, rel_tol=1e-6):
            return (f"the direction must have unit length on the surface: E u'² + 2F u'v' + G v'² = 1 "
                    f"(yours gives {speed:.4g}; eq. 14).")
        return "α is measured from x_v towards x_v⊥ = −G x_u + F x_v (eqs. 9, 10, 15)."

    return _numeric_task("start_velocity", func, samples, expected, diagnose, graded=graded, timeout=timeout,
                         shape_text="two numbers (u'(0), v'(0))")
