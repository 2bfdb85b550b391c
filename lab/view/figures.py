"""Matplotlib figures: path fans with polar isodistance curves, trimming loops, convergence of mesh estimators.

Puig-Pey et al. draw the normal sections (or geodesics) from a point with
their polar isodistance curves on the surface (Puig-Pey et al., figures 1, 2)
and in the parameter domain (figure 3); :func:`isodistance_figure` draws both
side by side.  Choi and Lee draw the trimming loops and the triangulation in
the domain (Choi & Lee, figures 2, 8a): :func:`trimming_figure`.  The error of curvature estimated on meshes
against the mesh size, on a log–log scale with the fitted orders (notebook 13): :func:`convergence_figure`.
"""

import io

import numpy as np

from ..i18n import _, decimal

__all__ = ["CLOSED_COLOR", "OPEN_COLOR", "PATH_COLOR", "convergence_figure", "isodistance_figure", "trimming_figure"]

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
            style = {"color": CLOSED_COLOR, "lw": 1.4} if piece.closed else {"color": OPEN_COLOR, "lw": 1.2, "ls": "--"}
            ax3.plot(*piece.points.T, **style)
            ax2.plot(piece.uv[:, 0], piece.uv[:, 1], **style)
    P = surface.evaluate(*fan.origin)
    ax3.plot(*np.asarray(P)[:, None], "ko", ms=3)
    ax2.plot(*fan.origin, "ko", ms=3)
    extent = np.ptp(X.reshape(-1, 3), axis=0)
    ax3.set_box_aspect(np.maximum(extent, 0.05 * extent.max()))
    ax3.set(xlabel="x", ylabel="y", zlabel="z")
    (u0, u1), (v0, v1) = surface.domain
    ax2.set(xlim=(u0, u1), ylim=(v0, v1), xlabel="u", ylabel="v", title=_("parameter domain"))
    ax2.set_ylabel("v", rotation=0, labelpad=8)  # upright: a rotated "v" reads ">"
    ax2.set_aspect("equal")  # one unit of u as long as one of v
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    return _png(fig)


def _png(fig):
    from IPython.display import Image

    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    return Image(data=buf.getvalue(), format="png")


def trimming_figure(trimmed, triangulation=None, *, title=None, size=(6.0, 5.0), arrows=8):
    """The trimming loops of a :class:`lab.trimming.TrimmedSurface` in its domain, with their direction.

    The outer loop is drawn blue, holes red, each with ``arrows`` arrow heads
    showing the direction (outer counter-clockwise, holes clockwise: the
    region lies to the left).  With ``triangulation`` (``(uv, triangles)``,
    e.g. ``trimmed.triangulate()``) its triangles are drawn too.

    Returns
    -------
    IPython.display.Image
        A PNG, like :func:`lab.render.show`.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    if not hasattr(trimmed, "outer") or not hasattr(trimmed, "holes"):
        raise TypeError(f"trimmed must be a lab.trimming.TrimmedSurface; got {type(trimmed).__name__}")
    fig = Figure(figsize=size, dpi=100)
    ax = fig.add_subplot()
    if triangulation is not None:
        uv, tri = triangulation
        ax.triplot(uv[:, 0], uv[:, 1], tri, color="#999999", lw=0.4)
    for loop, color in [(trimmed.outer, PATH_COLOR)] + [(h, CLOSED_COLOR) for h in trimmed.holes]:
        closed = np.vstack([loop, loop[:1]])
        ax.plot(closed[:, 0], closed[:, 1], color=color, lw=1.6)
        for i in np.linspace(0, len(loop), arrows, endpoint=False).astype(int):
            a, b = closed[i], closed[i + 1]
            ax.annotate("", xy=a + 0.6 * (b - a), xytext=a, arrowprops={"arrowstyle": "-|>", "color": color, "lw": 1.2})
    (u0, u1), (v0, v1) = trimmed.domain
    ax.set(xlim=(u0, u1), ylim=(v0, v1), xlabel="u", aspect="equal")
    ax.set_ylabel("v", rotation=0, labelpad=8)
    ax.set_title(title or _("trimming loops in the parameter domain"))
    fig.tight_layout()
    return _png(fig)


#: Colour and marker of each (quantity, region) of a convergence study (Okabe & Ito's colour-blind safe colours).
_SERIES = {("K", "inside"): ("#0072b2", "o", "-"), ("H", "inside"): ("#e69f00", "s", "-"),
           ("K", "boundary"): ("#0072b2", "o", ":"), ("H", "boundary"): ("#e69f00", "s", ":")}


def convergence_figure(studies, *, title=None, size=(9.0, 4.6), slopes=(1, 2)):
    """The largest relative error against the mesh size h of one or more :class:`lab.interrogation.estimators.Convergence`
    studies, log–log, each line labelled with its fitted order p; dashed grey lines show h¹ and h² (``slopes``).

    Returns
    -------
    IPython.display.Image
        A PNG, like :func:`lab.render.show`.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.figure import Figure

    studies = [studies] if hasattr(studies, "errors") else list(studies)
    if not studies or not all(hasattr(s, "errors") and hasattr(s, "h") for s in studies):
        raise TypeError("studies must be lab.interrogation.estimators.Convergence results (convergence(...))")
    names = {("K", "inside"): _("K inside"), ("K", "boundary"): _("K boundary"), ("H", "inside"): _("H inside"),
             ("H", "boundary"): _("H boundary")}
    fig = Figure(figsize=size, dpi=100)
    ax = fig.add_subplot()
    fills = ["full", "none", "left", "bottom"]
    for k, study in enumerate(studies):
        for key, errors in study.errors.items():
            if not np.all(np.isfinite(errors)):
                continue
            color, marker, line = _SERIES[key]
            label = f"{study.surface}: {names[key]}, p = {decimal(f'{study.orders[key]:.2f}')}"
            ax.loglog(study.h, errors, marker=marker, ls=line, color=color, fillstyle=fills[k % len(fills)],
                      label=label)
    h = np.concatenate([s.h for s in studies])
    lo, hi = float(h.min()), float(h.max())
    low = min(float(np.nanmin(e)) for s in studies for e in s.errors.values() if np.any(np.isfinite(e)))
    t = np.array([lo, hi])
    for p in slopes:  # from below the smallest error at the finest mesh, rising with the order
        ax.loglog(t, 0.3 * low * (t / lo) ** p, color="#999999", lw=0.8, ls="--")
        ax.annotate(f"∝ h{'¹²³'[p - 1] if 1 <= p <= 3 else p}", (hi, 0.3 * low * (hi / lo) ** p), color="#666666",
                    fontsize=9, xytext=(3, -3), textcoords="offset points")
    ax.set_xlim(lo / 1.3, hi * 2.2)  # room for the slopes' labels
    ax.set_xlabel(_("mesh size h (mean edge length)"))
    ax.set_ylabel(_("largest error / largest exact value"))
    ax.grid(True, which="major", color="#e5e5e5")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    ax.set_title(title or _("error of the discrete curvature against the mesh size"))
    fig.tight_layout()
    return _png(fig)
