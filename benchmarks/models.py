"""A real part from file to coloured mesh: the lab (lab.read + Model.to_mesh with exact curvature) against
OpenCASCADE's own read + BRepMesh tessellation of the same file, in the same run.

    .venv/bin/python benchmarks/models.py [--file PART] [--repeat 3]

Each side runs in a fresh process (so that the memory column is that side's own peak resident set) after its imports;
the import times are listed apart.  Default part: the impeller of pyiges (277 faces, 247 trimmed NURBS).
Wall-clock and CPU seconds are both listed (on a machine shared with other work the CPU seconds vary less), with
the load average before the runs; the fastest run of each side by wall-clock counts.
"""

import argparse
import json
import os
import subprocess
import sys
import time

CHILD = r"""
import json, resource, sys, time
t0 = time.perf_counter()
side, path, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
if side == "lab":
    import lab
    import lab.interrogation.cad.occ as occ
    occ.require_ocp(); import OCP.IGESControl, OCP.STEPControl, OCP.BRep  # the same OCCT modules as the other side
    import lab.interrogation.cad.mesh, pyvista  # noqa: F401
else:
    from OCP.BRep import BRep_Tool
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    import lab.interrogation.cad.occ as occ
    import numpy as np
t1 = time.perf_counter()
if side == "lab":
    c, t = time.process_time(), time.perf_counter(); model = lab.read(path)
    t_read, c_read = time.perf_counter() - t, time.process_time() - c
    c, t = time.process_time(), time.perf_counter(); mesh = model.to_mesh(n, n, curvature_mode="gaussian", color_map="linear")
    t_mesh, c_mesh = time.perf_counter() - t, time.process_time() - c
    points, cells = mesh.n_points, mesh.n_cells
else:
    c, t = time.process_time(), time.perf_counter(); shape = occ.occ_shape(path)
    t_read, c_read = time.perf_counter() - t, time.process_time() - c
    c, t = time.process_time(), time.perf_counter()
    BRepMesh_IncrementalMesh(shape, float(sys.argv[4]), False, 0.5, False)
    points = cells = 0
    explorer = TopExp_Explorer(shape, TopAbs_FACE)
    while explorer.More():  # the triangles as arrays, as a user who wants a mesh takes them
        face = occ._cast("Face")(explorer.Current())
        tri = BRep_Tool.Triangulation_s(face, TopLoc_Location())
        if tri is not None:
            P = np.array([[tri.Node(i).X(), tri.Node(i).Y(), tri.Node(i).Z()] for i in range(1, tri.NbNodes() + 1)])
            points += len(P); cells += tri.NbTriangles()
        explorer.Next()
    t_mesh, c_mesh = time.perf_counter() - t, time.process_time() - c
print(json.dumps({"import": t1 - t0, "read": t_read, "mesh": t_mesh, "cpu_read": c_read, "cpu_mesh": c_mesh,
                  "points": points, "cells": cells, "rss": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def run(side, path, n, deflection):
    out = subprocess.run([sys.executable, "-c", CHILD, side, str(path), str(n), str(deflection)], capture_output=True,
                         text=True, check=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", help="a STEP, IGES or BREP file (default: the impeller of pyiges)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per side; the fastest counts (default 3)")
    parser.add_argument("--n", type=int, default=16, help="the lab's iso-parameter lines per face (default 16)")
    parser.add_argument("--deflection", type=float, default=0.1,
                        help="BRepMesh's linear deflection in the part's units (default 0.1)")
    args = parser.parse_args(argv)
    if args.file is None:
        import lab

        args.file = lab.models.impeller_path()
    load = os.getloadavg()
    runs = {side: [] for side in ("lab", "occ")}
    for _ in range(args.repeat):  # the sides alternate, so that a change of the machine's load hits both
        for side, done in runs.items():
            done.append(run(side, args.file, args.n, args.deflection))
    rows = {side: min(r, key=lambda x: x["read"] + x["mesh"]) for side, r in runs.items()}
    print(f"\n{args.file}: file -> mesh, fastest of {args.repeat} runs each, one process per run "
          f"({time.strftime('%Y-%m-%d %H:%M')}, load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f} on "
          f"{os.cpu_count()} cores)")
    print(f"{'':<38} {'import':>7} {'read':>7} {'mesh':>7} {'total':>7} {'total CPU':>9} {'points':>8} "
          f"{'triangles':>9} {'peak RSS':>9}")
    names = {"lab": f"lab.read + to_mesh({args.n}, {args.n}), coloured",
             "occ": f"OCCT read + BRepMesh({args.deflection:g})"}
    for side, r in rows.items():
        total = r["read"] + r["mesh"]
        print(f"{names[side]:<38} {r['import']:>6.2f}s {r['read']:>6.2f}s {r['mesh']:>6.2f}s {total:>6.2f}s "
              f"{r['cpu_read'] + r['cpu_mesh']:>8.2f}s {r['points']:>8} {r['cells']:>9} {r['rss']:>6.0f} MB")
    ratio = (rows["lab"]["read"] + rows["lab"]["mesh"]) / (rows["occ"]["read"] + rows["occ"]["mesh"])
    cpu = ((rows["lab"]["cpu_read"] + rows["lab"]["cpu_mesh"]) / (rows["occ"]["cpu_read"] + rows["occ"]["cpu_mesh"]))
    pairs = sorted((a["read"] + a["mesh"]) / (b["read"] + b["mesh"]) for a, b in zip(runs["lab"], runs["occ"]))
    print(f"ratio lab / OCCT (read + mesh): {ratio:.2f}x wall-clock, {cpu:.2f}x CPU (fastest runs); run by run "
          f"{', '.join(f'{r:.2f}' for r in pairs)} (median {pairs[len(pairs) // 2]:.2f}x)   (goal <= 1.5x; the lab's "
          "mesh carries exact K, H, k1, k2, N and colours at every vertex, OCCT's none)")


if __name__ == "__main__":
    main()
