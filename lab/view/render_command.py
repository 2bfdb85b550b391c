"""The ``curvature-lab render`` command's work (the command line in :mod:`lab.cli` only parses and dispatches): a named
surface, a part read from a file or a named part, refined and coloured by its exact curvature (or by the draft angle,
the smallest radius of curvature, with curvature combs, or by a scan's deviation from the part), written as a picture (PNG, with title and legend), an
interactive scene (HTML), a mesh (VTK/VTP, geomview OFF) or coloured Bézier patches for geomview (BEZ), with progress
on stderr.  What cannot be done raises :class:`UsageError`, which the command line shows as a usage error.  A machine
that cannot draw (:class:`lab.view.render.RenderingUnavailable`) is found out before the work for a picture starts:
``curvature-lab: error: …`` on stderr, exit status 1, nothing written.
"""

import sys
import time
import warnings
from pathlib import Path

import numpy as np
from tqdm import tqdm

from ..i18n import _
from ..model import surfaces

__all__ = ["MAX_PATCHES", "MODELS", "OUTPUT_SUFFIXES", "RANGED_MAPS", "UsageError", "run"]


class UsageError(ValueError):
    """Options the command cannot honour, said in a sentence (the command line prints it with the usage)."""


def _refuse(message):
    raise UsageError(message)


OUTPUT_SUFFIXES = (".png", ".html", ".off", ".vtk", ".vtp", ".bez")


def run(args):
    out = Path(args.output)
    if out.suffix.lower() not in OUTPUT_SUFFIXES:
        _refuse(f"unknown output type {out.suffix or '(none)'!r} for {out}; expected one of {', '.join(OUTPUT_SUFFIXES)}")
    if args.depth < 0 or args.depth > 8:
        _refuse(f"--depth must be between 0 and 8; got {args.depth}")
    if out.parent and not out.parent.exists():
        _refuse(f"output folder {out.parent} does not exist")
    from .. import mesh as _mesh
    from . import render

    if out.suffix.lower() == ".png":
        try:  # the picture's memory, before anything is built
            render._window(args.window_size)
        except ValueError as exc:
            _refuse(f"--window-size: {exc}")
    options = _map_options(args)
    if sum(x is not None for x in (args.draft, args.min_radius, getattr(args, "deviation", None))) > 1:
        _refuse("--draft, --min-radius and --deviation are different colourings: give one of them")
    if getattr(args, "tolerance", None) is not None and getattr(args, "deviation", None) is None:
        _refuse("--tolerance belongs to --deviation SCAN")
    if args.file and args.model:
        _refuse("--file and --model both name a part: give one of them")
    simulate, band_lines = getattr(args, "simulate", None), getattr(args, "band_lines", False)
    if (simulate or band_lines) and out.suffix.lower() != ".png":
        _refuse(f"--simulate and --band-lines apply to pictures (.png); got {out.name}")
    if band_lines and (args.draft is not None or args.min_radius is not None or getattr(args, "deviation", None)):
        _refuse("--band-lines draws the borders of the curvature colours' bands, not of --draft, --min-radius or "
                "--deviation")
    if out.suffix.lower() == ".png":
        try:  # whether this machine can draw at all, before the work (Linux without EGL: never a segmentation fault)
            render.configure_offscreen()
        except render.RenderingUnavailable as exc:
            print(f"curvature-lab: error: {exc}", file=sys.stderr)
            return 1
    start = time.perf_counter()
    steps = 3 + args.depth
    label = _label(args)
    with tqdm(total=steps, desc=label, unit="step", disable=args.quiet, file=sys.stderr) as bar, \
            warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        bar.set_postfix_str("reading the file" if args.file or args.model else "building surface")
        if args.file or args.model:
            from ..interrogation.cad import models, read

            try:
                surface = read(args.file) if args.file else getattr(models, args.model)()
            except (OSError, ValueError, ImportError) as exc:
                _refuse(str(exc))
        else:
            surface = surfaces.REGISTRY[args.surface]()
        _check_size(args, surface)
        bar.update(1)
        if args.file or args.model:
            patches = None
            n = 8 * 2**args.depth * args.resolution + 1
            bar.update(args.depth)
            bar.set_postfix_str(f"{len(surface.faces)} faces, each on a {n} x {n} grid")
            from ..interrogation.faces import fill_normals

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
        mesh, lines, legend = _cad_maps(args, surface, mesh)
        bar.set_postfix_str(f"writing {out.name}")
        suffix = out.suffix.lower()
        if suffix == ".png" and legend is not None:
            render.save(mesh, out, window_size=args.window_size, edges=args.edges, lines=lines,
                        title=_title(args), camera=args.camera, legend=legend if args.legend else False,
                        simulate=simulate)
        elif suffix == ".png":
            render.save(mesh, out, args.curvature, args.color_map, window_size=args.window_size, edges=args.edges,
                        title=_title(args), camera=args.camera, map_options=options, legend=args.legend, lines=lines,
                        band_lines=band_lines, simulate=simulate)
        elif suffix == ".html":
            render.export_html(mesh, out, show_edges=args.edges, camera=args.camera)
        elif suffix == ".off":
            _mesh.write_off(mesh, out)
        elif suffix == ".bez":
            if patches is None:
                what = f"the part {label!r} is" if args.file or args.model else f"surface {label!r} is analytic,"
                _refuse(f"{what} not made of Bézier patches: no .bez export")
            _mesh.write_cbez(patches, out)
        else:
            mesh.save(str(out))
        bar.update(1)
    for w in {str(w.message) for w in caught}:
        print(f"note: {w}", file=sys.stderr)
    if not args.quiet:
        print(f"wrote {out} ({mesh.n_points} points, {time.perf_counter() - start:.2f} s)", file=sys.stderr)
    return 0


def _cad_maps(args, surface, mesh):
    """--draft, --min-radius and --combs: the mesh recoloured, the lines drawn over it, the legend (None: unchanged)."""
    from ..interrogation import combs as _combs
    from ..interrogation import maps as _maps
    from .legend import draft_legend, radius_legend

    lines, legend = [], None
    try:
        if getattr(args, "deviation", None) is not None:
            mesh, legend = _deviation_map(args, surface, mesh)
        elif args.draft is not None:
            mesh = _maps.draft_map(mesh, args.draft)
            lines.append(_maps.parting_line(mesh))
            legend = draft_legend()
        elif args.min_radius is not None:
            mesh = _maps.radius_map(mesh, args.min_radius)
            legend = radius_legend(args.min_radius)
    except ValueError as exc:
        _refuse(str(exc))
    if args.combs is not None:
        if not hasattr(surface, "derivatives"):
            _refuse("--combs needs a surface (--surface), not a part (--file, --model)")
        try:
            found = _combs.border_combs(surface, density=args.comb_density, scale=args.comb_scale, count=args.combs)
        except ValueError as exc:
            _refuse(str(exc))
        lines.append(_combs.comb_lines(found))
    if not lines:
        return mesh, None, legend
    return mesh, lines[0] if len(lines) == 1 else lines[0].merge(lines[1:]), legend


def _deviation_map(args, surface, mesh):
    """--deviation SCAN: the part's mesh coloured by the signed distance of the scan's points (the nearest
    point's where one is near, grey elsewhere), the legend, and the statistics printed for the report."""
    from ..interrogation.deviation import deviation
    from ..interrogation.scans import read_scan
    from .legend import deviation_legend

    try:
        points = read_scan(args.deviation)
    except (OSError, TypeError) as exc:
        _refuse(f"--deviation: {exc}")
    found = deviation(points, surface, tolerance=args.tolerance, name=_label(args))
    coloured = found.map(mesh, args.deviation_map)
    values = np.asarray(coloured.point_data["deviation"])
    top = float(np.nanmax(np.abs(found.distance))) if len(found.distance) else None
    legend = deviation_legend(found.tolerance, args.deviation_map, top, unscanned=bool(np.isnan(values).any()))
    args._deviation = found
    print(found.table())
    return coloured, legend


#: colour maps that take a range, and the keyword options --vmin / --vmax become
RANGED_MAPS = {"linear": ("vmin", "vmax"), "dill": ("vmin", "vmax"), "symmetric": (None, "vmax"),
               "linear-batlow": ("vmin", "vmax"), "dill-batlow": ("vmin", "vmax"), "symmetric-vik": (None, "vmax")}


#: Default of ``--max-patches``: the patches (or grid cells) a render may build, about 20 s of work (the practical's
#: surface at depth 7 has 802 816 patches; at depth 8, 3 211 264).
MAX_PATCHES = 1_000_000
#: Patches (or grid cells) per second, for the time estimate (measured with the practical's surface, depth 5).
PATCHES_PER_SECOND = 50_000


def estimate(args, surface):
    """What a render will build: ``(count, kind)``, the number of Bézier patches (or grid cells) at ``args.depth``."""
    if args.file or args.model:
        return len(surface.faces) * (8 * 2**args.depth * args.resolution) ** 2, _("grid cells")
    if hasattr(surface, "to_bezier_patches"):
        return len(surface.to_bezier_patches()) * 4**args.depth, _("patches")
    return (16 * 2**args.depth * args.resolution) ** 2, _("grid cells")


def _check_size(args, surface):
    """Refuse, before the work, a render larger than ``--max-patches``: with the estimate and the way forward."""
    from ..geometry.validation import format_count

    count, kind = estimate(args, surface)
    limit = getattr(args, "max_patches", MAX_PATCHES)
    if count > limit:
        smaller = args.depth
        while smaller > 0 and count / 4 ** (args.depth - smaller) > limit:
            smaller -= 1
        _refuse(_("--depth {depth} would build {count} {kind} (about {seconds} s), more than "
                  "--max-patches {limit}: use --depth {smaller} or less, or raise --max-patches if you can wait").format(
            depth=args.depth, count=format_count(count), kind=kind, seconds=format_count(round(count / PATCHES_PER_SECOND)),
            limit=limit, smaller=smaller))
    if count > 10 * PATCHES_PER_SECOND and not args.quiet:
        print(_("note: {count} {kind}, about {seconds} s (Ctrl-C stops)").format(
            count=format_count(count), kind=kind, seconds=round(count / PATCHES_PER_SECOND)), file=sys.stderr)


def _map_options(args):
    """--vmin / --vmax as the colour map's options (only for the maps that take a range)."""
    if args.vmin is None and args.vmax is None:
        return {}
    if args.color_map not in RANGED_MAPS:
        _refuse(f"--vmin/--vmax apply to the colour maps {', '.join(RANGED_MAPS)}; got --color-map {args.color_map}")
    low, high = RANGED_MAPS[args.color_map]
    if args.vmin is not None and low is None:
        _refuse("the symmetric map is centred at 0: give --vmax only (it spans -vmax … vmax)")
    for option, value in (("--vmin", args.vmin), ("--vmax", args.vmax)):
        if value is not None and not np.isfinite(value):
            _refuse(_("{option} must be a finite number; got {value}").format(option=option, value=value))
    if low is None and args.vmax is not None and not args.vmax > 0:
        _refuse(_("the symmetric map spans -vmax … vmax: --vmax must be positive; got {vmax:g}").format(vmax=args.vmax))
    if args.vmin is not None and args.vmax is not None and not args.vmin < args.vmax:
        _refuse(f"--vmin must be smaller than --vmax; got {args.vmin:g} and {args.vmax:g}")
    if args.color_map in ("dill", "dill-batlow") and (args.vmin is None or args.vmax is None):
        _refuse("Dill's bands need both --vmin and --vmax")
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
    from .legend import MEASURES

    name, symbol, _unit = MEASURES[args.curvature]
    label = _label(args)
    if args.file or args.model:  # a part: each face on n lines (depth means nothing for trimmed faces)
        resolution = _("{n} lines per face").format(n=8 * 2**args.depth * args.resolution + 1)
    else:
        resolution = _("depth {depth}").format(depth=args.depth)
    if getattr(args, "deviation", None) is not None:
        found = getattr(args, "_deviation", None)  # set by _deviation_map, before the picture is drawn
        lo, hi = (_legend_number(x) for x in found.tolerance) if found is not None else ("?", "?")
        return _("{label}: deviation from {scan}, tolerance {lo} … {hi}").format(
            label=label, scan=Path(args.deviation).name, lo=lo, hi=hi)
    if getattr(args, "draft", None) is not None:
        pull = ", ".join(f"{x:g}" for x in args.draft)
        return _("{label}: draft angle, pull ({pull}), {resolution}").format(label=label, pull=pull,
                                                                              resolution=resolution)
    if getattr(args, "min_radius", None) is not None:
        return _("{label}: radius of curvature below {r:g}, {resolution}").format(
            label=label, r=args.min_radius, resolution=resolution)
    return f"{label}: {name} {symbol}, {args.color_map} map, {resolution}"


def _legend_number(x):
    from .legend import _minus

    return _minus(f"{x:.3g}")


def _label(args):
    """What the picture shows: the file's name, the named part or the surface."""
    return Path(args.file).name if args.file else args.model or args.surface


#: named parts for --model (lab.models)
MODELS = ("bottle", "hammer", "impeller", "linkrods", "shell", "teapot", "terrain", "wing")
