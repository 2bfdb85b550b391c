"""The curvature tasks (notebooks 00-03): mean curvature, curves, fundamental forms, K/H/κ, derivative nets."""

import math
from fractions import Fraction

import numpy as np
import sympy as sp

from ...i18n import N_, _, decimal
from ..task import CaseSpec, Hint, Task, close, fmt
from . import ANALYTIC_BLOCK
from .hints import diagnose_indices, factor_hint, index_error_hint
from .hints import hint as variant_hint
from .references import NET_NAMES, rand_net, variant_corner_derivatives, variant_nets

__all__ = [
    "BEZIER_BLOCK",
    "CORNER_DERIVATIVES",
    "CURVATURES",
    "CURVATURE_BLOCK",
    "CURVE_CURVATURE",
    "DERIVATIVE_NETS",
    "FUNDAMENTAL_FORMS",
    "WARMUP",
]

#: What computes fundamental forms, normals or curvature from derivatives, also through a surface object built
#: on the given vectors (a ParametricSurface whose derivatives are the case's inputs).
CURVATURE_BLOCK = ANALYTIC_BLOCK + tuple(f"lab.geometry.curvature.{name}" for name in (
    "from_derivatives", "fundamental_forms", "principal_curvatures", "unit_normal", "shape_operator")) + (
    "lab.geometry.directions.from_derivatives", "lab.geometry.directions.eigen") + tuple(
    f"lab.model.surface.Surface.{name}" for name in ("normal", "fundamental_forms", "curvature", "curvature_grid",
                                                      "_curvature", "_directions")) + (
    # a CAD kernel's curvature of a part written from the case's net, the normal curvature across an edge, the
    # traceless part of the Weingarten map: roads to the same numbers (tests/test_roads.py finds them)
    "lab.interrogation.cad.kernel.occ_curvature", "lab.interrogation.continuity.measures",
    "lab.interrogation.umbilics.traceless")
#: What computes derivative nets or derivatives of a Bézier patch (the corner stencils too).
BEZIER_BLOCK = tuple(f"lab.geometry.bezier.{name}" for name in (
    "derivative_net", "derivatives", "corner_derivatives", "_corner_values", "_corner_stencil", "_both_corners",
    "_evaluate_nets")) + (
    "lab.geometry.bspline.basis_derivatives", "lab.geometry.bspline.basis_rows",
    "lab.geometry.tensor.point_derivatives", "lab.geometry.tensor.grouped_derivatives",
    "lab.geometry.tensor.grid_blocks", "lab.geometry.analytic._bernstein_exact",
    "lab.model.surface.Surface.derivatives", "lab.model.patches.BezierPatches.corner_derivatives",
    "lab.model.patches.BezierPatches.derivatives")


def _number(value):
    """A single number from a result (a 0-d or 1-element array), or None."""
    a = np.asarray(value, dtype=float) if isinstance(value, np.ndarray) else None
    return float(a.reshape(-1)[0]) if a is not None and a.size == 1 else None


# -- warmup: H = (k1 + k2) / 2 -------------------------------------------------------------------------


def _warmup_cases(rng, graded):
    values = [(1.0, 1.0), (2.0, -2.0)] + [tuple(rng.integers(-20, 21, 2) / 4) for _ in range(4 if graded else 2)]
    return [CaseSpec(_("H for k1 = {k1}, k2 = {k2}").format(k1=decimal(f"{k1:g}"), k2=decimal(f"{k2:g}")), (float(k1), float(k2)))
            for k1, k2 in values]


def _warmup_judge(case, value, exp):
    k1, k2 = case.args
    got = _number(value)
    if got is None:
        return False, decimal(f"{exp:g}"), fmt(value), _("return one number.")
    ok = abs(got - exp) <= 1e-12
    hint = ""
    if abs(got - (k1 + k2)) < 1e-12:
        hint = _("the mean of two numbers is their sum divided by 2.")
    elif abs(got - k1 * k2) < 1e-12:
        hint = _("k1 * k2 is the Gaussian curvature K; the mean curvature is (k1 + k2) / 2.")
    return ok, decimal(f"{exp:g}"), decimal(f"{got:g}"), hint


WARMUP = Task("warmup", _warmup_cases, lambda c: (c.args[0] + c.args[1]) / 2, _warmup_judge,
              summary=N_("one number, the mean curvature"))


# -- curvature of a space curve ---------------------------------------------------------------------------

_t = sp.Symbol("t")


def _curve_cases(rng, graded):
    r = Fraction(int(rng.integers(2, 9)), 2)
    w = int(rng.integers(2, 5))
    samples = [(_("circle of radius {r} at speed {speed}").format(r=r, speed=r * w), sp.Matrix([r * sp.cos(w * _t), r * sp.sin(w * _t), 0]),
                sp.Rational(1, 3)),
               (_("straight line"), sp.Matrix([1 + 2 * _t, 3 * _t, -_t]), sp.Rational(1, 2))]
    for k in range(3 if graded else 1):
        coeffs = rng.integers(-4, 5, size=(3, 4))
        c = sp.Matrix([sum(int(coeffs[i, j]) * _t**j for j in range(4)) for i in range(3)])
        samples.append((_("random cubic space curve {k}").format(k=k + 1), c, sp.Rational(int(rng.integers(1, 8)), 8)))
    cases = []
    for name, c, t0 in samples:
        d1 = np.array([float(x) for x in c.diff(_t).subs(_t, t0)])
        d2 = np.array([float(x) for x in c.diff(_t, 2).subs(_t, t0)])
        cases.append(CaseSpec(name, (d1, d2), info={"curve": c, "t0": t0}))
    return cases


def _curve_expected(case):
    c, t0 = case.info["curve"], case.info["t0"]
    cross = c.diff(_t).cross(c.diff(_t, 2)).subs(_t, t0)
    speed = c.diff(_t).subs(_t, t0).norm()
    return float(sp.N(cross.norm() / speed**3, 30))


def _curve_judge(case, value, exact):
    d1, d2 = case.args
    val = _number(value)
    if val is None:
        return False, _("a number ≈ {x}").format(x=decimal(f"{exact:.6g}")), fmt(value), _("return one number (a float).")
    ok = abs(val - exact) <= 1e-9 * max(1.0, abs(exact))
    hint = ""
    s1, cr = float(np.linalg.norm(d1)), float(np.linalg.norm(np.cross(d1, d2)))
    if math.isclose(val, cr / s1**2, rel_tol=1e-9):
        hint = _("divide by |c'|³, not |c'|²: the curvature of a curve is |c' × c''| / |c'|³.")
    elif math.isclose(val, float(np.linalg.norm(d2)), rel_tol=1e-9):
        hint = _("|c''| is the curvature only when the curve has unit speed; use |c' × c''| / |c'|³.")
    elif math.isclose(val, cr, rel_tol=1e-9):
        hint = _("|c' × c''| must be divided by |c'|³.")
    return ok, f"{exact:.10g}", f"{val:.10g}", hint


CURVE_CURVATURE = Task("curve_curvature", _curve_cases, _curve_expected, _curve_judge,
                       summary=N_("one number, the curvature κ"))


# -- fundamental forms -----------------------------------------------------------------------------------


def _random_vectors(rng):
    return [sp.Matrix([sp.Rational(int(x), 4) for x in rng.integers(-12, 13, size=3)]) for _ in range(5)]


def _forms_cases(rng, graded):
    cases = []
    for k in range(6 if graded else 3):
        vecs = _random_vectors(rng)
        while vecs[0].cross(vecs[1]).norm() == 0:
            vecs = _random_vectors(rng)
        args = tuple(np.array([float(x) for x in v]) for v in vecs)
        cases.append(CaseSpec(_("random derivatives {k}").format(k=k + 1), args, info={"vectors": vecs}))
    return cases


def _forms_expected(case):
    bu, bv, buu, buv, bvv = case.info["vectors"]
    Q = bu.cross(bv)
    N = Q / sp.sqrt(Q.dot(Q))
    vals = [bu.dot(bu), bu.dot(bv), bv.dot(bv), N.dot(buu), N.dot(buv), N.dot(bvv)]
    return np.array([float(sp.N(x, 30)) for x in vals])


def _forms_judge(case, value, exact):
    names = ("E", "F", "G", "e", "f", "g")
    if not isinstance(value, np.ndarray) or value.shape != (6,):
        return (False, _("a tuple (E, F, G, e, f, g) of six numbers"), fmt(value),
                _("return the six numbers in the order E, F, G, e, f, g."))
    ok = close(value, exact, rtol=1e-10)
    hint = ""
    W = float(np.linalg.norm(np.cross(case.args[0], case.args[1])))
    if close(value[:3], exact[:3]) and close(value[3:], exact[3:] * W):
        hint = variant_hint("unnormalised")
    elif close(value[:3], exact[:3]) and close(value[3:], -exact[3:]):
        hint = variant_hint("orientation")
    elif not close(value[:3], exact[:3]):
        wrong = [names[i] for i in range(3) if not close(value[i], exact[i])]
        hint = _("{names} wrong: E = ⟨b_u, b_u⟩, F = ⟨b_u, b_v⟩, G = ⟨b_v, b_v⟩.").format(names=", ".join(wrong))
    else:
        wrong = [names[i] for i in range(3, 6) if not close(value[i], exact[i])]
        hint = _("{names} wrong: e = ⟨N, b_uu⟩, f = ⟨N, b_uv⟩, g = ⟨N, b_vv⟩.").format(names=", ".join(wrong))
    return ok, fmt(exact), fmt(value), hint


FUNDAMENTAL_FORMS = Task("fundamental_forms", _forms_cases, _forms_expected, _forms_judge, blocked=CURVATURE_BLOCK,
                         allowed="numpy (np.cross, np.dot, np.linalg.norm)",
                         summary=N_("a tuple (E, F, G, e, f, g) of six numbers"))


# -- K, H, κ1, κ2 from the fundamental forms ----------------------------------------------------------------


def _umbilic_forms(rng):
    """(E, F, G, e, f, g) of an umbilic (II = λ I) for which H² − K computes slightly negative in floats."""
    for _attempt in range(1000):
        E, G = rng.uniform(0.5, 3, 2)
        F = rng.uniform(-0.4, 0.4) * math.sqrt(E * G)
        lam = rng.uniform(0.2, 2)
        e, f, g = lam * E, lam * F, lam * G
        det = E * G - F * F
        K = (e * g - f * f) / det
        H = 0.5 * (e * G - 2 * f * F + g * E) / det
        if H * H - K < 0:
            return (E, F, G, e, f, g), lam
    raise RuntimeError("no umbilic case with negative rounding found")  # pragma: no cover


def _curvatures_cases(rng, graded):
    cases = []
    for k in range(4 if graded else 2):
        E, G = rng.integers(1, 12, 2) / 4
        F = rng.integers(-3, 4) / 8
        while 4 * (E * G - F * F) < E * G:  # I must be positive definite (and not nearly singular): redraw F
            F = rng.integers(-3, 4) / 8
        e, f, g = rng.integers(-12, 13, 3) / 4
        cases.append(CaseSpec(_("random forms {k}").format(k=k + 1), tuple(float(x) for x in (E, F, G, e, f, g))))
    forms, lam = _umbilic_forms(rng)
    cases.append(CaseSpec(_("umbilic point (κ1 = κ2, H² − K rounds below 0)"), forms, info={"umbilic": lam}))
    cases.append(CaseSpec(_("saddle (K < 0)"), (1.0, 0.0, 1.0, 1.0, 0.0, -1.0)))
    return cases


def _curvatures_expected(case):
    if "umbilic" in case.info:
        lam = case.info["umbilic"]
        return np.array([lam * lam, lam, lam, lam])
    E, F, G, e, f, g = (sp.Rational(x) for x in case.args)
    det = E * G - F * F
    K = (e * g - f * f) / det
    H = (e * G - 2 * f * F + g * E) / (2 * det)
    root = sp.sqrt(H * H - K)
    return np.array([float(sp.N(x, 30)) for x in (K, H, H + root, H - root)])


def _curvatures_judge(case, value, exact):
    if not isinstance(value, np.ndarray) or value.shape != (4,):
        return (False, _("a tuple (K, H, k1, k2) of four numbers"), fmt(value),
                _("return the four numbers in the order K, H, k1, k2."))
    rtol = 1e-6 if "umbilic" in case.info else 1e-10  # at umbilics k1, k2 are only sqrt(eps)-accurate
    ok = close(value, exact, rtol=rtol)
    hint = ""
    if np.any(np.isnan(value)):
        hint = _("NaN: at umbilic points H² − K is 0 in theory but slightly negative after rounding; "
                 "take √(max(H² − K, 0)).")
    elif close(value[1], 2 * exact[1]):
        hint = variant_hint("no_half")
    elif close(value[1], -exact[1]):
        hint = _("H has the wrong sign: H = ½ (eG − 2fF + gE) / (EG − F²).")
    elif close(value[2:], exact[2:][::-1]):
        hint = variant_hint("principal_swapped")
    elif not close(value[0], exact[0]):
        hint = _("K = (eg − f²) / (EG − F²) (practical eq. 3).")
    return ok, fmt(exact), fmt(value), hint


def _curvatures_error_hint(case, message):
    if "math domain error" in message or "sqrt" in message:
        return _("at umbilic points (κ1 = κ2) rounding makes H² − K slightly negative: take √(max(H² − K, 0)).")
    return ""


CURVATURES = Task("curvatures", _curvatures_cases, _curvatures_expected, _curvatures_judge, blocked=CURVATURE_BLOCK,
                  allowed="math / numpy", error_hint=_curvatures_error_hint,
                  summary=N_("a tuple (K, H, k1, k2) of four numbers"))


# -- derivative nets and corner derivatives -------------------------------------------------------------------

_DEGREES = [(3, 3), (2, 3), (3, 2)]
_GRADED_DEGREES = [(4, 2), (2, 5), (5, 4)]


def _net_cases(rng, graded):
    return [CaseSpec(_("random {m}×{n} net").format(m=m, n=n), (rand_net(rng, m, n),))
            for m, n in _DEGREES + (_GRADED_DEGREES if graded else [])]


#: The net a transposed reading of the control net gives in place of each net.
_PARTNER = {"bu": "bv", "bv": "bu", "buu": "bvv", "buv": "buv", "bvv": "buu"}


def _factor_hint(P, got, reference_fn, net):
    """Name the mistake whose result equals ``got`` for the derivative ``net``: degree factors, swapped degrees."""
    for variant in ("no_factors", "second_factor", "swapped_degrees"):
        if close(got, reference_fn(P, variant)[net], rtol=1e-12):
            return variant_hint(variant)
    return factor_hint(P, net, got, reference_fn(P)[net])


def _nets_judge(case, value, exp, corners=False):
    (P,) = case.args
    m, n = P.shape[0] - 1, P.shape[1] - 1
    if isinstance(value, np.ndarray) and value.ndim > 1 and len(value) == 5:  # five arrays of one shape
        value = list(value)
    if not isinstance(value, list) or len(value) != 5:
        what = _("five (2, 2, 3) arrays (bu, bv, buu, buv, bvv)") if corners else _("five arrays (bu, bv, buu, buv, bvv)")
        got = fmt(value) if isinstance(value, np.ndarray) else repr(value)[:200]
        return False, what, got, _("return a tuple of the five in this order.")
    bad = [k for k, key in enumerate(NET_NAMES) if not close(value[k], exp[key], rtol=1e-12)]
    if not bad:
        return True, "", "", ""
    k = bad[0]
    net = NET_NAMES[k]
    g, e = value[k], exp[net]
    hint = ""
    if g.shape != e.shape:
        if corners:
            hint = _("each field must have shape (2, 2, 3): [a, b] is the corner (u, v) = (a, b).")
        else:
            hint = _("the net of {net} of a degree ({m}, {n}) patch has shape {shape}: "
                     "Δ^{{1,0}} reduces the first index, Δ^{{0,1}} the second.").format(net=net, m=m, n=n, shape=e.shape)
            if g.shape == e.shape[1::-1] + e.shape[2:]:
                hint = Hint(hint + " " + _("Yours looks transposed."), "transposed")
    elif corners and close(g, np.swapaxes(e, 0, 1), rtol=1e-12):
        hint = _("corners mixed up: index [a, b] is (u, v) = (a, b); [0, 1] is u = 0, v = 1.")
    elif corners and m == n and close(g, np.swapaxes(exp[_PARTNER[net]], 0, 1), rtol=1e-12) and net != "buv":
        hint = variant_hint("transposed")
    else:
        hint = _factor_hint(P, g, variant_corner_derivatives if corners else variant_nets, net)
    default = (_("the value at a corner is the corner point of the derivative net (practical fig. 3).") if corners
               else _("{net} is wrong; compare with the formulas of practical section 3.").format(net=net))
    return False, f"{net} = {fmt(e)}", f"{net} = {fmt(g)}", hint or default


def _swap_error_hint(case, message):
    P = case.args[0] if isinstance(case.args[0], np.ndarray) and case.args[0].ndim == 3 else None
    if "IndexError" in message and P is not None:
        return index_error_hint(P)
    return ""


DERIVATIVE_NETS = Task("derivative_nets", _net_cases, lambda c: variant_nets(c.args[0]), _nets_judge,
                       blocked=BEZIER_BLOCK, allowed="numpy (np.diff)", error_hint=_swap_error_hint,
                       diagnose=diagnose_indices,
                       summary=N_("a tuple of the five derivative nets (bu, bv, buu, buv, bvv)"))
CORNER_DERIVATIVES = Task("corner_derivatives", _net_cases, lambda c: variant_corner_derivatives(c.args[0]),
                          lambda c, v, e: _nets_judge(c, v, e, corners=True), blocked=BEZIER_BLOCK,
                          allowed="numpy", error_hint=_swap_error_hint, diagnose=diagnose_indices,
                          summary=N_("a tuple of five (2, 2, 3) arrays (bu, bv, buu, buv, bvv), indexed [a, b] "
                                     "for (u, v) = (a, b)"))
