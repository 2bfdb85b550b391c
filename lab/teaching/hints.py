"""Hints that name a student's mistake: the output is compared with the deliberately wrong variants."""

import numpy as np

from ..geometry import colormaps
from .references import MODE_FIELD, _expected_colors, _variant_corner_derivatives, _variant_curvature

VARIANT_HINTS = {
    "corner_order": "set_curvature(c00, c01, c10, c11) and set_colors(...) take c01 = the value at u = 0, v = 1; "
    "your corners are in another order (c01 and c10 exchanged).",
    "no_factors": "the derivative nets need the degree factors: b_u = m Δ^{1,0} b, b_uu = m(m-1) Δ^{1,0}Δ^{1,0} b, "
    "b_uv = mn Δ^{1,0}Δ^{0,1} b (practical section 3).",
    "second_factor": "the second derivatives need m(m-1) and n(n-1), not m and n (practical section 3).",
    "swapped_degrees": "m and n are swapped: m is the degree along u (first index of the control net), n along v. "
    "It only shows on non-square patches.",
    "unnormalised": "e, f, g need the unit normal N = b_u × b_v / |b_u × b_v|; you used the cross product without "
    "dividing by its length.",
    "orientation": "the normal is N = b_u × b_v / |b_u × b_v| (practical 2.2); you used the opposite orientation, "
    "so H, κ1 and κ2 have the wrong sign.",
    "no_half": "H = ½ (eG − 2fF + gE) / (EG − F²): the factor ½ is missing (practical eq. 4).",
    "principal_swapped": "κ1 = H + √(H² − K) is the larger principal curvature, κ2 = H − √(H² − K) the smaller.",
    "mode_ignored": "the values do not depend on curvature_mode: choose K, H, κ1 or κ2 according to it.",
}


def _diagnose_values(nets, mode, got, expected):
    """Name the classic mistake whose values match ``got``."""
    field_name = MODE_FIELD[mode]
    if np.any(np.isnan(got)):
        return (
            "some values are NaN. At umbilic points (κ1 = κ2, e.g. the vertex of a paraboloid) rounding makes "
            "H² − K slightly negative: use √(max(H² − K, 0))."
        )
    if _close(got, np.swapaxes(expected, 1, 2)):
        return VARIANT_HINTS["corner_order"]
    for variant in ("no_factors", "second_factor", "swapped_degrees"):
        vals = np.stack([_variant_curvature(_variant_corner_derivatives(P, variant))[field_name] for P in nets])
        if _close(got, vals):
            return VARIANT_HINTS[variant]
    for variant in ("unnormalised", "orientation", "no_half", "principal_swapped"):
        vals = np.stack([_variant_curvature(_variant_corner_derivatives(P), variant)[field_name] for P in nets])
        if _close(got, vals):
            return VARIANT_HINTS[variant]
    for other in MODE_FIELD.values():
        if other != field_name:
            vals = np.stack([_variant_curvature(_variant_corner_derivatives(P))[other] for P in nets])
            if _close(got, vals):
                return VARIANT_HINTS["mode_ignored"] + f" (you stored {other}, expected {field_name})"
    return "compare your formulas with practical eqs. (3), (4) and section 3."


def _close(a, b, rtol=1e-7):
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    if a.shape != b.shape or np.any(np.isnan(a)) or np.any(np.isnan(b)):
        return False
    scale = max(1.0, float(np.max(np.abs(b)))) if b.size else 1.0
    return bool(np.all(np.abs(a - b) <= rtol * scale))


def _fmt(x, digits=6):
    arr = np.asarray(x, dtype=float)
    return np.array2string(arr, precision=digits, suppress_small=False, max_line_width=100, threshold=12)




def _error_hint(message, values):
    """A hint for an exception in visualize_curvature, from its message and the case's values."""
    if "math domain error" in message or ("NaN" in message and np.ptp(values) > 0):
        return ("\nhint: at umbilic points (κ1 = κ2) rounding makes H² − K slightly negative, and the square "
                "root fails: use √(max(H² − K, 0)).")
    if "ZeroDivision" in message or ("NaN" in message and np.ptp(values) == 0):
        return ("\nhint: all curvature values are equal here, so κmax − κmin = 0: f2 must not divide by zero "
                "(give 0.5, green, in that case).")
    return ""


def _diagnose_colors(values, got, cmap, n_patches):
    if np.any(np.isnan(got)):
        if cmap == "linear" and np.ptp(values) == 0:
            return ("all curvature values are equal, so κmax − κmin = 0: f2 must not divide by zero "
                    "(give 0.5, green, in that case).")
        return "some colours are NaN."
    if _close(got, np.swapaxes(_expected_colors(values, cmap), 1, 2), rtol=1e-6):
        return VARIANT_HINTS["corner_order"]
    if cmap == "linear":
        per_patch = np.stack([colormaps.h(colormaps.f2(v, rtol=0)) for v in values])
        if _close(got, per_patch, rtol=1e-6):
            return "κmin and κmax are the minimum and maximum over the corners of ALL patches, not per patch."
    if cmap == "classification":
        noisy = np.abs(values) == 0
        if np.any(noisy):
            return ("at K = 0 (flat or parabolic points) the computed values are rounding noise like 1e-17: "
                    "f3 must compare with a tolerance, not with == 0.")
    for other in ("linear", "cut", "classification"):
        if other != cmap and _close(got, _expected_colors(values, other), rtol=1e-6):
            return f"these are the colours of the {other} map; use the colour map given by color_map."
    return "apply the colour map to the curvature values, then h (practical section 4)."


#: The tasks the autograder knows: name -> check function.
