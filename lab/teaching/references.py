"""Test cases and exact references of the checks: rational control nets, sympy-exact corner curvature, the
practical's colours, and the computation with deliberate mistakes (to name a student's mistake in a hint)."""

import numpy as np

from ..geometry import analytic, colormaps

# -- exact references -------------------------------------------------------------


def _rand_net(rng, m, n, kind="random"):
    """A control net with rational coordinates; kinds: random, level (z = 0), flat (tilted plane), umbilic (paraboloid vertex at the (0,0) corner)."""
    if kind == "level":
        # the plane z = 0: curvature exactly 0 everywhere, so all values are equal
        P = analytic.random_rational_net(rng, m, n)
        P[..., 2] = 0.0
        return P
    if kind == "flat":
        # a tilted plane z = a x + b y with dyadic a, b: exactly planar in binary, but rounding
        # in N makes the computed K and H tiny non-zero noise (as on real flat regions)
        P = analytic.random_rational_net(rng, m, n)
        a, b = rng.integers(1, 8, 2) / 8
        P[..., 2] = a * P[..., 0] + b * P[..., 1]
        return P
    if kind == "umbilic":
        # z = c (x^2 + y^2) over [0, s]^2 (needs m, n >= 2), umbilic at the corner (0, 0), turned about
        # the z axis by a rational rotation (3/5, 4/5): the same paraboloid, but the coordinates round,
        # and the net is chosen so that the textbook formula computes H^2 - K < 0 at that corner.
        i, j = np.arange(m + 1), np.arange(n + 1)
        for _ in range(200):
            s = float(rng.integers(1, 4))
            c = int(rng.integers(1, 5)) / 4
            ca, sa = [(0.6, 0.8), (0.8, 0.6), (5 / 13, 12 / 13), (12 / 13, 5 / 13)][int(rng.integers(4))]
            # Bernstein coefficients: x = s u -> s i / m; x^2 -> s^2 i (i - 1) / (m (m - 1)); sums add up.
            X, Y = np.meshgrid(s * i / m, s * j / n, indexing="ij")
            Z = c * s * s * ((i * (i - 1) / (m * (m - 1)))[:, None] + (j * (j - 1) / (n * (n - 1)))[None, :])
            P = np.stack([ca * X - sa * Y, sa * X + ca * Y, Z], axis=-1)
            d = _variant_corner_derivatives(P)
            if _naive_discriminant(d)[0, 0] < 0:
                break
        return P
    return analytic.random_rational_net(rng, m, n)


def _exact_corners(nets):
    """Exact K, H, k1, k2 at the corners of every net: dict of arrays (N, 2, 2)."""
    out = {k: np.zeros((len(nets), 2, 2)) for k in ("K", "H", "k1", "k2")}
    for p, P in enumerate(nets):
        for (a, b), c in analytic.bezier_corner_curvature_exact(P).items():
            c = analytic.to_float(c)
            for k in out:
                out[k][p, a, b] = getattr(c, k)
    return out


MODE_FIELD = {"gaussian": "K", "mean": "H", "k1": "k1", "k2": "k2"}


def _expected_colors(values, cmap):
    """Colours the practical's maps give to exact ``values`` (f3 with exact zeros)."""
    if cmap == "linear":
        return colormaps.h(colormaps.f2(values, rtol=0))
    if cmap == "cut":
        return colormaps.h(colormaps.f1(values))
    return colormaps.h(colormaps.f3(values, tol=0))


# -- wrong variants for hints -----------------------------------------------------


def _variant_nets(P, variant=None):
    """Derivative nets (bu, bv, buu, buv, bvv) by forward differences, with a deliberate mistake (or none)."""
    m, n = P.shape[0] - 1, P.shape[1] - 1
    fu1, fu2, fv1, fv2, fuv = m, m * (m - 1), n, n * (n - 1), m * n
    if variant == "no_factors":
        fu1 = fu2 = fv1 = fv2 = fuv = 1
    elif variant == "second_factor":
        fu2, fv2 = m, n
    elif variant == "swapped_degrees":
        fu1, fu2, fv1, fv2, fuv = n, n * (n - 1), m, m * (m - 1), n * m
    return {
        "bu": fu1 * np.diff(P, axis=0),
        "bv": fv1 * np.diff(P, axis=1),
        "buu": fu2 * np.diff(P, 2, axis=0),
        "buv": fuv * np.diff(np.diff(P, axis=0), axis=1),
        "bvv": fv2 * np.diff(P, 2, axis=1),
    }


def _variant_corner_derivatives(P, variant=None):
    """Corner derivatives (bu, bv, buu, buv, bvv), each (2, 2, 3), computed with a deliberate mistake."""
    return {k: D[[0, -1]][:, [0, -1]] for k, D in _variant_nets(P, variant).items()}


def _naive_discriminant(d):
    """H^2 - K at the corners computed with the textbook formulas, unclamped (may round below 0)."""
    c = _variant_curvature(d)
    return c["H"] * c["H"] - c["K"]


def _variant_curvature(d, variant=None):
    """K, H, k1, k2 from corner derivatives, with a deliberate mistake."""
    bu, bv = d["bu"], d["bv"]
    Q = np.cross(bu, bv)
    W = np.linalg.norm(Q, axis=-1)
    N = Q / (W[..., None] if variant != "unnormalised" else 1.0)
    if variant == "orientation":
        N = -N
    dot = lambda a, b: np.sum(a * b, axis=-1)  # noqa: E731
    E, F, G = dot(bu, bu), dot(bu, bv), dot(bv, bv)
    e, f, g = dot(N, d["buu"]), dot(N, d["buv"]), dot(N, d["bvv"])
    K = (e * g - f * f) / (E * G - F * F)
    H = (e * G - 2 * f * F + g * E) / (E * G - F * F)
    if variant != "no_half":
        H = 0.5 * H
    root = np.sqrt(np.maximum(H * H - K, 0))
    k1, k2 = H + root, H - root
    if variant == "principal_swapped":
        k1, k2 = k2, k1
    return {"K": K, "H": H, "k1": k1, "k2": k2}
