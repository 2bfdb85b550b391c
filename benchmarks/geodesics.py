"""Benchmark: fans of geodesics and normal sections, vectorised against one ``solve_ivp`` per path.

The main case is the one of the issue: a fan of 80 geodesics of the paper's
length on the practical's surface.  ``seeds/003`` draws 80 paths with
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

Usage: python benchmarks/geodesics.py [--runs 3] [--quick]
"""

import argparse
import functools
import time

import numpy as np

from lab import surfaces
from lab.geodesics import geodesic_fan, normal_section_fan

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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3, help="runs per timing (best is reported)")
    parser.add_argument("--quick", action="store_true", help="only the issue's case")
    args = parser.parse_args(argv)

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


if __name__ == "__main__":
    main()
