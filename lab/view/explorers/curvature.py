"""The curvature explorer: a surface coloured by K, H, κ1, κ2, strain energy or the classification, at any depth."""

import html

import ipywidgets as W
import numpy as np
import pyvista as pv

from ... import mesh as _mesh
from ...geometry import colormaps, palettes
from ...geometry import validation as _v
from ...geometry.curvature import Curvature, CurvatureMode, curvature_values, zero_tolerance
from ...i18n import N_, _, parse_number
from ...model.patches import BezierPatches
from .. import legend as _legend
from .. import style
from .base import Explorer, _dropdown, _layout, checkpoint, style_for
from .controls import full_row_text
from .edges import EdgeOverlay
from .models import ModelMeshes, face_borders, is_model
from .tools import CurvatureTools, scan_deviation

__all__ = ["CurvatureExplorer"]


# Colour maps of the explorer: label -> name; the practical's ramp h, Dill's bands, or a perceptual map.
_H_MAPS = {
    N_("h∘f2 linear (min/max)"): "linear",
    N_("h∘f1 cut [0, 1]"): "cut",
    N_("h∘f3 classification"): "classification",
    N_("Dill's five bands"): "dill",
    N_("symmetric (0 = green)"): "symmetric",
    N_("percentile 2–98"): "percentile",
    N_("signed log"): "signed-log",
}
# the practical's normalisations with one of Crameri's ramps: readable with a colour-vision deficiency
_READABLE = {
    N_("batlow, linear (min/max)"): "linear-batlow",
    N_("vik, symmetric (0 = white)"): "symmetric-vik",
    N_("vik, signed log"): "signed-log-vik",
    N_("classification: navy, white, orange"): "classification-vik",
    N_("Dill's five bands in batlow"): "dill-batlow",
}
_PERCEPTUAL = {"viridis": "viridis", "cividis": "cividis", N_("coolwarm (diverging)"): "coolwarm",
               N_("RdBu (diverging)"): "RdBu_r"}
_MEASURES = {
    N_("K  Gaussian"): "gaussian",
    N_("H  mean"): "mean",
    N_("κ1  max. principal"): "k1",
    N_("κ2  min. principal"): "k2",
    N_("κ1² + κ2²  strain energy"): "strain-energy",
    N_("classification (sign of K)"): "classification",
}
#: opacity of the surface while the control net is shown (the net runs above and below the surface)
NET_SURFACE_OPACITY = 0.45
#: maps whose range the range control sets (the others fix their own: cut [0, 1], ± max, percentiles, …)
_RANGED = {"linear", "dill", "linear-batlow", "dill-batlow", *_PERCEPTUAL.values()}


def _h_cmap():
    from matplotlib.colors import ListedColormap

    return ListedColormap(colormaps.h(np.linspace(0, 1, 256)), name="practical-h")


def _dill_cmap():
    from matplotlib.colors import ListedColormap

    return ListedColormap(colormaps.DILL_COLORS, name="dill")


def _cmap(name):
    """The lookup table's colours for the map ``name`` and how many: the ramp h, Dill's bands, a Crameri ramp."""
    from matplotlib.colors import ListedColormap

    if name == "dill":
        return _dill_cmap(), 5
    if name == "dill-batlow":
        return ListedColormap(palettes.bands(), name=name), 5
    if name == "classification-vik":
        return ListedColormap(palettes.classes(), name=name), 3
    if name in ("linear-batlow", "symmetric-vik", "signed-log-vik"):
        ramp = "batlow" if name == "linear-batlow" else "vik"
        return ListedColormap(palettes.table(ramp), name=ramp), 256
    if name in _PERCEPTUAL.values():
        return name, 256
    return _h_cmap(), 256


def _readout(value):
    """A range end as the readout shows it: 4 significant digits."""
    return _legend.format_values([value], spacing=max(abs(value), 1e-300) * 1e-2)[0].replace("−", "-")


class CurvatureExplorer(Explorer):
    """Curvature of a surface, coloured by a chosen measure and colour map, at a chosen subdivision depth.

    Parameters
    ----------
    surface : lab surface with ``to_bezier_patches()``, BezierPatches, or lab.Model
        What to show.  The patches are refined ``depth`` times (the practical's
        ``refine``) and coloured at their corners.  A model (a part from
        :func:`lab.read`) is shown face by face, each face on ``lines``
        iso-parameter lines in its trimmed region, with one colour range over
        all faces; its resolution control is "lines per face" instead of the
        depth, the borders are the faces' borders, and the combs and the
        point probe work on the face chosen in their "face" menu.
    patches_class : subclass of lab.BezierPatches, optional
        A class with the student's own ``visualize_curvature``: the explorer
        then shows the colours that method stores, for the practical's four
        measures and three maps, with the same colour bar.
    depth : int
        Initial subdivision depth.
    max_depth : int
    lines : int
        A model's initial lines per face (4 … 64).
    window_size, live, backend
        As :class:`lab.view.explorers.base.Explorer`.
    scan, tolerance : optional
        A scan of the part (points, file or mesh): the tools' map menu then offers its deviation (``self.deviation``).
    """

    title = N_("curvature explorer")

    def __init__(self, surface, patches_class=None, *, depth=2, max_depth=6, lines=16, window_size=(800, 500),
                 live=None, backend=None, scan=None, tolerance=None):
        _v.refuse_class(surface, "a lab surface or lab.BezierPatches")  # (hasattr would find a class's methods)
        self.model = surface if is_model(surface) else None
        if self.model is not None:
            if not self.model.faces:
                raise ValueError(f"the model has no faces to show; problems: {[str(p) for p in self.model.problems]}")
            base = None
            lines = int(min(max(int(lines), 4), 64))
        elif isinstance(surface, BezierPatches):
            base = surface
        elif hasattr(surface, "to_bezier_patches"):
            base = surface.to_bezier_patches()
        elif hasattr(surface, "derivatives") and hasattr(surface, "domain"):
            base = None  # an analytic surface: sampled on a grid that doubles with every depth step
        else:
            raise TypeError(f"expected a lab surface or lab.BezierPatches; got {type(surface).__name__}")
        if patches_class is not None and not (isinstance(patches_class, type) and issubclass(patches_class, BezierPatches)):
            raise TypeError(f"patches_class must be a subclass of lab.BezierPatches; got {patches_class!r}")
        if patches_class is not None and self.model is not None:
            raise TypeError("a model's faces are not one collection of Bézier patches: no visualize_curvature to show")
        if patches_class is not None and base is None:
            raise TypeError(f"{type(surface).__name__} is not made of Bézier patches: no visualize_curvature to show")
        depth = _v.as_positive_int(depth, "depth")
        max_depth = _v.as_positive_int(max_depth, "max_depth")
        super().__init__(window_size=window_size, live=live, backend=backend)
        self.student = patches_class
        self._base = base
        self._meshes = {}
        self.source = surface
        student = patches_class is not None
        measures = {k: v for k, v in _MEASURES.items() if not student or v in ("gaussian", "mean", "k1", "k2")}
        maps = dict(list(_H_MAPS.items())[:3]) if student else {**_H_MAPS, **_READABLE, **_PERCEPTUAL}
        c = self._control
        self.measure = c(_dropdown(list(measures.items()), "gaussian", N_("measure")))
        # a real part's curvature spans orders of magnitude (linkrods: K from -184 at its fillets to 20): the
        # linear map would paint it one colour; the signed log shows sign and size, in vik (not the practical's
        # rainbow: white at 0, dark blue and red at the ends, readable with a colour-vision deficiency)
        first = "signed-log-vik" if self.model is not None else "linear"
        self.color_map = c(_dropdown(list(maps.items()), first, N_("colour map")))
        if self.model is None:
            self.depth = c(W.IntSlider(value=depth, min=0, max=max_depth, description=_("depth"), style=style_for(),
                                       continuous_update=False, layout=_layout()))
        else:  # the resolution control of a model: lines per face (model.to_mesh(n, n)); depth means nothing here
            self._model_meshes = ModelMeshes(self.model)
            self.depth = c(W.IntSlider(value=lines, min=4, max=64, step=2, description=_("lines per face"),
                                       style=style_for(), continuous_update=False, layout=_layout()))
        self.range_mode = c(W.ToggleButtons(
            options=[(_("auto"), "auto"), ("± max", "symmetric"), (_("manual"), "manual")], value="auto",
            description=_("range"), style=style_for(short=True, button_width="auto"), layout=_layout(),
            tooltips=[_("min … max of the values"), _("−max|value| … +max|value|"), _("type min and max")]))
        self.range_mode.add_class("lab-range-mode")
        self.range_min = c(W.Text(value="", description=_("min"), continuous_update=False, disabled=True,
                                  style={"description_width": "30px"}, layout=W.Layout(width="auto", flex="1 1 0", min_width="0")))
        self.range_max = c(W.Text(value="", description=_("max"), continuous_update=False, disabled=True,
                                  style={"description_width": "30px"}, layout=W.Layout(width="auto", flex="1 1 0", min_width="0")))
        self.range_min.add_class("lab-range-min")
        self.range_max.add_class("lab-range-max")
        self.range_box = c(W.HBox([self.range_min, self.range_max], layout=_layout()))
        # the control the browser tests change (for the practical's maps on K, linear and cut look alike)
        (self.measure if student else self.color_map).add_class("lab-primary-control")
        self.depth.add_class("lab-depth")
        self.show_net = c(W.Checkbox(value=False, description=_("control net"), indent=False,
                                     layout=W.Layout(width="auto")))
        self.show_borders = c(W.Checkbox(value=False, description=_("face borders") if self.model is not None
                                         else _("patch borders"),
                                         indent=False, layout=W.Layout(width="auto")))
        self.show_edges = c(W.Checkbox(value=False, description=_("edges by continuity"), indent=False,
                                       layout=W.Layout(width="auto")))
        self.show_bands = c(W.Checkbox(value=False, description=_("band borders"), indent=False,
                                       tooltip=_("level lines where the colour bands meet: readable without colour"),
                                       layout=W.Layout(width="auto")))
        self.bands_mesh = self.bands_actor = None
        self.edge_legend = c(full_row_text())
        self.edges = EdgeOverlay(self._base if self._base is not None else surface)
        self.fit_button = c(W.Button(description=_("fit view"), tooltip=_("the oblique view of the whole surface"),
                                     layout=W.Layout(width="auto")))
        self.info = c(full_row_text())
        self.clim = (0.0, 1.0)  # the range of values the colours span now (what the readouts show)
        self._manual = None
        if student:
            self.range_mode.disabled = True
        # draft angle, minimum radius, combs and the point probe (lab/view/explorers/tools.py): on surfaces and
        # models (the combs and the probe on a face chosen there); not on a BezierPatches collection, which has
        # no (u, v) domain for the probe (issue 35): its curvature is shown, the tools need the surface
        self.deviation = scan_deviation(surface, scan, tolerance, student)  # a scan: one of the tools' maps
        on_surface = hasattr(surface, "derivatives") and not isinstance(surface, BezierPatches)
        self.tools = CurvatureTools(self) if not student and (on_surface or self.model is not None) else None
        self._build_scene()
        self._observe(self.color_map, self.recolor)
        self._observe(self.measure, self.recolor)
        self._observe(self.range_mode, self.change_range_mode)
        self._observe(self.range_min, self.type_range)
        self._observe(self.range_max, self.type_range)
        self._observe(self.depth, self.set_depth)
        self._observe(self.show_net, self.toggle_overlays)
        self._observe(self.show_borders, self.toggle_overlays)
        self._observe(self.show_edges, self.toggle_overlays)
        self._observe(self.show_bands, self.recolor)
        self.fit_button.on_click(lambda _button: self._on_main(self._request, self.fit_camera))

    def _controls(self):
        return [self.measure, self.color_map, self.range_mode, self.range_box, self.depth,
                W.HBox([self.show_net, self.show_borders, self.show_edges, self.show_bands, self.fit_button],
                       layout=W.Layout(width="auto", justify_content="space-between", align_items="center",
                                       flex_flow="row wrap")),
                self.edge_legend, self.info] + (self.tools.controls() if self.tools is not None else [])

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
        if self.model is not None:
            patches, mesh = None, self._model_meshes.mesh(depth).copy(deep=False)
        elif self._base is None:
            n = 8 * 2**depth + 1
            patches, mesh = None, _mesh.surface_mesh(self.source, n, n)
        else:
            patches = self._patches(depth)
            mesh = _mesh.patches_mesh(patches)
        _prepare(mesh)
        if self.student is None:
            self._meshes[depth] = mesh
        self._current_patches = patches
        return mesh

    def _build_scene(self):
        self.mesh = self._mesh_for(self.depth.value).copy()
        self.lut = pv.LookupTable()
        self.lut.apply_cmap(_h_cmap(), 256)
        self.actor = self.plotter.add_mesh(self.mesh, scalars="display", cmap=_h_cmap(), show_scalar_bar=False,
                                           **style.SURFACE_PROPERTIES)
        self.actor.prop.interpolation = "gouraud"  # smooth, with the exact normals N of the surface
        self.actor.mapper.lookup_table = self.lut
        self.net_actor = self._add_control_net()
        self.borders_actor = None
        style.fit_camera(self.plotter, self.mesh)
        self._run(self.recolor)

    def _fit_mesh(self):
        return self.mesh

    def _add_control_net(self):
        if self.model is not None:
            nets = [np.asarray(f.surface.control_points, dtype=float) for f in self.model.faces]
        else:
            P = getattr(self.source, "control_points", None)
            if P is None:
                return None
            P = np.asarray(P)
            nets = P[None] if P.ndim == 3 else P
        lines = [pv.lines_from_points(r) for net in nets for r in net] + [
            pv.lines_from_points(c) for net in nets for c in net.transpose(1, 0, 2)]
        net = pv.merge(lines + [pv.PolyData(np.concatenate([n.reshape(-1, 3) for n in nets]).astype(float))])
        # the net of a convex bump lies above the surface, elsewhere below it: where the surface would hide it,
        # the surface turns translucent while the net is shown (toggle_overlays), and the lines are drawn thick
        actor = self.plotter.add_mesh(net, color="#b3261e", line_width=2, point_size=6, pickable=False,
                                      render_points_as_spheres=True, lighting=False)
        actor.SetVisibility(False)
        return actor

    async def set_depth(self):
        """Recompute the patches at the slider's depth and update the mesh in place (cancelled by a newer depth)."""
        depth = self.depth.value
        if self.student is None and depth in self._meshes:
            new = self._meshes[depth]
        else:
            self._show_progress(0.1, _("refining to depth {depth} …").format(depth=depth))
            await checkpoint()
            if self.model is not None:
                steps = self._model_meshes.steps(depth)
                n = len(self.model.faces)
                while True:
                    try:
                        done = next(steps)
                    except StopIteration:
                        break
                    self._show_progress(0.05 + 0.8 * done, _("{k} of {n} faces on {lines} lines each …").format(
                        k=round(done * n), n=n, lines=depth))
                    await checkpoint()
                new = self._mesh_for(depth)
            elif self._base is not None and self.student is None:
                patches = self._base.copy()
                for level in range(depth):
                    patches.refine(1)
                    self._show_progress(0.1 + 0.4 * (level + 1) / max(depth, 1),
                                        _("refining to depth {depth}: {n} patches …").format(depth=depth, n=len(patches)))
                    await checkpoint()
                self._show_progress(0.6, _("curvature at the corners of {n} patches …").format(n=len(patches)))
                await checkpoint()
                new = _mesh.patches_mesh(patches)
                _prepare(new)
                self._meshes[depth] = new
            else:
                new = self._mesh_for(depth)
            self._show_progress(0.9, _("updating the view …"))
            await checkpoint()
        self.mesh.copy_from(new, deep=False)
        if self.borders_actor is not None:
            self.plotter.remove_actor(self.borders_actor)
            self.borders_actor = None
            if self.show_borders.value:
                self._add_borders()
        self.recolor()

    def _add_borders(self):
        lines = face_borders(self.mesh) if self.model is not None else self.mesh.extract_all_edges()
        self.borders_actor = self.plotter.add_mesh(lines, color="#333333", line_width=1, pickable=False,
                                                   lighting=False)

    def toggle_overlays(self):
        if self.net_actor is not None:
            self.net_actor.SetVisibility(self.show_net.value)
            self.actor.prop.opacity = NET_SURFACE_OPACITY if self.show_net.value else 1.0
        if self.show_borders.value and self.borders_actor is None:
            self._add_borders()
        if self.borders_actor is not None:
            self.borders_actor.SetVisibility(self.show_borders.value)
        self.edge_legend.value = self.edges.show(self.plotter, self.show_edges.value)
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

    def _map_name(self):
        return "classification" if self.measure.value == "classification" else self.color_map.value

    def _measure_for_tol(self):
        return "gaussian" if self.measure.value == "classification" else self.measure.value

    def _tol(self):
        size = float(np.linalg.norm(np.ptp(np.asarray(self.mesh.points), axis=0)))
        return zero_tolerance(self._measure_for_tol(), size)

    def change_range_mode(self):
        """Switch the range mode; "manual" starts at the range used now."""
        if self.range_mode.value == "manual":
            self._manual = tuple(self.clim) if self.clim is not None else (0.0, 1.0)
        self.recolor()

    def type_range(self):
        """A min or max typed in manual mode."""
        if self.range_mode.value != "manual" or self.student is not None:
            return
        lo, hi = self._manual or self.clim
        try:
            typed = (parse_number(self.range_min.value), parse_number(self.range_max.value))
        except ValueError:
            self._show_readouts()
            raise ValueError(_("min and max must be numbers, e.g. -0.5 and 2")) from None
        # an unchanged field keeps its exact value (the readout shows it rounded)
        lo = lo if self.range_min.value == _readout(lo) else typed[0]
        hi = hi if self.range_max.value == _readout(hi) else typed[1]
        if not hi > lo:
            self._show_readouts()
            raise ValueError(_("max must be larger than min; got min {lo:g}, max {hi:g}").format(lo=lo, hi=hi))
        self._manual = (lo, hi)
        self.recolor()

    def _range(self, v, name):
        """The colour range for ``v`` under map ``name`` and the range mode, in curvature units."""
        if name not in _RANGED:
            return _legend.map_range(name, v)
        finite = v[np.isfinite(v)]
        lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
        mode = self.range_mode.value
        if mode == "manual" and self._manual is not None:
            lo, hi = self._manual
        elif mode == "symmetric":
            m = max(abs(lo), abs(hi)) or 1.0
            lo, hi = -m, m
        return lo, hi

    def _show_readouts(self):
        """The min / max fields show the range used; editable in manual mode for the maps that take a range."""
        ranged = self._map_name() in _RANGED and self.student is None
        editable = ranged and self.range_mode.value == "manual"
        lo_text, hi_text = ("", "") if self.clim is None else (_readout(self.clim[0]), _readout(self.clim[1]))
        with self._quiet():
            for field, text in ((self.range_min, lo_text), (self.range_max, hi_text)):
                if field.value != text:
                    field.value = text
                if field.disabled == editable:
                    field.disabled = not editable
            if self.student is None and self.range_mode.disabled == ranged:
                self.range_mode.disabled = not ranged

    def _sync_map_menu(self):
        """With "classification" chosen as the measure the map menu says so (and waits); the map chosen before returns."""
        if self.student is not None:
            return
        classified = self.measure.value == "classification"
        with self._quiet():
            if classified and self.color_map.value != "classification":
                self._map_before = self.color_map.value
                self.color_map.value = "classification"
            elif not classified and self.color_map.disabled and getattr(self, "_map_before", None) is not None:
                self.color_map.value = self._map_before
                self._map_before = None
            if self.color_map.disabled != classified:
                self.color_map.disabled = classified

    def recolor(self):
        """Update colours only: point data, lookup table and scalar range of the existing actor."""
        if self.color_map.value is None or self.measure.value is None:  # a dropdown without a choice
            return
        self._sync_map_menu()
        if self.tools is not None and self.tools.active:
            self.tools.recolor_map()
            return
        if self.student is not None:
            self._recolor_student()
        else:
            self._recolor_library()
        self._show_readouts()
        self._draw_bands()
        self.refresh()

    def _draw_bands(self):
        """The level lines at the borders of the colour bands (the legend's ``levels``), when "band borders" is on."""
        from ...interrogation.bands import band_lines
        from .. import style as _style

        legend = self.legend() if self.show_bands.value and not (self.tools and self.tools.active) else None
        lines = None
        if legend is not None and legend.levels:
            values = self._legend_values()
            tol = self._tol() if colormaps.normalisation(self._map_name()) == "classification" else 0.0
            lines = band_lines(self.mesh, np.asarray(values, dtype=float), legend.levels, tol=tol)
        if lines is None or not lines.n_points:
            if self.bands_actor is not None:
                self.bands_actor.SetVisibility(False)
            return
        if self.bands_actor is None:
            self.bands_mesh = lines
            self.bands_actor = _style.add_lines_on_surface(self.plotter, self.bands_mesh, pickable=False,
                                                           lighting=False)
        else:
            self.bands_mesh.copy_from(lines)
        self.bands_actor.SetVisibility(True)

    def legend(self):
        """The colour bar (or classification legend) of the current colours, in curvature units."""
        if self.tools is not None and self.tools.active:
            return self.tools.legend()
        measure = self.measure.value
        name = self._map_name()
        values = self._legend_values()
        clim = self.clim if name in _RANGED else None
        return _legend.legend(measure, name, values, clim=clim, tol=self._tol())

    def _legend_values(self):
        if self.student is not None and "values" in self.mesh.point_data:
            return np.asarray(self.mesh.point_data["values"])
        return self.values()

    def resolution_text(self):
        """The resolution as the title says it: "depth 2", or "16 lines per face" on a model."""
        if self.model is not None:
            return _("{n} lines per face").format(n=self.depth.value)
        return _("depth {depth}").format(depth=self.depth.value)

    def picture_title(self):
        if self.tools is not None and self.tools.active:
            return self.tools.title(self.resolution_text())
        maps = {v: k for k, v in self.color_map.options}
        what = _legend.MEASURES[self.measure.value][1] if self.measure.value != "classification" else "K"
        title = _("{what}, {map}, {resolution}").format(
            what=what, map=maps.get(self.color_map.value, self.color_map.value), resolution=self.resolution_text())
        return title + (_(", your visualize_curvature") if self.student is not None else "")

    def _recolor_library(self):
        v = self.values()
        name = self._map_name()
        display = self.mesh.point_data["display"]
        cmap, n_colors = _cmap(name)
        clim = self._range(v, name)
        if name == "cut":
            display[:] = np.clip(np.nan_to_num(v), 0, 1)
            ends = (0.0, 1.0)
        elif name in ("classification", "classification-vik"):
            tol = self._tol()
            display[:] = np.where(v > tol, 1.0, np.where(v < -tol, 0.0, 0.5))
            ends = (0.0, 1.0)
        elif name in ("signed-log", "signed-log-vik"):
            finite = np.isfinite(v)
            display[:] = 0.5
            if finite.any():
                display[finite] = colormaps.signed_log(v[finite])
            ends = (0.0, 1.0)
        else:
            display[:] = v
            ends = clim
        lo, hi = ends
        if not hi > lo:
            hi = lo + max(abs(lo), 1.0) * 1e-9
        self.clim = clim
        self.lut.apply_cmap(cmap, n_colors)
        self.lut.scalar_range = (lo, hi)
        self.lut.nan_color = "gray"
        self.actor.mapper.scalar_range = (lo, hi)
        self.actor.mapper.SetScalarModeToUsePointFieldData()
        self.actor.mapper.SelectColorArray("display")
        self.mesh.point_data.active_scalars_name = "display"
        self.mesh.GetPointData().GetArray("display").Modified()  # the array was changed in place
        n = int(np.count_nonzero(self.mesh.point_data["degenerate"]))
        if self.model is not None:
            what = _("{faces} faces, {n} triangles ({depth} lines per face)").replace("{faces}", str(len(self.model)))
        elif self._base is not None:
            what = _("{n} patches at depth {depth}")
        else:
            what = _("{n} grid cells at depth {depth}")
        finite = v[np.isfinite(v)]
        span = (_("values {lo} … {hi}").format(lo=_readout(float(finite.min())),
                                               hi=_readout(float(finite.max()))).replace("-", "−")
                if finite.size else _("no finite values"))
        info = what.format(n=self.mesh.n_cells, depth=self.depth.value) + "; " + span
        if n:
            info += "; " + _("{n} degenerate points").format(n=n)
        self.info.value = f"<small>{html.escape(info)}</small>"

    def _recolor_student(self):
        """Run the student's visualize_curvature and show the colours it stored."""
        self.actor.mapper.ScalarVisibilityOff()  # a plain surface until the student's colours arrive
        patches = self._patches(self.depth.value)
        mode = self.measure.value
        cmap = self.color_map.value
        patches.visualize_curvature(CurvatureMode(mode), cmap)
        if not np.all(np.isfinite(patches.colors)):
            raise ValueError(_("your visualize_curvature did not store colours for every patch (set_colors)"))
        new = _mesh.patches_mesh(patches)
        _prepare(new)
        self.mesh.copy_from(new, deep=False)
        self.actor.mapper.SetScalarModeToUsePointFieldData()
        self.actor.mapper.SelectColorArray("RGB")
        self.mesh.point_data.active_scalars_name = "RGB"
        self.actor.mapper.SetColorModeToDirectScalars()
        self.actor.mapper.ScalarVisibilityOn()
        v = np.asarray(new.point_data["values"]) if "values" in new.point_data else self.values()
        self.clim = _legend.map_range(cmap, v) if cmap != "classification" else None
        info = _("your visualize_curvature on {n} patches; values {lo} … {hi}").format(
            n=len(patches), lo=_readout(float(np.nanmin(v))), hi=_readout(float(np.nanmax(v)))).replace("-", "−")
        self.info.value = f"<small>{html.escape(info)}</small>"


def _prepare(mesh):
    """Point data the view needs, in single precision (half the bytes to send to the browser and to draw):
    the colour array, and the exact unit normals N of the surface as the shading normals."""
    mesh.points = np.asarray(mesh.points, dtype=np.float32)
    mesh.point_data["display"] = np.zeros(mesh.n_points, dtype=np.float32)
    if "N" in mesh.point_data:
        mesh.point_data["Normals"] = np.nan_to_num(np.asarray(mesh.point_data["N"], dtype=np.float32))
        mesh.point_data.active_normals_name = "Normals"
    return mesh
