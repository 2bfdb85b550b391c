"""Scan against CAD: ``lab.deviation`` on 10^5 points against OpenCASCADE's per-point projection, in one run.

    .venv/bin/python benchmarks/deviation.py [--points 100000] [--occ-points 2000] [--part linkrods]

The scan: ``lab.interrogation.scans.sample_scan`` on a part of ``lab.models`` (uniform by area, a scanner's noise
of 2e-5 of the part's size).  The lab: ``lab.deviation`` on all points, its start mesh built inside the timing.
OpenCASCADE, point by point as a script does it (``lab.occ_projection``, the faces read once, outside the timing):

* ``BRepExtrema_DistShapeShape`` of a vertex against the part's faces: every face searched, trims respected
  (what a user must call who does not know the face of each point, as ``lab.deviation`` does not);
* ``GeomAPI_ProjectPointOnSurf`` onto the face the point was sampled on (a user who knows the face: faster, but
  trims ignored and the face told).

10^5 OCC calls take minutes on a shared machine, so OCC runs on ``--occ-points`` of the points (a random subset)
and its time is extrapolated linearly to all points (the table says so; ``--occ-points`` equal to ``--points``
times all).  Wall-clock and CPU seconds are both listed, with the load average before the runs.  The accuracy
column: the largest difference of |distance| from OCC's on the subset, where the lab's foot lies inside a face.
"""

import argparse
import os
import time

import numpy as np


def timed(f, *args, **kwargs):
    c, t = time.process_time(), time.perf_counter()
    out = f(*args, **kwargs)
    return out, time.perf_counter() - t, time.process_time() - c


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=100_000, help="scanned points (default 10^5)")
    parser.add_argument("--occ-points", type=int, default=2000,
                        help="points OCC projects one by one; its time is extrapolated to --points (default 2000)")
    parser.add_argument("--part", default="linkrods", help="a part of lab.models (default linkrods)")
    args = parser.parse_args(argv)
    import lab
    from lab.interrogation.cad.kernel import _faces, occ_projection
    from lab.interrogation.scans import sample_scan

    part = getattr(lab.models, args.part)()
    _faces(part.path, os.path.getmtime(part.path))  # OCC reads the file once, outside the timing
    mesh = part.to_mesh(8, 8)
    size = float(np.linalg.norm(np.ptp(np.asarray(mesh.points), axis=0)))
    scan = sample_scan(part, args.points, noise=2e-5 * size, seed=1)
    load = os.getloadavg()
    d, t_lab, c_lab = timed(lab.deviation, scan.points, part, tolerance=1e-3 * size)
    m = min(args.occ_points, args.points)
    some = np.sort(np.random.default_rng(5).choice(args.points, m, replace=False))
    (dist_b, _f, _uv), t_brep, c_brep = timed(occ_projection, part, scan.points[some])
    (dist_g, _f, _uv), t_geom, c_geom = timed(occ_projection, part, scan.points[some], faces=scan.face[some])
    inside = ~d.border[some]
    same = inside & (d.face[some] == scan.face[some])
    diff_b = (np.abs(d.distance[some]) - dist_b)[inside]
    err_b = float(np.nanmax(np.abs(diff_b)))
    err_g = float(np.nanmax(np.abs(np.abs(d.distance[some]) - dist_g)[same]))
    scale = args.points / m
    print(f"\n{args.part} ({len(part.faces)} faces), {args.points} scanned points, noise 2e-5 of the size "
          f"({time.strftime('%Y-%m-%d %H:%M')}, load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f} on "
          f"{os.cpu_count()} cores)")
    print(f"{'':<46} {'points run':>10} {'wall':>9} {'CPU':>9} {f'wall for {args.points}':>16} "
          f"{f'CPU for {args.points}':>15} {'lab faster (wall, CPU)':>23} {'max |Δ| vs lab':>15}")
    print(f"{'lab.deviation (all faces, trims)':<46} {args.points:>10} {t_lab:>8.2f}s {c_lab:>8.2f}s "
          f"{t_lab:>15.2f}s {c_lab:>14.2f}s {'':>23} {'':>15}")
    note = "" if m == args.points else "*"
    for name, t, c, err in (("OCC BRepExtrema_DistShapeShape (all faces)", t_brep, c_brep, err_b),
                            ("OCC GeomAPI_ProjectPointOnSurf (face told)", t_geom, c_geom, err_g)):
        ratios = f"{t * scale / t_lab:.1f}x, {c * scale / c_lab:.1f}x"
        print(f"{name:<46} {m:>10} {t:>8.2f}s {c:>8.2f}s {t * scale:>14.2f}s{note or ' '} {c * scale:>13.2f}s{note or ' '} "
              f"{ratios:>23} {err:>15.2e}")
    if note:
        print(f"* extrapolated linearly from {m} points ({scale:g}x); OCC's time per point does not depend on how "
              "many points there are")
    differ = int(np.count_nonzero(np.abs(diff_b) > 1e-8))
    print(f"BRepExtrema's distance minus the lab's: {-np.nanmax(diff_b):.2e} … {-np.nanmin(diff_b):.2e} "
          f"(> 0: OCC's foot is farther than the lab's); {differ} of {int(inside.sum())} points differ by more than "
          f"1e-8")
    if differ:
        far = np.abs(diff_b) > 1e-8
        planted = np.abs(scan.offset[some][inside])
        print(f"  of them: {int(np.count_nonzero((d.face[some] != scan.face[some])[inside][far]))} with the lab's foot "
              f"on another face than the point was sampled on; OCC's distance beyond the planted offset (the "
              f"sampled foot outside OCC's exact trim) at {int(np.count_nonzero((dist_b[inside] > planted + 1e-12)[far]))}")
    print(f"goal: lab >= 10x faster than OCC's per-point projection; the lab's feet inside a face: "
          f"{100 * (1 - d.border.mean()):.2f} %; distances in the part's unit (size {size:.3g})")


if __name__ == "__main__":
    main()
