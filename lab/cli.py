"""The ``curvature-lab`` command line.

``curvature-lab render``: colour a named surface by curvature and write a
picture (PNG), an interactive scene (HTML), a mesh (VTK/VTP, geomview OFF) or
coloured Bézier patches for geomview (BEZ).
"""

import argparse
import sys
import time
import warnings
from pathlib import Path

from tqdm import tqdm

from .geometry import colormaps
from .geometry.curvature import CurvatureMode
from .model import surfaces

OUTPUT_SUFFIXES = (".png", ".html", ".off", ".vtk", ".vtp", ".bez")


def _render(args, parser):
    out = Path(args.output)
    if out.suffix.lower() not in OUTPUT_SUFFIXES:
        parser.error(f"unknown output type {out.suffix or '(none)'!r} for {out}; expected one of {', '.join(OUTPUT_SUFFIXES)}")
    if args.depth < 0 or args.depth > 8:
        parser.error(f"--depth must be between 0 and 8; got {args.depth}")
    if out.parent and not out.parent.exists():
        parser.error(f"output folder {out.parent} does not exist")
    from . import mesh as _mesh
    from .view import render

    start = time.perf_counter()
    steps = 3 + args.depth
    with tqdm(total=steps, desc=f"{args.surface}", unit="step", disable=args.quiet, file=sys.stderr) as bar, \
            warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        bar.set_postfix_str("building surface")
        surface = surfaces.REGISTRY[args.surface]()
        bar.update(1)
        if hasattr(surface, "to_bezier_patches"):
            patches = surface.to_bezier_patches()
            for level in range(args.depth):
                bar.set_postfix_str(f"refining to depth {level + 1}: {4 * len(patches)} patches")
                patches.refine(1)
                bar.update(1)
            bar.set_postfix_str(f"curvature at the corners of {len(patches)} patches")
            patches.visualize_curvature(args.curvature, args.color_map)
            mesh = _mesh.patches_mesh(patches, resolution=args.resolution)
        else:
            patches = None
            n = 16 * 2**args.depth * args.resolution + 1
            bar.update(args.depth)
            bar.set_postfix_str(f"curvature on a {n} x {n} grid")
            mesh = _mesh.surface_mesh(surface, n, n, args.curvature, args.color_map)
        bar.update(1)
        bar.set_postfix_str(f"writing {out.name}")
        suffix = out.suffix.lower()
        if suffix == ".png":
            title = f"{args.surface}: {args.curvature}, {args.color_map}" if args.title else None
            render.screenshot(mesh, out, window_size=args.window_size, show_edges=args.edges, title=title)
        elif suffix == ".html":
            render.export_html(mesh, out, show_edges=args.edges)
        elif suffix == ".off":
            _mesh.write_off(mesh, out)
        elif suffix == ".bez":
            if patches is None:
                parser.error(f"surface {args.surface!r} is analytic, not made of Bézier patches: no .bez export")
            _mesh.write_cbez(patches, out)
        else:
            mesh.save(str(out))
        bar.update(1)
    for w in {str(w.message) for w in caught}:
        print(f"note: {w}", file=sys.stderr)
    if not args.quiet:
        print(f"wrote {out} ({mesh.n_points} points, {time.perf_counter() - start:.2f} s)", file=sys.stderr)
    return 0


def _window_size(text):
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"window size must look like 1024x768; got {text!r}") from None
    if w < 16 or h < 16:
        raise argparse.ArgumentTypeError(f"window size must be at least 16x16; got {text!r}")
    return w, h


def build_parser():
    parser = argparse.ArgumentParser(
        prog="curvature-lab",
        description="Curvature visualisation of free-form surfaces (Versuch 6: Krümmungsvisualisierung).",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser(
        "render",
        help="colour a surface by curvature and write PNG, HTML, VTK, OFF or BEZ",
        description="Colour a named surface by its exact curvature and write the result; "
        "the output type follows the file suffix (" + ", ".join(OUTPUT_SUFFIXES) + ").",
    )
    r.add_argument("--surface", default="practical", choices=sorted(surfaces.REGISTRY), help="surface (default: practical)")
    r.add_argument(
        "--curvature",
        default="gaussian",
        choices=[m.value for m in CurvatureMode],
        help="curvature measure: gaussian K, mean H, k1, k2, strain-energy (default: gaussian)",
    )
    r.add_argument(
        "--color-map", default="linear", choices=list(colormaps.COLOR_MAPS), help="colour map (default: linear = h∘f2)"
    )
    r.add_argument("--depth", type=int, default=1, help="subdivision depth: 4**depth patches per patch (default: 1)")
    r.add_argument("--resolution", type=int, default=1, help="quads per patch edge in the mesh (default: 1)")
    r.add_argument("--window-size", type=_window_size, default=(1024, 768), help="PNG size, e.g. 1024x768")
    r.add_argument("--edges", action="store_true", help="draw the patch/mesh edges")
    r.add_argument("--title", action="store_true", help="write the surface and map into the picture")
    r.add_argument("--quiet", action="store_true", help="no progress display")
    r.add_argument("-o", "--output", required=True, help="output file (.png, .html, .off, .vtk, .vtp, .bez)")
    r.set_defaults(func=_render)
    sub.add_parser("grade", help="grade a notebook or a folder of submissions (curvature-lab grade --help)", add_help=False)
    sub.add_parser("exercises", help="generate exercises/{en,de} and solutions/{en,de} from the bilingual solutions/ (curvature-lab exercises --help)", add_help=False)
    return parser


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] == "grade":
        from .teaching import grading

        return grading.main(argv[1:])
    if argv and argv[0] == "exercises":
        from .teaching import notebooks

        return notebooks.main(argv[1:])
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command == "render" and args.resolution < 1:
        parser.error(f"--resolution must be at least 1; got {args.resolution}")
    return args.func(args, parser)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
