r"""Colour tables of Crameri's scientific colour maps, read from the ``cmcrameri`` package's own data files.

The practical's ramp :math:`h` is a rainbow: its lightness rises and falls (yellow and cyan are light, blue
and red dark), so a smooth change of curvature shows a false edge where the ramp turns, and green, yellow and
cyan become one band for a student with a colour-vision deficiency (Borland & Taylor 2007; Crameri,
Shephard & Heron 2020).  The maps here replace :math:`h` in the second stage of the practical's recipe
(normalise, then ramp), never the normalisations:

* **batlow** (Crameri 2018, "Scientific colour maps", version 8): perceptually uniform and sequential, its
  lightness rises from dark blue to light pink; for unsigned measures and min/max ranges.
* **vik** (Crameri 2018): diverging, dark blue → near-white at 0 → dark red-brown; lightness rises to the middle
  and falls after it, so the sign of K or H reads as dark–light–dark around a white zero.
* **the classification** in three colours of vik: navy (position 0), near-white (0.5) and burnt orange (0.85),
  which stay at least 40 apart (CAM02-UCS ΔE) under protanopia, deuteranopia and tritanopia
  (:mod:`lab.geometry.vision`; ``benchmarks/colors.py``); 0.85 rather than vik's dark end keeps the orange
  bright enough to differ from the navy in lightness, not only in hue.
* **Dill's five bands** in five colours of batlow (positions 0, ¼, ½, ¾, 1): the lightness rises band by band.

The tables are the 256 sRGB colours (0 … 1) that ``cmcrameri`` ships as text files (``cmaps/<name>.txt``), read
without importing ``cmcrameri``, which would import matplotlib (not allowed in this layer).  numpy only.
"""

import functools
import importlib.util
import os

import numpy as np

__all__ = ["BAND_POSITIONS", "CLASS_POSITIONS", "PALETTES", "bands", "classes", "ramp", "table"]

#: The Crameri maps the lab uses (name -> what it is for).
PALETTES = {"batlow": "sequential", "vik": "diverging"}
#: Where the classification's colours sit on vik: hyperbolic (K < 0), parabolic (K = 0), elliptic (K > 0).
CLASS_POSITIONS = (0.0, 0.5, 0.85)
#: Where Dill's five bands take their colours on batlow, lowest band first.
BAND_POSITIONS = (0.0, 0.25, 0.5, 0.75, 1.0)


@functools.cache
def table(name):
    """The ``(256, 3)`` sRGB table of Crameri's map ``name`` (``"batlow"``, ``"vik"``), from ``cmcrameri``'s data."""
    if name not in PALETTES:
        raise ValueError(f"unknown palette {name!r}; expected one of {', '.join(PALETTES)}")
    spec = importlib.util.find_spec("cmcrameri")  # finds the package without running it (it imports matplotlib)
    if spec is None or not spec.submodule_search_locations:
        raise ImportError("the colour maps batlow and vik come from the package cmcrameri (Crameri's scientific colour "
                          "maps); install it: pip install cmcrameri")
    path = os.path.join(spec.submodule_search_locations[0], "cmaps", f"{name}.txt")
    data = np.loadtxt(path, dtype=float)
    if data.ndim != 2 or data.shape[1] != 3 or not np.all((data >= 0) & (data <= 1)):
        raise ValueError(f"{path} is not a table of sRGB colours in [0, 1]; got shape {data.shape}")
    data.setflags(write=False)
    return data


def ramp(name, x):
    """Colours of ``x`` (values in [0, 1]) on the map ``name``: the table interpolated linearly; ``x.shape + (3,)``."""
    x = np.asarray(x, dtype=float)
    if x.size and (np.nanmin(x) < -1e-12 or np.nanmax(x) > 1 + 1e-12):
        raise ValueError(f"the {name} ramp expects values in [0, 1]; got values in [{np.nanmin(x):g}, {np.nanmax(x):g}]")
    t = table(name)
    s = np.clip(x, 0.0, 1.0) * (len(t) - 1)
    i = np.minimum(s.astype(int), len(t) - 2)
    w = (s - i)[..., None]
    return t[i] * (1 - w) + t[i + 1] * w


def classes():
    """The classification's three colours, hyperbolic, parabolic, elliptic (:data:`CLASS_POSITIONS` on vik)."""
    return ramp("vik", np.array(CLASS_POSITIONS))


def bands():
    """The five colours of Dill's bands, lowest first (:data:`BAND_POSITIONS` on batlow)."""
    return ramp("batlow", np.array(BAND_POSITIONS))
