"""Matplotlib figures of path fans and polar isodistance curves, laid out like ``seeds/003`` figures 1–3.

The paper draws the normal sections (or geodesics) from a point with their
polar isodistance curves on the surface (figures 1, 2) and in the parameter
domain (figure 3); :func:`isodistance_figure` draws both side by side.
"""

import io

import numpy as np

__all__ = ["isodistance_figure", "PATH_COLOR", "CLOSED_COLOR", "OPEN_COLOR"]

PATH_COLOR = "#1f3b73"  #: the paths (normal sections or geodesics)
CLOSED_COLOR = "#d62728"  #: closed isodistance curves
OPEN_COLOR = "#ff7f0e"  #: open pieces of isodistance curves


def isodistance_figure(fan, curves, *, title=None, size=(10.0, 4.4), grid=41):
    """The fan and its polar isodistance curves on the surface (left) and in the (u, v) domain (right).

    Parameters
    ----------
    fan : lab.Fan
        Paths from one point (:func:`lab.normal_section_fan`, :func:`lab.geodesic_fan`).
    curves : list of list of lab.Isodistance
        :func:`lab.polar_isodistance` of the fan: closed curves are drawn red,
        open pieces orange and dashed.
    title : str, optional
    size : (float, float)
        Figure size in inches (100 dpi).
    grid : int
        Samples per parameter direction of the surface drawn on the left.

    Returns
    -------
    IPython.display.Image
        A PNG, like :func:`lab.render.show`.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from IPython.display import Image
    from matplotlib.figure import Figure

    if not hasattr(fan, "paths") or not hasattr(fan, "origin"):
        raise TypeError(f"fan must be a lab.Fan; got {type(fan).__name__}")
    surface = fan.surface
    fig = Figure(figsize=size, dpi=100)
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    ax2 = fig.add_subplot(1, 2, 2)
    U, V = surface.grid(grid, grid)
    X = surface.evaluate(U, V)
    ax3.plot_surface(X[..., 0], X[..., 1], X[..., 2], color="#dddddd", alpha=0.55, linewidth=0, shade=True)
    for p in fan:
        ax3.plot(*p.points.T, color=PATH_COLOR, lw=0.5)
        ax2.plot(p.uv[:, 0], p.uv[:, 1], color=PATH_COLOR, lw=0.5)
    for pieces in curves:
        for piece in pieces:
            style = dict(color=CLOSED_COLOR, lw=1.4) if piece.closed else dict(color=OPEN_COLOR, lw=1.2, ls="--")
            ax3.plot(*piece.points.T, **style)
            ax2.plot(piece.uv[:, 0], piece.uv[:, 1], **style)
    P = surface.evaluate(*fan.origin)
    ax3.plot(*np.asarray(P)[:, None], "ko", ms=3)
    ax2.plot(*fan.origin, "ko", ms=3)
    extent = np.ptp(X.reshape(-1, 3), axis=0)
    ax3.set_box_aspect(np.maximum(extent, 0.05 * extent.max()))
    ax3.set(xlabel="x", ylabel="y", zlabel="z")
    (u0, u1), (v0, v1) = surface.domain
    ax2.set(xlim=(u0, u1), ylim=(v0, v1), xlabel="u", ylabel="v", title="parameter domain")
    ax2.set_aspect("equal" if abs((u1 - u0) - (v1 - v0)) < 1e-12 else "auto")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return Image(data=buf.getvalue(), format="png")
