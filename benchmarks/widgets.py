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

With ``--models`` the rows are the explorers on a real part instead (OpenCASCADE's hammer, 45 trimmed B-spline
faces; Newell's teapot where OpenCASCADE's sample data is missing), each face on 16 lines:

* recolour: as above;
* lines per face 16 -> 32: the model's mesh built face by face (first visit), against the cached revisit;
* reflection lines (a new count) on the mesh built once, against building the model's mesh for every update;
* focal surface (a new scale) on the mesh built once, against ``lab.focal_surface(model)`` for every update.

Usage: python benchmarks/widgets.py [--repeat 5] [--models]
"""

import argparse
import statistics
import time
import warnings

from lab.widgets import CurvatureExplorer, GeodesicExplorer

from lab import surfaces

TARGETS = {"recolour at depth 5": 0.050, "depth change to 5": 0.300, "fan of 40 geodesics": 1.0,
           "model: recolour": 0.050, "model: lines 16 -> 32": 1.0, "model: reflection lines": 0.3,
           "model: focal scale": 0.05}


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


def _part():
    """The hammer from OpenCASCADE's sample data, or the teapot that ships with the lab."""
    import lab

    try:
        return lab.models.hammer()
    except FileNotFoundError:
        return lab.models.teapot()


def measure_models(repeat):
    """The rows of the table for the explorers on a model (see the module docstring)."""
    from lab.widgets import FocalExplorer, ReflectionExplorer

    import lab

    warnings.simplefilter("ignore")
    rows = []
    model = _part()
    start = time.perf_counter()
    e = CurvatureExplorer(model, live=False, lines=16)
    print(f"{model.name}: {len(model.faces)} faces; curvature explorer made in {time.perf_counter() - start:.2f} s "
          f"({e.mesh.n_points} points)")
    e.screenshot()
    maps = iter(["signed-log", "linear"] * (repeat + 1))

    def recolour():
        e.color_map.value = next(maps)
        _render(e)
        assert "error" not in e.status.value, e.status.value

    ours = timed(recolour, repeat)

    def rebuild():
        e.plotter.clear_actors()
        e.plotter.add_mesh(e.mesh.copy(), scalars="display", cmap="viridis", smooth_shading=True)
        e.plotter.render()

    rows.append(("model: recolour", ours, timed(rebuild, repeat), "rebuild the scene"))

    def fresh_lines():
        x = CurvatureExplorer(model, live=False, lines=16)
        x.screenshot()
        begin = time.perf_counter()
        x.depth.value = 32
        _render(x)
        elapsed = time.perf_counter() - begin
        assert "error" not in x.status.value, x.status.value
        x.close()
        return elapsed

    ours = [fresh_lines() for _ in range(repeat)]
    x = CurvatureExplorer(model, live=False, lines=16)
    x.depth.value = 32

    def cached():
        x.depth.value = 16
        _render(x)
        x.depth.value = 32
        _render(x)

    rows.append(("model: lines 16 -> 32", ours, [t / 2 for t in timed(cached, repeat)], "(revisit, cached)"))

    r = ReflectionExplorer(model, live=False)
    r.kind.value = "lines"
    r.screenshot()
    counts = iter([9, 8] * (repeat + 1))

    def new_count():
        r.count.value = next(counts)
        _render(r)
        assert "error" not in r.status.value, r.status.value

    ours = timed(new_count, repeat)

    def remesh():
        lab.reflection_lines(lab.interrogation.meshes.as_curvature_mesh(model, 16), count=9)

    rows.append(("model: reflection lines", ours, timed(remesh, repeat), "mesh the model per update"))

    f = FocalExplorer(model, live=False)
    f.screenshot()
    scales = iter([0.5, 1.0] * (repeat + 1))
    a = f.scale.value

    def new_scale():
        f.scale.value = a * next(scales)
        _render(f)

    ours = timed(new_scale, repeat)

    def focal_from_scratch():
        lab.focal_surface(model, scale=a, resolution=16)

    rows.append(("model: focal scale", ours, timed(focal_from_scratch, repeat), "lab.focal_surface(model) per update"))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--models", action="store_true", help="the explorers on a real part instead")
    args = parser.parse_args()
    rows = measure_models(args.repeat) if args.models else measure(args.repeat)
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
