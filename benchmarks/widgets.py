"""Benchmark: server-side latency of the explorers, from a control change to the finished (rendered) update.

Each row changes one control of an explorer the way a callback does (the
widget's value is set; the observer runs on this, the main, thread) and
times the whole action: computation, update of the existing scene, and an
offscreen render of the 640 x 480 view (llvmpipe here, no GPU).  The live
view's push to the browser (trame) is not included.  The baseline column
does the same job the naive way, in the same run:

* recolour: rebuild the scene (clear the plotter, add the mesh again) instead
  of changing point data, lookup table and range of the existing actor;
* depth change: the same in-place update, but recomputed from scratch every
  time (our explorer caches meshes per depth; the first visit is measured);
* geodesic fan: one ``solve_ivp`` call per path instead of the vectorised fan.

Usage: python benchmarks/widgets.py [--repeat 5]
"""

import argparse
import statistics
import time
import warnings

from lab.widgets import CurvatureExplorer, GeodesicExplorer

from lab import surfaces

TARGETS = {"recolour at depth 5": 0.050, "depth change to 5": 0.300, "fan of 40 geodesics": 1.0}


def _render(explorer):
    """The offscreen render a server-rendered view would do after the change (the browser push is not included)."""
    explorer.plotter.render()


def timed(action, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return times


def measure(repeat):
    """The rows of the table: (action, our times, baseline times, what the baseline is)."""
    warnings.simplefilter("ignore")
    rows = []
    args = argparse.Namespace(repeat=repeat)

    # recolour at depth 5: alternate two colour maps
    e = CurvatureExplorer(surfaces.practical(), live=False, depth=5)
    e.screenshot()  # the first render sets up the GL pipeline
    maps = iter(["signed-log", "linear"] * (args.repeat + 1))

    def recolour():
        e.color_map.value = next(maps)
        _render(e)
        assert "error" not in e.status.value, e.status.value

    ours = timed(recolour, args.repeat)

    def rebuild():
        e.plotter.clear_actors()
        e.plotter.add_mesh(e.mesh.copy(), scalars="display", cmap="viridis", smooth_shading=True)
        e.plotter.render()

    base = timed(rebuild, args.repeat)
    rows.append(("recolour at depth 5", ours, base, "rebuild the scene"))

    # depth change 3 -> 5, uncached each time (a fresh explorer per run), against the cached revisit
    def fresh_depth():
        x = CurvatureExplorer(surfaces.practical(), live=False, depth=3)
        x.screenshot()
        start = time.perf_counter()
        x.depth.value = 5
        _render(x)
        elapsed = time.perf_counter() - start
        assert "error" not in x.status.value, x.status.value
        x.close()
        return elapsed

    ours = [fresh_depth() for _ in range(args.repeat)]
    x = CurvatureExplorer(surfaces.practical(), live=False, depth=3)
    x.screenshot()
    x.depth.value = 5
    x.depth.value = 3

    def cached():
        x.depth.value = 5
        _render(x)
        x.depth.value = 3
        _render(x)

    revisit = [t / 2 for t in timed(cached, args.repeat)]
    rows.append(("depth change to 5", ours, revisit, "(revisit, cached)"))

    # fan of 40 geodesics on the practical's surface
    g = GeodesicExplorer(surfaces.practical(), start=(4.9, 2.1), n_angles=40, step=0.5, n_curves=9, live=False)
    g.screenshot()
    starts = iter([(4.8, 2.2), (4.9, 2.1)] * (args.repeat + 1))  # each differs from the one before

    def move_start():
        u, v = next(starts)
        with g._quiet():
            g.u0.value = u
        g.v0.value = v  # one callback: recompute the fan and the isodistance curves, update
        _render(g)

    ours = timed(move_start, args.repeat)
    from lab import geodesic_fan

    def per_path():
        geodesic_fan(surfaces.practical(), (4.9, 2.1), 40, 4.5, vectorized=False, n_samples=61)

    base = timed(per_path, max(1, args.repeat // 2))
    rows.append(("fan of 40 geodesics", ours, base, "solve_ivp per path"))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    rows = measure(args.repeat)
    import os

    header = f"{'action':24s} {'ours median':>12s} {'ours best':>10s} {'target':>8s} {'ok':>4s} | {'baseline':>10s}  baseline is"
    print(header)
    print("-" * len(header))
    for name, ours, base, what in rows:
        med = statistics.median(ours)
        ok = "yes" if med < TARGETS[name] else "NO"
        print(f"{name:24s} {1000 * med:10.1f}ms {1000 * min(ours):8.1f}ms {1000 * TARGETS[name]:6.0f}ms {ok:>4s} | "
              f"{1000 * statistics.median(base):8.1f}ms  {what}")
    print("\nserver side: computation + scene update + offscreen render (software OpenGL); medians of "
          f"{args.repeat} runs; the push to the browser is not included; load average {os.getloadavg()[0]:.2f}.")
    return 0 if all(statistics.median(o) < TARGETS[n] for n, o, _, _ in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
