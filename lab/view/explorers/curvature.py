"""The curvature explorer: a surface coloured by K, H, κ1, κ2, strain energy or the classification, at any depth."""

import html
import warnings

import ipywidgets as W
import numpy as np
import pyvista as pv

from ... import mesh as _mesh
from ...geometry import colormaps
from ...geometry.curvature import Curvature, CurvatureMode, DegeneratePointWarning, curvature_values
from ...model.patches import BezierPatches
from ..render import VIEW_DIRECTION, set_camera
from .base import Explorer, _dropdown

__all__ = ["CurvatureExplorer"]


# Colour maps of the explorer: label -> (kind, name); kind "h" uses the practical's ramp h.
_H_MAPS = {
    "h∘f2 linear (min/max)": "linear",
    "h∘f1 cut [0, 1]": "cut",
    "h∘f3 classification": "classification",
    "Dill's five bands": "dill",
    "symmetric (0 = green)": "symmetric",
    "percentile 2–98": "percentile",
    "signed log": "signed-log",
}
_PERCEPTUAL = {"viridis": "viridis", "cividis": "cividis", "coolwarm (diverging)": "coolwarm", "RdBu (diverging)": "RdBu_r"}
_MEASURES = {
    "K  Gaussian": "gaussian",
    "H  mean": "mean",
    "κ1  max. principal": "k1",
    "κ2  min. principal": "k2",
    "κ1² + κ2²  strain energy": "strain-energy",
    "classification (sign of K)": "classification",
}


def _h_cmap():
    from matplotlib.colors import ListedColormap

    return ListedColormap(colormaps.h(np.linspace(0, 1, 256)), name="practical-h")


def _dill_cmap():
    from matplotlib.colors import ListedColormap

    return ListedColormap(colormaps.DILL_COLORS, name="dill")


class CurvatureExplorer(Explorer):
    """Curvature of a surface, coloured by a chosen measure and colour map, at a chosen subdivision depth.

    Parameters
    ----------
    surface : lab surface with ``to_bezier_patches()``, or BezierPatches
        What to show.  The patches are refined ``depth`` times (the practical's
        ``refine``) and coloured at their corners.
    patches_class : subclass of lab.BezierPatches, optional
        A class with the student's own ``visualize_curvature``: the explorer
        then shows the colours that method stores, for the practical's four
        measures and three maps.
    depth : int
        Initial subdivision depth.
    max_depth : int
    """

    title = "curvature explorer"

    def __init__(self, surface, patches_class=None, *, depth=2, max_depth=6, window_size=(640, 480), live=None):
        super().__init__(window_size=window_size, live=live)
        if isinstance(surface, BezierPatches):
            base = surface
        elif hasattr(surface, "to_bezier_patches"):
            base = surface.to_bezier_patches()
        elif hasattr(surface, "derivatives") and hasattr(surface, "domain"):
            base = None  # an analytic surface: sampled on a grid that doubles with every depth step
        else:
            raise TypeError(f"expected a lab surface or lab.BezierPatches; got {type(surface).__name__}")
        if patches_class is not None and not (isinstance(patches_class, type) and issubclass(patches_class, BezierPatches)):
            raise TypeError(f"patches_class must be a subclass of lab.BezierPatches; got {patches_class!r}")
        if patches_class is not None and base is None:
            raise TypeError(f"{type(surface).__name__} is not made of Bézier patches: no visualize_curvature to show")
        self.student = patches_class
        self._base = base
        self._meshes = {}
        self.source = surface
        student = patches_class is not None
        measures = {k: v for k, v in _MEASURES.items() if not student or v in ("gaussian", "mean", "k1", "k2")}
        maps = dict(list(_H_MAPS.items())[:3]) if student else {**_H_MAPS, **_PERCEPTUAL}
        self.measure = _dropdown(list(measures.items()), "gaussian", "measure")
        self.color_map = _dropdown(list(maps.items()), "linear", "colour map")
        self.depth = W.IntSlider(value=depth, min=0, max=max_depth, description="depth", style={"description_width": "90px"},
                                 layout=W.Layout(width="300px"))
        self.range_mode = W.ToggleButtons(options=[("auto", "auto"), ("± max", "symmetric"), ("manual", "manual")],
                                          value="auto", description="range",
                                          style={"description_width": "90px", "button_width": "58px"},
                                          tooltips=["min … max of the values", "−max|value| … +max|value|",
                                                    "the min / max slider"])
        self.range = W.FloatRangeSlider(value=(-1.0, 1.0), min=-10.0, max=10.0, step=0.001, description="min / max",
                                        readout_format=".3g", disabled=True, style={"description_width": "90px"},
                                        layout=W.Layout(width="300px"))
        # the control the browser tests change (for the practical's maps on K, linear and cut look alike)
        (self.measure if patches_class is not None else self.color_map).add_class("lab-primary-control")
        self.show_net = W.Checkbox(value=False, description="control net", indent=False)
        self.show_borders = W.Checkbox(value=False, description="patch borders", indent=False)
        self.info = W.HTML()
        if student:
            self.range_mode.disabled = True
            self.range_mode.value = "auto"
        self._build_scene()
        self.color_map.observe(self._callback(self.recolor), "value")
        self.measure.observe(self._callback(self.recolor), "value")
        self.range_mode.observe(self._callback(self.recolor), "value")
        self.range.observe(self._callback(self.recolor), "value")
        self.depth.observe(self._callback(self.set_depth), "value")
        self.show_net.observe(self._callback(self.toggle_overlays), "value")
        self.show_borders.observe(self._callback(self.toggle_overlays), "value")

    def _controls(self):
        return [W.HTML(f"<b>{html.escape(self.title)}</b>"), self.measure, self.color_map, self.range_mode, self.range,
                self.depth, W.HBox([self.show_net, self.show_borders]), self.info]

    # -- geometry -------------------------------------------------------------

    def _patches(self, depth):
        if self.student is None:
            p = self._base.copy()
        else:
            p = self.student(self._base.control_points, self._base.weights, grid_shape=self._base.grid_shape)
        return p.refine(depth)

    def _mesh_for(self, depth):
        """The corner mesh at ``depth`` (cached; the student's mode recomputes colours each time)."""
        if self.student is None and depth in self._meshes:
            return self._meshes[depth]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DegeneratePointWarning)
            if self._base is None:
                n = 8 * 2**depth + 1
                patches, mesh = None, _mesh.surface_mesh(self.source, n, n)
            else:
                patches = self._patches(depth)
                mesh = _mesh.patches_mesh(patches)
        mesh.point_data["display"] = np.zeros(mesh.n_points)
        if self.student is None:
            self._meshes[depth] = mesh
        self._current_patches = patches
        return mesh

    def _build_scene(self):
        self.mesh = self._mesh_for(self.depth.value).copy()
        self.lut = pv.LookupTable()
        self.lut.apply_cmap(_h_cmap(), 256)
        self.actor = self.plotter.add_mesh(self.mesh, scalars="display", cmap=_h_cmap(), smooth_shading=True,
                                           show_scalar_bar=False)
        self.actor.mapper.lookup_table = self.lut
        self.scalar_bar = self.plotter.add_scalar_bar(mapper=self.actor.mapper, title="K", vertical=True,
                                                      position_x=0.86, position_y=0.15, width=0.08, height=0.7,
                                                      color="black", fmt="%.3g", n_labels=5)
        self.net_actor = self._add_control_net()
        self.borders_actor = None
        set_camera(self.plotter, self.mesh, VIEW_DIRECTION)
        self._legend = None
        self._run(self.recolor)

    def _add_control_net(self):
        src = self.source
        P = getattr(src, "control_points", None)
        if P is None:
            return None
        P = np.asarray(P)
        nets = P[None] if P.ndim == 3 else P
        lines = [pv.lines_from_points(r) for net in nets for r in net] + [
            pv.lines_from_points(c) for net in nets for c in net.transpose(1, 0, 2)]
        actor = self.plotter.add_mesh(pv.merge(lines), color="black", line_width=1, pickable=False)
        actor.SetVisibility(False)
        return actor

    def set_depth(self):
        """Recompute the patches at the slider's depth and update the mesh in place."""
        self._say(f"refining to depth {self.depth.value} …", "busy")
        new = self._mesh_for(self.depth.value)
        self.mesh.copy_from(new, deep=False)
        if self.borders_actor is not None:
            self.plotter.remove_actor(self.borders_actor)
            self.borders_actor = None
        self.recolor()

    def toggle_overlays(self):
        if self.net_actor is not None:
            self.net_actor.SetVisibility(self.show_net.value)
        if self.show_borders.value and self.borders_actor is None:
            self.borders_actor = self.plotter.add_mesh(self.mesh.extract_all_edges(), color="#333333", line_width=1,
                                                       pickable=False)
        if self.borders_actor is not None:
            self.borders_actor.SetVisibility(self.show_borders.value)
        self.refresh()

    # -- colours ----------------------------------------------------------------

    def values(self):
        """The current measure at the mesh vertices."""
        m = self.mesh.point_data
        curv = Curvature(m["K"], m["H"], m["k1"], m["k2"], m["degenerate"])
        mode = self.measure.value
        if mode == "classification":
            return np.asarray(m["K"])
        return np.asarray(curvature_values(curv, mode))

    def recolor(self):
        """Update colours only: point data, lookup table and scalar range of the existing actor."""
        if self.student is not None:
            self._recolor_student()
        else:
            self._recolor_library()
        self.refresh()

    def _range(self, v):
        """Colour range for ``v``: min/max (auto), ±max|v| (symmetric) or the slider (manual)."""
        finite = v[np.isfinite(v)]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
        mode = self.range_mode.value
        if mode == "manual":
            self.range.disabled = False
            lo, hi = self.range.value
        else:
            if mode == "symmetric":
                m = max(abs(lo), abs(hi)) or 1.0
                lo, hi = -m, m
            span = max(hi - lo, 1e-12)
            with self._quiet():  # the slider follows the automatic range without calling back
                self.range.min, self.range.max = -1e300, 1e300
                self.range.value = (lo, hi)
                self.range.min, self.range.max = lo - span, hi + span
                self.range.step = span / 1000
                self.range.disabled = True
        if hi <= lo:
            hi = lo + max(abs(lo), 1.0) * 1e-9
        return lo, hi

    def _recolor_library(self):
        v = self.values()
        name = self.color_map.value
        measure = self.measure.value
        if measure == "classification":
            name = "classification"
        display = self.mesh.point_data["display"]
        finite = np.isfinite(v)
        cmap = _h_cmap()
        if name in ("linear",) or name in _PERCEPTUAL.values():
            display[:] = v
            clim = self._range(v)
            cmap = _h_cmap() if name == "linear" else name
        elif name == "cut":
            display[:] = np.clip(np.nan_to_num(v), 0, 1)
            clim = (0.0, 1.0)
        elif name == "classification":
            size = float(np.linalg.norm(np.ptp(self.mesh.points, axis=0)))
            power = 2 if measure in ("gaussian", "classification", "strain-energy") else 1
            tol = colormaps.ZERO_TOL / size**power
            display[:] = np.where(v > tol, 1.0, np.where(v < -tol, 0.0, 0.5))
            clim = (0.0, 1.0)
        elif name == "dill":
            display[:] = v
            clim = colormaps.DILL_RANGE if self.range_mode.value == "auto" else self._range(v)
            cmap = _dill_cmap()
        elif name == "symmetric":
            display[:] = v
            m = float(np.max(np.abs(v[finite]))) if finite.any() else 1.0
            clim = (-m, m) if m > 0 else (-1.0, 1.0)
        elif name == "percentile":
            display[:] = v
            lo, hi = np.percentile(v[finite], [2, 98]) if finite.any() else (0.0, 1.0)
            clim = (float(lo), float(hi) if hi > lo else float(lo) + 1e-12)
        elif name == "signed-log":
            display[:] = np.nan_to_num(colormaps.signed_log(np.nan_to_num(v)), nan=0.5)
            clim = (0.0, 1.0)
        else:  # pragma: no cover - options are fixed
            raise ValueError(f"unknown colour map {name!r}")
        self.lut.apply_cmap(cmap, 5 if name == "dill" else 256)
        self.lut.scalar_range = clim
        self.lut.nan_color = "gray"
        self.actor.mapper.scalar_range = clim
        self.actor.mapper.SetScalarModeToUsePointFieldData()
        self.actor.mapper.SelectColorArray("display")
        self.mesh.point_data.active_scalars_name = "display"
        self.mesh.GetPointData().GetArray("display").Modified()  # the array was changed in place
        self._legend_for(name, measure)
        label = {"gaussian": "K", "mean": "H", "k1": "κ1", "k2": "κ2", "strain-energy": "κ1²+κ2²",
                 "classification": "K"}[measure]
        self.scalar_bar.SetTitle(label)
        self.scalar_bar.SetVisibility(name != "classification")
        n = int(np.count_nonzero(self.mesh.point_data["degenerate"]))
        what = "patches" if self._base is not None else "grid cells"
        self.info.value = (f"<small>{self.mesh.n_cells} {what} at depth {self.depth.value}; range "
                           f"{np.nanmin(v):.4g} … {np.nanmax(v):.4g}" + (f"; {n} degenerate points" if n else "") + "</small>")

    def _legend_for(self, name, measure):
        """Show the classification legend for the classification map, hide it otherwise (built once)."""
        if name == "classification" and self._legend is None:
            self._legend = self.plotter.add_legend(
                [["K > 0 elliptic", "red"], ["K = 0 parabolic, flat", "lime"], ["K < 0 hyperbolic", "blue"]],
                bcolor="white", face="rectangle", size=(0.42, 0.16), loc="lower right")
        if self._legend is not None:
            self._legend.SetVisibility(name == "classification")

    def _recolor_student(self):
        """Run the student's visualize_curvature and show the colours it stored."""
        self.actor.mapper.ScalarVisibilityOff()  # a plain surface until the student's colours arrive
        self.scalar_bar.SetVisibility(False)
        patches = self._patches(self.depth.value)
        mode = self.measure.value
        cmap = self.color_map.value
        patches.visualize_curvature(CurvatureMode(mode), cmap)
        if not np.all(np.isfinite(patches.colors)):
            raise ValueError("your visualize_curvature did not store colours for every patch (set_colors)")
        new = _mesh.patches_mesh(patches)
        self.mesh.copy_from(new, deep=False)
        self.actor.mapper.SetScalarModeToUsePointFieldData()
        self.actor.mapper.SelectColorArray("RGB")
        self.mesh.point_data.active_scalars_name = "RGB"
        self.actor.mapper.SetColorModeToDirectScalars()
        self.actor.mapper.ScalarVisibilityOn()
        self.info.value = f"<small>your visualize_curvature on {len(patches)} patches</small>"
