"""The ``curvature-lab`` command line.

``curvature-lab render``: colour a named surface (or a part read from a file, ``--file``) by curvature and write a
picture (PNG), an interactive scene (HTML), a mesh (VTK/VTP, geomview OFF) or
coloured Bézier patches for geomview (BEZ).
"""

import argparse
import math
import re
import sys
import time
import warnings
from pathlib import Path

from tqdm import tqdm

from .geometry import colormaps
from .geometry.curvature import CurvatureMode
from .i18n import N_, _
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

    if out.suffix.lower() == ".png":
        try:  # the picture's memory, before anything is built
            render._window(args.window_size)
        except ValueError as exc:
            parser.error(f"--window-size: {exc}")
    options = _map_options(args, parser)
    if args.draft is not None and args.min_radius is not None:
        parser.error("--draft and --min-radius are two colourings: give one of them")
    if args.file and args.model:
        parser.error("--file and --model both name a part: give one of them")
    start = time.perf_counter()
    steps = 3 + args.depth
    label = _label(args)
    with tqdm(total=steps, desc=label, unit="step", disable=args.quiet, file=sys.stderr) as bar, \
            warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        bar.set_postfix_str("reading the file" if args.file or args.model else "building surface")
        if args.file or args.model:
            from .interrogation.cad import models, read

            try:
                surface = read(args.file) if args.file else getattr(models, args.model)()
            except (OSError, ValueError, ImportError) as exc:
                parser.error(str(exc))
        else:
            surface = surfaces.REGISTRY[args.surface]()
        bar.update(1)
        if args.file or args.model:
            patches = None
            n = 8 * 2**args.depth * args.resolution + 1
            bar.update(args.depth)
            bar.set_postfix_str(f"{len(surface.faces)} faces, each on a {n} x {n} grid")
            from .interrogation.faces import fill_normals

            mesh = fill_normals(surface.to_mesh(n, n, curvature_mode=args.curvature, color_map=args.color_map,
                                                **options))
            for problem in surface.problems:
                print(f"note: left out {problem}", file=sys.stderr)
        elif hasattr(surface, "to_bezier_patches"):
            patches = surface.to_bezier_patches()
            for level in range(args.depth):
                bar.set_postfix_str(f"refining to depth {level + 1}: {4 * len(patches)} patches")
                patches.refine(1)
                bar.update(1)
            bar.set_postfix_str(f"curvature at the corners of {len(patches)} patches")
            patches.visualize_curvature(args.curvature, args.color_map, **options)
            mesh = _mesh.patches_mesh(patches, resolution=args.resolution)
        else:
            patches = None
            n = 16 * 2**args.depth * args.resolution + 1
            bar.update(args.depth)
            bar.set_postfix_str(f"curvature on a {n} x {n} grid")
            mesh = _mesh.surface_mesh(surface, n, n, args.curvature, args.color_map, **options)
        bar.update(1)
        mesh, lines, legend = _cad_maps(args, parser, surface, mesh)
        bar.set_postfix_str(f"writing {out.name}")
        suffix = out.suffix.lower()
        if suffix == ".png" and legend is not None:
            render.save(mesh, out, window_size=args.window_size, edges=args.edges, lines=lines,
                        title=_title(args), camera=args.camera, legend=legend if args.legend else False)
        elif suffix == ".png":
            render.save(mesh, out, args.curvature, args.color_map, window_size=args.window_size, edges=args.edges,
                        title=_title(args), camera=args.camera, map_options=options, legend=args.legend, lines=lines)
        elif suffix == ".html":
            render.export_html(mesh, out, show_edges=args.edges, camera=args.camera)
        elif suffix == ".off":
            _mesh.write_off(mesh, out)
        elif suffix == ".bez":
            if patches is None:
                what = f"the part {label!r} is" if args.file or args.model else f"surface {label!r} is analytic,"
                parser.error(f"{what} not made of Bézier patches: no .bez export")
            _mesh.write_cbez(patches, out)
        else:
            mesh.save(str(out))
        bar.update(1)
    for w in {str(w.message) for w in caught}:
        print(f"note: {w}", file=sys.stderr)
    if not args.quiet:
        print(f"wrote {out} ({mesh.n_points} points, {time.perf_counter() - start:.2f} s)", file=sys.stderr)
    return 0


def _cad_maps(args, parser, surface, mesh):
    """--draft, --min-radius and --combs: the mesh recoloured, the lines drawn over it, the legend (None: unchanged)."""
    from .interrogation import combs as _combs
    from .interrogation import maps as _maps
    from .view.legend import draft_legend, radius_legend

    lines, legend = [], None
    try:
        if args.draft is not None:
            mesh = _maps.draft_map(mesh, args.draft)
            lines.append(_maps.parting_line(mesh))
            legend = draft_legend()
        elif args.min_radius is not None:
            mesh = _maps.radius_map(mesh, args.min_radius)
            legend = radius_legend(args.min_radius)
    except ValueError as exc:
        parser.error(str(exc))
    if args.combs is not None:
        if not hasattr(surface, "derivatives"):
            parser.error("--combs needs a surface (--surface), not a part (--file, --model)")
        try:
            found = _combs.border_combs(surface, density=args.comb_density, scale=args.comb_scale, count=args.combs)
        except ValueError as exc:
            parser.error(str(exc))
        lines.append(_combs.comb_lines(found))
    if not lines:
        return mesh, None, legend
    return mesh, lines[0] if len(lines) == 1 else lines[0].merge(lines[1:]), legend


def _pull(text):
    try:
        p = [float(x) for x in text.split(",")]
    except ValueError:
        p = []
    if len(p) != 3 or not all(math.isfinite(x) for x in p) or not any(p):
        raise argparse.ArgumentTypeError(f"the pull direction must look like X,Y,Z (not all 0), e.g. 0,0,1; got {text!r}")
    return p


#: colour maps that take a range, and the keyword options --vmin / --vmax become
RANGED_MAPS = {"linear": ("vmin", "vmax"), "dill": ("vmin", "vmax"), "symmetric": (None, "vmax")}


def _map_options(args, parser):
    """--vmin / --vmax as the colour map's options (only for the maps that take a range)."""
    if args.vmin is None and args.vmax is None:
        return {}
    if args.color_map not in RANGED_MAPS:
        parser.error(f"--vmin/--vmax apply to the colour maps {', '.join(RANGED_MAPS)}; got --color-map {args.color_map}")
    low, high = RANGED_MAPS[args.color_map]
    if args.vmin is not None and low is None:
        parser.error("the symmetric map is centred at 0: give --vmax only (it spans -vmax … vmax)")
    if args.vmin is not None and args.vmax is not None and not args.vmin < args.vmax:
        parser.error(f"--vmin must be smaller than --vmax; got {args.vmin:g} and {args.vmax:g}")
    if args.color_map == "dill" and (args.vmin is None or args.vmax is None):
        parser.error("Dill's bands need both --vmin and --vmax")
    options = {}
    if args.vmin is not None:
        options[low] = args.vmin
    if args.vmax is not None:
        options[high] = args.vmax
    return options


def _title(args):
    if args.title is False:
        return None
    if isinstance(args.title, str):
        return args.title
    from .view.legend import MEASURES

    name, symbol, _unit = MEASURES[args.curvature]
    label = _label(args)
    if args.file or args.model:  # a part: each face on n lines (depth means nothing for trimmed faces)
        resolution = _("{n} lines per face").format(n=8 * 2**args.depth * args.resolution + 1)
    else:
        resolution = _("depth {depth}").format(depth=args.depth)
    if getattr(args, "draft", None) is not None:
        pull = ", ".join(f"{x:g}" for x in args.draft)
        return _("{label}: draft angle, pull ({pull}), {resolution}").format(label=label, pull=pull,
                                                                              resolution=resolution)
    if getattr(args, "min_radius", None) is not None:
        return _("{label}: radius of curvature below {r:g}, {resolution}").format(
            label=label, r=args.min_radius, resolution=resolution)
    return f"{label}: {name} {symbol}, {args.color_map} map, {resolution}"


def _label(args):
    """What the picture shows: the file's name, the named part or the surface."""
    return Path(args.file).name if args.file else args.model or args.surface


#: named parts for --model (lab.models)
MODELS = ("bottle", "hammer", "impeller", "linkrods", "shell", "teapot", "terrain", "wing")


def _camera(text):
    try:
        azimuth, elevation = (float(x) for x in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"camera must look like AZIMUTH,ELEVATION in degrees, e.g. -60,35; got {text!r}") from None
    if not (math.isfinite(azimuth) and math.isfinite(elevation)):
        raise argparse.ArgumentTypeError(f"camera angles must be finite numbers of degrees; got {text!r}")
    if not -90 <= elevation <= 90:
        raise argparse.ArgumentTypeError(f"the elevation must lie between -90 and 90 degrees; got {elevation:g}")
    return azimuth, elevation


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
        description=_("Curvature visualisation of free-form surfaces (Versuch 6: Krümmungsvisualisierung)."),
    )
    sub = parser.add_subparsers(dest="command", required=True)
    r = sub.add_parser(
        "render",
        help=_("colour a surface by curvature and write PNG, HTML, VTK, OFF or BEZ"),
        description=_("Colour a named surface by its exact curvature and write the result; "
                      "the output type follows the file suffix ({suffixes}).").format(suffixes=", ".join(OUTPUT_SUFFIXES)),
    )
    r.add_argument("--surface", default="practical", choices=sorted(surfaces.REGISTRY), help=_("surface (default: practical)"))
    r.add_argument(
        "--curvature",
        default="gaussian",
        choices=[m.value for m in CurvatureMode],
        help=_("curvature measure: gaussian K, mean H, k1, k2, strain-energy (default: gaussian)"),
    )
    r.add_argument(
        "--color-map", default="linear", choices=list(colormaps.COLOR_MAPS), help=_("colour map (default: linear = h∘f2)")
    )
    r.add_argument("--file", metavar="PART", help=_("a part from a file instead (STEP, IGES, BREP): each face on a "
                   "(8·2^depth·resolution + 1)² grid in its trimmed region; see lab.read"))
    r.add_argument("--model", choices=MODELS, help=_("a named part instead (lab.models: the teapot ships with the "
                   "lab, the others come from OpenCASCADE's sample data or pyiges), meshed as --file"))
    r.add_argument("--depth", type=int, default=1, help=_("subdivision depth: 4**depth patches per patch (default: 1)"))
    r.add_argument("--resolution", type=int, default=1, help=_("quads per patch edge in the mesh (default: 1)"))
    r.add_argument("--window-size", type=_window_size, default=(1024, 768), help=_("PNG size, e.g. 1024x768"))
    r.add_argument("--edges", action="store_true", help=_("draw the patch/mesh edges (at --resolution 1: the patch "
                   "borders; on a part: the faces' borders)"))
    r.add_argument("--vmin", type=float, help=_("lower end of the colour range (linear, dill)"))
    r.add_argument("--vmax", type=float, help=_("upper end of the colour range (linear, dill; symmetric: -vmax … vmax)"))
    r.add_argument("--camera", type=_camera, metavar="AZIMUTH,ELEVATION",
                   help=_("view direction in degrees: azimuth around z from +x, elevation above the xy-plane "
                        "(default: the oblique view that sees most of the surface)"))
    r.add_argument("--legend", action=argparse.BooleanOptionalAction, default=True,
                   help=_("draw the colour bar or classification legend in curvature units (default: yes)"))
    r.add_argument("--title", nargs="?", const=True, default=True, metavar="TEXT",
                   help=_("title of the picture (default: surface, measure, map and depth)"))
    r.add_argument("--no-title", dest="title", action="store_false", help=_("no title"))
    r.add_argument("--draft", type=_pull, metavar="X,Y,Z",
                   help=_("colour by the draft angle against this pull direction, with the parting line (0°) in black"))
    r.add_argument("--min-radius", type=float, metavar="R",
                   help=_("colour red where the smallest radius of curvature is below R"))
    r.add_argument("--combs", type=int, metavar="N",
                   help=_("curvature combs along the domain's borders and N iso-curves in each direction"))
    r.add_argument("--comb-scale", type=float, default=0.05, metavar="S",
                   help=_("length of a comb tooth per unit of normal curvature (default: 0.05)"))
    r.add_argument("--comb-density", type=int, default=48, metavar="D",
                   help=_("teeth per comb (default: 48)"))
    r.add_argument("--quiet", action="store_true", help=_("no progress display"))
    r.add_argument("-o", "--output", required=True, help=_("output file (.png, .html, .off, .vtk, .vtp, .bez)"))
    # "--camera -60,35": let a negative azimuth pass as a value, not an option
    r._negative_number_matcher = re.compile(r"^-\d+(\.\d*)?(,-?\d+(\.\d*)?)?$|^-\.\d+$")
    r.set_defaults(func=_render)
    for verb, (_module, text) in VERBS.items():
        sub.add_parser(verb, help=f"{_(text)} (curvature-lab {verb} --help)", add_help=False)
    return parser


#: The course's commands, in the order a course uses them: verb -> (module of lab.teaching with main(), help).
VERBS = {
    "exercises": ("notebooks", N_("generate exercises/{en,de} and solutions/{en,de} from the bilingual solutions/")),
    "release": ("release", N_("write the students' hand-out: exercises and the library without the answers")),
    "collect": ("collect", N_("collect an assignment from the students' homes, with hand-in times and lateness")),
    "grade": ("batch", N_("grade a notebook or a folder of submissions in a sandbox")),
    "feedback": ("feedback", N_("put each student's report into the student's home")),
    "gradebook": ("gradebook", N_("one row per student and a total, for Canvas, Moodle or CSV")),
    "gradescope": ("gradescope", N_("build a Gradescope autograder zip for an assignment")),
}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0] in VERBS:
        import importlib

        return importlib.import_module(f"lab.teaching.{VERBS[argv[0]][0]}").main(argv[1:])
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command == "render" and args.resolution < 1:
        parser.error(f"--resolution must be at least 1; got {args.resolution}")
    return args.func(args, parser)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
