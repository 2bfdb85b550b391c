"""The explorers' controls: labels that fit their text in the current language, dropdowns with translated options
that fit their cell, float sliders whose readout writes numbers as the language does."""

import collections
import math
import re

import ipywidgets as W

from ...i18n import _, decimal, language, using

__all__ = ["LABEL_WIDTH", "SHORT_LABEL_WIDTH", "cell", "fit_dropdowns", "fit_labels", "float_slider", "grid_cells",
           "slider_text", "style_for"]

#: width of the controls' labels per language (German labels are longer: "Farbabbildung", "Unterteilung"),
#: and of the short labels beside button rows ("range", "Bereich")
LABEL_WIDTH = {"en": "78px", "de": "104px"}
SHORT_LABEL_WIDTH = {"en": "46px", "de": "60px"}


def style_for(short=False, **extra):
    """The controls' label style in the current language (``short``: a short label; ``extra``: further keys)."""
    widths = SHORT_LABEL_WIDTH if short else LABEL_WIDTH
    return {"description_width": widths.get(language(), widths["en"]), **extra}


def _labelled(widgets):
    """The controls among ``widgets`` (and their children) whose description is a label on their left."""
    for w in widgets:
        yield from _labelled(getattr(w, "children", ()) or ())
        if isinstance(w, (W.Checkbox, W.Button)) or not getattr(w, "description", ""):
            continue
        if hasattr(getattr(w, "style", None), "description_width"):
            yield w


def fit_labels(widgets):
    """Give the labels of a row of controls one width that holds the longest of them, in this language.

    ``ch`` is the width of a digit; 1.1 ch per character plus one holds the labels in JupyterLab's sans-serif font
    (wide letters such as "m" and "ä" included); the browser test checks that no label is cut off.
    """
    labelled = [w for w in _labelled(widgets) if w.style.description_width not in ("", "initial")]
    groups = collections.defaultdict(list)
    for w in labelled:
        short = w.style.description_width in SHORT_LABEL_WIDTH.values()
        fixed = w.style.description_width not in (*LABEL_WIDTH.values(), *SHORT_LABEL_WIDTH.values())
        if not fixed:
            groups[short].append(w)
    for members in groups.values():
        longest = max(len(w.description) for w in members)
        width = f"{1.1 * longest + 1:.1f}ch"
        for w in members:
            w.style.description_width = width


#: the narrowest cell of the controls' grid (its columns are ``minmax(250px, 1fr)``), and a digit's width in
#: JupyterLab's 13 px sans-serif font, in px
CELL_WIDTH = 250
CH = 7.2
#: a select's arrow and padding, in ch
SELECT_EXTRA = 3.5


def _in_ch(width):
    """A CSS width in ch ("17.5ch", "104px")."""
    number = float(re.sub(r"[a-z]+$", "", width))
    return number / CH if width.endswith("px") else number


def dropdown_width(w):
    """The width (in ch) a dropdown needs to show its label and its longest option whole: 1.1 ch per character
    plus one, as :func:`fit_labels` estimates, and the select's arrow."""
    longest = max((len(label) for label in w._options_labels), default=0)
    label = _in_ch(w.style.description_width) if w.description else 0.0
    return label + 1.1 * longest + 1 + SELECT_EXTRA


def fit_dropdowns(widgets):
    """A dropdown whose longest option does not fit a grid cell spans the row, as wide as its options need
    ("reflection lines (light li…", "vorzeichenbehaftet l…" were cut off in a 250 px cell).  Call it after
    :func:`fit_labels`, which sets the labels' widths."""
    for w in widgets:
        if isinstance(w, W.Dropdown) and dropdown_width(w) * CH > CELL_WIDTH:
            w.layout.grid_column = FULL_ROW
            w.layout.max_width = f"{math.ceil(dropdown_width(w))}ch"
            w.add_class("lab-wide")


def slider_text(slider):
    """A float slider's value as its readout shows it, with the language's decimal separator ("0,05" in German)
    and a minus sign; a range slider's two values joined by an en dash."""
    values = slider.value if isinstance(slider.value, (tuple, list)) else (slider.value,)
    texts = []
    for x in values:
        text = format(x, slider.readout_format)
        if float(text) == 0:
            text = text.lstrip("-")
        texts.append(decimal(text).replace("-", "−"))
    return " – ".join(texts)


def float_slider(cls, description, **kwargs):
    """A float slider (``cls``: FloatSlider, FloatLogSlider, FloatRangeSlider) with the controls' label style.

    ipywidgets' readout (d3-format) always writes a decimal point; in German the slider has no readout of its own
    but a text beside it, written by :func:`slider_text` whenever the value (or the range) changes.  The two
    form one grid cell (:func:`cell`), which is shown or hidden with the slider's ``layout.display``."""
    slider = cls(description=description, style=style_for(), layout=_layout(), **kwargs)
    lang = language()  # the explorer's language, also when the value changes in another context
    if lang == "en":
        return slider
    slider.readout = False
    readout = W.Label(layout=W.Layout(flex="0 0 auto", margin="0 0 0 4px"))
    readout.add_class("lab-readout")
    box = W.HBox([slider, readout], layout=W.Layout(width="auto", min_width="0", align_items="center",
                                                    display=slider.layout.display))
    slider.layout.flex = "1 1 auto"

    def show(_change=None):
        with using(lang):
            readout.value = slider_text(slider)

    def follow(change):
        box.layout.display = change.new

    show()
    slider.observe(show, ["value", "min", "max", "readout_format"])
    slider.layout.observe(follow, "display")
    slider._lab_cell = box
    return slider


def cell(widget):
    """The grid cell that holds ``widget``: its box with the lab's readout, or the widget itself."""
    return getattr(widget, "_lab_cell", widget)


def grid_cells(widgets):
    """The cells of the controls' grid for ``widgets``: each in its :func:`cell`, labels fitted, long dropdowns
    widened."""
    cells = [cell(w) for w in widgets]
    fit_labels(cells)
    fit_dropdowns(cells)
    return cells


def _dropdown(options, value, description):
    """A dropdown with translated labels (``options``: (label, value) pairs, labels marked with ``N_``)."""
    return W.Dropdown(options=[(_(label), v) for label, v in options], value=value, description=_(description),
                      style=style_for(), layout=_layout())


def _layout(least=None):
    """A control that fills its grid cell (auto, not 100%: the widget's own margin would overflow the cell); with
    ``least``, a part of a wrapping row: as wide as the row allows, never narrower than ``least`` (it wraps)."""
    if least is None:
        return W.Layout(width="auto", min_width="0")
    return W.Layout(width="auto", min_width=least, flex="1 1 auto")


#: The grid columns a full row spans.
FULL_ROW = "1 / -1"
#: ipywidgets drops a layout's ``grid_column`` when it first draws a widget (it applies only later changes:
#: ipywidgets issue #2334), so these texts also have the class ``lab-full-row`` and the explorer this rule (and
#: the dropdowns :func:`fit_dropdowns` widens the class ``lab-wide``: a row of their own, not the row's width).
FULL_ROW_CSS = (f"<style>.lab-controls > .lab-full-row {{grid-column: {FULL_ROW}}} "
                f".lab-controls > .lab-wide {{grid-column: {FULL_ROW}}}</style>")


def full_row_text():
    """An HTML text (a legend, a readout, the mesh's info) across the whole grid of controls, not squeezed into
    one 250 px cell, where it wrapped word by word (the layout, and the class for :data:`FULL_ROW_CSS`)."""
    text = W.HTML(layout=W.Layout(grid_column=FULL_ROW, width="auto", min_width="0"))
    text.add_class("lab-full-row")
    return text
