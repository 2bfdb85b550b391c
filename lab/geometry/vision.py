r"""Colour as a student with a colour-vision deficiency sees it, and how far apart colours are (``colorspacious``).

About one man in twelve sees red and green differently (most of them deuteranomalous).  :func:`simulate`
shows colours as a dichromat sees them, after Machado, Oliveira & Fernandes (2009): a 3 × 3 matrix applied to
linear sRGB, for protanopia (no L cones), deuteranopia (no M cones) and tritanopia (no S cones), as implemented
by ``colorspacious`` (``cspace_convert`` with ``{"name": "sRGB1+CVD", "cvd_type": …, "severity": 100}``; a
severity below 100 is the anomalous trichromacy on the way there).  :func:`delta_e` measures the distance of two
colours in CAM02-UCS (Luo, Cui & Li 2006), a colour space in which equal distances look about equally different:
a ΔE of 1 is barely visible, 10 clearly, 40 at a glance.  :func:`measure` applies both to a colour map of
:data:`lab.geometry.colormaps.COLOR_MAPS` (``benchmarks/colors.py`` prints the table of all of them).  numpy and
colorspacious only.
"""

import dataclasses
import functools

import numpy as np

from ..i18n import N_, _

__all__ = ["DEFICIENCIES", "NAMES", "VISIONS", "MapMeasure", "delta_e", "lightness", "measure", "monotonic", "name",
           "simulate", "simulate_image", "smallest_difference"]

#: The simulated deficiencies -> colorspacious's ``cvd_type`` (at severity 100 the anomaly is the -opia).
DEFICIENCIES = {"protanopia": "protanomaly", "deuteranopia": "deuteranomaly", "tritanopia": "tritanomaly"}
#: The deficiencies as a student reads them (translated with ``_``).
NAMES = {"protanopia": N_("protanopia"), "deuteranopia": N_("deuteranopia"), "tritanopia": N_("tritanopia")}
#: Normal vision (None) and the three deficiencies, in the order tables list them.
VISIONS = (None, *DEFICIENCIES)
#: Normal vision as a table names it (marked for translation).
NORMAL = N_("normal")


def name(vision):
    """A vision of :data:`VISIONS` as a student reads it, in the lab's language: None is "normal", a deficiency its
    name (German "Deuteranopie" for "deuteranopia")."""
    if vision is not None and vision not in NAMES:
        raise ValueError(f"vision must be None or one of {', '.join(NAMES)}; got {vision!r}")
    return _(NORMAL if vision is None else NAMES[vision])


@functools.cache
def _colorspacious():
    try:
        import colorspacious
    except ImportError:  # pragma: no cover - a dependency of the lab
        raise ImportError("simulating colour-vision deficiencies needs the package colorspacious; "
                          "install it: pip install colorspacious") from None
    return colorspacious


def _rgb(rgb, name="rgb"):
    if isinstance(rgb, (str, bytes)) or rgb is None:
        raise TypeError(f"{name} must be an array of sRGB colours (..., 3) in [0, 1]; got {type(rgb).__name__}")
    try:
        a = np.asarray(rgb, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be an array of sRGB colours (..., 3) in [0, 1]; got {type(rgb).__name__}") from None
    if a.ndim == 0 or a.shape[-1] != 3:
        raise ValueError(f"{name} must have 3 channels (R, G, B) in its last axis; got shape {a.shape}")
    if not np.all(np.isfinite(a)) or (a.size and (a.min() < -1e-9 or a.max() > 1 + 1e-9)):
        raise ValueError(f"{name} must be sRGB colours in [0, 1] (divide 8-bit colours by 255); got values in "
                         f"[{np.nanmin(a):g}, {np.nanmax(a):g}]")
    return np.clip(a, 0.0, 1.0)


def check_deficiency(deficiency):
    """``deficiency`` if it is one of :data:`DEFICIENCIES` (or None: normal vision), else a ValueError."""
    if deficiency is not None and deficiency not in DEFICIENCIES:
        raise ValueError(f"deficiency must be one of {', '.join(DEFICIENCIES)} (or None for normal vision); "
                         f"got {deficiency!r}")
    return deficiency


def simulate(rgb, deficiency, severity=100):
    """``rgb`` (sRGB in [0, 1], any shape ``(..., 3)``) as seen with ``deficiency`` (Machado et al. 2009).

    ``deficiency`` is ``"protanopia"``, ``"deuteranopia"``, ``"tritanopia"`` or None (normal vision: ``rgb``
    unchanged); ``severity`` 0 … 100 (100: the dichromacy).  Colours the matrix takes out of the sRGB gamut are
    clipped back into [0, 1].  Each distinct colour is converted once (a picture has few of them).
    """
    rgb = _rgb(rgb)
    if check_deficiency(deficiency) is None:
        return rgb.copy()
    if isinstance(severity, bool) or not isinstance(severity, (int, float, np.integer, np.floating)) or \
            not 0 <= severity <= 100:
        raise ValueError(f"severity must be a number from 0 to 100; got {severity!r}")
    flat = rgb.reshape(-1, 3)
    unique, inverse = np.unique(flat, axis=0, return_inverse=True)
    space = {"name": "sRGB1+CVD", "cvd_type": DEFICIENCIES[deficiency], "severity": float(severity)}
    seen = _colorspacious().cspace_convert(unique, space, "sRGB1")
    return np.clip(seen, 0.0, 1.0)[inverse.reshape(-1)].reshape(rgb.shape)


def simulate_image(image, deficiency):
    """An 8-bit RGB(A) picture (``(h, w, 3 or 4)`` uint8) as seen with ``deficiency``; alpha is kept."""
    image = np.asarray(image)
    if image.dtype != np.uint8 or image.ndim != 3 or image.shape[-1] not in (3, 4):
        raise TypeError(f"image must be an 8-bit RGB or RGBA picture (h, w, 3 or 4) uint8; got {image.dtype} "
                        f"{image.shape}")
    if check_deficiency(deficiency) is None:
        return image.copy()
    out = image.copy()
    out[..., :3] = np.rint(simulate(image[..., :3] / 255.0, deficiency) * 255).astype(np.uint8)
    return out


def _ucs(rgb):
    return _colorspacious().cspace_convert(_rgb(rgb), "sRGB1", "CAM02-UCS")


def delta_e(a, b):
    """The CAM02-UCS colour difference ΔE of sRGB colours ``a`` and ``b`` (broadcast; in [0, 1])."""
    return np.linalg.norm(_ucs(a) - _ucs(b), axis=-1)


def lightness(rgb):
    """The CAM02-UCS lightness J' of sRGB colours (0 black … 100 white)."""
    return _ucs(rgb)[..., 0]


def smallest_difference(colors):
    """The smallest ΔE between two of ``colors`` ``(n, 3)`` (all pairs), and the pair ``(i, j)`` that has it."""
    c = _ucs(colors).reshape(-1, 3)
    if len(c) < 2:
        raise ValueError(f"smallest_difference needs at least two colours; got {len(c)}")
    d = np.linalg.norm(c[:, None] - c[None], axis=-1)
    d[np.tri(len(c), dtype=bool)] = np.inf
    i, j = np.unravel_index(np.argmin(d), d.shape)
    return float(d[i, j]), (int(i), int(j))


#: The values at which a continuous map's colours are compared (its range set to [-1, 1] by these values).
STEPS = (-1.0, -0.5, 0.0, 0.5, 1.0)


@dataclasses.dataclass(frozen=True)
class MapMeasure:
    """How readable a colour map is: the smallest ΔE between its classes (or steps) per vision, lightness order.

    Attributes
    ----------
    name : str
    kind : str
        ``"classes"`` (classification, Dill's bands: all pairs of its colours), ``"sequential"`` or
        ``"diverging"`` (neighbouring colours at :data:`STEPS`).
    colors : ndarray
        The colours compared.
    smallest : dict
        Vision (None, ``"protanopia"`` …) -> the smallest ΔE.
    ordered : bool
        Lightness monotonic along the map (a diverging map: on each side of 0; classes: along the classes'
        order, or on each side of the middle class).
    """

    name: str
    kind: str
    colors: np.ndarray
    smallest: dict
    ordered: bool

    @property
    def worst(self):
        """The smallest ΔE over normal vision and all three deficiencies."""
        return min(self.smallest.values())


def monotonic(J, tol=1.0):
    """Whether ``J`` rises (or falls) throughout, never dropping more than ``tol`` below a value before it."""
    J = np.asarray(J, dtype=float)
    rising = np.max(np.maximum.accumulate(J) - J) <= tol
    falling = np.max(J - np.minimum.accumulate(J)) <= tol
    return bool(rising or falling)


def measure(name):
    """:class:`MapMeasure` of the colour map ``name`` of :data:`lab.geometry.colormaps.COLOR_MAPS`.

    A classification or banded map is compared over all pairs of its colours; a continuous map over the
    neighbours among its colours at −1, −½, 0, ½, 1 (its range taken from these values; h∘f1, whose range is
    [0, 1], at 0, ¼, ½, ¾, 1).  Lightness order is judged on 257 colours along the map, up to 1 unit of J' (a
    step at the threshold of visibility: vik's lightest colour lies at 0.494, a hair before its middle).
    """
    from . import colormaps

    if name not in colormaps.COLOR_MAPS:
        raise ValueError(f"unknown colour map {name!r}; expected one of {', '.join(colormaps.COLOR_MAPS)}")
    base = colormaps.normalisation(name)
    if base in ("classification", "dill"):
        values = np.array([-1.0, 0.0, 1.0]) if base == "classification" else \
            np.array(colormaps.DILL_RANGE[0]) + (np.arange(5) + 0.5) * np.diff(colormaps.DILL_RANGE) / 5
        colors = colormaps.colors_for(values, name)
        dense = colors
        kind = "classes"
    else:
        values = np.array(STEPS)
        dense_values = np.linspace(-1.0, 1.0, 257)
        if base == "cut":
            values, dense_values = (values + 1) / 2, (dense_values + 1) / 2
        colors = colormaps.colors_for(values, name)
        dense = colormaps.colors_for(dense_values, name)
        kind = "diverging" if base in ("symmetric", "signed-log") else "sequential"
    smallest = {}
    for vision in VISIONS:
        seen = simulate(colors, vision)
        if kind == "classes":
            smallest[vision] = smallest_difference(seen)[0]
        else:
            smallest[vision] = float(np.min(delta_e(seen[:-1], seen[1:])))
    J = lightness(dense)
    if kind == "sequential" or (kind == "classes" and len(J) == 5):
        ordered = monotonic(J)
    else:  # diverging, or the three classes: each side of the middle
        mid = len(J) // 2
        ordered = monotonic(J[: mid + 1]) and monotonic(J[mid:]) and len(J) > 2 and \
            (J[mid] - J[0]) * (J[mid] - J[-1]) > 0
    return MapMeasure(name, kind, colors, smallest, ordered)
