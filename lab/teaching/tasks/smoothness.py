r"""The task of notebook 12: the principal directions at a patch corner from the Weingarten map.

``principal_directions(bu, bv, buu, buv, bvv)`` gets the corner derivatives of a Bézier patch (3-vectors)
and returns the unit principal directions ``[d1, d2]`` (a (2, 3) array) of κ1 ≥ κ2, with the practical's
normal N = b_u × b_v/|b_u × b_v|: the eigenvectors w of :math:`S = \mathbf G^{-1}\mathbf H` mapped to space,
d = w1 b_u + w2 b_v, normalised.  Either sign of each direction is right.  The exact answer is computed
in rational arithmetic (40 digits for the square root) from rational inputs (nets on a 1/4 grid,
derivatives by forward differences).
"""

from fractions import Fraction

import numpy as np

from ...i18n import N_, _
from ..task import CaseSpec, Task, fmt

__all__ = ["PRINCIPAL_DIRECTIONS", "SMOOTHNESS_BLOCK"]

#: What computes principal directions (or the Weingarten map and its eigenvalues) from derivatives.
SMOOTHNESS_BLOCK = (
    "lab.geometry.directions.from_derivatives", "lab.geometry.directions.eigen",
    "lab.geometry.curvature.shape_operator", "lab.geometry.curvature.from_derivatives",
    "lab.model.surface.Surface.curvature", "lab.model.surface.Surface._directions",
    "lab.model.surface.Surface.curvature_grid", "lab.model.surface.Surface._curvature",
    "lab.interrogation.umbilics.traceless", "lab.interrogation.geodesics.problem._line_direction",
    "lab.interrogation.cad.kernel.occ_curvature",
)

_SUMMARY = N_("a (2, 3) array: the unit directions d1 (of κ1) and d2 (of κ2)")


def _corner(P):
    """Corner derivatives at (u, v) = (0, 0) of a Bézier net by forward differences (practical section 3)."""
    m, n = P.shape[0] - 1, P.shape[1] - 1
    bu = m * (P[1, 0] - P[0, 0])
    bv = n * (P[0, 1] - P[0, 0])
    buu = m * (m - 1) * (P[2, 0] - 2 * P[1, 0] + P[0, 0])
    buv = m * n * (P[1, 1] - P[1, 0] - P[0, 1] + P[0, 0])
    bvv = n * (n - 1) * (P[0, 2] - 2 * P[0, 1] + P[0, 0])
    return bu, bv, buu, buv, bvv


def exact(bu, bv, buu, buv, bvv, *, variant="right"):
    """``[d1, d2]`` (2, 3): the Weingarten map in rational arithmetic, its eigenvectors with 40 digits (mpmath).

    ``variant`` gives a mistake's answer (for the hints): ``"H"`` eigenvectors of the second form alone,
    ``"transposed"`` of ``H G^-1``.  The eigenvector of κ is taken from the row of (S − κI)w = 0 that does
    not cancel (as :mod:`lab.geometry.directions` does).
    """
    import mpmath

    with mpmath.workdps(40):
        bu, bv, buu, buv, bvv = ([Fraction(float(c)) for c in x] for x in (bu, bv, buu, buv, bvv))
        dot = lambda a, b: sum(x * y for x, y in zip(a, b))
        Q = [bu[1] * bv[2] - bu[2] * bv[1], bu[2] * bv[0] - bu[0] * bv[2], bu[0] * bv[1] - bu[1] * bv[0]]
        E, F, G = dot(bu, bu), dot(bu, bv), dot(bv, bv)
        det = E * G - F * F
        A, B, C = dot(Q, buu), dot(Q, buv), dot(Q, bvv)  # W times e, f, g (W = |Q|)
        if variant == "right":  # G^-1 H times W
            S = [[(G * A - F * B) / det, (G * B - F * C) / det], [(E * B - F * A) / det, (E * C - F * B) / det]]
        elif variant == "H":
            S = [[A, B], [B, C]]
        else:  # H G^-1 times W
            S = [[(A * G - B * F) / det, (B * E - A * F) / det], [(B * G - C * F) / det, (C * E - B * F) / det]]
        mp = lambda x: mpmath.mpf(x.numerator) / x.denominator
        am, s12, s21 = mp((S[0][0] - S[1][1]) / 2), mp(S[0][1]), mp(S[1][0])
        r = mpmath.sqrt(am * am + s12 * s21)
        # the sign of W > 0 does not change the eigenvectors, and their order by eigenvalue only through it
        if am >= 0:
            w1, w2 = (r + am, s21), (s12, -(r + am))
        else:
            w1, w2 = (s12, r - am), (am - r, s21)
        out = []
        for w in (w1, w2):
            d = [w[0] * mp(x) + w[1] * mp(y) for x, y in zip(bu, bv)]
            n = mpmath.sqrt(sum(x * x for x in d))
            out.append([float(x / n) for x in d])
    return np.array(out)


def _weingarten(bu, bv, buu, buv, bvv):
    """The Weingarten map S = G⁻¹H (floats) with N = b_u × b_v/|b_u × b_v|: for choosing nets and for the mistakes a
    student makes with numpy (the exact answer is :func:`exact`)."""
    N = np.cross(bu, bv)
    N = N / np.linalg.norm(N)
    G = np.array([[bu @ bu, bu @ bv], [bu @ bv, bv @ bv]])
    return np.linalg.solve(G, np.array([[N @ buu, N @ buv], [N @ buv, N @ bvv]]))


def _net(rng):
    """A bicubic net on a 1/4 grid, near a graph over the plane, whose corner is regular and far from an umbilic."""
    while True:
        x = np.arange(4.0)
        P = np.stack(list(np.meshgrid(x, x, indexing="ij")) + [np.zeros((4, 4))], axis=-1)
        P[..., :2] += rng.integers(-2, 3, (4, 4, 2)) / 4
        P[..., 2] = rng.integers(-8, 9, (4, 4)) / 4
        d = _corner(P)
        Q = np.cross(d[0], d[1])
        if np.linalg.norm(Q) < 0.5:
            continue
        k = np.sort(np.linalg.eigvals(_weingarten(*d)).real)
        if k[1] - k[0] < 0.1 * (abs(k[0]) + abs(k[1]) + 0.1):
            continue
        return P, d


def _cases(rng, graded):
    """A plain corner (F = 0, E = G), a skewed and stretched one (F != 0, E != G: G matters), a saddle whose
    κ2 is larger in magnitude than κ1, and corners of random bicubic nets."""
    z = np.zeros(3)
    fixed = [
        (_("orthonormal parameters, z = x² + y²/4: d1 along x"),
         (np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 2.0]), z, np.array([0, 0, 0.5]))),
        (_("orthonormal parameters, z = x²/4 + y²: d1 along y (the larger curvature comes second)"),
         (np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 0.5]), z, np.array([0, 0, 2.0]))),
        (_("skewed, stretched parameters (F ≠ 0, E ≠ G): the first fundamental form matters"),
         (np.array([2.0, 0, 0]), np.array([1.0, 1.0, 0]), np.array([0, 0, 1.0]), np.array([0, 0, 0.5]),
          np.array([0, 0, -1.0]))),
        (_("a saddle: |κ2| > |κ1|, κ1 > 0 > κ2"),
         (np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 0.5]), np.array([0, 0, 0.25]),
          np.array([0, 0, -3.0]))),
    ]
    cases = [CaseSpec(name, args) for name, args in fixed]
    for k in range(5 if graded else 2):
        d = _net(rng)[1]
        cases.append(CaseSpec(_("corner (u, v) = (0, 0) of a random bicubic net, no. {k}").format(k=k + 1), d))
    return cases


def _same_line(a, b, tol=1e-7):
    """Rows of a and b parallel (either sign), both unit."""
    return bool(np.all(np.abs(np.abs(np.einsum("ij,ij->i", a, b)) - 1) <= tol))


def _hint(case, value, exp):
    norms = np.linalg.norm(value, axis=1)
    unit = value / np.where(norms > 0, norms, 1)[:, None]
    if _same_line(unit, exp[::-1]):
        return _("d1 and d2 are swapped: d1 belongs to κ1 = H + √(H² − K), the larger (signed, not by magnitude) "
                 "principal curvature, with N = b_u × b_v.")
    if _same_line(unit, exp) and not np.allclose(norms, 1, atol=1e-7):
        return _("the directions are right but not unit vectors: divide each by its length.")
    for variant, text in (
        ("H", _("these are the eigenvectors of the second fundamental form H alone: the Weingarten map is "
                "S = G⁻¹H; unless E = G and F = 0 the first fundamental form changes the directions.")),
        ("transposed", _("these are the eigenvectors of H G⁻¹, the transpose of the Weingarten map: use "
                         "S = G⁻¹H (S w = κ w for the parameter coordinates w of a direction).")),
    ):
        wrong = exact(*case.args, variant=variant)
        if _same_line(unit, wrong) or _same_line(unit, wrong[::-1]):
            return text
    rows = _rows_of_eigenvectors(*case.args)
    if rows is not None and (_same_line(unit, rows) or _same_line(unit, rows[::-1])):
        return _("these come from the rows of the eigenvector matrix: numpy's eig returns the eigenvectors as its "
                 "columns, w[:, i] belongs to the eigenvalue k[i].")
    if abs(unit[0] @ unit[1]) > 1e-6:
        return _("the two directions are not orthogonal in space: map the eigenvectors w of S to space as "
                 "d = w1 b_u + w2 b_v (not (w1, w2, 0)).")
    return _("the eigenvectors w of S = G⁻¹H (2 × 2, in the parameter plane) give d = w1 b_u + w2 b_v; "
             "sort them by their eigenvalues κ1 ≥ κ2 and normalise.")


def _rows_of_eigenvectors(bu, bv, buu, buv, bvv):
    """What taking the rows instead of the columns of numpy's eigenvector matrix of S = G⁻¹H gives (unit, sorted)."""
    k, w = np.linalg.eig(_weingarten(bu, bv, buu, buv, bvv))
    order = np.argsort(-k.real)
    d = np.array([w.real[i, 0] * bu + w.real[i, 1] * bv for i in order])
    norms = np.linalg.norm(d, axis=1)
    return None if np.any(norms == 0) else d / norms[:, None]


def _judge(case, value, exp):
    if not isinstance(value, np.ndarray) or value.shape != (2, 3):
        got = fmt(value) if isinstance(value, np.ndarray) else repr(value)
        hint = _("return {what}.").format(what=_(_SUMMARY))
        if isinstance(value, np.ndarray) and value.shape == (2, 2):
            hint = _("these are 2-vectors: map each eigenvector w to space, d = w1 b_u + w2 b_v.")
        return False, fmt(exp), got, hint
    if not np.all(np.isfinite(value)):
        return False, fmt(exp), fmt(value), _("NaN or inf: this corner is regular and not an umbilic.")
    ok = _same_line(value, exp) and np.allclose(np.linalg.norm(value, axis=1), 1, atol=1e-9)
    return ok, fmt(exp), fmt(value), "" if ok else _hint(case, value, exp)


def _error_hint(case, message):
    if "LinAlgError" in message or "Singular" in message:
        return _("G is invertible at a regular corner (EG − F² > 0): solve with G, not with H.")
    if "shape" in message or "broadcast" in message:
        return _("b_u, b_v, b_uu, b_uv, b_vv are 3-vectors; G and H are 2 × 2 matrices of dot products.")
    return ""


PRINCIPAL_DIRECTIONS = Task("principal_directions", _cases, lambda c: exact(*c.args), _judge,
                            blocked=SMOOTHNESS_BLOCK, allowed="numpy (np.cross, np.dot, np.linalg.eig, np.linalg.solve)",
                            error_hint=_error_hint, summary=_SUMMARY)
