"""Benchmark: curvature at the corners of the practical's surface, refined to depths 0-6.

Compares, in one run on the same tessellation:

* ours: ``BezierPatches.visualize_curvature`` (vectorised over all patches);
* loop: a straightforward per-patch, per-corner Python loop written the way a
  student would (kept here as the baseline);
* pyvista: ``PolyData.curvature("gaussian")`` on the welded corner mesh,
  triangulated (VTK's angle-deficit estimate expects triangles): a discrete,
  mesh-based estimate, what one gets without derivatives.

Errors are measured against exact values: sympy/rational arithmetic on a
random sample of corners (``err exact``: max |K - K_exact| / max |K_exact|),
and for ours also at every corner against the B-spline evaluator (an
independent code path, ``err all``).  Times are the best of several runs
(at least three for ours and PyVista; the loop runs once at depth >= 4);
the machine is shared, so read the ratios, not the absolute numbers.

Usage: python benchmarks/curvature.py [--max-depth 6] [--loop-max-depth 6] [--samples 120]
"""

import argparse
import time
import warnings

import numpy as np

import lab
from lab import analytic, colormaps, surfaces


def student_visualize(patches):
    """Gaussian curvature + linear colour map, one patch and one corner at a time (the baseline)."""
    values = []
    for patch in patches:
        P = patch.control_points
        m, n = patch.degree
        bu = m * (P[1:, :] - P[:-1, :])
        bv = n * (P[:, 1:] - P[:, :-1])
        buu = m * (m - 1) * (P[2:, :] - 2 * P[1:-1, :] + P[:-2, :])
        buv = m * n * (P[1:, 1:] - P[1:, :-1] - P[:-1, 1:] + P[:-1, :-1])
        bvv = n * (n - 1) * (P[:, 2:] - 2 * P[:, 1:-1] + P[:, :-2])
        corner = []
        for a, b in ((0, 0), (0, 1), (1, 0), (1, 1)):
            xu, xv = bu[-a, -b], bv[-a, -b]
            xuu, xuv, xvv = buu[-a, -b], buv[-a, -b], bvv[-a, -b]
            N = np.cross(xu, xv)
            N = N / np.linalg.norm(N)
            E, F, G = xu @ xu, xu @ xv, xv @ xv
            e, f, g = N @ xuu, N @ xuv, N @ xvv
            corner.append((e * g - f * f) / (E * G - F * F))
        patch.set_curvature(*corner)
        values.extend(corner)
    lo, hi = min(values), max(values)
    for patch in patches:
        c = patch.curvature
        cols = [tuple(colormaps.h((c[a, b] - lo) / (hi - lo))) for a in (0, 1) for b in (0, 1)]
        patch.set_colors(*cols)


def best_time(func, min_time=0.3, max_runs=5, min_runs=1):
    """Best wall time of ``func``: at least ``min_runs`` runs, more (up to ``max_runs``) while the total is short."""
    times = []
    while len(times) < min_runs or (len(times) < max_runs and sum(times) < min_time):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)


def patch_parameters(n_spans, depth):
    """Global (u, v) of the corners of every refined patch, in the grid order BezierPatches keeps.

    Returns an array (N, 2, 2, 2): [patch, a, b] -> (u, v); the B-spline's
    knots are 0..7, so span (i, j) covers [i, i+1] x [j, j+1].
    """
    k = n_spans * 2**depth
    size = 1.0 / 2**depth
    I, J = np.meshgrid(np.arange(k), np.arange(k), indexing="ij")  # row-major: patch I * k + J
    lo = size * np.stack([I.ravel(), J.ravel()], axis=-1).astype(float)
    ab = np.array([[[0, 0], [0, 1]], [[1, 0], [1, 1]]], dtype=float)
    return lo[:, None, None, :] + size * ab[None]


def exact_sample(nets, params, index, corner):
    """Exact K at sampled corners, from the original Bézier nets of the B-spline (rational arithmetic)."""
    out = []
    for k, (a, b) in zip(index, corner):
        u, v = params[k, a, b]
        su, sv = min(int(u), 6), min(int(v), 6)
        exact = analytic.bezier_curvature_exact(nets[su, sv], u - su, v - sv)
        out.append(analytic.to_float(exact).K)
    return np.array(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-depth", type=int, default=6)
    parser.add_argument("--loop-max-depth", type=int, default=6, help="skip the slow loop above this depth")
    parser.add_argument("--samples", type=int, default=120, help="corners per depth checked against sympy")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    rng = np.random.default_rng(0)
    surface = surfaces.practical()
    nets, _, _, _ = surface.bezier_nets()
    header = (
        f"{'depth':>5} {'patches':>8} | {'ours [s]':>9} {'loop [s]':>9} {'pyvista [s]':>11} | "
        f"{'loop/ours':>9} {'pv/ours':>8} | {'err exact ours':>14} {'err all ours':>12} "
        f"{'err exact loop':>14} {'err exact pv':>12}"
    )
    print(header)
    print("-" * len(header))
    for depth in range(args.max_depth + 1):
        base = surface.to_bezier_patches().refine(depth)
        ours = base.copy()
        t_ours = best_time(lambda: ours.visualize_curvature(ours.CURVATURE_GAUSSIAN, ours.COLOR_MAP_LINEAR), min_runs=3)
        params = patch_parameters(7, depth)
        n = len(ours)
        index = rng.integers(0, n, size=args.samples)
        corner = rng.integers(0, 2, size=(args.samples, 2))
        K_exact = exact_sample(nets, params, index, corner)
        scale = np.max(np.abs(K_exact))
        err_ours = np.max(np.abs(ours.curvature[index, corner[:, 0], corner[:, 1]] - K_exact)) / scale
        K_all = surface.curvature(params[..., 0], params[..., 1]).K
        err_all = np.max(np.abs(ours.curvature - K_all)) / np.max(np.abs(K_all))

        if depth <= args.loop_max_depth:
            loop = base.copy()
            t_loop = best_time(lambda: student_visualize(loop), min_time=0.0, max_runs=1 if depth >= 4 else 3)
            err_loop = np.max(np.abs(loop.curvature[index, corner[:, 0], corner[:, 1]] - K_exact)) / scale
            loop_txt = f"{t_loop:9.3f}"
            ratio_txt = f"{t_loop / t_ours:9.0f}"
            err_loop_txt = f"{err_loop:14.1e}"
        else:
            loop_txt, ratio_txt, err_loop_txt = f"{'-':>9}", f"{'-':>9}", f"{'-':>14}"

        mesh = ours.to_mesh().triangulate()
        t_pv = best_time(lambda: mesh.curvature("gaussian"))
        K_pv = mesh.curvature("gaussian")
        # map the sampled corners to mesh vertices (the mesh is welded, so look the points up)
        pts = ours.evaluate(np.array([0.0, 1.0])[:, None], np.array([0.0, 1.0])[None, :])  # (N, 2, 2, 3)
        from scipy.spatial import cKDTree

        _, vertex = cKDTree(mesh.points).query(pts[index, corner[:, 0], corner[:, 1]])
        interior = np.all((params[index, corner[:, 0], corner[:, 1]] > 0) & (params[index, corner[:, 0], corner[:, 1]] < 7), axis=-1)
        err_pv = np.max(np.abs(K_pv[vertex][interior] - K_exact[interior])) / scale
        print(
            f"{depth:5d} {n:8d} | {t_ours:9.4f} {loop_txt} {t_pv:11.4f} | {ratio_txt} {t_pv / t_ours:8.2f} | "
            f"{err_ours:14.1e} {err_all:12.1e} {err_loop_txt} {err_pv:12.1e}"
        )
    print(
        "\nerr exact: max |K - K_exact| / max |K_exact| over sampled corners (pyvista: interior vertices only, "
        "its boundary estimate is worse); err all: every corner against the B-spline evaluator."
    )


if __name__ == "__main__":

    main()
