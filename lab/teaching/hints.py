"""Hints that name a student's mistake: the result is compared with the computation done each classic wrong way."""

import numpy as np

from ..geometry import colormaps
from ..i18n import N_, _
from .references import (
    MAP_LABELS,
    MODE_FIELD,
    NET_NAMES,
    degree_factor,
    expected_colors,
    variant_corner_derivatives,
    variant_curvature,
)
from .spec import close as _close

__all__ = ["VARIANT_HINTS", "diagnose_colors", "diagnose_values", "hint", "visualize_error_hint"]

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
    "orientation": N_("the normal is N = b_u × b_v / |b_u × b_v| (practical 2.2); you used the opposite orientation, "
    "so H, κ1 and κ2 have the wrong sign."),
    "no_half": N_("H = ½ (eG − 2fF + gE) / (EG − F²): the factor ½ is missing (practical eq. 4)."),
    "principal_swapped": N_("κ1 = H + √(H² − K) is the larger principal curvature, κ2 = H − √(H² − K) the smaller."),
    "mode_ignored": N_("the values do not depend on curvature_mode: choose K, H, κ1 or κ2 according to it."),
}



def hint(key):
    """The hint ``key`` of :data:`VARIANT_HINTS` in the current language."""
    return _(VARIANT_HINTS[key])


_UMBILIC = N_("at umbilic points (κ1 = κ2, e.g. the vertex of a paraboloid) rounding makes H² − K slightly negative: "
            "use √(max(H² − K, 0)).")
_F2_ZERO = N_("all curvature values are equal, so κmax − κmin = 0: f2 must not divide by zero "
            "(give 0.5, green, in that case).")


def _values(nets, field_name, variant=None, net_variant=None):
    return np.stack([variant_curvature(variant_corner_derivatives(P, net_variant), variant)[field_name] for P in nets])


def diagnose_values(nets, mode, got, expected):
    """Name the classic mistake whose corner values (N, 2, 2) match ``got``."""
    field_name = MODE_FIELD[mode]
    scale = max(float(np.max(np.abs(expected))), 1e-300)  # relative to the case's own values (tiny on large models)

    def close(a, b):
        return _close(a, b, scale=scale)

    if np.any(np.isnan(got)):
        umbilic = _(_UMBILIC)
        return _("some values are NaN.") + " " + umbilic[0].upper() + umbilic[1:]
    if close(got, np.swapaxes(expected, 1, 2)):
        return hint("corner_order")
    for variant in ("no_factors", "second_factor", "swapped_degrees"):
        if close(got, _values(nets, field_name, net_variant=variant)):
            return hint(variant)
    for net in NET_NAMES:  # one net without its degree factor
        if close(got, _values(nets, field_name, net_variant=f"missing:{net}")):
            text, _value = degree_factor(nets[0], net)
            ratio = _ratio(got, expected)
            off = " " + _("(your values are {ratio} times the right ones)").format(ratio=f"{ratio:.6g}") if ratio is not None else ""
            return _("b_{net} lacks its degree factor {factor}{off}: practical section 3.").format(
                net=net[1:], factor=text, off=off)
    for variant in ("unnormalised", "orientation", "no_half", "principal_swapped"):
        if close(got, _values(nets, field_name, variant)):
            return hint(variant)
    for other in MODE_FIELD.values():
        if other != field_name and close(got, _values(nets, other)):
            return hint("mode_ignored") + " " + _("(you stored {got}, expected {expected})").format(got=other, expected=field_name)
    ratio = _ratio(got, expected)
    if ratio is not None:
        m, n = nets[0].shape[0] - 1, nets[0].shape[1] - 1
        names = {m: "m", n: "n", m * m: "m²", n * n: "n²", 1 / m: "1/m", 1 / n: "1/n", 1 / m**2: "1/m²", 1 / n**2: "1/n²"}
        for value, name in names.items():
            if value != 1 and abs(ratio - value) <= 1e-6 * abs(value):
                return _("your values are exactly {name} = {value} times the right ones: a degree factor is missing "
                         "or doubled in a derivative net (practical section 3).").format(name=name, value=f"{value:g}")
    return _("compare your formulas with practical eqs. (3), (4) and section 3.")


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
                    "size (e.g. 1e-9 / size² for K), giving 0.5 (green) everywhere.")
    if cmap == "classification":
        zero = np.abs(values) <= tol
        green = np.all(np.abs(got - colormaps.h(0.5)) < 1e-6, axis=-1)
        if np.any(zero & ~green):
            return _("where K = 0 (flat or parabolic points) the computed values are rounding noise like 1e-17: "
                    "f3 must compare with a tolerance, not with == 0.")
        if np.any(~zero & green):
            return _("genuinely curved points are painted as K = 0: your f3 tolerance is absolute and too large for this "
                    "model (here |K| is about 1e-4 relative to the model's size). Scale the tolerance with the model, "
                    "e.g. 1e-9 / size² for K.")
    for other in ("linear", "cut", "classification"):
        if other != cmap and close(got, expected_colors(values, other), rtol=1e-6):
            return _("these are the colours of the {other} map; use the colour map given by color_map.").format(
                other=_(MAP_LABELS[other]))
    return _("apply the colour map to the curvature values, then h (practical section 4).")


def visualize_error_hint(case, message, values):
    """A hint for an exception in visualize_curvature, from its message and the case's exact values."""
    nets = case.args[0]
    if "IndexError" in message and nets.shape[1] != nets.shape[2]:
        return hint("swapped_degrees") + " " + _("(Here it raised an IndexError on a non-square patch.)")
    if "math domain error" in message or ("NaN" in message and np.ptp(values) > 0):
        return _(_UMBILIC)
    if "ZeroDivision" in message or ("NaN" in message and np.ptp(values) == 0):
        return _(_F2_ZERO)
    return ""
