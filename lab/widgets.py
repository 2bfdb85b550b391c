"""Interactive explorers for JupyterLab: ipywidgets controls beside a live PyVista view.

Each explorer is one call in a notebook (``lab.CurvatureExplorer(surface)``)
and shows controls next to a 3D view.  The view is live (PyVista's ``trame``
backend: a trame server inside the kernel, shown in an iframe) when a
frontend can show it, and a static picture otherwise (``live=False``, when
grading, or when the trame server cannot start); in notebooks converted
with nbconvert the explorer's output also carries a PNG of its view.

Threads: VTK's OpenGL context belongs to the kernel's main thread.  JupyterLab
may deliver widget messages on a comm subshell thread; a render from there
kills the kernel.  Every callback therefore hops to the main thread
(``loop.call_soon_threadsafe``) before it touches the plotter (see
DESIGN.md, "Kernel crash trap"), and the project also ships a JupyterLab
settings override that keeps comms on the main thread.

Colour changes only update the colours (lookup table, scalar range, point
data) of the existing actor; geometry changes (depth, fans) update the
existing mesh in place; nothing is rebuilt from scratch.
"""

import asyncio
import base64
import contextlib
import html
import io
import os
import sys
import threading
import time
import traceback
import warnings
import weakref

import ipywidgets as W
import numpy as np
import pyvista as pv

from . import colormaps
from . import mesh as _mesh
from .curvature import DegeneratePointWarning
from .patches import BezierPatches, CurvatureMode, colors_for
from .render import VIEW_DIRECTION, configure_offscreen, set_camera

__all__ = ["Explorer", "CurvatureExplorer", "FocalExplorer", "ReflectionExplorer", "GeodesicExplorer",
           "live_view_possible", "in_jupyter_session",
           "callback_threads"]

_INSTANCES = weakref.WeakSet()


def callback_threads():
    """Names of the threads on which widget callbacks of all explorers arrived (renders ran on the main thread)."""
    return sorted({name for e in list(_INSTANCES) for name in e.callback_threads})


def in_jupyter_session():
    """Whether this kernel belongs to a Jupyter server session (JupyterLab, Notebook): a frontend that shows widgets.

    jupyter_server starts session kernels with ``JPY_SESSION_NAME`` set; kernels
    started by nbconvert / nbclient (conversion, grading) have no frontend.
    """
    if os.environ.get("LAB_INTERACTIVE") == "1":
        return True
    try:
        from IPython import get_ipython

        shell = get_ipython()
    except ImportError:  # pragma: no cover
        return False
    return shell is not None and type(shell).__name__ == "ZMQInteractiveShell" and "JPY_SESSION_NAME" in os.environ


def live_view_possible():
    """Whether a live trame view can be shown: in a Jupyter session, unless ``LAB_STATIC=1`` or grading."""
    if os.environ.get("LAB_STATIC") == "1" or os.environ.get("LAB_GRADING") == "1":
        return False
    return in_jupyter_session()


def _main_loop():
    try:
        return asyncio.get_event_loop()
    except RuntimeError:  # pragma: no cover - no loop in this thread
        return None


class Explorer:
    """Base of the explorers: a plotter, a view (live or static), a status line, main-thread callbacks.

    Parameters
    ----------
    window_size : (int, int)
        Size of the 3D view in pixels.
    live : bool, optional
        Force a live (trame) or a static view; default: live when possible.
    """

    title = "explorer"

    def __init__(self, *, window_size=(640, 480), live=None):
        configure_offscreen()
        self._loop = _main_loop()
        self.window_size = tuple(window_size)
        self.plotter = pv.Plotter(notebook=True, off_screen=True, window_size=list(self.window_size))
        self.plotter.set_background("white")
        # Multisampling triples the cost of a software (llvmpipe) render; explorers answer first.
        self.plotter.ren_win.SetMultiSamples(0)
        self.live = live_view_possible() if live is None else bool(live)
        self.status = W.HTML(layout=W.Layout(min_height="1.5em"))
        self.timings = {}
        self.callback_threads = []  # where widget callbacks arrived (the renders always run on the main thread)
        self._view = None
        self._viewer = None
        self._widget = None
        self._syncing = False
        _INSTANCES.add(self)

    # -- threads and errors -------------------------------------------------

    def _on_main(self, func, *args):
        """Run ``func`` on the kernel's main thread (now, if this is it)."""
        if threading.current_thread() is threading.main_thread() or self._loop is None:
            func(*args)
        else:
            self._loop.call_soon_threadsafe(func, *args)

    def _callback(self, action):
        """An ipywidgets observer that runs ``action`` on the main thread, timed, with errors shown in the status line."""

        def observer(change=None):
            if self._syncing:
                return
            self.callback_threads.append(threading.current_thread().name)
            self._on_main(self._run, action)

        return observer

    @contextlib.contextmanager
    def _quiet(self):
        """Change widget values from code without triggering the callbacks."""
        self._syncing = True
        try:
            yield
        finally:
            self._syncing = False

    def _run(self, action):
        start = time.perf_counter()
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                action()
            notes = sorted({str(w.message) for w in caught if issubclass(w.category, (DegeneratePointWarning, UserWarning))})
            self._say(" ".join(notes[:2]), "note" if notes else "ok")
        except NotImplementedError as exc:
            self._say(f"not implemented yet: {exc}", "note")
        except _Note as note:
            self._say(str(note), "note")
        except Exception as exc:  # shown to the user, never a traceback in the notebook
            self._say(f"{type(exc).__name__}: {exc}", "error")
            self.last_error = traceback.format_exc()
        self.timings[getattr(action, "__name__", "action")] = time.perf_counter() - start

    def _say(self, text, kind="ok"):
        colour = {"ok": "#57606a", "note": "#9a6700", "error": "#cf222e", "busy": "#0969da"}[kind]
        self.status.value = f'<span style="color:{colour}">{html.escape(text)}</span>' if text else ""

    # -- the view -----------------------------------------------------------

    def _build_scene(self):  # pragma: no cover - abstract
        raise NotImplementedError

    def _controls(self):  # pragma: no cover - abstract
        raise NotImplementedError

    def _extra_views(self):
        """Widgets shown below the 3D view (none by default)."""
        return []

    def refresh(self):
        """Render the current scene into the view (main thread only)."""
        self.plotter.render()
        if self._viewer is not None:
            self._viewer.update()
        elif isinstance(self._view, W.Image):
            self._view.value = self.png()

    def screenshot(self):
        """The current picture as an array (height, width, 3)."""
        self.plotter.render()
        return np.asarray(self.plotter.screenshot(None, return_img=True))

    def png(self):
        """The current picture as PNG bytes."""
        from PIL import Image

        buf = io.BytesIO()
        Image.fromarray(self.screenshot()).save(buf, format="PNG")
        return buf.getvalue()

    def _make_view(self):
        if self.live:
            # trame-vtklocal (pulled in by trame-pyvista) downloads a WASM bundle from gitlab.kitware.com when
            # the server starts; offline this prints a traceback into the notebook.  The explorers render on
            # the server, so keep PyVista from loading it (it imports it inside contextlib.suppress(ImportError)).
            if "trame.widgets.vtklocal" not in sys.modules:
                sys.modules["trame.widgets.vtklocal"] = None
            try:
                self._view = self.plotter.show(
                    jupyter_backend="trame", return_viewer=True, auto_close=False,
                    jupyter_kwargs={"collapse_menu": True},
                )
                self._viewer = getattr(self._view, "viewer", None)
                return self._view
            except Exception as exc:  # no trame server here: fall back to pictures
                self.live = False
                self._say(f"live 3D view unavailable ({type(exc).__name__}: {exc}); showing pictures", "note")
        self._view = W.Image(value=self.png(), format="png",
                             layout=W.Layout(width=f"{self.window_size[0]}px", height=f"{self.window_size[1]}px"))
        return self._view

    @property
    def widget(self):
        """The ipywidgets box: controls, status line and view."""
        if self._widget is None:
            view = self._make_view()
            left = W.VBox(self._controls() + [self.status], layout=W.Layout(width="320px", min_width="280px"))
            views = W.VBox([view] + self._extra_views())
            self._widget = W.HBox([left, views], layout=W.Layout(align_items="flex-start"))
            self._widget.add_class("lab-explorer")
        return self._widget

    def _repr_mimebundle_(self, include=None, exclude=None):
        # The picture survives nbconvert and viewers without a widget manager.  Without a frontend
        # (nbconvert, nbclient, grading) the explorer shows only that picture: a widget view would make
        # nbconvert's HTML depend on widget JavaScript from the network.
        bundle = {
            "image/png": base64.b64encode(self.png()).decode(),
            "text/plain": f"{self.title} (open the notebook in JupyterLab for the interactive view)",
        }
        if in_jupyter_session():
            bundle.update(self.widget._repr_mimebundle_(include=include, exclude=exclude))
        return bundle

    def close(self):
        """Close the plotter and the widgets."""
        if self._widget is not None:
            self._widget.close()
        self.plotter.close()


def _dropdown(options, value, description):
    return W.Dropdown(options=options, value=value, description=description, style={"description_width": "90px"},
                      layout=W.Layout(width="300px"))


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
        from .curvature import Curvature

        m = self.mesh.point_data
        curv = Curvature(m["K"], m["H"], m["k1"], m["k2"], m["degenerate"])
        mode = self.measure.value
        if mode == "classification":
            return np.asarray(m["K"])
        from .patches import curvature_values

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


class FocalExplorer(Explorer):
    """A surface and its generalised focal surface F = X + a f(κ1, κ2) N (seeds/002, section 4)."""

    title = "focal surface explorer"
    FUNCTIONS = {"H  mean": "mean", "K  Gaussian": "gaussian", "κ1² + κ2²": "strain-energy", "κ1": "k1", "κ2": "k2"}

    def __init__(self, surface, *, scale=None, resolution=48, window_size=(640, 480), live=None):
        from .interrogation import focal_surface

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
        from .interrogation import as_curvature_mesh

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DegeneratePointWarning)
            self.surface_mesh = as_curvature_mesh(self.source, self.resolution)
        self.surface_actor = self.plotter.add_mesh(self.surface_mesh, color="#e6e6e6", smooth_shading=True)
        self.overlay = pv.PolyData()
        self.overlay_actor = None
        set_camera(self.plotter, self.surface_mesh, VIEW_DIRECTION)
        self.update_lines()

    def update_lines(self):
        from .interrogation import isophotes, reflection_lines, stripe_mapping

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
        Isodistance step s_L; default: a tenth of the surface's size.
    count : int
        Number of isodistance curves; the paths have length ``step * count``.
    """

    title = "geodesic explorer"
    KINDS = {"geodesics": "geodesic", "normal sections": "normal-section"}

    def __init__(self, surface, start=None, *, n_angles=40, step=None, count=8, window_size=(640, 420), live=None):
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
            step = float(f"{size / (5 * count):.2g}")
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
        self.count = W.IntSlider(value=count, min=1, max=40, description="curves", style=style, layout=lay,
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
        from .geodesics import geodesic_fan, normal_section_fan, polar_isodistance

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


class _Note(Exception):
    """A remark for the status line that is not an error (raised after the scene is updated)."""


def _polylines(curves):
    """One PolyData holding the polylines ``curves`` (list of (k, 3) arrays)."""
    curves = [np.asarray(c, dtype=float) for c in curves if len(c) > 1]
    if not curves:
        return pv.PolyData()
    points = np.vstack(curves)
    lines, start = [], 0
    for c in curves:
        lines.append(np.r_[len(c), np.arange(start, start + len(c))])
        start += len(c)
    return pv.PolyData(points, lines=np.concatenate(lines))
