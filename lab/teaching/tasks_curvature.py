"""Checks of the curvature tasks (notebooks 00-03): mean curvature, curves, fundamental forms, K/H/κ, derivative nets."""

import math
from fractions import Fraction

import numpy as np
import sympy as sp

from .hints import VARIANT_HINTS, _close, _fmt
from .references import _rand_net, _variant_corner_derivatives, _variant_nets
from .report import Case
from .runner import DEFAULT_TIMEOUT, _BEZIER_BLOCK, _call, _report, _rng

__all__ = ["warmup", "curve_curvature", "fundamental_forms", "curvatures", "derivative_nets", "corner_derivatives"]


def warmup(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(k1, k2)`` returns the mean curvature (k1 + k2) / 2 (the start notebook's exercise)."""
    rng = _rng(seed)

    def cases():
        values = [(1.0, 1.0), (2.0, -2.0)] + [tuple(rng.integers(-20, 21, 2) / 4) for _ in range(4 if graded else 2)]
        for k1, k2 in values:
            got = _call("warmup", func, func, (k1, k2), timeout=timeout)
            exp = (k1 + k2) / 2
            ok = isinstance(got, (int, float, np.floating, np.integer)) and abs(float(got) - exp) <= 1e-12
            hint = ""
            if not ok and isinstance(got, (int, float)) and abs(got - (k1 + k2)) < 1e-12:
                hint = "the mean of two numbers is their sum divided by 2."
            elif not ok and isinstance(got, (int, float)) and abs(got - k1 * k2) < 1e-12:
                hint = "k1 * k2 is the Gaussian curvature K; the mean curvature is (k1 + k2) / 2."
            yield Case(f"H for k1 = {k1:g}, k2 = {k2:g}", ok, f"{exp:g}", repr(got), hint)

    return _report("warmup", graded, cases)


def curve_curvature(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(d1, d2)``: curvature κ = |c' × c''| / |c'|³ of a space curve from its first two derivatives."""
    rng = _rng(seed)
    t = sp.Symbol("t")

    def cases():
        r = Fraction(int(rng.integers(2, 9)), 2)
        w = int(rng.integers(2, 5))
        circle = sp.Matrix([r * sp.cos(w * t), r * sp.sin(w * t), 0])
        samples = [("circle of radius %s at speed %s" % (r, r * w), circle, sp.Rational(1, 3))]
        samples.append(("straight line", sp.Matrix([1 + 2 * t, 3 * t, -t]), sp.Rational(1, 2)))
        for k in range(3 if graded else 1):
            coeffs = rng.integers(-4, 5, size=(3, 4))
            c = sp.Matrix([sum(int(coeffs[i, j]) * t**j for j in range(4)) for i in range(3)])
            samples.append((f"random cubic space curve {k + 1}", c, sp.Rational(int(rng.integers(1, 8)), 8)))
        for name, c, t0 in samples:
            d1 = np.array([float(x) for x in c.diff(t).subs(t, t0)])
            d2 = np.array([float(x) for x in c.diff(t, 2).subs(t, t0)])
            cross = c.diff(t).cross(c.diff(t, 2)).subs(t, t0)
            speed = c.diff(t).subs(t, t0).norm()
            exact = float(sp.N(cross.norm() / speed**3, 30))
            got = _call("curve_curvature", func, func, (d1.copy(), d2.copy()), timeout=timeout)
            try:
                val = float(got)
            except (TypeError, ValueError):
                yield Case(name, False, f"a number ≈ {exact:.6g}", f"{got!r}", "return one number (a float).")
                continue
            ok = abs(val - exact) <= 1e-9 * max(1.0, abs(exact))
            hint = ""
            if not ok:
                s1 = float(np.linalg.norm(d1))
                cr = float(np.linalg.norm(np.cross(d1, d2)))
                if math.isclose(val, cr / s1**2, rel_tol=1e-9):
                    hint = "divide by |c'|³, not |c'|²: the curvature of a curve is |c' × c''| / |c'|³."
                elif math.isclose(val, float(np.linalg.norm(d2)), rel_tol=1e-9):
                    hint = "|c''| is the curvature only when the curve has unit speed; use |c' × c''| / |c'|³."
                elif math.isclose(val, cr, rel_tol=1e-9):
                    hint = "|c' × c''| must be divided by |c'|³."
            yield Case(name, ok, f"{exact:.10g}", f"{val:.10g}", hint)

    return _report("curve_curvature", graded, cases)


def _exact_forms(vectors):
    """Exact E, F, G, e, f, g (floats) from five sympy vectors."""
    bu, bv, buu, buv, bvv = vectors
    Q = bu.cross(bv)
    W = sp.sqrt(Q.dot(Q))
    N = Q / W
    vals = [bu.dot(bu), bu.dot(bv), bv.dot(bv), N.dot(buu), N.dot(buv), N.dot(bvv)]
    return np.array([float(sp.N(x, 30)) for x in vals])


def _random_vectors(rng):
    return [sp.Matrix([sp.Rational(int(x), 4) for x in rng.integers(-12, 13, size=3)]) for _ in range(5)]


def fundamental_forms(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(bu, bv, buu, buv, bvv)`` returns ``(E, F, G, e, f, g)`` (practical 2.5)."""
    rng = _rng(seed)
    names = ("E", "F", "G", "e", "f", "g")

    def cases():
        for k in range(6 if graded else 3):
            vecs = _random_vectors(rng)
            while vecs[0].cross(vecs[1]).norm() == 0:
                vecs = _random_vectors(rng)
            args = [np.array([float(x) for x in v]) for v in vecs]
            exact = _exact_forms(vecs)
            got = _call("fundamental_forms", func, func, [a.copy() for a in args], timeout=timeout)
            try:
                got = np.array([float(x) for x in got])
                assert got.shape == (6,)
            except (TypeError, ValueError, AssertionError):
                yield Case(f"random derivatives {k + 1}", False, "a tuple (E, F, G, e, f, g) of six numbers",
                           repr(got)[:200], "return the six numbers in the order E, F, G, e, f, g.")
                continue
            ok = _close(got, exact, rtol=1e-10)
            hint = ""
            if not ok:
                W = float(np.linalg.norm(np.cross(args[0], args[1])))
                if _close(got[:3], exact[:3]) and _close(got[3:], exact[3:] * W):
                    hint = VARIANT_HINTS["unnormalised"]
                elif _close(got[:3], exact[:3]) and _close(got[3:], -exact[3:]):
                    hint = VARIANT_HINTS["orientation"]
                elif not _close(got[:3], exact[:3]):
                    wrong = [names[i] for i in range(3) if not _close(got[i], exact[i])]
                    hint = f"{', '.join(wrong)} wrong: E = ⟨b_u, b_u⟩, F = ⟨b_u, b_v⟩, G = ⟨b_v, b_v⟩."
                else:
                    wrong = [names[i] for i in range(3, 6) if not _close(got[i], exact[i])]
                    hint = f"{', '.join(wrong)} wrong: e = ⟨N, b_uu⟩, f = ⟨N, b_uv⟩, g = ⟨N, b_vv⟩."
            yield Case(f"random derivatives {k + 1}", ok, _fmt(exact), _fmt(got), hint)

    return _report("fundamental_forms", graded, cases)


def _umbilic_forms(rng):
    """(E, F, G, e, f, g) of an umbilic (II = λ I) for which H² − K computes slightly negative in floats."""
    for _ in range(1000):
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


def curvatures(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(E, F, G, e, f, g)`` returns ``(K, H, k1, k2)`` with k1 >= k2 (practical eqs. 1–4)."""
    rng = _rng(seed)

    def exact_of(vals):
        E, F, G, e, f, g = (sp.Rational(x) for x in vals)
        det = E * G - F * F
        K = (e * g - f * f) / det
        H = (e * G - 2 * f * F + g * E) / (2 * det)
        root = sp.sqrt(H * H - K)
        return np.array([float(sp.N(x, 30)) for x in (K, H, H + root, H - root)])

    def cases():
        samples = []
        for k in range(4 if graded else 2):
            E, G = rng.integers(1, 12, 2) / 4
            F = rng.integers(-3, 4) / 8
            e, f, g = rng.integers(-12, 13, 3) / 4
            samples.append((f"random forms {k + 1}", (E, F, G, e, f, g)))
        samples.append(("umbilic point (κ1 = κ2, H² − K rounds below 0)", _umbilic_forms(rng)[0]))
        samples.append(("saddle (K < 0)", (1.0, 0.0, 1.0, 1.0, 0.0, -1.0)))
        for name, vals in samples:
            exact = exact_of(vals) if "umbilic" not in name else None
            if exact is None:
                E, F, G, e, f, g = vals
                lam = e / E
                exact = np.array([lam * lam, lam, lam, lam])
            got = _call("curvatures", func, func, vals, timeout=timeout)
            try:
                got = np.array([float(x) for x in got])
                assert got.shape == (4,)
            except (TypeError, ValueError, AssertionError):
                yield Case(name, False, "a tuple (K, H, k1, k2) of four numbers", repr(got)[:200],
                           "return the four numbers in the order K, H, k1, k2.")
                continue
            rtol = 1e-6 if "umbilic" in name else 1e-10  # at umbilics k1, k2 are only sqrt(eps)-accurate
            ok = _close(got, exact, rtol=rtol)
            hint = ""
            if not ok:
                if np.any(np.isnan(got)):
                    hint = ("NaN: at umbilic points H² − K is 0 in theory but slightly negative after rounding; "
                            "take √(max(H² − K, 0)).")
                elif _close(got[1], 2 * exact[1]):
                    hint = VARIANT_HINTS["no_half"]
                elif _close(got[1], -exact[1]):
                    hint = "H has the wrong sign: H = ½ (eG − 2fF + gE) / (EG − F²)."
                elif _close(got[2:], exact[2:][::-1]):
                    hint = VARIANT_HINTS["principal_swapped"]
                elif not _close(got[0], exact[0]):
                    hint = "K = (eg − f²) / (EG − F²) (practical eq. 3)."
            yield Case(name, ok, _fmt(exact), _fmt(got), hint)

    return _report("curvatures", graded, cases)


_NET_NAMES = ("bu", "bv", "buu", "buv", "bvv")


def derivative_nets(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(P)`` returns the Bézier nets of b_u, b_v, b_uu, b_uv, b_vv (practical section 3)."""
    rng = _rng(seed)

    def cases():
        degrees = [(3, 3), (2, 3), (3, 2)] + ([(4, 2), (2, 5), (5, 4)] if graded else [])
        for m, n in degrees:
            P = _rand_net(rng, m, n)
            exp = list(_variant_nets(P).values())
            got = _call("derivative_nets", func, func, (P.copy(),), timeout=timeout, blocked=_BEZIER_BLOCK)
            name = f"random {m}×{n} net"
            try:
                got = [np.asarray(x, dtype=float) for x in got]
                assert len(got) == 5
            except (TypeError, ValueError, AssertionError):
                yield Case(name, False, "five arrays (bu, bv, buu, buv, bvv)", repr(got)[:200],
                           "return a tuple of the five derivative nets in this order.")
                continue
            bad = [k for k, (g, e) in enumerate(zip(got, exp)) if not _close(g, e, rtol=1e-12)]
            if not bad:
                yield Case(name, True)
                continue
            k = bad[0]
            g, e = got[k], exp[k]
            hint = ""
            if g.shape != e.shape:
                hint = (f"the net of {_NET_NAMES[k]} of a degree ({m}, {n}) patch has shape {e.shape}: "
                        "Δ^{1,0} reduces the first index, Δ^{0,1} the second.")
                if g.shape == e.shape[1::-1] + e.shape[2:]:
                    hint += " Yours looks transposed."
            else:
                for variant in ("no_factors", "second_factor", "swapped_degrees"):
                    if _close(g, _variant_nets(P, variant)[_NET_NAMES[k]], rtol=1e-12):
                        hint = VARIANT_HINTS[variant]
                        break
            yield Case(name, False, f"{_NET_NAMES[k]} = {_fmt(e)}", f"{_NET_NAMES[k]} = {_fmt(g)}",
                       hint or f"{_NET_NAMES[k]} is wrong; compare with the formulas of practical section 3.")

    return _report("derivative_nets", graded, cases)


def corner_derivatives(func, *, graded=False, seed=None, timeout=DEFAULT_TIMEOUT):
    """Check ``func(P)`` returns b_u, b_v, b_uu, b_uv, b_vv at the four corners, each (2, 2, 3) indexed [a, b] for (u, v) = (a, b)."""
    rng = _rng(seed)

    def cases():
        degrees = [(3, 3), (2, 3), (3, 2)] + ([(4, 2), (2, 5)] if graded else [])
        for m, n in degrees:
            P = _rand_net(rng, m, n)
            exp = _variant_corner_derivatives(P)
            got = _call("corner_derivatives", func, func, (P.copy(),), timeout=timeout, blocked=_BEZIER_BLOCK)
            name = f"random {m}×{n} net"
            try:
                got = [np.asarray(x, dtype=float) for x in got]
                assert len(got) == 5
            except (TypeError, ValueError, AssertionError):
                yield Case(name, False, "five (2, 2, 3) arrays (bu, bv, buu, buv, bvv)", repr(got)[:200],
                           "return a tuple of five arrays, each indexed [a, b] for the corner (u, v) = (a, b).")
                continue
            bad = [k for k, key in enumerate(_NET_NAMES) if not _close(got[k], exp[key], rtol=1e-12)]
            if not bad:
                yield Case(name, True)
                continue
            k = bad[0]
            g, e = got[k], exp[_NET_NAMES[k]]
            hint = ""
            if g.shape != (2, 2, 3):
                hint = "each field must have shape (2, 2, 3): [a, b] is the corner (u, v) = (a, b)."
            elif _close(g, np.swapaxes(e, 0, 1), rtol=1e-12):
                hint = "corners mixed up: index [a, b] is (u, v) = (a, b); [0, 1] is u = 0, v = 1."
            else:
                for variant in ("no_factors", "second_factor", "swapped_degrees"):
                    if _close(g, _variant_corner_derivatives(P, variant)[_NET_NAMES[k]], rtol=1e-12):
                        hint = VARIANT_HINTS[variant]
                        break
            yield Case(name, False, f"{_NET_NAMES[k]} = {_fmt(e)}", f"{_NET_NAMES[k]} = {_fmt(g)}",
                       hint or "the value at a corner is the corner point of the derivative net (practical fig. 3).")

    return _report("corner_derivatives", graded, cases)
