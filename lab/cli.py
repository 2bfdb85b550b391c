"""The ``curvature-lab`` command line: it parses and dispatches, each verb's work is elsewhere.

``curvature-lab render`` (:mod:`lab.view.render_command`): colour a named surface (or a part read from a file,
``--file``) by curvature and write a picture (PNG), an interactive scene (HTML), a mesh (VTK/VTP, geomview OFF) or
coloured Bézier patches for geomview (BEZ).  The course's verbs (``exercises``, ``release``, ``collect``, ``grade``,
``feedback``, ``gradebook``, ``gradescope``) are ``lab.teaching.course.<verb>``.
"""

import argparse
import math
import re
import sys

from .geometry import colormaps
from .geometry.curvature import CurvatureMode
from .geometry.vision import DEFICIENCIES
from .i18n import N_, _
from .model import surfaces
from .view.render_command import MAX_PATCHES, MODELS, OUTPUT_SUFFIXES


def _pull(text):
    try:
        p = [float(x) for x in text.split(",")]
    except ValueError:
        p = []
    if len(p) != 3 or not all(math.isfinite(x) for x in p) or not any(p):
        raise argparse.ArgumentTypeError(f"the pull direction must look like X,Y,Z (not all 0), e.g. 0,0,1; got {text!r}")
    return p


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


def _render(args, parser):
    """``curvature-lab render``: the work is :func:`lab.view.render_command.run`'s; a refusal is a usage error."""
    from .view import render_command

    try:
        return render_command.run(args)
    except ValueError as exc:  # a refusal, or the lab's own clear message about the options' values
        parser.error(str(exc))


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
        "--color-map", default="linear", choices=list(colormaps.COLOR_MAPS),
        help=_("colour map (default: linear = h∘f2; readable with a colour-vision deficiency: linear-batlow, "
               "symmetric-vik, signed-log-vik, classification-vik, dill-batlow)")
    )
    r.add_argument("--file", metavar="PART", help=_("a part from a file instead (STEP, IGES, BREP): each face on a "
                   "(8·2^depth·resolution + 1)² grid in its trimmed region; see lab.read"))
    r.add_argument("--model", choices=MODELS, help=_("a named part instead (lab.models: the teapot ships with the "
                   "lab, the others come from OpenCASCADE's sample data or pyiges), meshed as --file"))
    r.add_argument("--depth", type=int, default=1, help=_("subdivision depth: 4**depth patches per patch (default: 1)"))
    r.add_argument("--resolution", type=int, default=1, help=_("quads per patch edge in the mesh (default: 1)"))
    r.add_argument("--max-patches", type=int, default=MAX_PATCHES, metavar="N",
                   help=_("refuse a render of more than N patches (or grid cells) before it starts (default: "
                          "{n}); raise it if you can wait").format(n=MAX_PATCHES))
    r.add_argument("--window-size", type=_window_size, default=(1024, 768), help=_("PNG size, e.g. 1024x768"))
    r.add_argument("--edges", action="store_true", help=_("draw the patch/mesh edges (at --resolution 1: the patch "
                   "borders; on a part: the faces' borders)"))
    r.add_argument("--vmin", type=float, help=_("lower end of the colour range (linear, dill)"))
    r.add_argument("--vmax", type=float, help=_("upper end of the colour range (linear, dill; symmetric: -vmax … vmax)"))
    r.add_argument("--camera", type=_camera, metavar="AZIMUTH,ELEVATION",
                   help=_("view direction in degrees: azimuth around z from +x, elevation above the xy-plane "
                        "(default: the oblique view that sees most of the surface)"))
    r.add_argument("--simulate", choices=list(DEFICIENCIES), metavar="DEFICIENCY",
                   help=_("the picture as a student with this colour-vision deficiency sees it: deuteranopia, "
                          "protanopia or tritanopia (Machado et al. 2009)"))
    r.add_argument("--band-lines", action="store_true",
                   help=_("draw level lines at the borders of the colour bands (parabolic lines, Dill's band edges, "
                          "the colour bar's ticks), so the picture reads without colour"))
    r.add_argument("--legend", action=argparse.BooleanOptionalAction, default=True,
                   help=_("draw the colour bar or classification legend in curvature units (default: yes)"))
    r.add_argument("--title", nargs="?", const=True, default=True, metavar="TEXT",
                   help=_("title of the picture (default: surface, measure, map and depth)"))
    r.add_argument("--no-title", dest="title", action="store_false", help=_("no title"))
    r.add_argument("--draft", type=_pull, metavar="X,Y,Z",
                   help=_("colour by the draft angle against this pull direction, with the parting line (0°) in black"))
    r.add_argument("--min-radius", type=float, metavar="R",
                   help=_("colour red where the smallest radius of curvature is below R"))
    r.add_argument("--deviation", metavar="SCAN",
                   help=_("colour by the signed distance of a scan's points to the part or surface (PLY, STL, OBJ, "
                          "XYZ …; see lab.deviation), grey where nothing was scanned; prints the statistics"))
    r.add_argument("--tolerance", type=float, metavar="T",
                   help=_("with --deviation: the tolerance band -T … T (default: 0.1 %% of the part's size)"))
    r.add_argument("--deviation-map", choices=("graded", "bands"), default="graded",
                   help=_("with --deviation: graded beyond the tolerance, or three bands (default: graded)"))
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
    for verb, text in VERBS.items():
        sub.add_parser(verb, help=f"{_(text)} (curvature-lab {verb} --help)", add_help=False)
    return parser


#: The course's commands, in the order a course uses them: verb -> help; each is ``lab.teaching.course.<verb>``, whose
#: ``main(argv)`` parses the verb's own options.
VERBS = {
    "start": N_("copy the exercise notebooks into a folder and open JupyterLab there (self-study)"),
    "exercises": N_("generate exercises/{en,de} and solutions/{en,de} from the bilingual solutions/"),
    "release": N_("write the students' hand-out: exercises and the library without the answers"),
    "collect": N_("collect an assignment from the students' homes, with hand-in times and lateness"),
    "similarity": N_("rank the pairs of submissions by shared code and text (evidence, not a verdict)"),
    "grade": N_("grade a notebook or a folder of submissions in a sandbox"),
    "mark": N_("mark the written answers of a collected assignment in JupyterLab"),
    "feedback": N_("put each student's report into the student's home"),
    "gradebook": N_("one row per student and a total, for Canvas, Moodle or CSV"),
    "gradescope": N_("build a Gradescope autograder zip for an assignment"),
}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        if argv and argv[0] in VERBS:
            import importlib

            return importlib.import_module(f"lab.teaching.course.{argv[0]}").main(argv[1:])
        parser = build_parser()
        args = parser.parse_args(argv)
        if args.command == "render" and args.resolution < 1:
            parser.error(f"--resolution must be at least 1; got {args.resolution}")
        return args.func(args, parser)
    except OSError as exc:  # a file or folder the command cannot read or write (missing, a name too long, no right)
        verb = argv[0] if argv and not argv[0].startswith("-") else ""
        print(f"curvature-lab {verb}: error: {exc}".replace("  ", " "), file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
