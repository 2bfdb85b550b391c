"""Hints that name a student's mistake: the result is compared with the computation done each classic wrong way."""

import numpy as np

from ...geometry import colormaps
from ...i18n import N_, _, decimal
from ..task import Hint
from ..task import close as _close
from . import mutants as _mutants
from .references import (
    MAP_LABELS,
    MODE_FIELD,
    NET_NAMES,
    degree_factor,
    expected_colors,
    variant_corner_derivatives,
    variant_curvature,
)

__all__ = ["VARIANT_HINTS", "diagnose_colors", "diagnose_indices", "diagnose_mutants", "diagnose_report",
           "diagnose_values", "factor_hint", "hint", "index_error_hint", "mutant_hint", "visualize_error_hint"]

VARIANT_HINTS = {
    "corner_order": N_("set_curvature(c00, c01, c10, c11) and set_colors(...) take c01 = the value at u = 0, v = 1; "
    "your corners are in another order (c01 and c10 exchanged)."),
    "no_factors": N_("the derivative nets need the degree factors: b_u = m Δ^{1,0} b, b_uu = m(m-1) Δ^{1,0}Δ^{1,0} b, "
    "b_uv = mn Δ^{1,0}Δ^{0,1} b (practical section 3)."),
    "second_factor": N_("the second derivatives need m(m-1) and n(n-1), not m and n (practical section 3)."),
    "swapped_degrees": N_("m and n are swapped: m is the degree along u (first index of the control net), n along v. "
    "It only shows on non-square patches."),
    "unnormalised": N_("e, f, g need the unit normal N = b_u × b_v / |b_u × b_v|; you used the cross product without "
    "dividing by its length."),
    "squared_norm": N_("e, f, g need the unit normal N = b_u × b_v / |b_u × b_v|; you divided the cross product by "
    "|b_u × b_v|², not by |b_u × b_v|."),
    "transposed": N_("your derivative nets are transposed: the first index of the control net runs along u (degree m), "
    "the second along v (degree n); Δ^{1,0} takes differences along the first index, Δ^{0,1} along the second."),
    "hard_coded_index": N_("your indices do not fit the sizes of the nets (a fixed degree, or one last index for all "
    "nets?): the control net has (m + 1) × (n + 1) points, b_u m × (n + 1), b_uu (m − 1) × (n + 1), b_uv m × n; take "
    "the degrees m and n from patch.degree and the last corner of every net with index -1."),
    "orientation": N_("the normal is N = b_u × b_v / |b_u × b_v| (practical 2.2); you used the opposite orientation, "
    "so H, κ1 and κ2 have the wrong sign."),
    "no_half": N_("H = ½ (eG − 2fF + gE) / (EG − F²): the factor ½ is missing (practical eq. 4)."),
    "principal_swapped": N_("κ1 = H + √(H² − K) is the larger principal curvature, κ2 = H − √(H² − K) the smaller."),
    "mode_ignored": N_("the values do not depend on curvature_mode: choose K, H, κ1 or κ2 according to it."),
}



def hint(key):
    """The hint ``key`` of :data:`VARIANT_HINTS` in the current language (a :class:`Hint` with that key)."""
    return Hint(_(VARIANT_HINTS[key]), key)


_NET_TEXT = {"bu": "b_u", "bv": "b_v", "buu": "b_uu", "buv": "b_uv", "bvv": "b_vv"}


def _render(mutant, transposed, m, n, labels=None):
    """The hint text and key of one mutant on a patch of degree (m, n); ``labels``: the factor labels to name
    (sets, from :func:`lab.teaching.tasks.mutants.common`), default the mutant's own."""
    parts, keys = [], []
    if transposed:
        parts.append(_(VARIANT_HINTS["transposed"]))
        keys.append("transposed")
    if mutant.family in ("no_factors", "second_factor", "swapped_degrees"):
        parts.append(_(VARIANT_HINTS[mutant.family]))
        keys.append(mutant.family)
    elif mutant.family == "hardcoded":
        a, b = mutant.degrees
        parts.append(_("your degree factors are those of degree ({a}, {b}), but this patch has degree ({m}, {n}): "
                       "take the degrees m and n from patch.degree, do not write them into the code (practical section 3).").format(
                           a=a, b=b, m=m, n=n))
        keys.append("hardcoded")
    else:
        right = _mutants.factor_choices(m, n)
        names = labels if labels is not None else [set(x.split(" or ")) if x else set() for x in mutant.labels]
        order = {net: [label for label, _v in right[net]] for net in NET_NAMES}
        wrong = []
        for i, net in enumerate(NET_NAMES):
            if not names[i]:
                continue
            used = " or ".join(sorted(names[i], key=lambda x: order[net].index(x) if x in order[net] else 99))
            if mutant.factors[i] == right[net][0][1]:
                wrong.append(_("{net} has the factor {used} instead of {right} (on this patch both are {value})").format(
                    net=_NET_TEXT[net], used=used, right=right[net][0][0], value=mutant.factors[i]))
            else:
                wrong.append(_("{net} has the factor {used} = {value} instead of {right} = {right_value}").format(
                    net=_NET_TEXT[net], used=used, value=mutant.factors[i], right=right[net][0][0],
                    right_value=right[net][0][1]))
        if wrong:
            parts.append(_("wrong degree factors (practical section 3): {list}.").format(list="; ".join(wrong)))
            keys.append("factors:" + ",".join(net for i, net in enumerate(NET_NAMES) if names[i]))
    for key, on in (("unnormalised", mutant.norm == "unnormalised"), ("squared_norm", mutant.norm == "squared_norm"),
                    ("orientation", mutant.orientation), ("no_half", mutant.no_half),
                    ("principal_swapped", mutant.principal_swapped)):
        if on:
            parts.append(_(VARIANT_HINTS[key]))
            keys.append(key)
    text = parts[0] if len(parts) == 1 else _("{n} mistakes: {list}").format(n=len(parts), list=" ".join(
        f"({k + 1}) {p}" for k, p in enumerate(parts)))
    return text, "+".join(keys)


def _ratio_text(ratio):
    return " " + _("(your values are {ratio} times the right ones)").format(ratio=decimal(f"{ratio:.6g}")) if ratio else ""


def mutant_hint(found, m, n, ratio=None):
    """The hint for the mutants :func:`lab.teaching.tasks.mutants.explain` found on a patch of degree (m, n): one
    mistake, or the few this case cannot tell apart (the report picks one, :func:`diagnose_mutants`)."""
    texts = [_render(mu, t, m, n) for mu, t in found]
    if len(texts) == 1:
        text, key = texts[0][0] + _ratio_text(ratio), texts[0][1]
    else:
        text = _("this case fits {k} mistakes, it cannot tell which: {list}").format(k=len(texts), list=" ".join(
            f"({k + 1}) {t}" for k, (t, _key) in enumerate(texts))) + _ratio_text(ratio)
        key = "ambiguous"
    out = Hint(text, key)
    out.mutants, out.degrees, out.ratio = list(found), (m, n), ratio
    return out


def _keep_case(found_hint, nets, field, got, atol):
    """The case's data on its hint, for :func:`diagnose_mutants` (trusted side only: never sent anywhere)."""
    found_hint.nets, found_hint.field, found_hint.got, found_hint.atol = np.asarray(nets), field, np.asarray(got), atol
    return found_hint


def diagnose_mutants(specs, cases):
    """One diagnosis across a report's cases: of the mistakes the failing cases suggest, the one that reproduces
    the most of them (tried on each case's nets; the first failing case's suggestions win ties), named in every
    case it reproduces, with the factor labels all of them allow."""
    explained = [c for c in cases if getattr(c.hint, "mutants", None)]
    if not explained:
        return
    options = list(dict.fromkeys(_mutants.signature(mu, t) for c in explained for mu, t in c.hint.mutants))
    best, best_fits = None, {}
    for kind, labels in options:
        fitted, labels = {}, [set(x) for x in labels]
        for k, c in enumerate(explained):
            m, n = c.hint.degrees
            for mu, t, used in _mutants.instances((kind, tuple(frozenset(x) for x in labels)), m, n):
                if _mutants.fits(mu, t, c.hint.nets, c.hint.field, c.hint.got, atol=c.hint.atol):
                    fitted[k] = (mu, t)
                    labels = [x & u if u else x for x, u in zip(labels, used)]
                    break
        if len(fitted) > len(best_fits):
            best, best_fits = (kind, labels), fitted
    for k, (mu, t) in best_fits.items():
        c = explained[k]
        m, n = c.hint.degrees
        text, key = _render(mu, t, m, n, best[1])
        new = Hint(text + _ratio_text(c.hint.ratio), key)
        new.__dict__.update({**c.hint.__dict__, "key": key, "mutants": [(mu, t)]})
        c.hint, c.mistake = new, key


def diagnose_report(specs, cases):
    """The report-level diagnosis of the curvature tasks: mutants, then IndexErrors."""
    diagnose_mutants(specs, cases)
    diagnose_indices(specs, cases)


_UMBILIC = N_("at umbilic points (κ1 = κ2, e.g. the vertex of a paraboloid) rounding makes H² − K slightly negative: "
            "use √(max(H² − K, 0)).")
_F2_ZERO = N_("all curvature values are equal, so κmax − κmin = 0: f2 must not divide by zero "
            "(give 0.5, green, in that case).")


def _values(nets, field_name, variant=None, net_variant=None):
    return np.stack([variant_curvature(variant_corner_derivatives(P, net_variant), variant)[field_name] for P in nets])


def diagnose_values(nets, mode, got, expected, atol=0.0):
    """Name the mistake whose corner values (N, 2, 2) match ``got``: the simplest mutant of the computation
    (:mod:`lab.teaching.tasks.mutants`) that gives them; ``atol`` is the case's rounding noise."""
    field_name = MODE_FIELD[mode]
    scale = max(float(np.max(np.abs(expected))), 1e-300)  # relative to the case's own values (tiny on large models)

    def close(a, b):
        return _close(a, b, scale=scale)

    if np.any(np.isnan(got)):
        umbilic = _(_UMBILIC)
        return Hint(_("some values are NaN.") + " " + umbilic[0].upper() + umbilic[1:], "nan")
    if close(got, np.swapaxes(expected, 1, 2)):
        return hint("corner_order")
    m, n = nets[0].shape[0] - 1, nets[0].shape[1] - 1
    found = _mutants.explain(nets, field_name, got, atol=atol)
    if found:
        ratio = _ratio(got, expected)
        return _keep_case(mutant_hint(found, m, n, ratio if ratio != 1 else None), nets, field_name, got, atol)
    for other in MODE_FIELD.values():
        if other != field_name and close(got, _values(nets, other)):
            return Hint(hint("mode_ignored") + " " + _("(you stored {got}, expected {expected})").format(
                got=other, expected=field_name), "mode_ignored")
    ratio = _ratio(got, expected)
    if ratio is not None:
        names = {m: "m", n: "n", m * m: "m²", n * n: "n²", 1 / m: "1/m", 1 / n: "1/n", 1 / m**2: "1/m²", 1 / n**2: "1/n²"}
        for value, name in names.items():
            if value != 1 and abs(ratio - value) <= 1e-6 * abs(value):
                return _("your values are exactly {name} = {value} times the right ones: a degree factor is missing "
                         "or doubled in a derivative net (practical section 3).").format(name=name, value=decimal(f"{value:g}"))
    return _("compare your formulas with practical eqs. (3), (4) and section 3.")


def factor_hint(P, net, got, expected):
    """The hint for a derivative net ``net`` of the control net ``P`` that is a multiple of the right one."""
    m, n = P.shape[0] - 1, P.shape[1] - 1
    ratio = _ratio(got, expected)
    if ratio is None:
        return ""
    right_label, right = degree_factor(P, net)
    used = ratio * right
    labels = [label for label, value in _mutants.factor_choices(m, n)[net] if abs(value - used) <= 1e-9 * right]
    if not labels:
        return Hint(_("{net} is {ratio} times the right net: its degree factor is {right} = {value}, yours is "
                      "{used} (practical section 3).").format(net=net, ratio=decimal(f"{ratio:.6g}"), right=right_label,
                                                              value=right, used=decimal(f"{used:.6g}")), f"factors:{net}")
    return Hint(_("wrong degree factors (practical section 3): {list}.").format(
        list=_("{net} has the factor {used} = {value} instead of {right} = {right_value}").format(
            net=_NET_TEXT[net], used=" or ".join(dict.fromkeys(labels)), value=decimal(f"{used:g}"), right=right_label,
            right_value=right)), f"factors:{net}")


def _square(spec):
    """Whether a case's patches are square (m = n): swapped degrees do not show on them."""
    P = np.asarray(spec.args[0])
    return P.shape[-3] == P.shape[-2]


def diagnose_indices(specs, cases):
    """One diagnosis for IndexErrors across a report: m and n swapped only when every square case passes;
    an IndexError on a square patch too is a fixed degree or index; square cases whose values are those of the
    transposed net (for K: c01 and c10 exchanged) mean the net is read transposed."""
    index = [(c, s) for c, s in zip(cases, specs) if c.mistake == "index_error"]
    if not index:
        return
    squares = [(c, s) for c, s in zip(cases, specs) if _square(s)]
    square_index = [c for c, _s in squares if c.mistake == "index_error"]
    transposed = [c for c, _s in squares if "transposed" in c.mistake or c.mistake == "corner_order"]
    if square_index:
        text = Hint(_("an IndexError also on a square patch ({case}), so m and n are not just swapped: {hint}").format(
            case=square_index[0].name, hint=_(VARIANT_HINTS["hard_coded_index"])), "hard_coded_index")
        changed = [c for c, _s in index]
    elif transposed:
        text = Hint(_(VARIANT_HINTS["transposed"]) + " " + _(
            "(It raised an IndexError on the non-square patches and gave the transposed net's values on the square "
            "ones.)"), "transposed")
        changed = [c for c, _s in index] + transposed
    elif squares and all(sq.passed for sq, _s in squares):
        changed = []
        for c, s in index:
            if not _square(s):
                shape = np.asarray(s.args[0]).shape[-3:-1]
                c.hint = Hint(_(VARIANT_HINTS["swapped_degrees"]) + " " + _(
                    "(Here it raised an IndexError on a patch of degree ({m}, {n}); the square cases pass.)").format(
                        m=shape[0] - 1, n=shape[1] - 1), "swapped_degrees")
                c.mistake = c.hint.key
        return
    else:
        return
    for c in changed:
        c.hint, c.mistake = text, text.key


def _ratio(got, expected):
    """The common ratio got / expected where expected is not 0, if there is one."""
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    if got.shape != expected.shape:
        return None
    nz = np.abs(expected) > 1e-12 * max(1e-300, float(np.max(np.abs(expected), initial=0.0)))
    if not np.any(nz):
        return None
    r = got[nz] / expected[nz]
    return float(r[0]) if np.allclose(r, r[0], rtol=1e-6, atol=0) else None


def close(a, b, rtol=1e-7):
    return _close(a, b, rtol)


def diagnose_colors(values, got, cmap, tol):
    """Name the mistake behind wrong colours for exact corner ``values`` (N, 2, 2) under the map ``cmap``."""
    if np.any(np.isnan(got)):
        if cmap == "linear" and np.ptp(values) == 0:
            return _(_F2_ZERO)
        return _("some colours are NaN.")
    if close(got, np.swapaxes(expected_colors(values, cmap), 1, 2), rtol=1e-6):
        return hint("corner_order")
    if cmap == "linear":
        per_patch = np.stack([colormaps.h(colormaps.f2(v, rtol=0)) for v in values])
        if close(got, per_patch, rtol=1e-6):
            return _("κmin and κmax are the minimum and maximum over the corners of ALL patches, not per patch.")
        if np.ptp(values) <= tol:
            return _("the exact values are all equal (a flat patch), but your colours vary: the computed values differ "
                    "only by rounding noise, so κmax − κmin must count as 0 below a tolerance relative to the model's "
                    "size (e.g. 1e-9 / s² for K, s the diagonal of the bounding box of all control points), giving 0.5 (green) everywhere.")
    if cmap == "classification":
        zero = np.abs(values) <= tol
        green = np.all(np.abs(got - colormaps.h(0.5)) < 1e-6, axis=-1)
        if np.any(zero & ~green):
            return _("where K = 0 (flat or parabolic points) the computed values are rounding noise like 1e-17: "
                    "f3 must compare with a tolerance, not with == 0.")
        if np.any(~zero & green):
            return _("genuinely curved points are painted as K = 0: your f3 tolerance is absolute and too large for this "
                    "model (here |K| is about 1e-4 relative to the model's size). Scale the tolerance with the model, "
                    "e.g. 1e-9 / s² for K, s the diagonal of the bounding box of all control points.")
    for other in ("linear", "cut", "classification"):
        if other != cmap and close(got, expected_colors(values, other), rtol=1e-6):
            return _("these are the colours of the {other} map; use the colour map given by color_map.").format(
                other=_(MAP_LABELS[other]))
    return _("apply the colour map to the curvature values, then h (practical section 4).")


def index_error_hint(nets):
    """The first hint for an IndexError on ``nets`` (made precise by :func:`diagnose_indices`)."""
    m, n = np.asarray(nets).shape[-3] - 1, np.asarray(nets).shape[-2] - 1
    return Hint(_("an IndexError on a patch of degree ({m}, {n}): the first index of the control net runs over "
                  "0 … m (along u), the second over 0 … n (along v).").format(m=m, n=n), "index_error")


def visualize_error_hint(case, message, values):
    """A hint for an exception in visualize_curvature, from its message and the case's exact values."""
    nets = case.args[0]
    if "IndexError" in message:
        return index_error_hint(nets)
    if "math domain error" in message or ("NaN" in message and np.ptp(values) > 0):
        return _(_UMBILIC)
    if "ZeroDivision" in message or (("NaN" in message or "inf" in message) and np.ptp(values) == 0):
        return _(_F2_ZERO)
    return ""
