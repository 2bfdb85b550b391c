"""Benchmark: exact curvature against the tools people would pick instead.

Three tables, each measured in one run on this machine (the machine may be
shared: read the ratios, and the load average printed first):

1. **Curvature at points.**  ``surface.curvature(u, v)`` at random points and
   ``surface.curvature_grid(u, v)`` on a grid of the same size, on the
   practical's surface, a random NURBS and the torus, against OpenCASCADE's
   ``GeomLProp_SLProps`` called point by point from Python (cadquery-ocp, the
   ``bench`` extra; its column is skipped with a note when it is missing).  The
   OCCT loop runs on the first ``--occt-points`` of the same points and is
   reported per point.  ``temp`` is the peak of the memory traced during our
   call (tracemalloc, in a separate untimed run) minus the result, per point.
   ``|ours - OCCT|`` is the largest difference of K, H, k1, k2 relative to
   the largest value.
2. **Meshes with curvature.**  ``lab.mesh.surface_mesh`` (exact K, H, k1, k2 at
   every vertex of an n x n grid, welded by index) against the discrete
   estimates of VTK (``PolyData.curvature``, angle deficit) and libigl
   (``gaussian_curvature`` / Voronoi area, and ``principal_curvature``, a
   quadric fit) on the same triangulated mesh: time, and the largest error of
   K over **all** vertices and over interior vertices, relative to max |K|.
3. **The practical's task.**  ``refine`` and ``visualize_curvature`` of the
   practical's surface at depths 0 … 7: CPU time and peak memory per patch
   (linear means constant per patch), against a per-patch, per-corner
   Python loop (the student's way) and with the error against sympy-exact
   values at sampled corners and against the B-spline evaluator at all corners.
   The times are CPU times, the least of ``--rounds`` samples per depth, taken
   in rounds over all depths, each sample at least 0.2 s; the kernel's part
   (first touch of new memory) is shown apart, and refine also "cold", with
   memory that was freed long before (on a virtual machine that returns freed
   memory to its host, touching it again is slow).

4. **Principal directions.**  ``curvature(u, v, directions=True)`` at 10^5
   random points against OpenCASCADE's ``CurvatureDirections`` called point by
   point, with the largest angle between the two.
5. **Continuity.**  ``lab.continuity`` of the practical's B-spline and of its
   Bézier patches refined 0 … 4 times (12 544 patches, 24 864 borders).
6. **Third derivatives on real parts.**  The faces' third derivatives at every
   sample of every shared edge (what G3 of ``lab.continuity`` compares), one
   call per face, against OpenCASCADE's ``Geom_Surface::D3`` called point by
   point on the file's own surfaces, with the largest difference; and what G3
   adds to the whole report of each part.

Usage: python benchmarks/curvature.py [--points 100000 1000000] [--occt-points 100000] [--max-depth 7]
       [--loop-max-depth 4] [--resolutions 57 113 225 449] [--rounds 9] [--quick]
"""

import argparse
import gc
import os
import resource
import statistics
import sys
import time
import warnings

import numpy as np

import lab
from lab import analytic, colormaps, surfaces
from lab.mesh import surface_mesh

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from tests.measure import traced_peak  # the tests measure memory the same way
from tests.occ_support import occt_surface  # the tests build the OpenCASCADE surfaces the same way


def load():
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.2f} {five:.2f} {fifteen:.2f} on {os.cpu_count()} cores"


def best_time(func, min_time=0.3, max_runs=5, min_runs=1):
    """Best wall time of ``func``: at least ``min_runs`` runs, more (up to ``max_runs``) while the total is short."""
    times = []
    while len(times) < min_runs or (len(times) < max_runs and sum(times) < min_time):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return min(times)


def cpu_sample(func, reps):
    """CPU time (user + system) of ``reps`` calls of ``func``, and the system part, per call; no GC meanwhile.

    ``func(i)`` gets the index of the call.  The system part is the kernel's, mostly the first touch of
    freshly mapped memory (page faults, zeroing the pages).
    """
    gc.collect()
    gc.disable()
    try:
        r0 = resource.getrusage(resource.RUSAGE_SELF)
        c0 = time.process_time()
        for i in range(reps):
            func(i)
        cpu = time.process_time() - c0
        r1 = resource.getrusage(resource.RUSAGE_SELF)
    finally:
        gc.enable()
    return cpu / reps, (r1.ru_stime - r0.ru_stime) / reps


# ----------------------------------------------------------------------------- OpenCASCADE


def occt_curvature(geom, u, v):
    """K, H, k_max, k_min at each point with ``GeomLProp_SLProps``, one call per point (what a user writes)."""
    from OCP.GeomLProp import GeomLProp_SLProps

    props = GeomLProp_SLProps(geom, 2, 1e-9)
    out = np.empty((len(u), 4))
    for k in range(len(u)):
        props.SetParameters(float(u[k]), float(v[k]))
        props.IsCurvatureDefined()  # computes the curvatures; without it GaussianCurvature() returns a stale value
        out[k] = (props.GaussianCurvature(), props.MeanCurvature(), props.MaxCurvature(), props.MinCurvature())
    return out


def random_nurbs(rng):
    """A bicubic NURBS on 8 x 9 control points with random interior knots and weights in [0.5, 2]."""
    nu, nv = 8, 9
    P = rng.normal(size=(nu, nv, 3))
    P[..., 0] += 2 * np.arange(nu)[:, None]
    P[..., 1] += 2 * np.arange(nv)[None, :]
    ku = np.r_[[0.0] * 4, np.sort(rng.uniform(0, 1, nu - 4)), [1.0] * 4]
    kv = np.r_[[0.0] * 4, np.sort(rng.uniform(0, 1, nv - 4)), [1.0] * 4]
    return lab.BSplineSurface(P, ku, kv, 3, 3, weights=rng.uniform(0.5, 2.0, (nu, nv)))


def points_table(args, rng):
    try:
        import OCP  # noqa: F401

        have_occt = True
    except ImportError:
        have_occt = False
    print("\n1. Exact curvature at points: ours (random points, and a grid of the same size) vs OpenCASCADE's "
          "GeomLProp_SLProps per point")
    if not have_occt:
        print("   (cadquery-ocp is not installed: the OCCT columns are skipped; pip install -e '.[bench]')")
    header = (f"{'surface':<10} {'points':>8} | {'random':>8} {'grid':>8} {'OCCT':>8} [us/pt] | {'OCCT/rand':>9} "
              f"{'OCCT/grid':>9} | {'temp rand':>9} {'temp grid':>9} [B/pt] | {'|ours-OCCT|':>11} {'rand-grid':>9}")
    print(header)
    print("-" * len(header))
    cases = [("practical", surfaces.practical()), ("NURBS", random_nurbs(rng)), ("torus", surfaces.torus())]
    for name, s in cases:
        geom = occt_surface(s) if have_occt else None
        (u0, u1), (v0, v1) = s.domain
        for n in args.points:
            u, v = rng.uniform(u0, u1, n), rng.uniform(v0, v1, n)
            side = round(np.sqrt(n))
            gu, gv = np.linspace(u0, u1, side), np.linspace(v0, v1, side)
            s.curvature(u[:100], v[:100])  # warm-up
            t_rand = best_time(lambda: s.curvature(u, v), min_runs=3) / n
            t_grid = best_time(lambda: s.curvature_grid(gu, gv), min_runs=3) / side**2
            peak, c = traced_peak(lambda: s.curvature(u, v))
            temp_rand = (peak - 33 * n) / n  # the result: K, H, k1, k2 (8 bytes each) and degenerate (1)
            peak, cg = traced_peak(lambda: s.curvature_grid(gu, gv))
            temp_grid = (peak - 33 * side**2) / side**2
            U, V = np.meshgrid(gu, gv, indexing="ij")
            cp = s.curvature(U.ravel(), V.ravel())  # the random-point path on the grid's points
            scale = max(np.max(np.abs(x)) for x in cg[:4])
            rand_grid = max(np.max(np.abs(a.ravel() - b)) for a, b in zip(cg[:4], cp[:4])) / scale
            if have_occt:
                m = min(n, args.occt_points)
                t_occt = best_time(lambda: occt_curvature(geom, u[:m], v[:m]), max_runs=2) / m
                ref = occt_curvature(geom, u[:m], v[:m])
                diff = max(np.max(np.abs(getattr(c, f)[:m] - ref[:, i])) for i, f in enumerate(("K", "H", "k1", "k2")))
                diff /= max(np.max(np.abs(getattr(c, f))) for f in ("K", "H", "k1", "k2"))
                occt_txt = f"{1e6 * t_occt:8.3f}"
                ratio_txt = f"{t_occt / t_rand:8.1f}x {t_occt / t_grid:8.1f}x"
                diff_txt = f"{diff:11.1e}"
            else:
                occt_txt, ratio_txt, diff_txt = f"{'-':>8}", f"{'-':>9} {'-':>9}", f"{'-':>11}"
            print(f"{name:<10} {n:>8} | {1e6 * t_rand:8.3f} {1e6 * t_grid:8.3f} {occt_txt}         | {ratio_txt} | "
                  f"{temp_rand:9.0f} {temp_grid:9.0f}        | {diff_txt} {rand_grid:9.1e}")
    print("   targets: OCCT/ours >= 5x at random points, >= 15x on grids, <= 150 B temporary memory per point; "
          f"OCCT timed on the first {args.occt_points} points")


# ----------------------------------------------------------------------------- discrete estimates on meshes


def mesh_table(args):
    try:
        import igl
    except ImportError:
        igl = None
    print("\n2. Meshes of the practical's surface: exact curvature at every vertex (ours) vs discrete estimates "
          "on the same triangles")
    if igl is None:
        print("   (libigl is not installed: its columns are skipped; pip install -e '.[bench]')")
    header = (f"{'grid':>5} {'vertices':>8} | {'ours [s]':>8} {'VTK [s]':>8} {'igl [s]':>8} | "
              f"{'K error, all vertices':^32} | {'K error, interior':^32}")
    sub = f"{'':>5} {'':>8} | {'':>8} {'':>8} {'':>8} | {'VTK':>10} {'igl defect':>10} {'igl quadric':>10} | " \
          f"{'VTK':>10} {'igl defect':>10} {'igl quadric':>10}"
    print(header)
    print(sub)
    print("-" * len(header))
    s = surfaces.practical()
    for n in args.resolutions:
        t_ours = best_time(lambda: surface_mesh(s, n, n), min_runs=2, max_runs=3)
        mesh = surface_mesh(s, n, n)
        tri = mesh.triangulate()
        V = np.asarray(tri.points, dtype=float)
        F = np.asarray(tri.faces).reshape(-1, 4)[:, 1:]
        K = np.asarray(tri.point_data["K"])
        uv = np.asarray(tri.point_data["uv"])
        interior = np.all((uv > 0) & (uv < 7), axis=1)
        scale = np.max(np.abs(K))
        t_vtk = best_time(lambda: tri.curvature("gaussian"), min_runs=2, max_runs=3)
        errors = {"VTK": np.abs(np.asarray(tri.curvature("gaussian")) - K) / scale}
        if igl is not None:
            def defect():
                area = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI).diagonal()
                return igl.gaussian_curvature(V, F) / area

            t_igl = best_time(defect, min_runs=2, max_runs=3)
            errors["igl defect"] = np.abs(defect() - K) / scale
            _, _, k_max, k_min = igl.principal_curvature(V, F)[:4]
            errors["igl quadric"] = np.abs(k_max * k_min - K) / scale
        cols_all = " ".join(f"{errors[k].max():10.2e}" if k in errors else f"{'-':>10}"
                            for k in ("VTK", "igl defect", "igl quadric"))
        cols_in = " ".join(f"{errors[k][interior].max():10.2e}" if k in errors else f"{'-':>10}"
                           for k in ("VTK", "igl defect", "igl quadric"))
        igl_txt = f"{t_igl:8.3f}" if igl is not None else f"{'-':>8}"
        print(f"{n:>5} {mesh.n_points:>8} | {t_ours:8.3f} {t_vtk:8.3f} {igl_txt} | {cols_all} | {cols_in}")
    print("   errors: max |K_estimate - K_exact| / max |K_exact|; ours is exact (sympy-checked in the tests). "
          "VTK's and libigl's times are for the estimate alone, on a mesh they are given; ours includes building "
          "the mesh.  Target: 449 x 449 (201k vertices) with exact curvature in <= 1 s.")


# ----------------------------------------------------------------------------- the practical's task


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


def patch_parameters(n_spans, depth):
    """Global (u, v) of the corners of every refined patch, in the grid order BezierPatches keeps: (N, 2, 2, 2)."""
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


def practical_table(args, rng):
    print("\n3. The practical's task on its surface: refine and visualize_curvature (Gaussian, linear map), "
          "per patch")
    surface = surfaces.practical()
    depths = list(range(args.max_depth + 1))
    times = interleaved_times(surface, depths, args.rounds)
    window = [d for d in depths if 3 <= d <= 7]
    reference = {}
    for work in ("refine", "visualize"):
        if window:
            reference[work] = statistics.median(min(c for c, _ in times[work, d]) / (49 * 4**d) for d in window)
            reference[work, "user"] = statistics.median(min(c - k for c, k in times[work, d]) / (49 * 4**d)
                                                        for d in window)
    header = (f"{'depth':>5} {'patches':>8} | {'refine':>7} {'(sys)':>6} {'user':>6} {'cold':>6} {'(sys)':>6} "
              f"{'visualize':>9} {'(sys)':>6} {'user':>6} [us/patch] | {'refine':>7} {'visualize':>9} [B/patch] | "
              f"{'loop [s]':>8} {'loop/ours':>9} | {'err exact':>9} {'err all':>8}")
    print(header)
    print("-" * len(header))
    nets, _, _, _ = surface.bezier_nets()
    for depth in depths:
        n = 49 * 4**depth
        cols, flags = [], []
        for work in ("refine", "cold", "visualize"):
            cpu, sys_ = min(times[work, depth])  # the sample with the least CPU time
            user = min(c - k for c, k in times[work, depth])
            cols.append(f"{1e6 * cpu / n:{9 if work == 'visualize' else 7}.3f} {1e6 * sys_ / n:6.3f} "
                        f"{1e6 * user / n:6.3f}")
            if work == "cold":
                cols[-1] = f"{1e6 * cpu / n:6.3f} {1e6 * sys_ / n:6.3f}"
            elif depth in window:
                flags += [cpu / n / reference[work] - 1, user / n / reference[work, "user"] - 1]
        base = surface.to_bezier_patches()
        peak_refine, refined = traced_peak(lambda: base.refine(depth))
        held = refined.control_points.nbytes + refined.curvature.nbytes + refined.colors.nbytes
        peak_vis, _ = traced_peak(lambda: refined.visualize_curvature("gaussian", "linear"))
        mem_refine = peak_refine / n  # everything refine allocates, the result included
        mem_vis = (held + peak_vis) / n  # the collection it works on plus what it allocates
        ours = refined
        params = patch_parameters(7, depth)
        index = rng.integers(0, n, size=args.samples)
        corner = rng.integers(0, 2, size=(args.samples, 2))
        K_exact = exact_sample(nets, params, index, corner)
        err_exact = np.max(np.abs(ours.curvature[index, corner[:, 0], corner[:, 1]] - K_exact)) / np.max(np.abs(K_exact))
        K_all = surface.curvature(params[..., 0], params[..., 1]).K
        err_all = np.max(np.abs(ours.curvature - K_all)) / np.max(np.abs(K_all))
        refined = ours = None  # freed before the next depth
        if depth <= args.loop_max_depth:
            loop = surface.to_bezier_patches().refine(depth)
            t_loop = best_time(lambda: student_visualize(loop), min_time=0.0, max_runs=1 if depth >= 4 else 3)
            t_vis = min(c for c, _ in times["visualize", depth])
            loop_txt = f"{t_loop:8.3f} {t_loop / t_vis:8.0f}x"
        else:
            loop_txt = f"{'-':>8} {'-':>9}"
        verdict = ""
        if depth in window:
            cpu_ok = max(abs(flags[0]), abs(flags[2])) <= 0.3
            user_ok = max(abs(flags[1]), abs(flags[3])) <= 0.3
            verdict = ("  " + " ".join(f"{100 * x:+.0f}%" for x in flags)
                       + f"  cpu {'ok' if cpu_ok else 'OUT'}, user {'ok' if user_ok else 'OUT'}")
        print(f"{depth:5d} {n:8d} | {cols[0]} {cols[1]} {cols[2]}            | {mem_refine:7.0f} {mem_vis:9.0f}"
              "           | "
              f"{loop_txt} | {err_exact:9.1e} {err_all:8.1e}{verdict}")
    if window:
        print("   median over depths 3-7 [us/patch]: " + ", ".join(
            f"{w} {1e6 * reference[w]:.3f} (user {1e6 * reference[w, 'user']:.3f})" for w in ("refine", "visualize"))
            + "; the last columns: each depth's refine CPU, refine user, visualize CPU, visualize user time per "
            "patch relative to that median, and whether the CPU times and the user times are within 30% of it")
    print(f"   time: CPU time (user + sys) per patch, the least of {args.rounds} samples taken in rounds over all "
          "depths (so that a busy moment of the machine hits every depth alike), each sample at least 0.2 s of "
          "repeated calls, GC off; (sys): its kernel part, mostly the first touch of new memory; user: without it. "
          "refine: the memory its result will get touched and freed just before (as after any recent work of that "
          "size); cold: not, the result's memory was freed a round before.  A result above glibc's 32 MiB mmap "
          "threshold (depth >= 6) is new memory every time, a smaller one reuses freed memory.  On a virtual machine "
          "that hands freed memory back to its host (virtio-balloon free page reporting), the first touch of "
          "memory freed seconds before costs about 2 ns per byte (the host backs the pages again), of memory freed "
          "just before about 0.1 ns: the difference of cold and refine.")
    print("   memory: refine's peak (its result included) and visualize_curvature's peak plus the collection it "
          "colours, per patch; targets: time per patch constant within 30% from depth 3 to 7, <= 1.2 KiB per patch. "
          "err exact: sympy at sampled corners; err all: every corner against the B-spline evaluator.")


def interleaved_times(surface, depths, rounds):
    """``{(work, depth): [(cpu, sys), ...]}`` per call of refine and visualize_curvature, in rounds over the depths.

    ``refine``: its memory touched and freed just before (so the pages it gets are ready); ``cold``: not (a
    previous sample of the same depth freed it a round before); see :func:`practical_table`.
    """
    base = surface.to_bezier_patches()
    collections = {d: surface.to_bezier_patches().refine(d) for d in depths}
    times = {(w, d): [] for w in ("refine", "cold", "visualize") for d in depths}
    for _ in range(rounds):
        for d in depths:
            p = collections[d]
            reps = max(1, int(0.2 / (0.6e-6 * len(p))))  # about 0.2 s of work per sample

            def refine(i, starts, d=d):
                starts[i] = starts[i].refine(d)
                starts[i] = None  # the result freed before the next call, as in a session that refines again

            starts = [base.copy() for _ in range(reps)]
            times["cold", d].append(cpu_sample(lambda i, starts=starts: refine(i, starts), reps))
            starts = [base.copy() for _ in range(reps)]
            np.full(72 * len(p), 0.0)  # touched and freed: the memory of the result (512 B per patch) and more
            times["refine", d].append(cpu_sample(lambda i, starts=starts: refine(i, starts), reps))
            times["visualize", d].append(
                cpu_sample(lambda i, p=p: p.visualize_curvature(p.CURVATURE_GAUSSIAN, p.COLOR_MAP_LINEAR), reps))
    return times


# ----------------------------------------------------------------------------- directions and continuity


def occt_directions(geom, u, v):
    """Unit directions of k_max and k_min at each point with ``GeomLProp_SLProps.CurvatureDirections``, per point."""
    from OCP.GeomLProp import GeomLProp_SLProps
    from OCP.gp import gp_Dir

    props = GeomLProp_SLProps(geom, 2, 1e-9)
    out = np.full((len(u), 2, 3), np.nan)
    dmax, dmin = gp_Dir(), gp_Dir()
    for k in range(len(u)):
        props.SetParameters(float(u[k]), float(v[k]))
        if props.IsCurvatureDefined() and not props.IsUmbilic():
            props.CurvatureDirections(dmax, dmin)
            out[k, 0] = dmax.X(), dmax.Y(), dmax.Z()
            out[k, 1] = dmin.X(), dmin.Y(), dmin.Z()
    return out


def directions_table(args, rng):
    try:
        import OCP  # noqa: F401

        have_occt = True
    except ImportError:
        have_occt = False
    print("\n4. Principal directions at random points: curvature(u, v, directions=True) vs OpenCASCADE's "
          "CurvatureDirections per point")
    if not have_occt:
        print("   (cadquery-ocp-novtk is not installed: the OCCT columns are skipped; pip install -e '.[bench]')")
    header = (f"{'surface':<10} {'points':>8} | {'ours':>8} {'no dirs':>8} {'OCCT':>8} [us/pt] | {'OCCT/ours':>9} | "
              f"{'max angle to OCCT [rad]':>23}")
    print(header)
    print("-" * len(header))
    n = args.direction_points
    for name, s in [("practical", surfaces.practical()), ("NURBS", random_nurbs(rng)),
                    ("ellipsoid", surfaces.ellipsoid(3, 2, 1))]:
        (u0, u1), (v0, v1) = s.domain
        u, v = rng.uniform(u0, u1, n), rng.uniform(v0 + 1e-3, v1 - 1e-3, n)
        s.curvature(u[:100], v[:100], directions=True)  # warm-up
        t_ours = best_time(lambda: s.curvature(u, v, directions=True), min_runs=3) / n
        t_plain = best_time(lambda: s.curvature(u, v), min_runs=3) / n
        c = s.curvature(u, v, directions=True)
        if have_occt:
            geom = occt_surface(s)
            t_occt = best_time(lambda: occt_directions(geom, u, v), max_runs=2) / n
            ref = occt_directions(geom, u, v)
            cos1 = np.abs(np.einsum("ij,ij->i", ref[:, 0], c.d1))
            cos2 = np.abs(np.einsum("ij,ij->i", ref[:, 1], c.d2))
            ok = np.isfinite(cos1) & np.isfinite(cos2)
            sin = np.sqrt(np.maximum(0.0, 1 - np.minimum(cos1[ok], cos2[ok]) ** 2))
            occt_txt = f"{1e6 * t_occt:8.3f}"
            ratio_txt = f"{t_occt / t_ours:8.1f}x"
            diff_txt = f"{np.max(sin):23.1e}"
        else:
            occt_txt, ratio_txt, diff_txt = f"{'-':>8}", f"{'-':>9}", f"{'-':>23}"
        print(f"{name:<10} {n:>8} | {1e6 * t_ours:8.3f} {1e6 * t_plain:8.3f} {occt_txt}         | {ratio_txt} | "
              f"{diff_txt}")
    print("   target: OCCT/ours >= 5x.  'no dirs' is curvature(u, v) without directions.  The angle is the largest "
          "over the points where OCCT defines directions (sin of it, from |cos|: the sign of a direction is free)")


def continuity_table(args):
    print("\n5. The continuity report (lab.continuity) of the practical's surface and its refinements")
    header = f"{'object':<30} {'edges':>7} {'samples':>8} {'time [s]':>9} {'us/sample':>10} | {'achieved':>8} " \
             f"{'max g1 [deg]':>12} {'max g2':>9}"
    print(header)
    print("-" * len(header))
    s = surfaces.practical()
    cases = [("B-spline (knot lines)", lambda: s)]
    for depth in range(args.continuity_depth + 1):
        cases.append((f"patches refined {depth}x", lambda depth=depth: s.to_bezier_patches().refine(depth)))
    for name, build in cases:
        obj = build()
        t = best_time(lambda: lab.continuity(obj), max_runs=3)
        rep = lab.continuity(obj)
        n_samples = sum(len(e.gap) for e in rep.edges)
        print(f"{name:<30} {len(rep.edges):>7} {n_samples:>8} {t:9.3f} {1e6 * t / n_samples:10.2f} | "
              f"{rep.achieved:>8} {max(e.g1 for e in rep.edges):12.1e} {max(e.g2 for e in rep.edges):9.1e}")
    print("   every sample: both sides' exact one-sided derivatives, gap, normal angle and the cross-boundary normal "
          "curvature jump; the refined surface is the same C2 surface, so every border is G2 (to rounding)")



def third_table(args):
    print("\n6. Third derivatives at a model's edge samples (G3 across its face edges) against OCCT's D3 point by point")
    from OCP.BRep import BRep_Tool
    from OCP.gp import gp_Pnt, gp_Vec

    from lab.interrogation.cad.models import impeller_path
    from lab.model import reparametrized, surface
    from tests.occ_support import occ_faces

    header = (f"{'part':<14} {'samples':>8} | {'ours [ms]':>9} {'OCCT [ms]':>9} {'OCCT/ours':>9} | {'max diff':>8} | "
              f"{'report [s]':>10} {'without G3':>10} {'G3 edges':>8}")
    print(header)
    print("-" * len(header))
    data = os.environ.get("LAB_OCC_DATA", "/usr/share/opencascade/data")
    for name, path in (("shell1.brep", os.path.join(data, "occ", "shell1.brep")),
                       ("linkrods.step", os.path.join(data, "step", "linkrods.step")),
                       ("impeller.igs", impeller_path())):
        model = lab.read(path)
        edges = [e for e in model.edges if len(e.faces) == 2]
        wanted = {}
        for e in edges:
            for index, uv in zip(e.faces, e.uv):
                wanted.setdefault(index, []).append(np.asarray(uv, dtype=float))
        wanted = {i: np.concatenate(x) for i, x in wanted.items()}
        n = sum(len(x) for x in wanted.values())
        ours = {}

        def lab_side():
            for i, uv in wanted.items():
                ours[i] = np.stack(model.face(i).file_surface.third_derivatives(uv[:, 0], uv[:, 1]), axis=1)

        geoms = [BRep_Tool.Surface_s(f) for f in occ_faces(path)]
        theirs = {}

        def occt_side():
            point, vectors = gp_Pnt(), [gp_Vec() for _ in range(9)]
            for i, uv in wanted.items():
                rows = []
                for u, v in uv:
                    geoms[i].D3(float(u), float(v), point, *vectors)
                    rows.append([[x.X(), x.Y(), x.Z()] for x in (vectors[5], vectors[7], vectors[8], vectors[6])])
                theirs[i] = np.array(rows)

        t_ours, t_occt = best_time(lab_side, max_runs=3), best_time(occt_side, max_runs=3)
        diff = max(float(np.max(np.abs(ours[i] - theirs[i]).max(axis=(1, 2)) / np.abs(theirs[i]).max(axis=(1, 2))))
                   for i in wanted)
        t_report = best_time(lambda: lab.continuity(model), max_runs=2)
        g3 = lab.continuity(model).counts().get("G3", 0)
        kept = surface._SplineSurface.third_derivatives, reparametrized.ReparametrizedSurface.third_derivatives

        def none(self, u, v):
            raise NotImplementedError

        surface._SplineSurface.third_derivatives = reparametrized.ReparametrizedSurface.third_derivatives = none
        try:
            t_without = best_time(lambda: lab.continuity(model), max_runs=2)
        finally:
            surface._SplineSurface.third_derivatives, reparametrized.ReparametrizedSurface.third_derivatives = kept
        print(f"{name:<14} {n:>8} | {1e3 * t_ours:9.1f} {1e3 * t_occt:9.1f} {t_occt / t_ours:8.1f}x | {diff:8.1e} | "
              f"{t_report:10.2f} {t_without:10.2f} {g3:>8}")
    print("   max diff: relative to each sample's largest component; ours: one call per face (NURBS: basis "
          "functions' third derivatives and the quotient rule; analytic faces: the chain rule with the parameter maps)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, nargs="+", default=[100_000, 1_000_000])
    parser.add_argument("--occt-points", type=int, default=100_000, help="points of the OCCT loop (per point times)")
    parser.add_argument("--resolutions", type=int, nargs="+", default=[57, 113, 225, 449])
    parser.add_argument("--max-depth", type=int, default=7)
    parser.add_argument("--loop-max-depth", type=int, default=4, help="skip the slow per-corner loop above this depth")
    parser.add_argument("--samples", type=int, default=60, help="corners per depth checked against sympy")
    parser.add_argument("--rounds", type=int, default=9, help="timing samples per depth (rounds over all depths)")
    parser.add_argument("--quick", action="store_true", help="1e5 points, grids up to 225, depths up to 5")
    parser.add_argument("--direction-points", type=int, default=100_000, help="points of the directions table")
    parser.add_argument("--continuity-depth", type=int, default=4, help="refine the practical's patches up to this")
    parser.add_argument("--only", choices=["points", "meshes", "practical", "directions", "continuity", "third"],
                        nargs="+")
    args = parser.parse_args()
    if args.quick:
        args.points, args.resolutions, args.max_depth = [100_000], [57, 113, 225], 5
    warnings.simplefilter("ignore")
    rng = np.random.default_rng(0)
    print(load())
    tables = args.only or ["points", "meshes", "practical", "directions", "continuity", "third"]
    if "points" in tables:
        points_table(args, rng)
    if "meshes" in tables:
        mesh_table(args)
    if "practical" in tables:
        practical_table(args, rng)
    if "directions" in tables:
        directions_table(args, rng)
    if "continuity" in tables:
        continuity_table(args)
    if "third" in tables:
        third_table(args)
    print("\n" + load())


if __name__ == "__main__":
    main()
