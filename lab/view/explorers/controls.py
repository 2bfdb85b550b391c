"""The explorers' controls: labels that fit their text in the current language, dropdowns with translated options."""

import collections

import ipywidgets as W

from ...i18n import _, language

__all__ = ["LABEL_WIDTH", "SHORT_LABEL_WIDTH", "fit_labels", "style_for"]

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


def _dropdown(options, value, description):
    """A dropdown with translated labels (``options``: (label, value) pairs, labels marked with ``N_``)."""
    return W.Dropdown(options=[(_(label), v) for label, v in options], value=value, description=_(description),
                      style=style_for(), layout=_layout())


def _layout():
    """A control that fills its grid cell (auto, not 100%: the widget's own margin would overflow the cell)."""
    return W.Layout(width="auto", min_width="0")


#: The grid columns a full row spans.
FULL_ROW = "1 / -1"
#: ipywidgets drops a layout's ``grid_column`` when it first draws a widget (it applies only later changes:
#: ipywidgets issue #2334), so these texts also have the class ``lab-full-row`` and the explorer this rule.
FULL_ROW_CSS = f"<style>.lab-controls > .lab-full-row {{grid-column: {FULL_ROW}}}</style>"


def full_row_text():
    """An HTML text (a legend, a readout, the mesh's info) across the whole grid of controls, not squeezed into
    one 250 px cell, where it wrapped word by word (the layout, and the class for :data:`FULL_ROW_CSS`)."""
    text = W.HTML(layout=W.Layout(grid_column=FULL_ROW, width="auto", min_width="0"))
    text.add_class("lab-full-row")
    return text
