"""The lab's picture gallery: ``python -m lab.view.gallery`` (or ``make docs``) redraws every picture in ``docs/``.

Each picture is made by running the command line (``python -m lab.cli
render``, in a subprocess: the CLI sits above this layer), with the options
written under it in the site's gallery (``docs/gallery/index.md``, made from :data:`PICTURES` when the site is
built), so the README, the gallery and a student's own call give the same picture with the same caption.  Rendering is
deterministic (fixed sizes, the automatic camera is a fixed rule), so
re-running the command after a change of the library redraws exactly what
changed.
"""

import argparse
import subprocess
import sys
from pathlib import Path

__all__ = ["PICTURES", "SIZE", "main"]

#: The size every picture is drawn at.
SIZE = "800x600"

#: (file name, ``curvature-lab render`` options, caption); README pictures live in docs/, the others in docs/gallery/.
PICTURES = [
    ("practical_gaussian_linear.png",
     "--surface practical --curvature gaussian --color-map linear --depth 1 --edges",
     ("The practical's setting: its B-spline surface as 7 × 7 Bézier patches refined once (patch borders drawn), "
      "Gaussian curvature with the linear map h∘f2. The bump's top (K ≈ 37 at the corners) takes the red end of "
      "the range, so everything else, K from −1.1 to 0.53, is blue.")),
    ("practical_gaussian_signed_log.png",
     "--surface practical --curvature gaussian --color-map signed-log --depth 3",
     ("The same surface refined three times, with the signed-logarithmic map: the elliptic top of the bump (red to "
      "yellow), hyperbolic zones on both sides of its foot (cyan, K ≈ −1), and |K| below 0.1 everywhere else "
      "(green, yellow-green where slightly positive).")),
    ("gallery/practical_gaussian_classification.png",
     "--surface practical --curvature gaussian --color-map classification --depth 3",
     ("Classification by the sign of K (h∘f3): elliptic (red) on the bump's top and in two gently convex regions, "
      "one behind the bump and one in front of it; hyperbolic (blue) everywhere else; the parabolic lines lie on "
      "the red–blue borders.")),
    ("gallery/practical_mean_symmetric.png",
     "--surface practical --curvature mean --color-map symmetric --depth 3",
     ("Mean curvature H with the zero-centred map (green at H = 0): only the bump's top stands out. The sign of H, "
      "and so the end of the scale it takes, follows the orientation of the normal N = b_u × b_v / |b_u × b_v|.")),
    ("gallery/torus_gaussian_classification.png",
     "--surface torus --curvature gaussian --color-map classification --depth 3",
     "Torus: elliptic outside (red), hyperbolic inside (blue), parabolic circles on top and bottom (green)."),
    ("gallery/torus_gaussian_dill.png",
     "--surface torus --curvature gaussian --color-map dill --vmin -1 --vmax 0.3333 --depth 3",
     "Torus with Dill's five bands over −1 … 1/3 (his figure 7): the bands follow the parallels."),
    ("gallery/practical_gaussian_classification_deuteranopia.png",
     "--surface practical --curvature gaussian --color-map classification --depth 3 --simulate deuteranopia",
     ("The classification h∘f3 above as a deuteranope sees it (simulated after Machado et al. 2009): elliptic red "
      "and parabolic green both turn olive-yellow (ΔE 25 in CAM02-UCS), only the blue stays apart.")),
    ("gallery/practical_gaussian_classification_vik.png",
     "--surface practical --curvature gaussian --color-map classification-vik --depth 3 --band-lines",
     ("The same classification in colours every student can read: hyperbolic navy, parabolic near-white, elliptic "
      "burnt orange (three colours of Crameri's vik, at least 48 apart under every simulated deficiency), with the "
      "parabolic lines drawn, so that the borders do not depend on colour at all.")),
    ("gallery/torus_gaussian_dill_batlow.png",
     "--surface torus --curvature gaussian --color-map dill-batlow --vmin -1 --vmax 0.3333 --depth 3 --band-lines",
     ("Torus with Dill's five bands in five lightnesses of batlow instead of the rainbow, each band named in the "
      "legend (its range and whether it is elliptic, near parabolic or hyperbolic) and its edges drawn.")),
    ("gallery/hood_mean_dill.png",
     "--surface hood --curvature mean --color-map dill --vmin -1.5 --vmax 0.5 --depth 3",
     "Car hood (Dill's figure 9), mean curvature in five bands: the crease is the narrow band of strong curvature."),
    ("gallery/catenoid_gaussian_dill.png",
     "--surface catenoid --curvature gaussian --color-map dill --vmin -1 --vmax 0 --depth 2",
     ("Catenoid (Dill's figure 8), seen from above into its waist: K from −1 at the waist (blue) to nearly 0 on the "
      "flaring rims (red); H = 0 everywhere.")),
    ("gallery/monkey-saddle_gaussian_symmetric.png",
     "--surface monkey-saddle --curvature gaussian --color-map symmetric --depth 3",
     ("Monkey saddle: K < 0 everywhere except at the flat point in the middle (green), most negative on a ring "
      "around it.")),
    ("gallery/teapot_gaussian_classification.png",
     "--model teapot --curvature gaussian --color-map classification --depth 2 --camera -100,25",
     ("Newell's teapot (32 bicubic Bézier faces, each on 33 × 33 lines, one colour range over all) classified by "
      "the sign of K: the body, the lid and the knob are elliptic (red) like a sphere; hyperbolic (blue) are the "
      "saddles: the inner side of the handle, the spout's underside and its mouth, the knob's neck and the "
      "lid's dip around it, the bands where the lid meets its rim, where the rim meets the body and where the "
      "body curls under into the bottom. The lid's top and "
      "the bottom's centre are collapsed patch edges (degenerate points, b_u × b_v = 0): their colour is the "
      "limit from inside the faces, elliptic. K's sign does not depend on the normal (the file's patches face "
      "inwards).")),
    ("gallery/hammer_mean_signed_log.png",
     "--model hammer --curvature mean --color-map signed-log --depth 2",
     ("A real CAD part: OpenCASCADE's hammer (BREP, 45 trimmed B-spline faces, each on 33 × 33 lines), mean "
      "curvature H with the signed-log map. H's sign follows each face's normal, which the file orients out of "
      "the solid (9 faces are stored reversed; lab.read flips them): where the part is convex it bends away "
      "from the outside and H < 0, as on a sphere with its outward normal (blue: the rounded rims of the head "
      "and the handle, the handle itself, H ≈ −1/(2r)); where it is concave H > 0 (yellow: the hollowed flanks "
      "of the neck between head and face, curved one way only, K = 0, H = κ1/2). The flat faces have H = 0 "
      "(green).")),
    ("gallery/impeller_gaussian_signed_log.png",
     "--model impeller --curvature gaussian --color-map signed-log --depth 1 --camera 30,-50",
     ("The impeller of pyiges' examples (IGES, 277 trimmed faces, each on 17 × 17 lines), seen from below, "
      "Gaussian curvature K with the signed-log map: the blades are nearly developable (K ≈ 0, green), their "
      "rounded edges and the bore elliptic or parabolic, the fillets at the blades' roots hyperbolic. The IGES "
      "file gives no face orientation (by a ray test, 188 of its 277 faces have normals into the solid), so it is coloured "
      "by K, whose sign does not depend on the normal.")),
]


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m lab.view.gallery", description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs", help="the docs folder (default: docs)")
    parser.add_argument("--size", default=SIZE, help=f"picture size (default: {SIZE})")
    parser.add_argument("--only", help="only the pictures whose file name contains this text")
    args = parser.parse_args(argv)
    out = Path(args.out)
    (out / "gallery").mkdir(parents=True, exist_ok=True)
    for name, options, _caption in PICTURES:
        if args.only and args.only not in name:
            continue
        path = out / name
        command = [sys.executable, "-m", "lab.cli", "render", *options.split(), "--window-size", args.size, "--quiet",
                   "-o", str(path)]
        result = subprocess.run(command, capture_output=True, text=True, check=False)
        if result.returncode:
            print(result.stderr, file=sys.stderr)
            return result.returncode
        print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
