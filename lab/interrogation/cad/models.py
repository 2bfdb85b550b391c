"""Real parts to interrogate, from the packages the installation brings (origins and licences: the site, Library → "Real parts").

- OpenCASCADE's sample data (Debian's ``occt-misc``, LGPL-2.1 with OCCT's exception), in
  ``/usr/share/opencascade/data`` or the folder ``LAB_OCC_DATA`` names: :func:`wing`, :func:`shell`,
  :func:`hammer`, :func:`terrain`, :func:`linkrods`, :func:`bottle`, :func:`sample`.
- The impeller that ``pyiges`` ships (MIT): :func:`impeller`.
- Newell's teapot (public domain data), shipped with the lab: :func:`teapot`.
"""

import os
from pathlib import Path

from ...i18n import _

__all__ = ["bottle", "hammer", "impeller", "impeller_path", "linkrods", "occ_data", "sample", "shell", "teapot", "terrain",
           "wing"]


def occ_data():
    """The folder of OpenCASCADE's sample data (``LAB_OCC_DATA``, else Debian's ``/usr/share/opencascade/data``)."""
    return Path(os.environ.get("LAB_OCC_DATA", "/usr/share/opencascade/data"))


def sample(name):
    """A part from OpenCASCADE's sample data by its path there, e.g. ``"occ/Top.brep"`` or ``"iges/bearing.iges"``."""
    from . import read

    path = occ_data() / name
    if not path.is_file():
        raise FileNotFoundError(_("{path}: OpenCASCADE's sample part is missing. On Debian or Ubuntu: apt install "
                                  "occt-misc (make setup does). Elsewhere: download OpenCASCADE's source (its data "
                                  "folder holds occ/, iges/ and step/) and set LAB_OCC_DATA to that data folder. "
                                  "lab.models.teapot() needs neither").format(path=path))
    return read(path)


def wing():
    """OpenCASCADE's ``occ/wing.brep``: a wing of 4 B-spline faces."""
    return sample("occ/wing.brep")


def shell():
    """OpenCASCADE's ``occ/shell1.brep``: a shell of 99 B-spline faces."""
    return sample("occ/shell1.brep")


def hammer():
    """OpenCASCADE's ``occ/hammer.brep``: a hammer head of 45 B-spline faces (9 reversed)."""
    return sample("occ/hammer.brep")


def terrain():
    """OpenCASCADE's ``occ/terrain.brep``: one B-spline face."""
    return sample("occ/terrain.brep")


def linkrods():
    """OpenCASCADE's ``step/linkrods.step``: 37 faces, 18 B-spline, the others planes, cylinders and tori."""
    return sample("step/linkrods.step")


def bottle():
    """OpenCASCADE's ``occ/bottle.brep``: 71 faces, mostly analytic, a thread among them (a cylinder face that winds twice)."""
    return sample("occ/bottle.brep")


def impeller_path():
    """The path of ``impeller.igs`` in the installed ``pyiges`` (its examples folder)."""
    try:
        import pyiges.examples
    except ImportError:
        raise ImportError(_("the impeller comes with the package pyiges: pip install -e '.[cad]' "
                            "(make setup installs it)")) from None
    return Path(pyiges.examples.__file__).parent / "impeller.igs"


def impeller(orient=False):
    """The impeller of ``pyiges``'s examples (IGES): 277 faces, 247 trimmed NURBS and 30 surfaces of revolution.

    ``orient=True`` orients its faces outwards (see :func:`lab.read`; 245 of them point inwards in the file), which
    sews them during the read (about 12 s)."""
    from . import read

    return read(impeller_path(), orient=orient)


def teapot():
    """Newell's teapot as 32 bicubic Bézier faces with the bottom (``lab/interrogation/cad/data/teapot.bbp``).

    Patches 0-27 are the original's (as Debian's geomview ships them), 28-31 the bottom of Newell's 32-patch
    set; the lid's top and the bottom's centre are collapsed patch edges, so their points are degenerate
    (flagged, with the limit values; see :meth:`lab.Surface.curvature`).
    """
    from .geomview import read_geomview

    return read_geomview(Path(__file__).parent / "data" / "teapot.bbp", name="teapot")
