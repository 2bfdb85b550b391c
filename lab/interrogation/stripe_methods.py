"""The exact stripe split and Choi and Lee's own facet colouring on the same triangulation, side by side.

:func:`compare_stripe_methods` runs :func:`lab.stripe_mapping` with
``method="exact"`` and ``method="paper"`` on one tessellation of a surface and
measures on how much of the surface the two show different colours
(:func:`lab.interrogation.reflection_paper.area_difference`).
"""

from typing import NamedTuple

import numpy as np

from ..i18n import _, decimal
from .meshes import _triangles, as_curvature_mesh, stripe_mapping
from .reflection_paper import area_difference

__all__ = ["StripeComparison", "compare_stripe_methods"]


class StripeComparison(NamedTuple):
    """Both stripe mappings of one tessellation and the share of the area where their colours differ."""

    exact: object  #: pyvista.PolyData of the exact split
    paper: object  #: pyvista.PolyData of the paper's cases 1–3
    difference: float  #: fraction of the surface area (0 … 1) coloured differently
    unresolved: int  #: case-3 pieces the paper's recursion left at its depth limit

    def __repr__(self):
        return "StripeComparison({})".format(decimal(_(
            "exact: {exact} cells, paper: {paper} cells, colours differ on {percent} of the area").format(
                exact=self.exact.n_cells, paper=self.paper.n_cells, percent=f"{100 * self.difference:.2f} %")))


def _parts(mapped):
    """(points, triangles, parent, colour keys) of a stripe mapping; equal RGB means equal colour."""
    triangles = np.asarray(mapped.faces).reshape(-1, 4)[:, 1:]
    _, keys = np.unique(np.asarray(mapped.cell_data["RGB"]), axis=0, return_inverse=True)
    return np.asarray(mapped.points), triangles, np.asarray(mapped.cell_data["parent"]), keys.ravel()


def compare_stripe_methods(surface, *, resolution=None, order=12, **options):
    """The exact split and the paper's on the same triangulation, and where their colours differ.

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches or pyvista.PolyData
    resolution : int, optional
        As in :func:`lab.stripe_mapping`; the surface is tessellated once.
    order : int
        Colour samples per triangle edge for the measurement.
    **options
        Further options of :func:`lab.stripe_mapping` (``n_stripes``, ``eye``, ``view``, …);
        not ``method`` or ``shaded``.

    Returns
    -------
    StripeComparison
    """
    for name in ("method", "shaded"):
        if name in options:
            raise TypeError(f"compare_stripe_methods runs both methods unshaded; do not pass {name}=")
    mesh = as_curvature_mesh(surface, resolution)
    exact = stripe_mapping(mesh, **options)
    paper = stripe_mapping(mesh, method="paper", **options)
    difference = area_difference(_parts(exact), _parts(paper), np.asarray(mesh.points), _triangles(mesh), order)
    return StripeComparison(exact, paper, difference, int(paper.field_data["unresolved"][0]))
