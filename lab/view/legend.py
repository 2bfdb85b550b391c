"""Colour bars and class legends in curvature units, for every colour map of the lab.

One :class:`Legend` describes what a colour means: the colours along the bar
(``stops``), tick positions with labels in curvature units (``ticks``), or, for
the classification map, a list of classes.  The same description is drawn as
HTML beside a live explorer (:meth:`Legend.html`) and with matplotlib into
the static pictures (``lab.view.style``), so both always say the same.

The positions are fractions of the bar, 0 (left/bottom) … 1 (right/top).  For
maps that are linear in the value (h∘f2, h∘f1, symmetric, percentile, Dill,
the perceptual maps) a value x sits at ``(x - lo) / (hi - lo)``; for the
signed-log map at ``signed_log(x)`` (nonlinear: its ticks are placed where
their values fall, so the labels stay in curvature units).
"""

import dataclasses
import html as _html
import math
from dataclasses import dataclass

import numpy as np

from ..geometry import colormaps, palettes, vision
from ..i18n import N_, _, decimal

__all__ = ["H_STOPS", "Legend", "format_values", "legend", "map_range", "measure_title", "nice_ticks", "stored_legend"]

#: The practical's ramp h is piecewise linear with these knots: five stops draw it exactly.
H_STOPS = tuple((float(t), tuple(float(c) for c in colormaps.h(np.array(t)))) for t in (0.0, 0.25, 0.5, 0.75, 1.0))

#: measure -> (name, symbol, power of 1/length in its unit)
MEASURES = {
    "gaussian": (N_("Gaussian curvature"), "K", 2),
    "classification": (N_("Gaussian curvature"), "K", 2),
    "mean": (N_("mean curvature"), "H", 1),
    "k1": (N_("max. principal curvature"), "κ1", 1),
    "k2": (N_("min. principal curvature"), "κ2", 1),
    "strain-energy": (N_("strain energy"), "κ1² + κ2²", 2),
}

PERCEPTUAL = ("viridis", "cividis", "coolwarm", "RdBu_r")


def measure_title(measure, *, long=True):
    """The bar's title with units, e.g. ``"Gaussian curvature K  [1/length²]"``."""
    name, symbol, power = MEASURES[measure]
    unit = _("1/length²") if power == 2 else _("1/length")
    return f"{_(name)} {symbol}  [{unit}]" if long else f"{symbol} [{unit}]"


def _minus(text):
    """A label as people read it: a real minus sign, the decimal comma in German."""
    return decimal(text.replace("-", "−"))


def nice_ticks(lo, hi, n=5):
    """About ``n`` round values inside ``[lo, hi]`` (steps 1, 2, 2.5 or 5 times a power of ten)."""
    lo, hi = float(lo), float(hi)
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        return np.array([lo])
    raw = (hi - lo) / max(n, 1)
    power = 10.0 ** math.floor(math.log10(raw))
    step = next((m * power for m in (1, 2, 2.5, 5, 10) if m * power >= raw * 0.999), 10 * power)
    first = math.ceil(lo / step - 1e-9) * step
    ticks = first + step * np.arange(math.floor((hi - first) / step + 1e-9) + 1)
    ticks[np.abs(ticks) < step * 1e-9] = 0.0
    return ticks


def _sci(x, digits):
    mantissa, exponent = f"{x:.{digits}e}".split("e")
    if "." in mantissa:
        mantissa = mantissa.rstrip("0").rstrip(".")
    return f"{mantissa}e{int(exponent)}"


def format_values(values, *, spacing=None):
    """Short labels for ``values``: the fewest digits that keep neighbours apart.

    ``spacing`` (default: the smallest gap between the values) sets the
    precision a label must keep: within 2% of it.  Plain decimals for
    magnitudes from 0.001 to 10⁶, else scientific (``2.5e-4``).  Exact zeros (and
    values far below the spacing) read "0", never "-0.00"; the minus is a real minus sign.
    """
    v = np.asarray(values, dtype=float).ravel()
    if v.size == 0:
        return []
    finite = v[np.isfinite(v)]
    if spacing is None:
        gaps = np.diff(np.sort(finite))
        gaps = gaps[gaps > 0]
        spacing = float(gaps.min()) if gaps.size else max(float(np.max(np.abs(finite))) if finite.size else 1.0, 1e-300)
    spacing = max(float(spacing), 1e-300)
    big = float(np.max(np.abs(finite))) if finite.size else 0.0
    scientific = big >= 1e6 or 0 < big < 1e-3
    for digits in range(10):
        labels = []
        for x in v:
            if not math.isfinite(x):
                labels.append("nan")
            elif abs(x) < spacing * 1e-6:
                labels.append("0")
            else:
                labels.append(_sci(x, digits) if scientific else f"{x:.{digits}f}")
        back = np.array([float(s) for s in labels])
        ok = np.all(np.abs(back - v)[np.isfinite(v)] <= 0.02 * spacing + 1e-300)
        if ok and len(set(labels)) == len(labels):
            return [_minus(s) for s in labels]
    return [_minus(f"{x:.8g}") for x in v]


@dataclass(frozen=True)
class Legend:
    """What the colours of a picture mean.

    Attributes
    ----------
    title : str
        Measure and unit, e.g. ``"Gaussian curvature K  [1/length²]"``.
    stops : tuple of (float, (r, g, b))
        Colours along the bar (positions 0 … 1, RGB in 0 … 1); two stops at one
        position make a hard edge (Dill's bands).
    ticks : tuple of (float, str)
        Tick positions on the bar and their labels in curvature units.
    classes : tuple of (str, (r, g, b))
        For the classification map: the classes instead of a bar.
    clim : (float, float) or None
        The range of values the colours span (what the explorers' readouts show).
    note : str
        A remark printed under the bar (e.g. how the map treats values outside).
    levels : tuple of float
        The borders of the bands in curvature units, where level lines go (:func:`legend`).
    """

    title: str
    stops: tuple = ()
    ticks: tuple = ()
    classes: tuple = ()
    clim: tuple = None
    note: str = ""
    levels: tuple = ()

    def simulated(self, deficiency):
        """This legend with its colours as seen with ``deficiency`` (:func:`lab.vision.simulate`; None: itself)."""
        if vision.check_deficiency(deficiency) is None:
            return self
        stops = tuple((p, _rgb(c)) for (p, _c), c in zip(self.stops, vision.simulate(
            np.array([c for _p, c in self.stops]).reshape(-1, 3), deficiency))) if self.stops else ()
        classes = tuple((label, _rgb(c)) for (label, _c), c in zip(self.classes, vision.simulate(
            np.array([c for _l, c in self.classes]).reshape(-1, 3), deficiency))) if self.classes else ()
        return dataclasses.replace(self, stops=stops, classes=classes)

    @property
    def is_bar(self):
        return not self.classes

    def colors(self, n=256):
        """``(n, 3)`` colours sampled evenly along the bar (for drawing it)."""
        t = (np.arange(n) + 0.5) / n
        pos = np.array([p for p, _ in self.stops])
        rgb = np.array([c for _, c in self.stops])
        out = np.empty((n, 3))
        for k in range(3):
            # hard edges: two stops at one position; np.interp takes the right one at the edge
            out[:, k] = np.interp(t, pos, rgb[:, k])
        return out

    def html(self):
        """The legend as HTML (a horizontal bar with ticks, or the class list); fits any width."""
        title = _html.escape(self.title)
        if self.classes:
            items = "".join(
                f'<span class="lab-legend-item" style="display:inline-flex;align-items:center;margin:0 1em 0 0;'
                f'white-space:nowrap"><span style="display:inline-block;width:1em;height:1em;margin-right:.35em;'
                f'border:1px solid #555;background:{_css(c)}"></span>{_html.escape(label)}</span>'
                for label, c in self.classes)
            return (f'<div class="lab-legend" style="font-size:12px;line-height:1.6;padding:2px 0">'
                    f'<span style="font-weight:600;margin-right:1em">{title}</span>'
                    f'<span style="display:inline-flex;flex-wrap:wrap">{items}</span></div>')
        gradient = ", ".join(f"{_css(c)} {100 * p:.3f}%" for p, c in self.stops)
        marks = "".join(
            f'<span style="position:absolute;left:{100 * p:.3f}%;top:0;width:1px;height:5px;background:#333"></span>'
            for p, _ in self.ticks)
        labels = "".join(
            f'<span class="lab-colorbar-label" style="position:absolute;left:{100 * p:.3f}%;top:5px;'
            f'transform:translateX(-50%);white-space:nowrap">{_html.escape(label)}</span>'
            for p, label in self.ticks)
        note = (f'<div style="color:#57606a;font-size:11px;text-align:center">{_html.escape(self.note)}</div>'
                if self.note else "")
        return (
            '<div class="lab-colorbar" style="font-size:12px;padding:2px 3.2em 0 3.2em;box-sizing:border-box;'
            'max-width:46em;margin:0 auto">'
            f'<div class="lab-colorbar-title" style="text-align:center;font-weight:600;margin-bottom:2px">{title}</div>'
            f'<div class="lab-colorbar-bar" style="height:14px;border:1px solid #777;'
            f'background:linear-gradient(to right, {gradient})"></div>'
            f'<div style="position:relative;height:22px">{marks}{labels}</div>{note}</div>'
        )


def _css(rgb):
    r, g, b = (round(255 * float(x)) for x in rgb)
    return f"rgb({r},{g},{b})"


def _linear_ticks(lo, hi):
    if not hi - lo > 1e-6 * max(abs(lo), abs(hi)):  # one value (up to rounding): one label, in the middle
        mid = 0.5 * (lo + hi)
        return ((0.5, format_values([mid], spacing=max(abs(mid), 1e-300) * 1e-3)[0]),)
    ticks = nice_ticks(lo, hi)
    if ticks.size < 2:  # a range narrower than one round step: label the ends
        ticks = np.array([lo, hi])
    labels = format_values(ticks, spacing=float(np.min(np.diff(ticks))) if ticks.size > 1 else None)
    return tuple(((float(t) - lo) / (hi - lo), s) for t, s in zip(ticks, labels))


def _signed_log_ticks(M, s):
    """Ticks of the signed-log bar: 0, ±M and round values between, where the map puts them."""
    def pos(x):
        return 0.5 + 0.5 * math.copysign(math.log1p(abs(x) / s) / math.log1p(M / s), x)

    ends = format_values([M], spacing=M * 1e-2)[0]
    chosen = [(0.0, 0.5, "0"), (-M, 0.0, "−" + ends), (M, 1.0, ends)]
    top = math.floor(math.log10(M))
    candidates = []
    for k in range(top, top - 6, -1):
        for m in (1, 5, 2):
            x = m * 10.0**k
            if x < M * 0.999:
                candidates.append(x)
    for x in candidates:
        for value in (x, -x):
            p = pos(value)
            if all(abs(p - q) >= 0.085 for _, q, _ in chosen):
                chosen.append((value, p, format_values([value], spacing=abs(value) * 0.1)[0]))
    chosen.sort(key=lambda c: c[1])
    return tuple((p, label) for _, p, label in chosen)


def map_range(color_map, values, *, clim=None, options=None):
    """The range of values a colour map spans for these values: what the colours mean from … to.

    ``clim`` overrides the data range of the maps that take one (linear, Dill,
    the perceptual maps); ``options`` are the map's keyword options (``vmin``,
    ``vmax``, ``scale``, ``lower``, ``upper``) as :func:`lab.colormaps.apply` takes them.
    Returns ``(lo, hi)``, or None for the classification map.
    """
    options = dict(options or {})
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    lo, hi = (float(v.min()), float(v.max())) if v.size else (0.0, 1.0)
    m = max(abs(lo), abs(hi))
    if color_map in colormaps.COLOR_MAPS:
        color_map = colormaps.normalisation(color_map)
    if color_map == "classification":
        return None
    if color_map == "cut":
        return (0.0, 1.0)
    if color_map == "dill":
        if clim is not None:
            return tuple(float(x) for x in clim)
        return (float(options.get("vmin", colormaps.DILL_RANGE[0])), float(options.get("vmax", colormaps.DILL_RANGE[1])))
    if color_map == "symmetric":
        m = float(options.get("vmax", m))
        return (-m, m)
    if color_map == "percentile":
        if not v.size:
            return (0.0, 1.0)
        p = np.percentile(v, [options.get("lower", 2.0), options.get("upper", 98.0)])
        return (float(p[0]), float(p[1]))
    if color_map == "signed-log":
        return (-m, m)
    if clim is not None:
        return tuple(float(x) for x in clim)
    return (float(options.get("vmin", lo)), float(options.get("vmax", hi)))


def _rgb(c):
    return tuple(float(x) for x in c)


def _palette_stops(name, n=17):
    """Stops along a bar drawn with Crameri's ramp ``name`` (piecewise linear in 17 stops: within 1/255 of it)."""
    t = np.linspace(0.0, 1.0, n)
    return tuple((float(p), _rgb(c)) for p, c in zip(t, palettes.ramp(name, t)))


def _class_colors(color_map):
    """The colours of (elliptic, parabolic, hyperbolic) in the classification map ``color_map``."""
    if color_map == "classification-vik":
        hyperbolic, parabolic, elliptic = (_rgb(c) for c in palettes.classes())
        return elliptic, parabolic, hyperbolic
    return tuple(_rgb(colormaps.h(np.array(t))) for t in (1.0, 0.5, 0.0))


def band_label(symbol, lo, hi, *, first=False, last=False, spacing=None):
    """A band of values in words: its range and, for K, the kind of point (elliptic, parabolic, hyperbolic).

    ``first`` and ``last`` bands also take the values beyond (``K < −0.05``, ``K > 0.01``); a band that holds 0
    is "≈ 0" (parabolic for K), one below 0 hyperbolic, one above elliptic.
    """
    a, b = format_values([lo, hi], spacing=spacing or (hi - lo))
    span = f"{symbol} < {b}" if first else f"{symbol} > {a}" if last else f"{a} … {b}"
    if symbol != "K":
        return span
    if lo < 0 < hi or (first and hi > 0) or (last and lo < 0):
        kind = _("≈ 0, parabolic")
    elif hi <= 0:
        kind = _("hyperbolic")
    else:
        kind = _("elliptic")
    return f"{span}: {kind}"


def legend(measure, color_map, values=None, *, clim=None, options=None, tol=None):
    """The legend of a picture coloured by ``measure`` under ``color_map``.

    Besides colours and labels it gives the band borders (``levels``, in curvature units) where
    :func:`lab.interrogation.bands.band_lines` draws level lines, so that a picture is readable without colour:
    0 for a classification (the parabolic lines), Dill's inner band edges, the labelled ticks of a bar.

    Parameters
    ----------
    measure : str
        ``gaussian``, ``mean``, ``k1``, ``k2``, ``strain-energy`` or ``classification``.
    color_map : str
        A name of :data:`lab.colormaps.COLOR_MAPS` or a perceptual map
        (``viridis``, ``cividis``, ``coolwarm``, ``RdBu_r``).
    values : array_like, optional
        The values shown (for ranges the map takes from the data).
    clim : (float, float), optional
        The range actually used, where the map takes one (linear, Dill, perceptual).
    options : dict, optional
        The map's keyword options, as given to the colour map.
    tol : float, optional
        The zero tolerance of the classification (shown in its legend).
    """
    options = dict(options or {})
    values = np.zeros(0) if values is None else np.asarray(values, dtype=float)
    symbol = MEASURES[measure][1]
    title = measure_title(measure)
    base = colormaps.normalisation(color_map) if color_map in colormaps.COLOR_MAPS else color_map
    if measure == "classification" or base == "classification":
        elliptic, parabolic, hyperbolic = _class_colors(color_map)
        zero = "≈ 0" if tol else "= 0"
        if symbol == "K":
            classes = ((_("K > 0 elliptic"), elliptic), (_("K {zero} parabolic, flat").format(zero=zero), parabolic),
                       (_("K < 0 hyperbolic"), hyperbolic))
        else:
            classes = ((f"{symbol} > 0", elliptic), (f"{symbol} {zero}", parabolic), (f"{symbol} < 0", hyperbolic))
        note = _("|{symbol}| ≤ {tol} counts as 0").format(symbol=symbol, tol=_minus(_sci(tol, 1))) if tol else ""
        return Legend(title=title, classes=classes, note=note, levels=(0.0,))
    lo, hi = map_range(color_map, values, clim=clim, options=options)
    if base == "dill":
        edges = lo + (hi - lo) * np.arange(6) / 5
        levels = tuple(float(x) for x in edges[1:-1])
        if color_map == "dill-batlow":  # bands in words, lowest at the bottom as on a bar
            classes = tuple((band_label(symbol, edges[k], edges[k + 1], first=k == 0, last=k == 4,
                                        spacing=(hi - lo) / 5), _rgb(c))
                            for k, c in reversed(list(enumerate(palettes.bands()))))
            return Legend(title=title, classes=classes, clim=(lo, hi), levels=levels,
                          note=_("five bands (Dill) in rising lightness"))
        stops = []
        for k, c in enumerate(colormaps.DILL_COLORS):
            stops += [(k / 5, _rgb(c)), ((k + 1) / 5, _rgb(c))]
        labels = format_values(edges, spacing=(hi - lo) / 5)
        return Legend(title=title, stops=tuple(stops), ticks=tuple(zip((np.arange(6) / 5).tolist(), labels)),
                      clim=(lo, hi), note=_("five bands (Dill); values outside take the nearest band"), levels=levels)
    ramp = {"linear-batlow": "batlow", "symmetric-vik": "vik", "signed-log-vik": "vik"}.get(color_map)
    if base == "signed-log":
        stops = _palette_stops(ramp) if ramp else H_STOPS
        a = np.abs(values[np.isfinite(values)])
        M = hi
        if not M > 0:
            return Legend(title=title, stops=stops, ticks=((0.5, "0"),), clim=(0.0, 0.0), levels=(0.0,))
        s = float(options.get("scale") or (np.median(a) if a.size else 0.0))
        if s <= 0:
            s = M * 1e-3
        ticks = _signed_log_ticks(M, s)
        # a tick's value from its place on the bar (the inverse of the signed-log map)
        levels = tuple(math.copysign(s * math.expm1(abs(2 * p - 1) * math.log1p(M / s)), p - 0.5)
                       for p, _label in ticks if 0 < p < 1)
        return Legend(title=title, stops=stops, ticks=ticks, clim=(-M, M), levels=levels,
                      note=_("signed logarithmic scale, linear below {s}").format(
                          s=format_values([s], spacing=s * 0.1)[0]))
    if ramp:
        stops = _palette_stops(ramp)
    elif color_map in PERCEPTUAL:
        from matplotlib import colormaps as mpl_colormaps

        cmap = mpl_colormaps[color_map]
        t = np.linspace(0, 1, 17)
        stops = tuple((float(x), tuple(float(c) for c in cmap(x)[:3])) for x in t)
    else:
        stops = H_STOPS
    note = {"cut": _("values below 0 and above 1 take the end colours (f1)"),
            "percentile": _("2nd to 98th percentile; values beyond take the end colours")}.get(base, "")
    if hi > lo and not hi - lo > 1e-6 * max(abs(lo), abs(hi)):
        note = _("all values {value} up to rounding ({spread})").format(
            value=format_values([0.5 * (lo + hi)], spacing=abs(hi) * 1e-3)[0], spread=_minus(_sci(hi - lo, 1)))
    ticks = _linear_ticks(lo, hi)
    levels = tuple(lo + p * (hi - lo) for p, _label in ticks if 0 < p < 1) if hi > lo else ()
    return Legend(title=title, stops=stops, ticks=ticks, clim=(lo, hi), note=note, levels=levels)


def _stored_measure(patches, values):
    """Which curvature the stored corner values are (``"gaussian"``, ``"mean"``, ``"k1"``, ``"k2"``), or None."""
    exact = patches.corner_curvature()
    finite = np.isfinite(values)
    for name, field in (("gaussian", "K"), ("mean", "H"), ("k1", "k1"), ("k2", "k2")):
        ref = np.asarray(getattr(exact, field), dtype=float)
        if ref.shape != values.shape:
            return None
        scale = float(np.nanmax(np.abs(ref))) if np.isfinite(ref).any() else 0.0
        ok = finite & np.isfinite(ref)
        if ok.any() and np.all(np.abs(values[ok] - ref[ok]) <= 1e-6 * scale + 1e-12):
            return name
    return None


def stored_legend(patches):
    """The colour bar of the colours stored in ``patches`` (by a ``visualize_curvature``, the student's or the library's).

    The measure is recognised from the stored values (against the exact corner curvature), the map from the
    colours: h∘f2 (linear over the stored range), h∘f1 (cut to [0, 1]), h∘f3 (classification) or one of the
    library's designs (symmetric, signed-log, percentile, Dill's bands, the maps with Crameri's ramps), whichever
    reproduces them; colours of
    another map get the ramp h over the stored range with a note saying so.
    None when the patches have no colours or no stored values.
    """
    from ..geometry.curvature import zero_tolerance

    colors = np.asarray(patches.colors, dtype=float)
    values = np.asarray(patches.curvature, dtype=float)
    finite = np.isfinite(values)
    if not np.all(np.isfinite(colors)) or not finite.any():
        return None
    measure = _stored_measure(patches, values)
    tol = zero_tolerance(measure or "gaussian", patches.size)
    found = None
    for name in ("linear", "cut", "classification", "symmetric", "signed-log", "percentile", "dill",
                 *colormaps.NORMALISATIONS):
        want = colormaps.colors_for(values, name, tol=tol)
        if np.all(np.abs(want - colors)[finite] <= 0.02):
            found = name
            break
    chosen = legend(measure or "gaussian", found or "linear", values[finite], tol=tol)
    changes = {}
    if measure is None:
        changes["title"] = _("values stored with set_curvature")
    if found is None:
        changes["note"] = _("your own colours: the bar shows h over the range of the stored values")
    return dataclasses.replace(chosen, **changes) if changes else chosen


def draft_legend():
    """The legend of :func:`lab.draft_map`'s colours (blue undercut … white 0° … red), with the parting line's note."""
    from ..interrogation import maps

    stops = ((0.0, maps.NEGATIVE), (0.5, maps.ZERO), (1.0, maps.POSITIVE))
    return Legend(title=_("draft angle δ  [°]"), stops=stops,
                  ticks=((0.0, "−90°"), (0.25, "−45°"), (0.5, "0°"), (0.75, "45°"), (1.0, "90°")),
                  clim=(-90.0, 90.0), note=_("black line: parting line (0°); below 0: undercut"))


def radius_legend(r):
    """The legend of :func:`lab.radius_map`'s colours for the threshold ``r``."""
    from ..interrogation import maps

    text = decimal(f"{r:g}")
    return Legend(title=_("min. radius of curvature 1/max(|κ1|, |κ2|)"),
                  classes=((_("below r = {r}").format(r=text), maps.FLAGGED),
                           (_("at least r = {r}").format(r=text), maps.CLEAR)))


def deviation_legend(tolerance, color_map="graded", vmax=None, *, unscanned=False):
    """The legend of a deviation's colours (:func:`lab.interrogation.deviation.deviation_colors`): the three bands
    as classes, or the graded bar from ``-vmax`` to ``vmax`` with the band within the tolerance in its middle;
    ``unscanned`` adds the grey of the places no scanned point is near."""
    from ..interrogation import deviation as _dev

    lo, hi = _dev.tolerance_band(tolerance)
    grey = ((_("not scanned"), _dev.NO_SCAN),) if unscanned else ()
    text = {x: _minus(f"{x:.3g}") for x in (lo, hi)}
    if color_map == "bands":
        below, within, above = (_rgb(c) for c in _dev.deviation_colors(np.array([lo - 1.0, 0.0, hi + 1.0]),
                                                                      (lo, hi), "bands"))
        return Legend(title=_("signed distance to the part  [length]"),
                      classes=((_("below {lo}").format(lo=text[lo]), below),
                               (_("within {lo} … {hi}").format(lo=text[lo], hi=text[hi]), within),
                               (_("above {hi}").format(hi=text[hi]), above)) + grey,
                      levels=(lo, hi))
    top = max(float(vmax) if vmax is not None else 0.0, hi, -lo) or 1.0
    t = np.linspace(0.0, 1.0, 17)
    stops = []
    for a, b in ((-top, lo), (lo, hi), (hi, top)):  # hard edges at the tolerance's borders
        d = a + t * (b - a)
        d[-1] = b - 1e-12 * top if b != top else b
        d[0] = a + 1e-12 * top if a != -top else a
        colors = _dev.deviation_colors(d, (lo, hi), "graded", vmax=top)
        stops += [((x + top) / (2 * top), _rgb(c)) for x, c in zip(d, colors)]
    ends = ((0.0, _minus(f"{-top:.3g}")), (1.0, _minus(f"{top:.3g}")))
    if (hi - lo) / (2 * top) >= 0.16:  # the tolerance's ticks apart enough to read
        ticks = (ends[0], ((lo + top) / (2 * top), text[lo]), ((hi + top) / (2 * top), text[hi]), ends[1])
    else:
        ticks = (ends[0], (0.5, "0"), ends[1])
    note = _("white: within the tolerance {lo} … {hi}; orange: above the part, blue: below").format(
        lo=text[lo], hi=text[hi])
    if unscanned:
        note += "; " + _("grey: not scanned")
    return Legend(title=_("signed distance to the part  [length]"), stops=tuple(stops), ticks=ticks,
                  clim=(-top, top), note=note, levels=(lo, hi))


def simulated_note(legend, deficiency):
    """``legend`` with a note that the picture is simulated for ``deficiency`` (:func:`lab.vision.simulate`)."""
    said = _("seen with {deficiency} (simulated)").format(deficiency=vision.name(deficiency))
    return dataclasses.replace(legend, note=f"{legend.note}\n{said}" if legend.note else said)
