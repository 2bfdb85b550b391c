r"""Colour maps from curvature values to RGB (the practical's sheet, §4; Dill 1981).

The practical colours in two stages: a function :math:`f:\mathbb R\to[0,1]`
normalises a curvature value and the ramp :math:`h:[0,1]\to[0,1]^3` turns it
into a colour, blue (small) → green (middle) → red (large):

.. math::
    :label: colormaps-1

    h(x) = \begin{cases} (0, 4x, 1) & 0 \le x \le 0.25\\ (0, 1, 2-4x) & 0.25 < x \le 0.5\\
                          (4x-2, 1, 0) & 0.5 < x \le 0.75\\ (1, 4-4x, 0) & 0.75 < x \le 1\end{cases}

with the normalisations :func:`f1` (cut), :func:`f2` (linear min/max) and
:func:`f3` (classification by sign).  :func:`dill` is the five-band table of
Dill's figure 6; :func:`symmetric`, :func:`percentile` and :func:`signed_log`
are our answers to the practical's question "Entwerfen Sie selbst andere
sinnvolle Funktionen".  Every map takes an array of values and returns
colours of shape ``values.shape + (3,)``.

Beside the practical's maps, which keep the ramp :math:`h`, five maps keep a normalisation and replace
:math:`h` by one of Crameri's scientific colour maps (:mod:`lab.geometry.palettes`), readable with a
colour-vision deficiency (measured in :mod:`lab.geometry.vision`): ``linear-batlow`` (f2, batlow),
``symmetric-vik`` and ``signed-log-vik`` (zero in vik's white middle), ``classification-vik`` (f3 in navy,
near-white and burnt orange) and ``dill-batlow`` (Dill's bands in five lightnesses of batlow).  Their names
say both stages: normalisation, then ramp.
"""

import enum
import math

import numpy as np

from ..i18n import N_, _
from . import palettes
from . import validation as _v
from .validation import as_number

__all__ = [
    "COLOR_MAPS",
    "DILL_COLORS",
    "DILL_NAMES",
    "DILL_RANGE",
    "ZERO_TOL",
    "ColorMap",
    "apply",
    "colors_for",
    "dill",
    "dill_names",
    "f1",
    "f2",
    "f3",
    "h",
    "map_range",
    "normalisation",
    "percentile",
    "signed_log",
    "symmetric",
]

#: Default tolerance below which a value counts as zero in :func:`f3`.
ZERO_TOL = 1e-9
#: Values coloured at a time by :func:`colors_for`.
COLOR_CHUNK = 16384

#: Dill's colours, from the lowest band to the highest (figure 6).
DILL_COLORS = np.array(
    [
        [0.0, 0.0, 1.0],  # blue
        [0.0, 1.0, 1.0],  # turquoise
        [0.0, 1.0, 0.0],  # green
        [1.0, 1.0, 0.0],  # yellow
        [1.0, 0.0, 0.0],  # red
    ]
)
#: The names of Dill's colours, in the order of :data:`DILL_COLORS` (English, marked for translation: :func:`dill_names`
#: gives them in the lab's language).
DILL_NAMES = (N_("blue"), N_("turquoise"), N_("green"), N_("yellow"), N_("red"))
#: Dill's default curvature range, five bands of width 0.02.
DILL_RANGE = (-0.07, 0.03)


def _values(x, name="values"):
    x = _v.as_array(x, name, finite=False)
    # the maps make a few temporaries of the values' size (and copy a broadcast view): estimated first
    _v.check_memory(8.0 * 4 * x.size, f"a colour map of {_v.format_count(x.size)} values")
    low, high = (x.min(), x.max()) if x.size else (0.0, 0.0)  # NaN and inf show here, without a temporary array
    if np.isnan(low):
        raise ValueError(f"{name} contain NaN; colour maps need finite numbers (a NaN comes from 0/0 or from the "
                         "square root of a negative number, e.g. √(H² − K) at an umbilic point)")
    if np.isinf(low) or np.isinf(high):
        raise ValueError(f"{name} must be finite for a colour map; got inf (lab.colormaps.colors_for paints "
                         "non-finite values grey)")
    return x


def _scalar(x):
    """``x`` as a float when it is one real number (the practical's per-corner calls), else None.

    The scalar paths of :func:`h` and :func:`f2` give the same numbers as the array paths, only without numpy's
    per-call overhead (a student's loop calls them 12 545 times for the practical's surface at depth 3).
    """
    if type(x) in (float, int) or isinstance(x, (np.floating, np.integer)):
        try:
            x = float(x)
        except OverflowError:  # an int beyond the float range: the array path names it
            return None
        return x if math.isfinite(x) else None  # NaN and inf: the array path raises its messages
    return None


def _number(value, name, minimum=None):
    """:func:`as_number` for a parameter, with the scalar path's shortcut for a plain finite float in range."""
    s = _scalar(value)
    if s is not None and (minimum is None or s >= minimum):
        return s
    return as_number(value, name, minimum=minimum)


def _range_needs_values(x, what, given):
    """A map that finds its range from the values refuses an empty array unless the range is ``given``."""
    if not x.size:
        raise ValueError(f"{what} needs at least one value to find its range; got an empty array (give {given} "
                         "to colour no values)")


def h(x):
    r"""The practical's colour ramp :math:`h: [0,1] \to [0,1]^3` (blue → green → red).

    Parameters
    ----------
    x : array_like
        Values in [0, 1].

    Returns
    -------
    ndarray, shape ``x.shape + (3,)``
    """
    s = _scalar(x)
    if s is not None:
        if s < -1e-12 or s > 1 + 1e-12:
            raise ValueError(f"h expects values in [0, 1]; got {s:g}")
        s = min(max(s, 0.0), 1.0)
        g = 4.0 * s if s <= 0.25 else 1.0 if s <= 0.75 else 4.0 - 4.0 * s
        return np.array([min(max(4.0 * s - 2.0, 0.0), 1.0), g, min(max(2.0 - 4.0 * s, 0.0), 1.0)])
    x = _values(x)
    if x.size and (x.min() < -1e-12 or x.max() > 1 + 1e-12):
        raise ValueError(f"h expects values in [0, 1]; got values in [{x.min():g}, {x.max():g}]")
    x = np.clip(x, 0.0, 1.0)
    r = np.clip(4.0 * x - 2.0, 0.0, 1.0)
    g = np.where(x <= 0.25, 4.0 * x, np.where(x <= 0.75, 1.0, 4.0 - 4.0 * x))
    b = np.clip(2.0 - 4.0 * x, 0.0, 1.0)
    return np.stack([r, g, b], axis=-1)


def f1(x):
    """Cut: values below 0 become 0, above 1 become 1, others stay.

    Pros: absolute, so colours of different surfaces compare; no parameters.
    Cons: only curvature in [0, 1] is resolved, which depends on the units of
    the model; everything negative is the same blue.
    """
    return np.clip(_values(x), 0.0, 1.0)


def f2(x, vmin=None, vmax=None, *, atol=0.0, rtol=1e-9):
    r"""Linear: :math:`(x - \kappa_{min}) / (\kappa_{max} - \kappa_{min})`, min/max over all values.

    When all values are equal (a plane, a sphere) the quotient is 0/0; the
    result is then 0.5 (green) everywhere.  Values that differ only by
    rounding noise, ``max - min <= max(atol, rtol * max|x|)``, count as equal
    too, so a sphere is not painted with its rounding errors.

    Pros: uses the whole colour range for any surface.
    Cons: one outlier (a near-degenerate point) squeezes all other colours
    together; the colour of zero curvature moves from surface to surface, so
    the sign cannot be read off.
    """
    s = _scalar(x)
    x = np.float64(s) if s is not None else _values(x)
    if vmin is None or vmax is None:
        _range_needs_values(x, "f2", "vmin and vmax")
    lo = np.min(x) if vmin is None else _number(vmin, "vmin")
    hi = np.max(x) if vmax is None else _number(vmax, "vmax")
    atol, rtol = _number(atol, "atol", minimum=0), _number(rtol, "rtol", minimum=0)
    if hi < lo:
        raise ValueError(f"f2 needs vmin <= vmax; got vmin={lo:g}, vmax={hi:g}")
    # halves throughout: hi - lo and x - lo overflow for values near the float limit (1.7e308 - -1.7e308)
    half_span = hi / 2 - lo / 2
    if half_span <= max(atol, rtol * max(abs(lo), abs(hi))) / 2:
        return np.full(np.shape(x), 0.5)
    if s is not None:
        return np.float64(min(max((s / 2 - lo / 2) / half_span, 0.0), 1.0))
    return np.clip((x / 2 - lo / 2) / half_span, 0.0, 1.0)


def f3(x, tol=ZERO_TOL):
    """Classification: 0 for ``x < -tol``, 0.5 for ``|x| <= tol``, 1 for ``x > tol``.

    Applied to the Gaussian curvature it paints hyperbolic points blue,
    parabolic and flat points green and elliptic points red (practical 2.4).
    The tolerance matters: computed curvature of a cylinder is rounding noise
    around 0, never exactly 0.

    Pros: shows the shape class at a glance, independent of scale.
    Cons: no magnitude at all; parabolic lines are thin and may fall between vertices.
    """
    x = _values(x)
    tol = as_number(tol, "tol", minimum=0)
    return np.where(x > tol, 1.0, np.where(x < -tol, 0.0, 0.5))


def symmetric(x, vmax=None):
    """Zero-centred linear map: ``0.5 + x / (2 max|x|)``, so zero curvature is always green.

    Pros: the sign is readable (blue < 0 < red) and magnitudes are linear.
    Cons: a surface whose curvature is all of one sign uses only half the ramp.
    """
    x = _values(x)
    if vmax is None:
        _range_needs_values(x, "symmetric", "vmax")
    m = np.max(np.abs(x)) if vmax is None else as_number(vmax, "vmax", minimum=0)
    if m <= 0:
        return np.full(x.shape, 0.5)
    with np.errstate(over="ignore"):  # |x| / m beyond the float range (a tiny vmax): clipped to the ends
        return np.clip(0.5 + 0.5 * x / m, 0.0, 1.0)


def percentile(x, lower=2.0, upper=98.0, *, vmin=None, vmax=None):
    """Robust linear map: f2 between the ``lower`` and ``upper`` percentiles, values beyond are cut.

    Pros: a few extreme values (near a degenerate point, a tiny crease) no
    longer wash out the rest of the surface.
    Cons: the extreme values themselves are not distinguished; the range
    depends on the sampling density.
    """
    x = _values(x)
    if vmin is not None and vmax is not None:  # the percentiles, found before (see map_range)
        return f2(x, vmin, vmax)
    lower, upper = _percentiles(lower, upper)
    _range_needs_values(x, "percentile", "vmin and vmax")
    lo, hi = np.percentile(x, [lower, upper])
    return f2(x, lo, hi)


def _percentiles(lower, upper):
    lower, upper = as_number(lower, "lower", minimum=0, maximum=100), as_number(upper, "upper", minimum=0, maximum=100)
    if not lower < upper:
        raise ValueError(f"percentiles must satisfy 0 <= lower < upper <= 100; got {lower}, {upper}")
    return lower, upper


def signed_log(x, scale=None, vmax=None):
    r"""Signed logarithmic map :math:`0.5 + 0.5\,\mathrm{sign}(x)\log(1+|x|/s)/\log(1+M/s)`.

    ``s`` (default: the median of ``|x|``) sets where the map turns from
    linear to logarithmic; ``M = max|x|`` (or ``vmax``).

    Pros: small and large curvatures are both visible; the sign stays readable.
    Cons: magnitudes are no longer proportional to colour distances.
    """
    x = _values(x)
    a = np.abs(x)
    scale = None if scale is None else as_number(scale, "scale", minimum=0)  # checked even for no values
    M = (np.max(a) if a.size else 0.0) if vmax is None else as_number(vmax, "vmax", minimum=0)
    if M <= 0 or not a.size:
        return np.full(x.shape, 0.5)
    s = 2 * float(np.median(a / 2)) if scale is None else scale  # halves: no overflow
    if s <= 0:  # (at least the smallest normal float: M * 1e-3 underflows for a subnormal M)
        s = max(M * 1e-3, np.finfo(float).tiny)
    if M < 1e-8 * s:  # the scale far above every value: the map is linear to 1e-8 (and log1p(M/s) may underflow)
        with np.errstate(over="ignore"):  # a subnormal vmax: beyond it the colour saturates, as it should
            return np.clip(0.5 + 0.5 * (x / M), 0.0, 1.0)  # x / M first: 0.5 * x underflows for a subnormal x

    def log1p_ratio(v):  # log(1 + v/s), also where v/s overflows (v near the float limit, s tiny): log v - log s
        with np.errstate(over="ignore", divide="ignore"):
            r = v / s
            return np.where(np.isfinite(r), np.log1p(r), np.log(np.maximum(v, np.finfo(float).tiny)) - np.log(s))

    return np.clip(0.5 + 0.5 * np.sign(x) * (log1p_ratio(a) / log1p_ratio(M)), 0.0, 1.0)


def dill(x, vmin=DILL_RANGE[0], vmax=DILL_RANGE[1]):
    """Dill's five-band colour table (1981, figure 6): five equal intervals of ``[vmin, vmax]``.

    From low to high: blue, turquoise, green, yellow, red; values outside the
    range take the colour of the nearest band.  The default range -0.07 …
    0.03 is Dill's (bands of width 0.02, yellow for -0.01 … 0.01, so red
    means K > 0.01).  To keep zero in the middle of the yellow band when
    changing the range, scale both ends by the same factor ``a``
    (``vmin = -0.07 a``, ``vmax = 0.03 a``).

    Pros: a "school grade" reading (Dill): bands are easy to name and compare.
    Cons: the range must be chosen per surface, and variation inside a band is invisible.

    Returns
    -------
    ndarray, shape ``x.shape + (3,)``
    """
    return DILL_COLORS[_dill_band(x, vmin, vmax)]


def dill_names(x, vmin=DILL_RANGE[0], vmax=DILL_RANGE[1]):
    """The names of the colours :func:`dill` gives ``x`` ("blue" … "red"), as a string array of ``x``'s shape, in the
    lab's language (German "blau" … "rot" after ``lab.set_language("de")``).

    With Dill's default range: ``dill_names([-0.06, 0.0, 0.02])`` is
    ``["blue", "yellow", "red"]`` – zero curvature is yellow, red means K > 0.01.
    """
    band = _dill_band(x, vmin, vmax)
    return np.array([_(name) for name in DILL_NAMES])[band]


def dill_batlow(x, vmin=DILL_RANGE[0], vmax=DILL_RANGE[1]):
    """Dill's five bands (:func:`dill`) in five colours of batlow whose lightness rises band by band
    (:func:`lab.geometry.palettes.bands`): the bands stay apart without hue, for every student."""
    return palettes.bands()[_dill_band(x, vmin, vmax)]


def classification_vik(x, tol=ZERO_TOL):
    """The classification :func:`f3` in navy (hyperbolic), near-white (parabolic) and burnt orange (elliptic):
    three colours of vik (:func:`lab.geometry.palettes.classes`) that stay apart under every colour-vision
    deficiency, where f3's red and green do not."""
    return palettes.classes()[np.rint(2 * f3(x, tol)).astype(int)]


def _dill_band(x, vmin, vmax):
    x = _values(x)
    vmin, vmax = as_number(vmin, "vmin"), as_number(vmax, "vmax")
    if not vmin < vmax:
        raise ValueError(f"dill needs vmin < vmax; got vmin={vmin:g}, vmax={vmax:g}")
    # halves: x - vmin and vmax - vmin overflow near the float limit; clipped before the cast to int
    with np.errstate(over="ignore"):  # beyond the range: inf, clipped into the last band
        t = (x / 2 - vmin / 2) / (vmax / 2 - vmin / 2)
    return np.floor(5.0 * np.clip(t, 0.0, 0.999999)).astype(int)


#: Colour maps by name: each takes values (and keyword options) and returns RGB.
COLOR_MAPS = {
    "linear": lambda x, **kw: h(f2(x, **kw)),
    "cut": lambda x, **kw: h(f1(x, **kw)),
    "classification": lambda x, **kw: h(f3(x, **kw)),
    "dill": dill,
    "symmetric": lambda x, **kw: h(symmetric(x, **kw)),
    "percentile": lambda x, **kw: h(percentile(x, **kw)),
    "signed-log": lambda x, **kw: h(signed_log(x, **kw)),
    "linear-batlow": lambda x, **kw: palettes.ramp("batlow", f2(x, **kw)),
    "symmetric-vik": lambda x, **kw: palettes.ramp("vik", symmetric(x, **kw)),
    "signed-log-vik": lambda x, **kw: palettes.ramp("vik", signed_log(x, **kw)),
    "classification-vik": classification_vik,
    "dill-batlow": dill_batlow,
}

#: The maps with one of Crameri's ramps -> the practical's map whose normalisation they use.
NORMALISATIONS = {"linear-batlow": "linear", "symmetric-vik": "symmetric", "signed-log-vik": "signed-log",
                  "classification-vik": "classification", "dill-batlow": "dill"}


def normalisation(name):
    """The practical's map whose normalisation (f1, f2, f3, symmetric, …) the map ``name`` uses: ``name`` itself
    for the practical's maps, e.g. ``"linear"`` for ``"linear-batlow"``."""
    name = name.value if isinstance(name, ColorMap) else name
    return NORMALISATIONS.get(name, name)


def apply(name, values, **options):
    """Colours of ``values`` under the colour map called ``name`` (a key of :data:`COLOR_MAPS`)."""
    name = _v.as_choice(_v.choice_name(name), list(COLOR_MAPS), "colour map")
    try:
        return COLOR_MAPS[name](values, **options)
    except TypeError as exc:
        if "unexpected keyword argument" not in str(exc):
            raise
        raise TypeError(f"colour map {name!r} does not take the option(s) {', '.join(sorted(options))}: it takes "
                        f"{_options_of(name)}") from None


def _options_of(name):
    """The keyword options the colour map ``name`` takes, as text (for a message)."""
    import inspect

    func = {"linear": f2, "linear-batlow": f2, "cut": f1, "classification": f3, "classification-vik": f3,
            "dill": dill, "dill-batlow": dill, "symmetric": symmetric, "symmetric-vik": symmetric,
            "percentile": percentile, "signed-log": signed_log, "signed-log-vik": signed_log}.get(name)
    if func is None:
        return "no documented options"
    names = [p.name for p in list(inspect.signature(func).parameters.values())[1:] if p.kind == p.KEYWORD_ONLY
             or p.default is not inspect.Parameter.empty]
    return ", ".join(names) or "no options"


class ColorMap(str, enum.Enum):
    """The practical's colour maps (section 4); other names of :data:`lab.colormaps.COLOR_MAPS` work too."""

    LINEAR = "linear"  #: h ∘ f2
    CUT = "cut"  #: h ∘ f1
    CLASSIFICATION = "classification"  #: h ∘ f3


def colors_for(values, color_map, *, tol=ZERO_TOL, out=None, chunk=COLOR_CHUNK, **options):
    """RGB colours for curvature ``values`` under ``color_map``; non-finite values become grey.

    ``tol`` is the size below which a value (or, for f2, the spread of the
    values) is rounding noise: f3 paints such values as zero and f2 paints
    such a spread as one colour.  Values without a finite limit at degenerate
    points (NaN) are painted mid-grey and excluded from the min/max.

    The range of the map (min/max, max |x|, percentiles, median) is found once
    over all finite values (:func:`map_range`); the colours are then computed
    ``chunk`` values at a time into ``out`` (shape ``values.shape + (3,)``,
    allocated if None), so large collections need no full-size temporaries.
    """
    name = _v.as_choice(_v.choice_name(color_map), list(COLOR_MAPS), "colour map")
    values = _v.as_array(values, "values", finite=False)
    chunk = _v.as_positive_int(chunk, "chunk", minimum=1)
    # the finite values, the flat copy of a broadcast view and the colours: about five floats per value
    _v.check_memory(8.0 * 5 * values.size, f"colours for {_v.format_count(values.size)} values")
    if out is None:
        out = np.empty(values.shape + (3,))
    if normalisation(name) == "classification":
        options.setdefault("tol", tol)
    elif normalisation(name) == "linear":
        options.setdefault("atol", tol)
    flat, rgb = values.reshape(-1), out.reshape(-1, 3)
    options = map_range(name, flat[np.isfinite(flat)], **options)
    for a in range(0, max(flat.size, 1), chunk):
        x = flat[a : a + chunk]
        finite = np.isfinite(x)
        rgb[a : a + chunk] = 0.5
        if np.any(finite):
            rgb[a : a + chunk][finite] = apply(name, x[finite], **options)
    return out


def map_range(name, values, **options):
    """``options`` completed with the range of colour map ``name`` over ``values``, so it maps elementwise.

    The maps that normalise by the values themselves (linear, symmetric,
    percentile, signed-log) get their range here once; applied to any part
    of the values with these options they colour it as they would all of them.
    """
    x = _values(values)
    name = normalisation(name)
    if not x.size:
        return options
    if name == "linear":
        options.setdefault("vmin", float(np.min(x)))
        options.setdefault("vmax", float(np.max(x)))
    elif name == "symmetric":
        options.setdefault("vmax", float(np.max(np.abs(x))))
    elif name == "percentile":
        lower, upper = _percentiles(options.pop("lower", 2.0), options.pop("upper", 98.0))
        lo, hi = np.percentile(x, [lower, upper])
        options.update(vmin=float(lo), vmax=float(hi))
    elif name == "signed-log":
        a = np.abs(x)
        options.setdefault("vmax", float(np.max(a)))
        options.setdefault("scale", float(np.median(a)))
    return options
