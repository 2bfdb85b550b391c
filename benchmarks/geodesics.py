"""Benchmark: fans of geodesics and normal sections, vectorised against one ``solve_ivp`` per path.

The main case is the one of the issue: a fan of 80 geodesics of the paper's
length on the practical's surface.  Puig-Pey et al. draw 80 paths with
distances up to s_L = 4.5 (figure 1) and starts its geodesics at the relative
position (0.7, 0.3) of the domain (figure 2); on the practical's domain
[0, 7]² that is (u, v) = (4.9, 2.1).  The further rows are the paper's own
two (reconstructed) surfaces with its settings, and a torus, where paths wrap
around.

* vectorised: ``geodesic_fan`` / ``normal_section_fan`` (all paths in one
  Dormand–Prince 8(5,3) stepper with per-path step sizes, surface evaluated
  once per stage for all paths);
* per path: the same functions with ``vectorized=False``, i.e. one
  ``scipy.integrate.solve_ivp(method="DOP853")`` per path (restarted at each
  patch edge, as the paper prescribes).

Both use the default tolerances (rtol = 1e-10, atol = 1e-12).  ``max |dx|`` is
the largest distance between corresponding samples of the two results (the
vectorised stepper takes the same steps, so it is at rounding level).  Times
are the best of several runs; the machine may be shared, so read the ratios.

A second table is the explorer's fan (40 geodesics of length 4.5 and their
isodistance curves, library level: no rendering), the first call (which
builds the surface's patch polynomials) and the following ones.

A third table times ``lab.geodesic_between`` on pairs of points of the
practical's surface and the paper's NURBS, with what one would use instead
on a triangle mesh of the surface (about 5000 vertices, the mesh the first
guess of ``geodesic_between`` is found on): potpourri3d's edge-flip geodesic
(FlipOut) and pygeodesic's exact polyhedral distance (Mitchell-Mount-Papadimitriou),
both between the mesh vertices nearest to A and B; their lengths are compared
with ours (ours hits B to 1e-9; the mesh paths are off by the mesh).

Usage: python benchmarks/geodesics.py [--runs 3] [--repeats 7] [--quick] [--only fans explorer between]
"""

import argparse
import functools
import os
import statistics
import time
import warnings

import numpy as np
from lab.geodesics import geodesic_between, geodesic_fan, normal_section_fan, polar_isodistance

from lab import surfaces
from lab.interrogation.geodesics.polyhedral import polyhedral_mesh

TARGET_SPEEDUP = 5.0
TARGET_SECONDS = 1.0


def best_time(func, runs):
    """Best wall time of ``func`` over ``runs`` runs, and its last result."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        result = func()
        times.append(time.perf_counter() - start)
    return min(times), result


def compare(fast, slow):
    """Largest distance between corresponding samples, and whether the paths stopped alike."""
    same_ends = all(a.end == b.end for a, b in zip(fast, slow))
    worst = max(float(np.abs(a.points - b.points).max()) for a, b in zip(fast, slow))
    worst_length = max(abs(a.length - b.length) for a, b in zip(fast, slow))
    return max(worst, worst_length), same_ends


CASES = [
    # name, surface factory, start, fan function, n, length, is the target case
    ("practical, geodesics", surfaces.practical, (4.9, 2.1), geodesic_fan, 80, 4.5, True),
    ("practical, normal sections", surfaces.practical, (4.9, 2.1), normal_section_fan, 80, 4.5, False),
    ("paper fig. 1, normal sections", surfaces.isodistance_sections_example, (0.5, 0.5), normal_section_fan, 80, 4.5,
     False),
    ("paper fig. 2, geodesics", surfaces.isodistance_geodesics_example, (0.7, 0.3), geodesic_fan, 40, 20.0, False),
    ("torus (wraps), geodesics", surfaces.torus, (0.1, 0.2), geodesic_fan, 40, 10.0, False),
]


#: Pairs (A, B) of parameters for geodesic_between.  The practical's pairs were chosen (and the previous
#: implementation's lengths measured) with u along x; the surface now runs u along y as the course program
#: does, so the same points have their parameters swapped.
_PRACTICAL_XY = [((1.0, 1.0), (6.0, 2.0)), ((1.0, 5.5), (5.5, 1.5)), ((0.5, 0.5), (6.5, 6.5)),
                 ((2.0, 3.0), (5.0, 4.0)), ((3.5, 0.5), (3.5, 6.5)), ((0.3, 6.2), (6.1, 0.4)),
                 ((4.9, 2.1), (1.2, 3.3)), ((2.5, 2.5), (4.5, 4.5)), ((6.0, 6.0), (1.0, 3.0))]
PAIRS = {
    "practical": [(a[::-1], b[::-1]) for a, b in _PRACTICAL_XY],
    "paper fig. 2": [((0.7, 0.3), (0.2, 0.8)), ((0.1, 0.1), (0.9, 0.9)), ((0.5, 0.1), (0.5, 0.9)),
                     ((0.8, 0.6), (0.2, 0.3)), ((0.3, 0.5), (0.9, 0.2))],
}
FACTORIES = {"practical": surfaces.practical, "paper fig. 2": surfaces.isodistance_geodesics_example}
#: Lengths from the previous geodesic_between (fan guesses, Gauss-Newton, solve_ivp), before the polyhedral start.
PREVIOUS = {
    "practical": [6.478681175016995, 7.881070623665791, 11.928690845642647, 4.220369431352226, 8.989255866854778,
                  11.555092818675748, 4.566742527084935, 5.144198363741283, 6.66849070818442],
    "paper fig. 2": [21.012584129742088, 35.5268093700236, 24.525026950721163, 19.700056350798985,
                     20.661233089756664],
}


def load():
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.2f} {five:.2f} {fifteen:.2f} on {os.cpu_count()} cores"


def fans_table(args):
    header = (
        f"{'case':<31} {'paths':>5} {'length':>6} {'stopped':>7} {'vectorised':>10} {'per path':>9} "
        f"{'speed-up':>8} {'max |dx|':>9}"
    )
    print(header)
    print("-" * len(header))
    verdict = None
    for name, factory, uv, fan_function, n, length, target in CASES:
        if args.quick and not target:
            continue
        surface = factory()
        fan_function(surface, uv, 4, length)  # warm-up (imports, caches)
        fan = functools.partial(fan_function, surface, uv, n, length)
        t_fast, fast = best_time(fan, args.runs)
        t_slow, slow = best_time(functools.partial(fan, vectorized=False), max(1, args.runs - 1))
        diff, same_ends = compare(fast, slow)
        stopped = int(sum(p.end != "length" for p in fast))
        print(
            f"{name:<31} {n:>5} {length:>6g} {stopped:>7} {t_fast:>9.3f}s {t_slow:>8.2f}s "
            f"{t_slow / t_fast:>7.1f}x {diff:>9.1e}" + ("" if same_ends else "  (ends differ!)")
        )
        if target:
            verdict = (t_slow / t_fast, t_fast, diff)
    if verdict is not None:
        ratio, seconds, diff = verdict
        ok = ratio >= TARGET_SPEEDUP and seconds < TARGET_SECONDS
        print()
        print(
            f"issue target (80 geodesics on the practical's surface): >= {TARGET_SPEEDUP:g}x and < {TARGET_SECONDS:g} s "
            f"-> {ratio:.1f}x, {seconds:.3f} s: {'met' if ok else 'NOT met'}"
        )


def explorer_table(args):
    """The geodesic explorer's computation: 40 geodesics of length 4.5 and 9 isodistance curves."""
    print("\nexplorer fan: 40 geodesics of length 4.5 from (4.9, 2.1) on the practical's surface, 61 samples each, "
          "and their 9 isodistance curves (library level, no rendering)")
    surface = surfaces.practical()
    distances = 0.5 * np.arange(1, 10)

    def run(start):
        fan = geodesic_fan(surface, start, 40, 4.5, n_samples=61)
        polar_isodistance(fan, distances)

    t0, c0 = time.perf_counter(), time.process_time()
    run((4.9, 2.1))
    first = (time.perf_counter() - t0, time.process_time() - c0)
    walls, cpus = [], []
    for k in range(max(3, 2 * args.runs)):
        t0, c0 = time.perf_counter(), time.process_time()
        run((4.8, 2.2) if k % 2 else (4.9, 2.1))
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    print(f"  first call {first[0]:.3f} s (cpu {first[1]:.3f} s); then median {statistics.median(walls):.3f} s "
          f"(cpu {statistics.median(cpus):.3f} s), best {min(walls):.3f} s; target <= 0.250 s")


def between_table(args):
    try:
        import pygeodesic.geodesic as pygeodesic
    except ImportError:
        pygeodesic = None
    print("\ngeodesic_between: ours (polyhedral start + exact shooting) vs mesh geodesics between the nearest "
          "vertices (about 5000 vertices)")
    if pygeodesic is None:
        print("   (pygeodesic is not installed: its columns are skipped; pip install -e '.[bench]')")
    header = (f"{'surface':<13} {'A':>12} {'B':>12} | {'ours [s]':>8} {'cpu':>6} {'length':>14} {'vs previous':>11} | "
              f"{'flip [ms]':>9} {'rel err':>8} | {'exact [ms]':>10} {'rel err':>8}")
    print(header)
    print("-" * len(header))
    summary = {}
    for name, pairs in PAIRS.items():
        surface = FACTORIES[name]()
        t0 = time.perf_counter()
        mesh = polyhedral_mesh(surface)
        t_mesh = time.perf_counter() - t0
        exact = pygeodesic.PyGeodesicAlgorithmExact(mesh.vertices, mesh.faces) if pygeodesic else None
        geodesic_between(surface, *pairs[0])  # warm-up: the surface's patch polynomials (built once per surface)
        walls, cpus = [], []
        for (a, b), previous in zip(pairs, PREVIOUS[name]):
            wall_runs, cpu_runs = [], []
            for _ in range(args.repeats):
                t0, c0 = time.perf_counter(), time.process_time()
                path = geodesic_between(surface, a, b)
                cpu_runs.append(time.process_time() - c0)
                wall_runs.append(time.perf_counter() - t0)
            wall, cpu = statistics.median(wall_runs), statistics.median(cpu_runs)
            walls.append(wall)
            cpus.append(cpu)
            ia = mesh.nearest_vertex(surface.evaluate(*a))
            ib = mesh.nearest_vertex(surface.evaluate(*b))
            t0 = time.perf_counter()
            poly = mesh.path(ia, ib)
            t_flip = time.perf_counter() - t0
            flip = float(np.linalg.norm(np.diff(poly, axis=0), axis=1).sum())
            if exact is not None:
                t0 = time.perf_counter()
                dist, _ = exact.geodesicDistance(ia, ib)
                t_exact = time.perf_counter() - t0
                exact_txt = f"{1e3 * t_exact:10.2f} {(dist - path.length) / path.length:8.1e}"
            else:
                exact_txt = f"{'-':>10} {'-':>8}"
            print(f"{name:<13} {a!s:>12} {b!s:>12} | {wall:8.3f} {cpu:6.3f} {path.length:14.10f} "
                  f"{path.length - previous:11.1e} | {1e3 * t_flip:9.2f} {(flip - path.length) / path.length:8.1e} | "
                  f"{exact_txt}")
        summary[name] = (statistics.median(walls), statistics.median(cpus), t_mesh)
    for name, (median, cpu, t_mesh) in summary.items():
        print(f"  {name}: median {median:.3f} s per pair, cpu {cpu:.3f} s (target <= 0.2 s: "
              f"{'met' if cpu <= 0.2 else 'NOT met'}); mesh and solver built once in {t_mesh:.3f} s")
    print(f"  ours: median of {args.repeats} runs per pair (wall and CPU time of this process); the summary is the "
          "median over the pairs")
    print("  vs previous: our length minus that of the previous implementation (fan guesses, solve_ivp), which took "
          "1.5 to 21 s per pair on the practical's surface; rel err: (mesh length - ours) / ours, between the "
          "vertices nearest to A and B")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="runs per timing (best is reported)")
    parser.add_argument("--repeats", type=int, default=7, help="runs per pair of geodesic_between (median is reported)")
    parser.add_argument("--quick", action="store_true", help="only the issue's case of the fans")
    parser.add_argument("--only", choices=["fans", "explorer", "between"], nargs="+")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    print(load())
    tables = args.only or ["fans", "explorer", "between"]
    if "fans" in tables:
        fans_table(args)
    if "explorer" in tables:
        explorer_table(args)
    if "between" in tables:
        between_table(args)
    print("\n" + load())


if __name__ == "__main__":
    main()
