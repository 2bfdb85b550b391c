"""The edge overlay: knot lines, patch borders and a model's face edges drawn as lines coloured by what each achieves.

One function builds the lines from a :func:`lab.continuity` report, one adds them to a plotter and one writes
the legend; the curvature and reflection explorers call them behind their "edges by continuity" checkbox.
"""

import html

import numpy as np
import pyvista as pv

from ...i18n import _
from ...interrogation.continuity import LEVELS, continuity, level_name
from ...interrogation.faces import is_model
from ...model.patches import BezierPatches
from ...model.surface import BSplineSurface
from .. import style

__all__ = ["EDGE_COLORS", "EdgeOverlay", "add_edge_overlay", "edge_legend_html", "edge_lines", "edge_report"]

#: the colour of each level (worst first: violet for an open gap (unlike red at a glance), red a kink, orange a
#: curvature jump; the two smooth levels achromatic, white G2 and black G3, which no colour-vision deficiency
#: changes: black differs from each of the others by CAM02-UCS ΔE >= 41 under normal vision, protanopia,
#: deuteranopia and tritanopia (lab.geometry.vision; the four others are 28 apart at least))
EDGE_COLORS = {"none": "#7b2cbf", "G0": "#d7191c", "G1": "#fdae61", "G2": "#ffffff", "G3": "#000000"}


def edge_report(source):
    """The continuity report of what an explorer shows, or None (an analytic surface has no edges).

    A model (:func:`lab.read`) gives its face edges (``model.edges``: the edges two faces share in the file),
    measured with the default tolerances of :func:`lab.continuity`."""
    if isinstance(source, (BSplineSurface, BezierPatches)) or is_model(source):
        return continuity(source)
    return None


def edge_lines(report):
    """The report's edges as polylines, one cell per segment, with cell data ``edge`` (the edge's index in the
    report), ``level`` (index in LEVELS) and ``RGB``."""
    if report is None or not report.edges:
        return pv.PolyData()
    lines = []
    for index, edge in enumerate(report.edges):
        line = pv.lines_from_points(np.asarray(edge.points, dtype=float))
        n = line.n_cells
        line.cell_data["edge"] = np.full(n, index)
        line.cell_data["level"] = np.full(n, LEVELS.index(edge.achieved))
        rgb = np.array([int(EDGE_COLORS[edge.achieved][k:k + 2], 16) for k in (1, 3, 5)], dtype=np.uint8)
        line.cell_data["RGB"] = np.tile(rgb, (n, 1))
        lines.append(line)
    return pv.merge(lines)


def add_edge_overlay(plotter, report, *, line_width=4.0):
    """Add the report's edges to ``plotter`` in front of the surface; returns the actor (None without edges)."""
    lines = edge_lines(report)
    if lines.n_points == 0:
        return None
    actor = plotter.add_mesh(lines, scalars="RGB", rgb=True, preference="cell", line_width=line_width,
                             lighting=False, pickable=False, show_scalar_bar=False)
    return style.offset_lines(actor)


def edge_legend_html(report):
    """The legend: a swatch per level with the number of edges achieving it, and the tolerances' source."""
    if report is None:
        return ""
    counts = report.counts()
    items = []
    for level in counts:  # best first; G3 where it was measured
        swatch = (f'<span style="display:inline-block;width:14px;height:4px;background:{EDGE_COLORS[level]};'
                  f'border:1px solid #555;vertical-align:middle"></span>')
        items.append(f"{swatch} {html.escape(level_name(level))}: {counts[level]}")
    title = html.escape(_("edges by continuity"))
    return f"<small>{title}: " + " &nbsp; ".join(items) + "</small>"



class EdgeOverlay:
    """The checkbox's state in an explorer: the report and actor made on first use, then only shown or hidden."""

    def __init__(self, source):
        self.source = source
        self.report = None
        self.actor = None
        self._made = False

    def show(self, plotter, visible):
        """Show or hide the overlay; returns the legend's HTML (empty when hidden or without edges)."""
        if visible and not self._made:
            self.report = edge_report(self.source)
            self.actor = add_edge_overlay(plotter, self.report)
            self._made = True
        if self.actor is not None:
            self.actor.SetVisibility(bool(visible))
        if not visible:
            return ""
        if self.report is None:
            return "<small>" + html.escape(_("no edges: an analytic surface is one piece")) + "</small>"
        if is_model(self.source) and not self.report.edges:
            return "<small>" + html.escape(_("no shared edges: the file's faces are not sewn to each other")) + \
                "</small>"
        return edge_legend_html(self.report)
