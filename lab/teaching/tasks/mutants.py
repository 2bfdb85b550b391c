"""A student's possible mistakes in the practical's computation, tried on a failing case (trusted side).

The corner curvature of a Bézier patch is computed from the corner derivatives; each classic mistake is
a *mutant* of that computation: a missing or wrong degree factor in any of b_u, b_v, b_uu, b_uv, b_vv
(any combination), the normal left unnormalised or divided by |b_u × b_v|², the opposite orientation, H
without its ½, κ1 and κ2 exchanged, hard-coded degrees, m and n swapped, the control net read transposed.
:func:`explain` computes all of them at once on a case's nets (the derivatives scale linearly with their
factors, so every combination is a few array products) and returns the simplest that reproduces the
student's values: the fewest mistakes, a named one (no factors, swapped degrees …) before a combination.
"""

from dataclasses import dataclass
from functools import lru_cache
from itertools import product

import numpy as np

from .references import NET_NAMES

__all__ = ["FACTORS", "Mutant", "explain", "factor_choices", "mutant_values"]


def factor_choices(m, n):
    """Per derivative net, the factors a student may write: (label, value), the right one first."""
    return {
        "bu": [("m", m), ("1", 1), ("n", n), ("m − 1", m - 1)],
        "bv": [("n", n), ("1", 1), ("m", m), ("n − 1", n - 1)],
        "buu": [("m(m − 1)", m * (m - 1)), ("1", 1), ("m", m), ("m²", m * m), ("m − 1", m - 1),
                ("n(n − 1)", n * (n - 1))],
        "buv": [("mn", m * n), ("1", 1), ("(m − 1)n", (m - 1) * n), ("m(n − 1)", m * (n - 1)),
                ("(m − 1)(n − 1)", (m - 1) * (n - 1)), ("m", m), ("n", n), ("m²", m * m), ("n²", n * n)],
        "bvv": [("n(n − 1)", n * (n - 1)), ("1", 1), ("n", n), ("n²", n * n), ("n − 1", n - 1),
                ("m(m − 1)", m * (m - 1))],
    }


#: The right degree factor of each net, as the practical writes it (section 3).
FACTORS = {net: choices[0][0] for net, choices in factor_choices(3, 3).items()}

#: How the normal may be scaled: the unit normal, b_u × b_v itself, b_u × b_v / |b_u × b_v|².
NORMS = ("unit", "unnormalised", "squared_norm")


@dataclass(frozen=True)
class Mutant:
    """One way of computing: a family (``factors``, ``no_factors``, ``second_factor``, ``swapped_degrees``,
    ``hardcoded``, ``transposed``), the factor used per net, and the curvature formula's variants."""

    family: str
    factors: tuple  # (bu, bv, buu, buv, bvv) values used
    labels: tuple  # their labels where a label fits ("" for the right one)
    norm: str = "unit"
    orientation: bool = False  # N = −(b_u × b_v)/|…|
    no_half: bool = False
    principal_swapped: bool = False
    degrees: tuple = ()  # the hard-coded degrees (family "hardcoded")

    @property
    def mistakes(self):
        """How many separate mistakes this mutant makes (0: the right computation)."""
        named = 0 if self.family == "factors" else 1
        wrong = sum(bool(label) for label in self.labels) if self.family == "factors" else 0
        return named + wrong + (self.norm != "unit") + self.orientation + self.no_half + self.principal_swapped


@lru_cache(maxsize=64)
def _mutants(m, n):
    """The factor and normal mutants for a patch of degree (m, n), simplest first (the formula's variants
    orientation, ½ and κ1/κ2 are tried on their values, :func:`_variants`)."""
    choices = factor_choices(m, n)
    right = tuple(choices[net][0][1] for net in NET_NAMES)
    named = [("no_factors", (1, 1, 1, 1, 1), ()), ("second_factor", (m, n, m, m * n, n), ()),
             ("swapped_degrees", (n, m, n * (n - 1), m * n, m * (m - 1)), ())]
    named += [("hardcoded", (a, b, a * (a - 1), a * b, b * (b - 1)), (a, b))
              for a in range(1, 7) for b in range(1, 7) if (a, b) != (m, n)]
    bases = [Mutant(family, f, ("",) * 5, degrees=d) for family, f, d in named if f != right and 0 not in f]
    seen = {base.factors for base in bases}
    for combo in product(*(range(len(choices[net])) for net in NET_NAMES)):
        factors = tuple(choices[net][k][1] for net, k in zip(NET_NAMES, combo))
        if 0 in factors or (factors in seen and factors != right):
            continue
        seen.add(factors)
        labels = tuple("" if factors[i] == right[i] else _labels(choices[net], factors[i])
                       for i, net in enumerate(NET_NAMES))
        bases.append(Mutant("factors", factors, labels))
    out = [Mutant(base.family, base.factors, base.labels, norm, degrees=base.degrees) for base in bases
           for norm in NORMS]
    out.sort(key=lambda mu: (mu.mistakes, mu.family == "factors"))
    return tuple(out)


def _labels(choices, value):
    """Every label of a factor value ("(m − 1)n or m(n − 1)" on a square patch)."""
    return " or ".join(dict.fromkeys(label for label, v in choices if v == value))


def _base(nets):
    """Corner quantities without degree factors, arrays (patch, a, b): dot products and normal components."""
    P = np.asarray(nets, dtype=float)
    d = {"bu": np.diff(P, axis=1), "bv": np.diff(P, axis=2), "buu": np.diff(P, 2, axis=1),
         "buv": np.diff(np.diff(P, axis=1), axis=2), "bvv": np.diff(P, 2, axis=2)}
    d = {k: v[:, [0, -1]][:, :, [0, -1]] for k, v in d.items()}
    Q = np.cross(d["bu"], d["bv"])
    W = np.linalg.norm(Q, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        N = Q / W[..., None]

    def dot(a, b):
        return np.sum(a * b, axis=-1)

    return {"E": dot(d["bu"], d["bu"]), "F": dot(d["bu"], d["bv"]), "G": dot(d["bv"], d["bv"]), "W": W,
            "e": dot(N, d["buu"]), "f": dot(N, d["buv"]), "g": dot(N, d["bvv"])}


def mutant_values(nets, mutants, transposed=False):
    """K and H at the corners (mutant, patch, a, b) of every mutant on ``nets`` (patch, m+1, n+1, 3), with
    the right orientation, the ½ and κ1 ≥ κ2 (:func:`_variants` adds those mistakes).

    ``transposed``: the net is read with its first index along v (the values are stored at the corners
    of the transposed net, as such code stores them).
    """
    nets = np.asarray(nets, dtype=float)
    if transposed:
        nets = np.swapaxes(nets, 1, 2)
    b = _base(nets)
    f = np.array([mu.factors for mu in mutants], dtype=float)[:, :, None, None, None]
    fu, fv, fuu, fuv, fvv = (f[:, k] for k in range(5))
    power = np.array([{"unit": 0.0, "unnormalised": 1.0, "squared_norm": -1.0}[mu.norm] for mu in mutants])
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        s = (fu * fv * b["W"]) ** power[:, None, None, None]  # N = s · unit normal
        E, F, G = fu * fu * b["E"], fu * fv * b["F"], fv * fv * b["G"]
        e, ff, g = s * fuu * b["e"], s * fuv * b["f"], s * fvv * b["g"]
        det = E * G - F * F
        K = (e * g - ff * ff) / det
        H = 0.5 * (e * G - 2 * ff * F + g * E) / det
    out = {"K": K, "H": H}
    if transposed:
        out = {k: np.swapaxes(v, 2, 3) for k, v in out.items()}
    return out


#: The formula's variants tried on every mutant's values: (orientation, no ½, κ1 and κ2 exchanged).
_FORMULA = [(o, h, p) for o in (False, True) for h in (False, True) for p in (False, True)]


def _variants(field, K, H):
    """``field`` computed from K and H with each formula variant: [(orientation, no_half, swapped), values]."""
    if field == "K":
        return [((False, False, False), K)]
    out = []
    for orientation, no_half, swapped in _FORMULA:
        if field == "H" and swapped:
            continue
        h = H * (-1.0 if orientation else 1.0) * (2.0 if no_half else 1.0)
        if field == "H":
            out.append(((orientation, no_half, False), h))
            continue
        with np.errstate(invalid="ignore", over="ignore"):
            root = np.sqrt(np.maximum(h * h - K, 0.0))
        plus = (field == "k1") != swapped
        out.append(((orientation, no_half, swapped), h + root if plus else h - root))
    return out


def _stages(m, n, field):
    """(transposed, mutants, formula variants) in the order they are tried: the common mistakes first."""
    mutants = _mutants(m, n)
    right = [mu for mu in _mutants(n, m) if mu.family == "factors" and not any(mu.labels)]
    base = [v for v in _FORMULA if not any(v)]
    return [(False, mutants, base), (False, mutants, [v for v in _FORMULA if any(v)]), (True, right, _FORMULA)]


def explain(nets, field, got, rtol=1e-6, atol=0.0, limit=6):
    """The simplest mutants whose ``field`` values at the corners equal ``got`` (patch, 2, 2).

    Returns a list of ``(mutant, transposed)``, every one with the fewest mistakes (reading the net
    transposed counts as one; it is tried with the right factors only), at most ``limit``; more than one
    when this case cannot tell them apart (on a square patch a missing m in b_u gives the same K as a missing
    n in b_v).  Empty when none fits, or when the right computation does (the values are right).  Values
    match within ``rtol`` of the mutant's largest value plus ``atol`` (the rounding noise of the case).
    """
    nets = np.asarray(nets, dtype=float)
    got = np.asarray(got, dtype=float)
    if got.shape != (len(nets), 2, 2) or not np.all(np.isfinite(got)):
        return []
    m, n = nets.shape[1] - 1, nets.shape[2] - 1
    found = []
    for transposed, mutants, formula in _stages(m, n, field):
        if found and min(f[0] for f in found) <= 1:
            break  # every later stage makes at least one mistake
        base = mutant_values(nets, mutants, transposed)
        for (orientation, no_half, swapped), values in _variants(field, base["K"], base["H"]):
            if (orientation, no_half, swapped) not in formula:
                continue
            finite = np.all(np.isfinite(values), axis=(1, 2, 3))
            big = np.max(np.abs(np.where(np.isfinite(values), values, 0.0)), axis=(1, 2, 3))
            ok = finite & np.all(np.abs(values - got) <= (rtol * big + atol)[:, None, None, None], axis=(1, 2, 3))
            for k in np.flatnonzero(ok)[:64]:
                mu = mutants[k]
                mu = Mutant(mu.family, mu.factors, mu.labels, mu.norm, orientation, no_half, swapped, mu.degrees)
                if transposed and mu.family != "factors":
                    continue  # read transposed and one more named mistake: too far-fetched to name
                if mu.mistakes + transposed == 0:
                    return []  # the right computation: the values are right (within the tolerance)
                found.append((mu.mistakes + transposed, mu.family == "factors", transposed, mu))
    if not found:
        return []
    least = min(f[0] for f in found)
    best = sorted((f for f in found if f[0] == least), key=lambda f: f[:3])
    named = [f for f in best if not f[1]]
    best = named or best  # a named mistake (swapped degrees …) is the one a combination of factors imitates
    return [(mu, transposed) for _c, _f, transposed, mu in best[:limit]]


def signature(mutant, transposed):
    """What a mutant does, independent of the patch's degree: ``(kind, labels)`` with the factor labels as sets
    (an empty set: the right factor)."""
    labels = tuple(frozenset(label.split(" or ")) if label else frozenset() for label in mutant.labels)
    return (mutant.family, mutant.degrees, mutant.norm, mutant.orientation, mutant.no_half,
            mutant.principal_swapped, transposed), labels


def instances(sig, m, n):
    """The mutants of signature ``sig`` on a patch of degree (m, n): ``[(mutant, transposed, labels)]``, one per
    choice of the labels (on this patch two labels of a net may mean different factors)."""
    (family, degrees, norm, orientation, no_half, swapped, transposed), labels = sig
    dm, dn = (n, m) if transposed else (m, n)
    choices = factor_choices(dm, dn)
    if family != "factors":
        base = next((mu for mu in _mutants(dm, dn) if mu.family == family and mu.degrees == degrees), None)
        if base is None:  # the family's factors are the right ones on this patch (hard-coded (m, n) itself)
            base = Mutant("factors", tuple(choices[net][0][1] for net in NET_NAMES), ("",) * 5)
        return [(Mutant(base.family, base.factors, base.labels, norm, orientation, no_half, swapped, base.degrees),
                 transposed, labels)]
    values = {net: dict(choices[net]) for net in NET_NAMES}
    options = [[(choices[net][0][1], frozenset())] if not labels[i] else
               [(values[net][label], frozenset({label})) for label in sorted(labels[i]) if label in values[net]]
               for i, net in enumerate(NET_NAMES)]
    out = []
    for combo in product(*options):
        factors = tuple(f for f, _l in combo)
        mu = Mutant("factors", factors, tuple(" or ".join(sorted(lab)) for _f, lab in combo), norm, orientation,
                    no_half, swapped)
        out.append((mu, transposed, tuple(lab for _f, lab in combo)))
    return out


def fits(mutant, transposed, nets, field, got, rtol=1e-6, atol=0.0):
    """Whether ``mutant`` gives ``got`` (patch, 2, 2) for ``field`` on ``nets``."""
    base = mutant_values(nets, [Mutant(mutant.family, mutant.factors, mutant.labels, mutant.norm)], transposed)
    variant = (mutant.orientation, mutant.no_half, mutant.principal_swapped)
    values = next(v for key, v in _variants(field, base["K"], base["H"]) if key == variant)[0]
    if not np.all(np.isfinite(values)) or values.shape != np.shape(got):
        return False
    return bool(np.all(np.abs(values - got) <= rtol * np.max(np.abs(values)) + atol))
