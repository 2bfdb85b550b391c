"""Explorers of the interrogation tools: focal surfaces, reflection lines and isophotes, geodesic fans."""

import html
import warnings
from typing import ClassVar

import ipywidgets as W
import numpy as np
import pyvista as pv

from ... import mesh as _mesh
from ...geometry.curvature import DegeneratePointWarning
from ...i18n import N_, _, decimal
from ...interrogation.faces import face_surface, is_face, is_model
from ...interrogation.geodesics import Fan, geodesic_fan, normal_section_fan, polar_isodistance
from ...interrogation.meshes import (
    MODEL_RESOLUTION,
    as_curvature_mesh,
    focal_surface,
    isophotes,
    reflection_lines,
    stripe_mapping,
)
from ...interrogation.reflection import DEFAULT_COLORS, VIEW_DIRECTION
from .. import legend as _legend
from .. import style
from ..figures import CLOSED_COLOR, PATH_COLOR
from .base import Explorer, _dropdown, _layout, _Note, _polylines, checkpoint, style_for
from .controls import float_slider, full_row_text
from .edges import EdgeOverlay
from .models import default_point, face_mesh

__all__ = ["FocalExplorer", "GeodesicExplorer", "ReflectionExplorer"]

#: how far the geodesic explorer lifts its lines off the surface, relative to the surface's size
LIFT = 3e-3


def _slider(cls, description, **kwargs):
    kwargs.setdefault("continuous_update", False)  # act on release: no intermediate values
    if cls in (W.FloatSlider, W.FloatLogSlider, W.FloatRangeSlider):
        return float_slider(cls, _(description), **kwargs)
    return cls(description=_(description), style=style_for(), layout=_layout(), **kwargs)


def _curvature_mesh(source, resolution, default):
    """The explorer's mesh with exact curvature, built once: a surface on a ``resolution``² grid (``default`` when
    None), a model on ``resolution`` lines per face (16 when None: one vertex set per face, see lab.Model.to_mesh)."""
    if is_model(source):
        return as_curvature_mesh(source, MODEL_RESOLUTION if resolution is None else resolution)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DegeneratePointWarning)
        return as_curvature_mesh(source, default if resolution is None else resolution)


class FocalExplorer(Explorer):
    """A surface and its generalised focal surface F = X + a f(κ1, κ2) N (Choi & Lee, §4).

    ``surface`` may be a model (:func:`lab.read`): every face has its focal surface, with the face's normal,
    on ``resolution`` lines per face (default 16; a surface's grid is ``resolution``², default 48).  The
    surface's mesh with its curvature is built once; a change of the function or the scale moves its points.
    """

    title = N_("focal surface explorer")
    FUNCTIONS: ClassVar[dict] = {N_("H  mean"): "mean", N_("K  Gaussian"): "gaussian", "κ1² + κ2²": "strain-energy", "κ1": "k1",
                 "κ2": "k2"}

    def __init__(self, surface, *, scale=None, resolution=None, window_size=(800, 500), live=None, backend=None):
        super().__init__(window_size=window_size, live=live, backend=backend)
        self._focal = focal_surface
        self.source = surface
        self.resolution = resolution
        self.model = surface if is_model(surface) else None
        self._mesh = _curvature_mesh(surface, resolution, 48)
        self.function = self._control(_dropdown(list(self.FUNCTIONS.items()), "mean", N_("function")))
        if scale is None:  # the largest displacement a tenth of the model's size
            probe = focal_surface(self._mesh, scale=1.0, function="mean")
            size = float(np.linalg.norm(np.ptp(probe.point_data["X"], axis=0)))
            fmax = float(np.max(np.abs(probe.point_data["f"]))) or 1.0
            scale = float(f"{0.1 * size / fmax:.2g}")
        limit = 10 * abs(scale) or 1.0
        self.scale = self._control(_slider(W.FloatSlider, N_("scale a"), value=scale, min=-limit, max=limit,
                                           step=limit / 500, readout_format=".3g"))
        self.function.add_class("lab-primary-control")
        self.show_surface = self._control(W.Checkbox(value=True, description=_("surface"), indent=False))
        self._build_scene()
        for w in (self.function, self.scale, self.show_surface):
            self._observe(w, self.update_focal)

    def _controls(self):
        return [self.function, self.scale, self.show_surface]

    def _build_scene(self):
        base = self._focal(self._mesh, scale=0.0, function="mean")
        self.surface_mesh = base.copy()
        self.surface_actor = self.plotter.add_mesh(self.surface_mesh, color="#c8c8c8", opacity=0.45,
                                                   smooth_shading=True, **style.SURFACE_PROPERTIES)
        self.focal_mesh = base.copy()
        self.focal_actor = self.plotter.add_mesh(self.focal_mesh, scalars="f", cmap="coolwarm", smooth_shading=True,
                                                 show_scalar_bar=False, **style.SURFACE_PROPERTIES)
        style.fit_camera(self.plotter, self.surface_mesh)
        self._run(self.update_focal)

    def _fit_mesh(self):
        return self.surface_mesh

    def legend(self):
        lim = getattr(self, "_lim", 1.0)
        return _legend.legend(self.function.value, "coolwarm", clim=(-lim, lim))

    def update_focal(self):
        new = self._focal(self._mesh, scale=self.scale.value, function=self.function.value)
        self.focal_mesh.points = new.points
        self.focal_mesh.point_data["f"] = new.point_data["f"]
        f = np.asarray(new.point_data["f"])
        self._lim = float(np.max(np.abs(f[np.isfinite(f)]))) if np.isfinite(f).any() else 1.0
        self._lim = self._lim or 1.0
        self.focal_actor.mapper.scalar_range = (-self._lim, self._lim)
        self.surface_actor.SetVisibility(self.show_surface.value)
        self.refresh()


#: What each colour of the stripe box is (:data:`lab.reflection.DEFAULT_COLORS`): the wall of the box a point reflects.
STRIPE_WALLS = (N_("wall −x"), N_("wall +x"), N_("wall −y"), N_("wall +y"), N_("floor (−z)"), N_("ceiling (+z)"))


def stripe_legend_html():
    """The stripe box's legend: a swatch per colour and the wall of the box it is reflected from."""
    items = []
    for rgb, wall in zip(DEFAULT_COLORS, STRIPE_WALLS):
        colour = "#" + "".join(f"{round(255 * x):02x}" for x in rgb)
        swatch = (f'<span style="display:inline-block;width:14px;height:10px;background:{colour};'
                  f'border:1px solid #555;vertical-align:middle"></span>')
        items.append(f"{swatch} {html.escape(_(wall))}")
    text = html.escape(_("the colour says which wall of the box a point reflects; white: the gaps between stripes"))
    return f"<small>{' &nbsp; '.join(items)}<br>{text}</small>"


def stripe_legend():
    """The stripe box's walls as swatches beside a saved picture (:func:`stripe_legend_html` under the controls)."""
    return _legend.Legend(title=_("stripe box"), classes=tuple((_(wall), tuple(float(x) for x in rgb))
                                                              for rgb, wall in zip(DEFAULT_COLORS, STRIPE_WALLS)),
                          note=_("white: the gaps between stripes"))


class ReflectionExplorer(Explorer):
    """Reflection lines, isophotes and the striped box mapping on a surface (Choi & Lee, §3).

    ``surface`` may be a model (:func:`lab.read`), on ``resolution`` lines per face (default 16; a surface's
    grid is ``resolution``², default 64).  Its faces are not welded: the lines are joined across face borders
    where their ends meet (:mod:`lab.interrogation.faces`), so they run on over tangent-continuous edges and
    break at kinks, as the "edges by continuity" overlay shows them.
    """

    title = N_("reflection explorer")
    camera_direction = VIEW_DIRECTION  # reflections depend on the eye: look from the one they are computed for
    KINDS: ClassVar[dict] = {N_("stripe box mapping"): "stripes", N_("reflection lines (light lines)"): "lines",
             N_("isophotes"): "isophotes"}

    def __init__(self, surface, *, resolution=None, window_size=(800, 500), live=None, backend=None):
        super().__init__(window_size=window_size, live=live, backend=backend)
        self.source = surface
        self.resolution = resolution
        self.model = surface if is_model(surface) else None
        c = self._control
        self.kind = c(_dropdown(list(self.KINDS.items()), "stripes", N_("show")))
        self.kind.add_class("lab-primary-control")
        self.count = c(_slider(W.IntSlider, N_("stripes / lines"), value=8, min=1, max=40))
        self.azimuth = c(_slider(W.FloatSlider, N_("light dir. °"), value=0.0, min=0.0, max=180.0, step=1.0,
                                 readout_format=".0f"))
        self.elevation = c(_slider(W.FloatSlider, N_("light elev. °"), value=60.0, min=-90.0, max=90.0, step=1.0,
                                   readout_format=".0f"))
        self.orientation = c(W.ToggleButtons(options=[(_("horizontal"), "horizontal"), (_("vertical"), "vertical")],
                                             value="horizontal", description=_("stripes"),
                                             style=style_for(button_width="auto"),
                                             layout=_layout()))
        # light-line spacing as a multiple of the default, which spreads the lines over three diagonals
        self.spacing = c(_slider(W.FloatSlider, N_("line spacing ×"), value=1.0, min=0.1, max=3.0, step=0.05,
                                 readout_format=".2f"))
        self.show_edges = c(W.Checkbox(value=False, description=_("edges by continuity"), indent=False,
                                       layout=W.Layout(width="auto")))
        self.edge_legend = c(full_row_text())
        self.stripe_legend = c(full_row_text())
        self.stripe_legend.value = stripe_legend_html()
        self.edges = EdgeOverlay(surface)
        self._show_controls()
        self._build_scene()
        for w in (self.kind, self.count, self.azimuth, self.elevation, self.orientation, self.spacing):
            self._observe(w, self.update_lines)
        self._observe(self.show_edges, self.toggle_edges)

    def _controls(self):
        return [self.kind, self.count, self.orientation, self.spacing, self.azimuth, self.elevation,
                self.stripe_legend, self.show_edges, self.edge_legend]

    #: The controls each kind uses: the stripe box has no light direction and no line spacing; lines and isophotes
    #: have no box whose stripes could run horizontally or vertically.
    USES: ClassVar[dict] = {"stripes": ("orientation", "stripe_legend"), "lines": ("spacing", "azimuth", "elevation"),
                            "isophotes": ("azimuth", "elevation")}

    def _show_controls(self):
        """Show only the controls (and the stripes' legend) that apply to the chosen kind."""
        used = self.USES[self.kind.value]
        for name in ("orientation", "stripe_legend", "spacing", "azimuth", "elevation"):
            getattr(self, name).layout.display = None if name in used else "none"

    def toggle_edges(self):
        """Show or hide the edges coloured by what they achieve (lab.continuity), with their legend."""
        self.edge_legend.value = self.edges.show(self.plotter, self.show_edges.value)
        self.refresh()

    def _direction(self):
        a = np.radians(self.azimuth.value)
        e = np.radians(self.elevation.value)
        return np.array([np.cos(a) * np.cos(e), np.sin(a) * np.cos(e), np.sin(e)])

    def _build_scene(self):
        self.surface_mesh = _curvature_mesh(self.source, self.resolution, 64)
        self.surface_actor = self.plotter.add_mesh(self.surface_mesh, color="#e6e6e6", smooth_shading=True,
                                                   **style.SURFACE_PROPERTIES)
        self.overlay = pv.PolyData()
        self.overlay_actor = None
        style.fit_camera(self.plotter, self.surface_mesh, self.camera_direction)
        self._run(self.update_lines)

    def _fit_mesh(self):
        return self.surface_mesh

    def update_lines(self):
        self._show_controls()  # here, not in an observer of its own: that one would clear this one's status
        kind = self.kind.value
        n = self.count.value
        d = self._direction()
        size = float(np.linalg.norm(np.ptp(self.surface_mesh.points, axis=0)))
        if kind == "stripes":
            # stripes counted across z on the walls (horizontal, like light tubes) or across the walls' other axis
            axes = (2, 2, 2, 2, 1, 1) if self.orientation.value == "horizontal" else (1, 1, 0, 0, 0, 0)
            new = stripe_mapping(self.surface_mesh, n_stripes=n, axes=axes)
        elif kind == "lines":
            horizontal = np.array([d[0], d[1], 0.0])
            if np.linalg.norm(horizontal) < 1e-9:
                raise ValueError(_("the light lines need a direction with a horizontal part; lower the elevation"))
            new = reflection_lines(self.surface_mesh, direction=horizontal, count=n,
                                   spacing=self.spacing.value * 3.0 * size / n)
        else:
            new = isophotes(self.surface_mesh, light=d, count=n)
        if self.overlay_actor is not None:
            self.plotter.remove_actor(self.overlay_actor)
            self.overlay_actor = None
        if new.n_points == 0:
            self.surface_actor.SetVisibility(True)
            self.refresh()
            raise _Note(_("no lines fall on the surface for this direction and spacing: change them"))
        if kind == "stripes":
            self.overlay_actor = self.plotter.add_mesh(new, scalars="RGB", rgb=True, preference="cell",
                                                       **style.SURFACE_PROPERTIES)
            self.surface_actor.SetVisibility(False)
        else:
            self.surface_actor.SetVisibility(True)
            self.overlay_actor = style.add_lines_on_surface(self.plotter, new, render_lines_as_tubes=False)
        self.overlay = new
        self.refresh()

    def picture_legend(self):
        """The stripe box's walls beside a picture of the stripe box mapping (the lines need no legend)."""
        return stripe_legend() if self.kind.value == "stripes" else None

    def picture_title(self):
        """What the picture shows: stripes, light lines or isophotes, how many, and the light's direction."""
        kinds = {v: k for k, v in self.kind.options}
        return decimal(_("{kind}, {count}, light {azimuth}° / {elevation}°").format(
            kind=kinds.get(self.kind.value, self.kind.value), count=self.count.value,
            azimuth=f"{self.azimuth.value:g}", elevation=f"{self.elevation.value:g}"))


class GeodesicExplorer(Explorer):
    """Fans of geodesics or normal sections from a point and their polar isodistance curves (Puig-Pey et al.).

    The paths and the isodistance curves are drawn on the surface and, below
    it, in the parameter domain (like figures 2 and 3 of the paper).  Only what
    a change needs is recomputed: a new step s_L or number of curves within the
    length already integrated reuses the paths and recomputes the curves only.

    Parameters
    ----------
    surface : lab surface or lab.Face
        A surface, or a face of a model (:func:`lab.read`): the paths then stop where they leave the face's
        trimmed region, the start sliders span the face's loops and the parameter domain shows them.
    start : (float, float), optional
        Start point (u0, v0); default: the domain's centre (on a face: a point inside it).
    n_angles : int
    step : float, optional
        Isodistance step s_L; default: a fifth of the surface's size divided by ``n_curves``.
    n_curves : int
        Number of isodistance curves (s_L = step, 2 step, …); the paths have
        length ``step * n_curves``.  The number of paths is ``n_angles``.
    count : int, optional
        Deprecated name of ``n_curves``.
    """

    title = N_("geodesic explorer")
    KINDS: ClassVar[dict] = {N_("geodesics"): "geodesic", N_("normal sections"): "normal-section"}
    # paths integrated per step: progress, and a newer request cancels between steps.  The vectorised integrator
    # costs about the same per call whatever the number of paths, so steps are large (2 x 20 paths: +75%).
    CHUNK = 40

    def __init__(self, surface, start=None, *, n_angles=40, step=None, n_curves=8, window_size=(800, 500), live=None,
                 backend=None, count=None):
        if count is not None:
            warnings.warn("GeodesicExplorer(count=…) is deprecated: the number of isodistance curves is now "
                          "n_curves=… (the number of paths is n_angles)", DeprecationWarning, stacklevel=2)
            n_curves = count
        super().__init__(window_size=window_size, live=live, backend=backend)
        self.face = surface if is_face(surface) else None
        self.source = face_surface(surface) if self.face is not None else surface
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DegeneratePointWarning)
            if self.face is None:
                self.surface_mesh = _mesh.surface_mesh(surface, 64, 64)
                (u0, u1), (v0, v1) = surface.domain
            else:  # the face in its trimmed region; the sliders span its loops
                self.surface_mesh = face_mesh(self.face, 32)
                (u0, u1), (v0, v1) = self._box()
        if start is None:
            start = (default_point(self.surface_mesh, self.face.index) if self.face is not None
                     else (0.5 * (u0 + u1), 0.5 * (v0 + v1)))
        size = float(np.linalg.norm(np.ptp(self.surface_mesh.points, axis=0)))
        if step is None:
            step = float(f"{size / (5 * n_curves):.2g}")
        c = self._control
        self.kind = c(_dropdown(list(self.KINDS.items()), "geodesic", N_("paths")))
        self.u0 = c(_slider(W.FloatSlider, N_("start u0"), value=start[0], min=u0, max=u1, step=(u1 - u0) / 200))
        self.v0 = c(_slider(W.FloatSlider, N_("start v0"), value=start[1], min=v0, max=v1, step=(v1 - v0) / 200))
        self.u0.add_class("lab-primary-control")
        self.n_angles = c(_slider(W.IntSlider, N_("angles"), value=n_angles, min=3, max=160))
        self.angle_range = c(_slider(W.FloatRangeSlider, N_("α range °"), value=(0.0, 360.0), min=0.0, max=360.0,
                                     step=1.0, readout_format=".0f"))
        self.step = c(W.BoundedFloatText(value=step, min=size * 1e-4, max=size * 10, step=step / 10,
                                         description=_("step s_L"), style=style_for(), layout=_layout()))
        self.count = c(_slider(W.IntSlider, N_("curves"), value=n_curves, min=1, max=40))
        self.domain_view = c(W.HTML(layout=W.Layout(width="100%")))
        self.domain_view.add_class("lab-domain-view")
        self._fan_key = None
        self.fan = None
        self._build_scene()
        for w in (self.kind, self.u0, self.v0, self.n_angles, self.angle_range, self.step, self.count):
            self._observe(w, self.update_fan)

    def _controls(self):
        return [self.kind, self.u0, self.v0, self.n_angles, self.angle_range, self.step, self.count]

    def _extra_views(self):
        return [self.domain_view]

    def _build_scene(self):
        self.plotter.add_mesh(self.surface_mesh, color="#e8e8e8", smooth_shading=True, **style.SURFACE_PROPERTIES)
        self.paths_mesh = pv.PolyData()
        self.iso_mesh = pv.PolyData()
        self.start_mesh = pv.PolyData(np.zeros((1, 3)))
        self.paths_actor = None
        self.iso_actor = None
        self.plotter.add_mesh(self.start_mesh, color="black", point_size=10, render_points_as_spheres=True)
        style.fit_camera(self.plotter, self.surface_mesh)
        self._run(self.update_fan)

    def _fit_mesh(self):
        return self.surface_mesh

    def legend_html(self):
        if self.fan is None:
            return ""
        kind = _("geodesics") if self.kind.value == "geodesic" else _("normal sections")
        curves = html.escape(_("polar isodistance curves at"))
        return (f'<div class="lab-legend" style="font-size:12px;text-align:center">'
                f'<span style="color:{PATH_COLOR};font-weight:700">━</span> {len(self.fan or [])} {kind} &nbsp; '
                f'<span style="color:{CLOSED_COLOR};font-weight:700">━</span> {curves} '
                f's<sub>L</sub>, 2 s<sub>L</sub>, … (s<sub>L</sub> = {decimal(f"{self.step.value:g}")})</div>')

    def picture_legend(self):
        """The two kinds of line as swatches beside a saved picture (the view below has them as text)."""
        if self.fan is None:
            return None
        kind = _("geodesics") if self.kind.value == "geodesic" else _("normal sections")
        rgb = [tuple(int(c[k:k + 2], 16) / 255 for k in (1, 3, 5)) for c in (PATH_COLOR, CLOSED_COLOR)]
        return _legend.Legend(title=_("lines"), classes=((f"{len(self.fan)} {kind}", rgb[0]),
                                                         (_("polar isodistance curves"), rgb[1])),
                              note=decimal(_("at $s_L$, $2 s_L$, … ($s_L$ = {step})").format(step=f"{self.step.value:g}")))

    def _angles(self):
        lo, hi = self.angle_range.value
        n = self.n_angles.value
        if hi - lo >= 360.0 - 1e-9:
            return 2 * np.pi * np.arange(n) / n, True
        if hi <= lo:
            raise ValueError(_("the angle range is empty: move its two ends apart"))
        return np.radians(np.linspace(lo, hi, n)), False

    async def update_fan(self):
        """Recompute what changed: the fan (in steps, with progress) if its start, angles or length grew; the curves."""
        angles, full = self._angles()
        n = len(angles)
        length = self.step.value * self.count.value
        kind = self.kind.value
        uv0 = (self.u0.value, self.v0.value)
        key = (kind, uv0, n, self.angle_range.value)
        if self._fan_key != key or self.fan is None or self.fan.length < length * (1 - 1e-12):
            fan_fn = geodesic_fan if kind == "geodesic" else normal_section_fan
            paths = []
            for first in range(0, n, self.CHUNK):
                what = (_("computing {n} geodesics of length {length:g}: {done} done …") if kind == "geodesic"
                        else _("computing {n} normal sections of length {length:g}: {done} done …"))
                self._show_progress(first / n, what.format(n=n, length=length, done=first))
                await checkpoint()
                part = fan_fn(self.face or self.source, uv0, None, length, angles=angles[first:first + self.CHUNK],
                              n_samples=61)
                paths += part.paths
            self.fan = Fan(paths, angles, part.origin, part.length, part.kind, part.surface, full)
            self._fan_key = key
            self._show_progress(1.0, _("isodistance curves …"))
            await checkpoint()
        fan = self.fan
        distances = self.step.value * np.arange(1, self.count.value + 1)
        iso = polar_isodistance(fan, distances)
        self.isodistance = iso
        self.start_mesh.points = self.source.evaluate(*uv0)[None]
        paths = [(p.points[keep], p.uv[keep]) for p in fan for keep in [p.s <= length * (1 + 1e-9)]]
        self.paths_mesh.copy_from(_polylines(self._lifted(paths)), deep=True)
        curves = [(piece.points, piece.uv) for pieces in iso for piece in pieces if len(piece.points) > 1]
        self.iso_mesh.copy_from(_polylines(self._lifted(curves)), deep=True)
        if self.paths_actor is None and self.paths_mesh.n_points:
            self.paths_actor = self.plotter.add_mesh(self.paths_mesh, color=PATH_COLOR, line_width=1.5)
        if self.iso_actor is None and self.iso_mesh.n_points:
            self.iso_actor = self.plotter.add_mesh(self.iso_mesh, color=CLOSED_COLOR, line_width=2.5)
        self.domain_view.value = self._domain_svg(fan, iso, length)
        reached = [d for d, pieces in zip(distances, iso) if pieces]
        short = [p for p in fan if p.length < length * (1 - 1e-9)]
        stopped = sum(1 for p in short if p.hit_boundary)
        what = (_("{stopped} of {n} paths leave the face before length {length:g}") if self.face is not None
                else _("{stopped} of {n} paths reach the boundary before length {length:g}"))
        note = what.format(stopped=stopped, n=len(fan), length=length) if stopped else ""
        if len(reached) < len(distances):
            note += ("; " if note else "") + _("no path reaches s_L ≥ {s:g}").format(s=distances[len(reached)])
        self.refresh()
        if note:
            raise _Note(note)

    def _lifted(self, curves):
        """Each curve on the surface twice, lifted a little off it along +N and −N.

        A line drawn exactly on a surface fights with it in the depth buffer and looks dashed where the
        triangles bulge over it (near the edges, at grazing view); the browser's renderer (vtk.js) knows no
        depth offset, so the lines move instead: by 0.3% of the surface's size, invisible at any zoom that shows
        the whole surface, and one of the two copies faces the eye from either side.
        """
        size = float(np.linalg.norm(np.ptp(np.asarray(self.surface_mesh.points), axis=0))) or 1.0
        out = []
        for points, uv in curves:
            if len(points) < 2:
                continue
            D = self.source.derivatives(uv[:, 0], uv[:, 1])
            N = np.cross(D.bu, D.bv)
            N /= np.maximum(np.linalg.norm(N, axis=-1, keepdims=True), 1e-300)
            N = np.nan_to_num(N)
            out += [points + LIFT * size * N, points - LIFT * size * N]
        return out

    def _box(self):
        """The (u, v) box shown: the surface's domain, or the bounding box of a face's loops."""
        if self.face is None or self.face.trim is None:
            return self.source.domain
        X = np.concatenate(self.face.trim.loops)
        lo, hi = X.min(axis=0), X.max(axis=0)
        return (float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))

    def _domain_svg(self, fan, iso, length):
        """The paths and curves in the parameter domain as SVG (drawn by the browser, crisp at any width)."""
        (u0, u1), (v0, v1) = self._box()
        H_, m = 300.0, 34.0
        # one unit of u as long as one of v: a circle in the domain is drawn round (the box is square on a square domain)
        ph = H_ - 2 * m
        pw = min(ph * (u1 - u0) / (v1 - v0), 3 * ph)
        W_ = pw + 2 * m + 40.0
        left = m + 20.0

        def xy(uv):  # the box spans x in [left, left + pw], y in [m - 10, m - 10 + ph] (v upwards)
            x = left + (uv[:, 0] - u0) / (u1 - u0) * pw
            y = H_ - m - 10 - (uv[:, 1] - v0) / (v1 - v0) * ph
            return " ".join(f"{a:.1f},{b:.1f}" for a, b in zip(x, y))

        parts = []
        if self.face is not None and self.face.trim is not None:  # the face's loops, outer first
            for loop in self.face.trim.loops:
                parts.append(f'<polygon points="{xy(loop)}" fill="none" stroke="#57606a" stroke-width="1.2"/>')
        for p in fan:
            keep = p.s <= length * (1 + 1e-9)
            parts.append(f'<polyline points="{xy(p.uv[keep])}" fill="none" stroke="{PATH_COLOR}" stroke-width="0.8"/>')
        for pieces in iso:
            for piece in pieces:
                parts.append(f'<polyline points="{xy(piece.uv)}" fill="none" stroke="{CLOSED_COLOR}" stroke-width="1.6"/>')
        ox, oy = xy(np.asarray(fan.origin, dtype=float)[None]).split(",")
        box = (f'<rect x="{left}" y="{m - 10}" width="{pw}" height="{ph}" fill="none" '
               'stroke="#57606a" stroke-width="1"/>')
        labels = "".join(
            f'<text x="{x}" y="{y}" font-size="11" fill="#1f2328" text-anchor="{a}">{html.escape(decimal(t))}</text>'
            for x, y, a, t in ((left, H_ - m + 4, "middle", f"{u0:g}"), (left + pw, H_ - m + 4, "middle", f"{u1:g}"),
                               (left + pw / 2, H_ - m + 8, "middle", "u"), (left - 4, H_ - m - 10, "end", f"{v0:g}"),
                               (left - 4, m - 6, "end", f"{v1:g}"), (left - 14, H_ / 2 - 6, "end", "v"),
                               (left + pw / 2, 14, "middle", _("parameter domain"))))
        clip = (f'<clipPath id="lab-domain-clip"><rect x="{left}" y="{m - 10}" width="{pw}" '
                f'height="{ph}"/></clipPath>')
        return (f'<svg viewBox="0 0 {W_:.0f} {H_:.0f}" style="width:100%;max-width:{W_ * 1.4:.0f}px;height:auto;'
                f'display:block;margin:0 auto" xmlns="http://www.w3.org/2000/svg"><defs>{clip}</defs>{box}'
                f'<g clip-path="url(#lab-domain-clip)">{"".join(parts)}</g>'
                f'<circle cx="{ox}" cy="{oy}" r="3" fill="black"/>{labels}</svg>')
