"""Explorers of the interrogation tools: focal surfaces, reflection lines and isophotes, geodesic fans."""

import io
import warnings

import ipywidgets as W
import numpy as np
import pyvista as pv

from ... import mesh as _mesh
from ...geometry.curvature import DegeneratePointWarning
from ...interrogation.geodesics import geodesic_fan, normal_section_fan, polar_isodistance
from ...interrogation.meshes import as_curvature_mesh, focal_surface, isophotes, reflection_lines, stripe_mapping
from ..render import VIEW_DIRECTION, set_camera
from .base import Explorer, _dropdown, _Note, _polylines

__all__ = ["FocalExplorer", "ReflectionExplorer", "GeodesicExplorer"]


class FocalExplorer(Explorer):
    """A surface and its generalised focal surface F = X + a f(κ1, κ2) N (seeds/002, section 4)."""

    title = "focal surface explorer"
    FUNCTIONS = {"H  mean": "mean", "K  Gaussian": "gaussian", "κ1² + κ2²": "strain-energy", "κ1": "k1", "κ2": "k2"}

    def __init__(self, surface, *, scale=None, resolution=48, window_size=(640, 480), live=None):
        super().__init__(window_size=window_size, live=live)
        self._focal = focal_surface
        self.source = surface
        self.resolution = resolution
        self.function = _dropdown(list(self.FUNCTIONS.items()), "mean", "function")
        if scale is None:  # the largest displacement a tenth of the model's size
            probe = focal_surface(surface, scale=1.0, function="mean", resolution=resolution)
            size = float(np.linalg.norm(np.ptp(probe.point_data["X"], axis=0)))
            fmax = float(np.max(np.abs(probe.point_data["f"]))) or 1.0
            scale = float(f"{0.1 * size / fmax:.2g}")
        limit = 10 * abs(scale) or 1.0
        self.scale = W.FloatSlider(value=scale, min=-limit, max=limit, step=limit / 500, description="scale a",
                                   readout_format=".3g", style={"description_width": "90px"},
                                   layout=W.Layout(width="300px"))
        self.function.add_class("lab-primary-control")
        self.show_surface = W.Checkbox(value=True, description="surface", indent=False)
        self._build_scene()
        self.function.observe(self._callback(self.update_focal), "value")
        self.scale.observe(self._callback(self.update_focal), "value")
        self.show_surface.observe(self._callback(self.update_focal), "value")

    def _controls(self):
        return [W.HTML(f"<b>{self.title}</b>"), self.function, self.scale, self.show_surface]

    def _build_scene(self):
        base = self._focal(self.source, scale=0.0, function="mean", resolution=self.resolution)
        self.surface_mesh = base.copy()
        self.surface_actor = self.plotter.add_mesh(self.surface_mesh, color="#c8c8c8", opacity=0.45,
                                                   smooth_shading=True)
        self.focal_mesh = base.copy()
        self.focal_actor = self.plotter.add_mesh(self.focal_mesh, scalars="f", cmap="coolwarm", smooth_shading=True,
                                                 scalar_bar_args={"title": "f", "color": "black"})
        set_camera(self.plotter, self.surface_mesh, VIEW_DIRECTION)
        self.update_focal()

    def update_focal(self):
        new = self._focal(self.source, scale=self.scale.value, function=self.function.value,
                          resolution=self.resolution)
        self.focal_mesh.points = new.points
        self.focal_mesh.point_data["f"] = new.point_data["f"]
        f = np.asarray(new.point_data["f"])
        lim = float(np.max(np.abs(f))) or 1.0
        self.focal_actor.mapper.scalar_range = (-lim, lim)
        self.surface_actor.SetVisibility(self.show_surface.value)
        self.refresh()


class ReflectionExplorer(Explorer):
    """Reflection lines, isophotes and the striped box mapping on a surface (seeds/002, section 3)."""

    title = "reflection explorer"
    KINDS = {"stripe box mapping": "stripes", "reflection lines (light lines)": "lines", "isophotes": "isophotes"}

    def __init__(self, surface, *, resolution=64, window_size=(640, 480), live=None):
        super().__init__(window_size=window_size, live=live)
        self.source = surface
        self.resolution = resolution
        self.kind = _dropdown(list(self.KINDS.items()), "stripes", "show")
        self.kind.add_class("lab-primary-control")
        self.count = W.IntSlider(value=8, min=1, max=40, description="stripes / lines", style={"description_width": "90px"},
                                 layout=W.Layout(width="300px"))
        self.azimuth = W.FloatSlider(value=0.0, min=0.0, max=180.0, step=1.0, description="direction °",
                                     style={"description_width": "90px"}, layout=W.Layout(width="300px"))
        self.elevation = W.FloatSlider(value=60.0, min=-90.0, max=90.0, step=1.0, description="light elev. °",
                                       style={"description_width": "90px"}, layout=W.Layout(width="300px"))
        self.orientation = W.ToggleButtons(options=["horizontal", "vertical"], value="horizontal",
                                           description="stripes", style={"description_width": "90px",
                                                                         "button_width": "100px"})
        # light-line spacing as a multiple of the default, which spreads the lines over three diagonals
        self.spacing = W.FloatSlider(value=1.0, min=0.1, max=3.0, step=0.05, description="line spacing ×",
                                     readout_format=".2f", style={"description_width": "90px"},
                                     layout=W.Layout(width="300px"))
        self._build_scene()
        for w in (self.kind, self.count, self.azimuth, self.elevation, self.orientation, self.spacing):
            w.observe(self._callback(self.update_lines), "value")

    def _controls(self):
        return [W.HTML(f"<b>{self.title}</b>"), self.kind, self.count, self.orientation, self.spacing,
                W.HTML("<small>light direction (lines, isophotes):</small>"), self.azimuth, self.elevation]

    def _direction(self):
        a = np.radians(self.azimuth.value)
        e = np.radians(self.elevation.value)
        return np.array([np.cos(a) * np.cos(e), np.sin(a) * np.cos(e), np.sin(e)])

    def _build_scene(self):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DegeneratePointWarning)
            self.surface_mesh = as_curvature_mesh(self.source, self.resolution)
        self.surface_actor = self.plotter.add_mesh(self.surface_mesh, color="#e6e6e6", smooth_shading=True)
        self.overlay = pv.PolyData()
        self.overlay_actor = None
        set_camera(self.plotter, self.surface_mesh, VIEW_DIRECTION)
        self.update_lines()

    def update_lines(self):
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
                raise ValueError("the light lines need a direction with a horizontal part; lower the elevation")
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
            raise _Note("no lines fall on the surface for this direction and spacing: change them")
        if kind == "stripes":
            self.overlay_actor = self.plotter.add_mesh(new, scalars="RGB", rgb=True, preference="cell")
            self.surface_actor.SetVisibility(False)
        else:
            self.surface_actor.SetVisibility(True)
            self.overlay_actor = self.plotter.add_mesh(new, color="black", line_width=2, render_lines_as_tubes=False)
        self.overlay = new
        self.refresh()


class GeodesicExplorer(Explorer):
    """Fans of geodesics or normal sections from a point and their polar isodistance curves (seeds/003).

    The paths and the isodistance curves are drawn on the surface and, below
    it, in the parameter domain (like figures 2 and 3 of the paper).

    Parameters
    ----------
    surface : lab surface
    start : (float, float), optional
        Start point (u0, v0); default: the domain's centre.
    n_angles : int
    step : float, optional
        Isodistance step s_L; default: a fifth of the surface's size divided by ``n_curves``.
    n_curves : int
        Number of isodistance curves (s_L = step, 2 step, …); the paths have
        length ``step * n_curves``.  The number of paths is ``n_angles``.
    count : int, optional
        Deprecated name of ``n_curves``.
    """

    title = "geodesic explorer"
    KINDS = {"geodesics": "geodesic", "normal sections": "normal-section"}

    def __init__(self, surface, start=None, *, n_angles=40, step=None, n_curves=8, window_size=(640, 420), live=None,
                 count=None):
        if count is not None:
            warnings.warn("GeodesicExplorer(count=…) is deprecated: the number of isodistance curves is now "
                          "n_curves=… (the number of paths is n_angles)", DeprecationWarning, stacklevel=2)
            n_curves = count
        super().__init__(window_size=window_size, live=live)
        self.source = surface
        (u0, u1), (v0, v1) = surface.domain
        if start is None:
            start = (0.5 * (u0 + u1), 0.5 * (v0 + v1))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DegeneratePointWarning)
            self.surface_mesh = _mesh.surface_mesh(surface, 64, 64)
        size = float(np.linalg.norm(np.ptp(self.surface_mesh.points, axis=0)))
        if step is None:
            step = float(f"{size / (5 * n_curves):.2g}")
        style = {"description_width": "90px"}
        lay = W.Layout(width="300px")
        self.kind = _dropdown(list(self.KINDS.items()), "geodesic", "paths")
        self.u0 = W.FloatSlider(value=start[0], min=u0, max=u1, step=(u1 - u0) / 200, description="start u0",
                                style=style, layout=lay, continuous_update=False)
        self.v0 = W.FloatSlider(value=start[1], min=v0, max=v1, step=(v1 - v0) / 200, description="start v0",
                                style=style, layout=lay, continuous_update=False)
        self.u0.add_class("lab-primary-control")
        self.n_angles = W.IntSlider(value=n_angles, min=3, max=160, description="angles", style=style, layout=lay,
                                    continuous_update=False)
        self.angle_range = W.FloatRangeSlider(value=(0.0, 360.0), min=0.0, max=360.0, step=1.0, description="α range °",
                                              style=style, layout=lay, continuous_update=False)
        self.step = W.BoundedFloatText(value=step, min=size * 1e-4, max=size * 10, step=step / 10,
                                       description="step s_L", style=style, layout=lay)
        self.count = W.IntSlider(value=n_curves, min=1, max=40, description="curves", style=style, layout=lay,
                                 continuous_update=False)
        self.domain_view = W.Image(format="png", layout=W.Layout(width=f"{window_size[0]}px"))
        self._build_scene()
        for w in (self.kind, self.u0, self.v0, self.n_angles, self.angle_range, self.step, self.count):
            w.observe(self._callback(self.update_fan), "value")

    def _controls(self):
        return [W.HTML(f"<b>{self.title}</b>"), self.kind, self.u0, self.v0, self.n_angles, self.angle_range,
                self.step, self.count]

    def _extra_views(self):
        return [self.domain_view]

    def _build_scene(self):
        self.plotter.add_mesh(self.surface_mesh, color="#e8e8e8", smooth_shading=True)
        self.paths_mesh = pv.PolyData()
        self.iso_mesh = pv.PolyData()
        self.start_mesh = pv.PolyData(np.zeros((1, 3)))
        self.paths_actor = None
        self.iso_actor = None
        self.plotter.add_mesh(self.start_mesh, color="black", point_size=10, render_points_as_spheres=True)
        set_camera(self.plotter, self.surface_mesh, VIEW_DIRECTION)
        self._run(self.update_fan)

    def _angles(self):
        lo, hi = self.angle_range.value
        n = self.n_angles.value
        if hi - lo >= 360.0 - 1e-9:
            return None, True
        if hi <= lo:
            raise ValueError("the angle range is empty: move its two ends apart")
        return np.radians(np.linspace(lo, hi, n)), False

    def update_fan(self):
        """Recompute the fan and the isodistance curves and update the scene in place."""
        angles, full = self._angles()
        n = self.n_angles.value
        length = self.step.value * self.count.value
        self._say(f"computing {n} {self.kind.value.replace('-', ' ')}s of length {length:g} …", "busy")
        fan_fn = geodesic_fan if self.kind.value == "geodesic" else normal_section_fan
        uv0 = (self.u0.value, self.v0.value)
        fan = fan_fn(self.source, uv0, None if angles is not None else n, length, angles=angles, n_samples=61)
        distances = self.step.value * np.arange(1, self.count.value + 1)
        iso = polar_isodistance(fan, distances)
        self.fan, self.isodistance = fan, iso
        self.start_mesh.points = self.source.evaluate(*uv0)[None]
        self.paths_mesh.copy_from(_polylines([p.points for p in fan]), deep=True)
        curves = [piece.points for pieces in iso for piece in pieces if len(piece.points) > 1]
        self.iso_mesh.copy_from(_polylines(curves), deep=True)
        if self.paths_actor is None and self.paths_mesh.n_points:
            self.paths_actor = self.plotter.add_mesh(self.paths_mesh, color="#1f3b73", line_width=1.5)
        if self.iso_actor is None and self.iso_mesh.n_points:
            self.iso_actor = self.plotter.add_mesh(self.iso_mesh, color="#d62728", line_width=2.5)
        self.domain_view.value = self._domain_png(fan, iso)
        reached = [d for d, pieces in zip(distances, iso) if pieces]
        stopped = int(fan.hit_boundary.sum())
        note = f"{stopped} of {len(fan)} paths reach the boundary before length {length:g}" if stopped else ""
        if len(reached) < len(distances):
            note += ("; " if note else "") + f"no path reaches s_L ≥ {distances[len(reached)]:g}"
        self.refresh()
        if note:
            self._say(note, "note")
            raise _Note(note)

    def _domain_png(self, fan, iso):
        import matplotlib

        matplotlib.use("Agg", force=False)
        from matplotlib.figure import Figure

        fig = Figure(figsize=(self.window_size[0] / 100, 3.2), dpi=100)
        ax = fig.add_subplot()
        for p in fan:
            ax.plot(p.uv[:, 0], p.uv[:, 1], color="#1f3b73", lw=0.7)
        for pieces in iso:
            for piece in pieces:
                ax.plot(piece.uv[:, 0], piece.uv[:, 1], color="#d62728", lw=1.4)
        ax.plot(*fan.origin, "ko", ms=4)
        (u0, u1), (v0, v1) = self.source.domain
        ax.set_xlim(u0, u1)
        ax.set_ylim(v0, v1)
        ax.set_xlabel("u")
        ax.set_ylabel("v")
        ax.set_title("parameter domain", fontsize=9)
        ax.set_aspect("auto")
        fig.tight_layout()
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        return buf.getvalue()
