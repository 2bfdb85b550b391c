"""Test nets and exact references of the checks (trusted side: never sent to the student's code).

Control nets have rational coordinates (dyadic, exact in binary), so the exact curvature at the corners
is computed with sympy in rational arithmetic and no answer can be hard-coded.  Besides random nets there
are nets that decide between right and wrong: umbilic corners, level and tilted flat patches, gently
curved patches far from and near to the rounding noise, scaled up and down by powers of two.  Also here:
the same computation with one deliberate mistake each (to name a student's mistake in a hint).
"""

import numpy as np

from ...geometry import analytic, colormaps
from ...geometry.curvature import zero_tolerance
from ...i18n import N_

MODE_FIELD = {"gaussian": "K", "mean": "H", "k1": "k1", "k2": "k2"}
#: How a report names the curvature modes and colour maps (translated where shown).
MODE_LABELS = {"gaussian": N_("the Gaussian curvature K"), "mean": N_("the mean curvature H"),
               "k1": N_("the principal curvature κ1"), "k2": N_("the principal curvature κ2")}
MAP_LABELS = {"linear": N_("linear (f2)"), "cut": N_("cut (f1)"), "classification": N_("classification (f3)")}

#: The derivative nets and their degree factors, as the practical writes them (section 3).
NET_NAMES = ("bu", "bv", "buu", "buv", "bvv")


def rand_net(rng, m, n, kind="random", scale=1.0):
    """A control net with dyadic rational coordinates, multiplied by ``scale`` (a power of two keeps it exact).

    Kinds: ``random``; ``level`` (z = 0); ``flat`` (a tilted plane z = a x + b y: exactly planar, but the
    computed K and H are rounding noise, as on real flat regions); ``umbilic`` (a paraboloid's vertex at
    the (0, 0) corner, turned so that the textbook formula computes H² − K < 0 there; needs m, n >= 2);
    ``bowl`` and ``saddle`` (a tilted plane plus a gentle z = ±c(x² ± y²): genuine curvature with
    |K| ≈ 1e-4 relative to the patch's size, elliptic or hyperbolic everywhere); ``twisted`` (z = a x + b y
    + c x y over x = i, y = j: b_uu = b_vv = 0 exactly and b_uv ≠ 0, so a wrong factor of b_uv shows alone).
    """
    if kind == "umbilic":
        P = _umbilic_net(rng, m, n)
    elif kind == "twisted":
        X, Y = np.meshgrid(np.arange(m + 1.0), np.arange(n + 1.0), indexing="ij")
        a, b = rng.integers(-7, 8, 2) / 8
        c = int(rng.choice([-3, -2, -1, 1, 2, 3])) / 4
        P = np.stack([X, Y, a * X + b * Y + c * X * Y], axis=-1)
    elif kind in ("bowl", "saddle"):
        # x = m u, y = n v (Bernstein coefficients i and j); (m u)^2 has the coefficients m i (i - 1) / (m - 1).
        # z = a x + b y + c (x^2 ± y^2) with c = 2^-7 / (m + n): |K| = 4 c^2 / (1 + ...)^2 ≈ 1e-4 / size^2.
        i, j = np.arange(m + 1.0), np.arange(n + 1.0)
        xx, yy = m * i * (i - 1) / (m - 1), n * j * (j - 1) / (n - 1)
        a, b = rng.integers(1, 8, 2) / 8
        c = 2.0**-7 / (m + n)
        X, Y = np.meshgrid(i, j, indexing="ij")
        Z = a * X + b * Y + c * (xx[:, None] + (1.0 if kind == "bowl" else -1.0) * yy[None, :])
        P = np.stack([X, Y, Z], axis=-1)
    else:
        P = analytic.random_rational_net(rng, m, n)
        if kind in ("level", "flat"):
            a, b = (0.0, 0.0) if kind == "level" else rng.integers(1, 8, 2) / 8
            P[..., 2] = a * P[..., 0] + b * P[..., 1]
    return P * scale


def _umbilic_net(rng, m, n):
    """z = c (x² + y²) over [0, s]², umbilic at the corner (0, 0), turned about z by a rational rotation."""
    i, j = np.arange(m + 1), np.arange(n + 1)
    for _ in range(200):
        s = float(rng.integers(1, 4))
        c = int(rng.integers(1, 5)) / 4
        ca, sa = [(0.6, 0.8), (0.8, 0.6), (5 / 13, 12 / 13), (12 / 13, 5 / 13)][int(rng.integers(4))]
        # Bernstein coefficients: x = s u -> s i / m; x^2 -> s^2 i (i - 1) / (m (m - 1)); sums add up
        X, Y = np.meshgrid(s * i / m, s * j / n, indexing="ij")
        Z = c * s * s * ((i * (i - 1) / (m * (m - 1)))[:, None] + (j * (j - 1) / (n * (n - 1)))[None, :])
        P = np.stack([ca * X - sa * Y, sa * X + ca * Y, Z], axis=-1)
        if naive_discriminant(variant_corner_derivatives(P))[0, 0] < 0:
            break
    return P


def model_size(nets):
    """Diagonal of the bounding box of all control points: the length scale of a case."""
    P = np.asarray(nets, dtype=float).reshape(-1, 3)
    return float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))


def exact_corners(nets):
    """Exact K, H, k1, k2 at the corners of every net: dict of arrays (N, 2, 2) indexed [patch, u, v]."""
    out = {k: np.zeros((len(nets), 2, 2)) for k in ("K", "H", "k1", "k2")}
    for p, P in enumerate(nets):
        for (a, b), c in analytic.bezier_corner_curvature_exact(P).items():
            c = analytic.to_float(c)
            for k, values in out.items():
                values[p, a, b] = getattr(c, k)
    return out


def expected_colors(values, cmap):
    """Colours the practical's maps give to exact ``values`` (exact zeros are zero; no noise to absorb)."""
    if cmap == "linear":
        return colormaps.h(colormaps.f2(values, rtol=0))
    if cmap == "cut":
        return colormaps.h(colormaps.f1(values))
    return colormaps.h(colormaps.f3(values, tol=0))


def value_tolerance(values, mode, size, rtol):
    """Absolute tolerance for computed curvature against exact ``values``: relative to the largest value,
    plus the rounding noise of a flat region of a model of this size (a flat patch's exact 0)."""
    return rtol * float(np.max(np.abs(values), initial=0.0)) + zero_tolerance(mode, size)


# -- the computation with one deliberate mistake ------------------------------------------------------


def variant_nets(P, variant=None):
    """Derivative nets (bu, bv, buu, buv, bvv) by forward differences, with a deliberate mistake (or none).

    Variants: ``no_factors``; ``second_factor`` (m, n instead of m(m-1), n(n-1)); ``swapped_degrees``;
    ``missing:<net>`` (only that net lacks its degree factor, e.g. ``missing:bu``).
    """
    m, n = P.shape[0] - 1, P.shape[1] - 1
    f = {"bu": m, "bv": n, "buu": m * (m - 1), "buv": m * n, "bvv": n * (n - 1)}
    if variant == "no_factors":
        f = dict.fromkeys(f, 1)
    elif variant == "second_factor":
        f["buu"], f["bvv"] = m, n
    elif variant == "swapped_degrees":
        f = {"bu": n, "bv": m, "buu": n * (n - 1), "buv": n * m, "bvv": m * (m - 1)}
    elif variant and variant.startswith("missing:"):
        f[variant.split(":", 1)[1]] = 1
    return {
        "bu": f["bu"] * np.diff(P, axis=0),
        "bv": f["bv"] * np.diff(P, axis=1),
        "buu": f["buu"] * np.diff(P, 2, axis=0),
        "buv": f["buv"] * np.diff(np.diff(P, axis=0), axis=1),
        "bvv": f["bvv"] * np.diff(P, 2, axis=1),
    }


def degree_factor(P, net):
    """The degree factor of a derivative net (m, n, m(m-1), mn, n(n-1)) as text and value."""
    m, n = P.shape[0] - 1, P.shape[1] - 1
    return {"bu": ("m", m), "bv": ("n", n), "buu": ("m(m−1)", m * (m - 1)), "buv": ("mn", m * n),
            "bvv": ("n(n−1)", n * (n - 1))}[net]


def variant_corner_derivatives(P, variant=None):
    """Corner derivatives (bu, bv, buu, buv, bvv), each (2, 2, 3), computed with a deliberate mistake."""
    return {k: D[[0, -1]][:, [0, -1]] for k, D in variant_nets(P, variant).items()}


def naive_discriminant(d):
    """H^2 - K at the corners computed with the textbook formulas, unclamped (may round below 0)."""
    c = variant_curvature(d)
    return c["H"] * c["H"] - c["K"]


def variant_curvature(d, variant=None):
    """K, H, k1, k2 from corner derivatives, with a deliberate mistake."""
    bu, bv = d["bu"], d["bv"]
    Q = np.cross(bu, bv)
    W = np.linalg.norm(Q, axis=-1)
    N = Q / (W[..., None] if variant != "unnormalised" else 1.0)
    if variant == "orientation":
        N = -N

    def dot(a, b):
        return np.sum(a * b, axis=-1)

    E, F, G = dot(bu, bu), dot(bu, bv), dot(bv, bv)
    e, f, g = dot(N, d["buu"]), dot(N, d["buv"]), dot(N, d["bvv"])
    with np.errstate(divide="ignore", invalid="ignore"):
        K = (e * g - f * f) / (E * G - F * F)
        H = (e * G - 2 * f * F + g * E) / (E * G - F * F)
    if variant != "no_half":
        H = 0.5 * H
    root = np.sqrt(np.maximum(H * H - K, 0))
    k1, k2 = H + root, H - root
    if variant == "principal_swapped":
        k1, k2 = k2, k1
    return {"K": K, "H": H, "k1": k1, "k2": k2}
