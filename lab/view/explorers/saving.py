"""Pictures for the report: every explorer's "save picture" control and :func:`save_picture`.

The picture is the explorer's own (:meth:`~lab.view.explorers.base.Explorer.picture`: the current view, its colour
bar or legend, as the colour-vision control shows it), drawn at the chosen size (say 2400 px wide, the view's aspect
kept) with a caption naming the surface, the measure, the colour map and the range of values, in the lab's language.
"""

import html
import os
import re

import ipywidgets as W

from ...i18n import _, decimal
from ...model.surface import label
from .. import style
from .controls import _layout, style_for
from .edges import edge_legend_html

__all__ = ["caption", "save_control", "save_picture"]

#: The width a saved picture has unless told otherwise (pixels): sharp on a printed A4 page.
DEFAULT_WIDTH = 2400
#: The widths the control allows (pixels).
WIDTHS = (200, 8000)


def _plain(markup):
    """The text of a legend's HTML on one line."""
    markup = re.sub(r"</?(sub|sup|i|b|em)>", "", markup)  # inline: s<sub>L</sub> stays sL
    text = html.unescape(re.sub(r"<[^>]+>", " ", markup)).replace(" \xa0 ", ", ").replace("━", " ")
    return " ".join(text.split())


def caption(explorer):
    """The picture's caption: the surface's name, the explorer's title (measure, map, …) and the colour range; an
    explorer whose picture has no legend adds its legend's text, and a shown edge overlay the number of edges of
    each level."""
    text = _("{surface}: {title}").format(surface=label(getattr(explorer, "source", None)),
                                          title=explorer.picture_title())
    legend = explorer.picture_legend()
    clim = getattr(legend, "clim", None)
    if clim is not None:
        text += decimal(_("; range {lo} … {hi}").format(lo=f"{clim[0]:.4g}", hi=f"{clim[1]:.4g}"))
    elif legend is None and _plain(explorer.legend_html()):
        text += "; " + _plain(explorer.legend_html())
    edges = getattr(explorer, "edges", None)
    if getattr(getattr(explorer, "show_edges", None), "value", False) and getattr(edges, "report", None) is not None:
        text += "; " + _plain(edge_legend_html(edges.report))
    return text


def wrap(text, size):
    """``text`` broken at its "; " into lines that fit a picture of ``size`` (the title's font, :class:`style.Frame`)."""
    frame = style.Frame(size, text, None)
    room = frame.title[2]
    lines = []
    for part in text.split("; "):
        if lines and style._text_width(f"{lines[-1]}; {part}", frame.font * 1.25) <= room:
            lines[-1] = f"{lines[-1]}; {part}"
        else:
            lines.append(part)
    return "\n".join(lines)


def save_picture(explorer, path, width=DEFAULT_WIDTH):
    """Write the explorer's current picture with its caption to ``path`` (PNG), ``width`` pixels wide and as tall as
    the view's aspect asks; returns ``(path, (width, height))``."""
    from PIL import Image

    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a file name (str or os.PathLike); got {type(path).__name__}")
    if isinstance(width, bool) or not isinstance(width, int) or not WIDTHS[0] <= width <= WIDTHS[1]:
        raise ValueError(f"width must be a whole number of pixels in {WIDTHS[0]} … {WIDTHS[1]}; got {width!r}")
    path = os.fspath(path)
    if not path.lower().endswith(".png"):
        raise ValueError(f"the picture is written as PNG: path must end in .png; got {path!r}")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(f"{path}: the folder {folder} does not exist")
    w, h = explorer.window_size
    size = (width, max(1, round(width * h / w)))
    image = explorer.picture(size, title=wrap(caption(explorer), size))
    Image.fromarray(image).save(path, format="PNG")
    return path, (image.shape[1], image.shape[0])


def save_control(explorer):
    """The row "save picture": a width in pixels, a file name and the button (its result in the status line)."""
    width = W.BoundedIntText(value=DEFAULT_WIDTH, min=WIDTHS[0], max=WIDTHS[1], step=100,
                             description=_("width [px]"), style=style_for(), layout=_layout("13em"))
    name = W.Text(value="picture.png", description=_("file"), style=style_for(), layout=_layout("16em"))
    button = W.Button(description=_("save picture"), icon="download", layout=_layout("max-content"),
                      tooltip=_("write the view with its colour bar, legend and caption as a PNG file"))

    def save():
        try:
            path, (w, h) = save_picture(explorer, name.value, int(width.value))
        except (OSError, ValueError, TypeError) as exc:
            explorer._say(_("not saved: {error}").format(error=exc), "error")
            return
        explorer._say(_("saved {path} ({w} × {h} px)").format(path=path, w=w, h=h), "ok")

    button.on_click(lambda _button: explorer._on_main(save))
    for widget in (width, name, button):
        explorer._control(widget)
    # a narrow output (JupyterLab's split view) wraps the row's three parts instead of squeezing them
    box = W.HBox([width, name, button], layout=W.Layout(grid_column="1 / -1", align_items="center",
                                                        flex_flow="row wrap"))
    box.add_class("lab-save-picture")
    box.add_class("lab-full-row")
    return explorer._control(box)
