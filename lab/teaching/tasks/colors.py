"""The colour tasks (notebooks 04, 05): h, f1, f2, f3 and the practical's visualize_curvature."""

import numpy as np

from ...geometry import colormaps
from ...geometry.curvature import zero_tolerance
from ...i18n import N_, _, decimal, number_list
from ...model.patches import BezierPatches
from ..task import CaseSpec, Task, fmt, scalar_judge
from .curvature import BEZIER_BLOCK, CURVATURE_BLOCK
from .hints import diagnose_colors, diagnose_report, diagnose_values, visualize_error_hint
from .references import MODE_FIELD, MODE_LABELS, exact_corners, expected_colors, model_size, rand_net, value_tolerance

__all__ = ["COLOR_BLOCK", "F1", "F2", "F3", "VISUALIZE_BLOCK", "VISUALIZE_CURVATURE", "H"]

#: The maps and what applies them; ``symmetric`` is f2 after a shift of the values.
COLOR_BLOCK = tuple(f"lab.geometry.colormaps.{name}" for name in ("h", "f1", "f2", "f3", "apply", "colors_for",
                                                                   "symmetric"))
#: Everything that computes curvature or its colours (h, f1, f2, f3 are allowed: the student's own map functions
#: may be replaced by the library's).
VISUALIZE_BLOCK = tuple(dict.fromkeys(CURVATURE_BLOCK + BEZIER_BLOCK + COLOR_BLOCK[4:] + (
    "lab.geometry.curvature.curvature_values",
    "lab.model.patches.BezierPatches.visualize_curvature",
    "lab.model.patches.BezierPatches.corner_curvature",
    "lab.model.patches.BezierPatches.curvature_at",
)))




# -- h, f1, f2, f3 ----------------------------------------------------------------------------------------


def _h_cases(rng, graded):
    xs = [0.0, 0.25, 0.5, 0.75, 1.0] + list(np.round(rng.uniform(0, 1, 6 if graded else 3), 4))
    return [CaseSpec(f"h({number_list([x])})", (float(x),)) for x in xs]


def _h_hint(args, val, exp):
    x = args[0]
    if np.all(val == np.round(val)) and np.max(val) > 1:
        return _("colours are (r, g, b) in [0, 1], not 0–255.")
    piece = min(int(x * 4), 3)
    return _("check the piece for x in [{a}, {b}]: ").format(a=decimal(f"{piece / 4:g}"), b=decimal(f"{(piece + 1) / 4:g}")) + [
        "(0, 4x, 1)", "(0, 1, 2 − 4x)", "(4x − 2, 1, 0)", "(1, 4 − 4x, 0)"][piece]


H = Task("h", _h_cases, lambda c: colormaps.h(c.args[0]), scalar_judge(_h_hint, N_("an (r, g, b) tuple")),
         blocked=COLOR_BLOCK, summary=N_("an (r, g, b) tuple"))


def _f1_cases(rng, graded):
    xs = [-2.0, 0.0, 0.3, 1.0, 7.5] + list(np.round(rng.uniform(-2, 3, 4 if graded else 2), 3))
    return [CaseSpec(f"f1({number_list([x])})", (float(x),)) for x in xs]


F1 = Task("f1", _f1_cases, lambda c: min(max(c.args[0], 0.0), 1.0),
          scalar_judge(lambda a, v, e: _("values below 0 give 0, above 1 give 1, others stay.")),
          blocked=COLOR_BLOCK, summary=N_("one number"))


def _f2_cases(rng, graded):
    # the arguments as the language writes them: "f2(0.7, 0.7, 0.7)", in German "f2(0,7; 0,7; 0,7)"
    cases = [CaseSpec(f"f2({number_list(args)})", args) for args in ((3.0, 1.0, 5.0), (-2.0, -2.0, 6.0))]
    cases.append(CaseSpec(_("all values equal: {call}").format(call=f"f2({number_list([0.7] * 3)})"), (0.7, 0.7, 0.7)))
    for _k in range(4 if graded else 1):
        lo, hi = sorted(rng.integers(-20, 20, 2) / 4)
        hi = hi + 1
        cases.append(CaseSpec(f"f2({number_list(['x', lo, hi])})", (float(rng.uniform(lo, hi)), float(lo), float(hi))))
    return cases


def _f2_hint(args, val, exp):
    _x, lo, hi = args
    if hi == lo:
        return _("when all curvature values are equal, κmax − κmin = 0 and the quotient is 0/0: "
                 "return 0.5 (green) in that case.")
    return _("f2(x) = (x − κmin) / (κmax − κmin).")


def _f2_error_hint(case, message):
    if "ZeroDivision" in message:
        return _("when all curvature values are equal, κmax − κmin = 0; return 0.5 (green) in that case "
                 "instead of dividing.")
    return ""


F2 = Task("f2", _f2_cases, lambda c: 0.5 if c.args[2] == c.args[1] else (c.args[0] - c.args[1]) / (c.args[2] - c.args[1]),
          scalar_judge(_f2_hint), blocked=COLOR_BLOCK, error_hint=_f2_error_hint, summary=N_("one number"))


def _f3_cases(rng, graded):
    cases = [CaseSpec(f"f3({number_list([x])})", (x,)) for x in (-2.0, 0.0, 0.5)]
    cases += [CaseSpec(_("rounding noise: f3({x})").format(x=number_list([x])), (x,)) for x in (1e-17, -3e-16)]
    # the tolerance belongs to the model (its size): a fixed one in the function fails one of these
    cases += [CaseSpec(_("a large model's genuine small value: f3(3e-12, tol=1e-14)"), (3e-12, 1e-14)),
              CaseSpec(_("a coarse model's rounding noise: f3(-4e-7, tol=1e-6)"), (-4e-7, 1e-6))]
    if graded:
        cases += [CaseSpec(f"f3({number_list([x])})", (x,)) for x in (-1e-3, 1e-4)]
    return cases


def _f3_expected(case):
    x = case.args[0]
    tol = case.args[1] if len(case.args) > 1 else 1e-9
    return 0.5 if abs(x) <= tol else (1.0 if x > 0 else 0.0)


def _f3_hint(args, val, exp):
    x = args[0]
    tol = args[1] if len(args) > 1 else 1e-9
    if abs(x) <= tol:
        if len(args) > 1:
            return _("|x| = {x} is below the tolerance tol = {tol} you were given: use tol, not a fixed number.").format(
                x=decimal(f"{abs(x):g}"), tol=decimal(f"{tol:g}"))
        return _("computed curvature is rounding noise around 0 (a flat region gives K ≈ 1e-17): "
                 "compare |x| with the tolerance tol instead of x == 0.")
    if len(args) > 1:
        return _("tol = {tol} was given and |x| = {x} is larger: use the tolerance you are given, not a fixed one.").format(
            tol=decimal(f"{tol:g}"), x=decimal(f"{abs(x):g}"))
    return _("f3 is 0 for negative, 0.5 for zero, 1 for positive values.")


def _f3_error_hint(case, message):
    if "TypeError" in message and len(case.args) > 1:
        return _("f3 takes the model's tolerance as its second argument: def f3(x, tol=1e-9).")
    return ""


F3 = Task("f3", _f3_cases, _f3_expected, scalar_judge(_f3_hint), blocked=COLOR_BLOCK, error_hint=_f3_error_hint,
          summary=N_("one number"))


# -- visualize_curvature --------------------------------------------------------------------------------------


def _visualize_cases(rng, graded):
    """Cases of the practical's task: (nets, depth, mode, map); the nets are refined here, not by the student."""
    big = 2.0**20  # |K| about 1e-18 absolute: below any absolute tolerance a student would write
    specs = [
        (N_("one 3×3 patch, Gaussian curvature, linear map"), [rand_net(rng, 3, 3)], 0, "gaussian", "linear"),
        (N_("a twisted 2×3 patch (z = c·xy: only b_uv ≠ 0 of the second derivatives), Gaussian curvature"),
         [rand_net(rng, 2, 3, "twisted")], 0, "gaussian", "linear"),
        (N_("three 2×3 patches, mean curvature"), [rand_net(rng, 2, 3) for _k in range(3)], 0, "mean", "linear"),
        (N_("two 3×2 patches, κ1 (max)"), [rand_net(rng, 3, 2) for _k in range(2)], 0, "k1", "linear"),
        (N_("two 2×3 patches refined once, κ2 (min)"), [rand_net(rng, 2, 3) for _k in range(2)], 1, "k2", "linear"),
        (N_("two 3×2 patches, Gaussian curvature, cut map"), [rand_net(rng, 3, 2) for _k in range(2)], 0, "gaussian", "cut"),
        (N_("two 2×3 patches, classification map"), [rand_net(rng, 2, 3) for _k in range(2)], 0, "gaussian", "classification"),
        (N_("umbilic corners (paraboloid vertices), κ1"), [rand_net(rng, 2, 3, "umbilic") for _k in range(6)], 0, "k1", "linear"),
        (N_("plane z = 0, linear map (all values equal)"), [rand_net(rng, 2, 2, "level")], 0, "gaussian", "linear"),
        (N_("tilted flat patch refined once, classification map"), [rand_net(rng, 3, 2, "flat")], 1, "gaussian", "classification"),
        (N_("tilted flat patch, linear map (rounding noise only: one colour)"), [rand_net(rng, 2, 3, "flat")], 0, "gaussian", "linear"),
        (N_("a tilted flat patch beside a curved one, classification map"),
         [rand_net(rng, 3, 2, "flat"), rand_net(rng, 3, 2)], 0, "gaussian", "classification"),
        (N_("a large, gently curved bowl and saddle (|K| ≈ 1e-4 relative to the size), classification map"),
         [rand_net(rng, 3, 2, "bowl", big), rand_net(rng, 3, 2, "saddle", big)], 0, "gaussian", "classification"),
    ]
    if graded:
        specs += [
            (N_("three 2×4 patches refined twice, mean curvature"), [rand_net(rng, 2, 4) for _k in range(3)], 2, "mean", "linear"),
            (N_("two 4×2 patches, κ2, classification map"), [rand_net(rng, 4, 2) for _k in range(2)], 0, "k2", "classification"),
            (N_("umbilic corner refined once, Gaussian curvature, cut map"), [rand_net(rng, 3, 3, "umbilic")], 1, "gaussian", "cut"),
            (N_("four 3×3 patches, κ1, cut map"), [rand_net(rng, 3, 3) for _k in range(4)], 0, "k1", "cut"),
            (N_("a gently curved bowl and saddle of ordinary size, classification map"),
             [rand_net(rng, 2, 3, "bowl"), rand_net(rng, 2, 3, "saddle")], 0, "gaussian", "classification"),
        ]
    cases = []
    for name, nets, depth, mode, cmap in specs:
        refined = BezierPatches(np.array(nets)).refine(depth).control_points.copy()
        flat = name.startswith(("tilted flat", "plane z = 0"))
        # the twisted patch (b_uu = b_vv = 0) is blind to leaving out every degree factor: that is the
        # reparametrisation u -> m u, v -> n v there, so K and H come out right; it does not vouch for the flat cases
        cases.append(CaseSpec(_(name), (refined, mode, cmap), info={"size": model_size(refined)}, guard=flat,
                              decides=not name.startswith("a twisted")))
    return cases


def _visualize_expected(case):
    nets, mode, cmap = case.args
    values = exact_corners(nets)[MODE_FIELD[mode]]
    return {"values": values, "colors": expected_colors(values, cmap)}


def _visualize_judge(case, value, exp):
    nets, mode, cmap = case.args
    values, colours = exp["values"], exp["colors"]
    got_v, got_c = value["curvature"], value["colors"]
    if got_v.shape != values.shape or got_c.shape != colours.shape:
        return (False, _("values {a}, colours {b}").format(a=values.shape, b=colours.shape), f"{got_v.shape}, {got_c.shape}",
                _("keep the collection's patches: call set_curvature and set_colors on each patch."))
    missing = np.isnan(got_v).all(axis=(1, 2))
    if np.any(missing):
        k = int(np.argmax(missing))
        return (False, _("set_curvature called for every patch"),
                _("patch {k} (of {n}) has no curvature values").format(k=k, n=len(nets)),
                _("call patch.set_curvature(c00, c01, c10, c11) for every patch of the collection."))
    # at umbilics κ1, κ2 = H ± √(H² − K) are only accurate to √eps relative
    tol = value_tolerance(values, mode, case.info["size"], 1e-7 if mode in ("k1", "k2") else 1e-8)
    if not np.all(np.abs(got_v - values) <= tol):
        return (False, _("{mode} at the corners: {values}").format(mode=_(MODE_LABELS[mode]), values=fmt(values)), fmt(got_v),
                diagnose_values(nets, mode, got_v, values, zero_tolerance(mode, case.info["size"])))
    if np.isnan(got_c).all(axis=(1, 2, 3)).any():
        return (False, _("set_colors called for every patch"), _("some patches have no colours"),
                _("call patch.set_colors(c00, c01, c10, c11) with (r, g, b) tuples for every patch."))
    if np.all(np.abs(got_c - colours) <= 1e-6):
        return True, "", "", ""
    noise = zero_tolerance(mode, case.info["size"])
    return False, _("colours {colours}").format(colours=fmt(colours, 3)), fmt(got_c, 3), diagnose_colors(values, got_c, cmap, noise)


def _visualize_error_hint(case, message):
    return visualize_error_hint(case, message, _visualize_expected(case)["values"])


VISUALIZE_CURVATURE = Task(
    "visualize_curvature", _visualize_cases, _visualize_expected, _visualize_judge, protocol="patches",
    blocked=VISUALIZE_BLOCK, allowed="lab.colormaps.h, f1, f2, f3, math, numpy", error_hint=_visualize_error_hint,
    diagnose=diagnose_report,
    summary=N_("the curvature stored with set_curvature and the colours stored with set_colors for every patch"))
