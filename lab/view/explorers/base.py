"""Interactive explorers for JupyterLab: compact ipywidgets controls above a live 3D view that fills the cell.

Each explorer is one call in a notebook (``lab.CurvatureExplorer(surface)``).
The view is live when a frontend can show it and a static picture otherwise
(``live=False``, grading, nbconvert); in converted notebooks the explorer's
output also carries a PNG of its view, drawn in the lab's picture style
(:mod:`lab.view.style`).

**Rendering mode.** By default the browser renders the geometry itself
(PyVista's ``client`` backend: vtk.js in the page, the kernel only sends the
changed arrays), so turning the camera needs no kernel round trip; the
kernel's plotter never renders while the view is live.  ``backend="server"``
(images rendered in the kernel and streamed, trame's remote view) and
``backend="trame"`` (trame's hybrid view, remote by default) remain available,
also through ``LAB_VIEW_BACKEND``; ``benchmarks/browser.py`` compares the three.

**Work only on a user action.** Nothing runs by itself: no timers, no
animation, and widget values set by the explorer itself never call back.
A control change starts its action as a task on the kernel's event loop; a
newer change of the same action cancels the older task (intermediate values
are dropped, never queued), and long actions yield between steps and show
their progress.

**Threads.** VTK's OpenGL context belongs to the kernel's main thread.
JupyterLab may deliver widget messages on a comm subshell thread; every
callback therefore hops to the main thread (``loop.call_soon_threadsafe``)
before it touches the plotter (the developers' guide, "Runtime facts": the kernel crash trap), and the
project also ships a JupyterLab settings override that keeps comms there.

**Lifecycle.** Re-running a cell closes the explorers that cell made before
(their trame view, plotter, widgets and callbacks), so kernel memory does not
grow with re-runs; :meth:`Explorer.close` does the same on request.
"""

import asyncio
import base64
import collections
import html
import importlib.util
import io
import os
import threading
import time
import traceback
import warnings
import weakref

import ipywidgets as W
import numpy as np
import pyvista as pv

from ...geometry.curvature import DegeneratePointWarning
from ...i18n import N_, _
from .. import style
from ..render import configure_offscreen
from .controls import FULL_ROW_CSS, _dropdown, _layout, fit_labels, grid_cells, style_for  # noqa: F401
from .live import push_camera as _push_camera
from .live import release as _release_view
from .live import rendering as _rendering
from .live import show as _show_live
from .live import update as _update_live
from .saving import DEFAULT_WIDTH, save_control
from .saving import save_picture as _save_picture
from .vision import SceneVision, deficiency, simulate_css, vision_control

__all__ = ["Explorer", "callback_threads", "checkpoint", "fit_labels", "in_jupyter_session", "live_view_choice",
           "live_view_possible"]

_INSTANCES = weakref.WeakSet()
_BY_CELL = {}  # cell id -> (execution count, [weakref to explorer, ...])
BACKENDS = ("client", "server", "trame")
DEFAULT_BACKEND = "client"
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


def live_view_choice():
    """``(live, why)``: whether an explorer made with ``live=None`` shows a live view here, and if not, why.

    Static without a note outside a Jupyter session (nbconvert, grading) or with ``LAB_STATIC=1``.  Static
    with a note when the view would have to go through jupyter-server-proxy (under JupyterHub,
    ``JUPYTERHUB_SERVICE_PREFIX``, or with ``PYVISTA_TRAME_SERVER_PROXY_PREFIX``: the browser reaches only
    the Jupyter server) and the package is not importable in the kernel's environment.  That is the
    server's environment in the lab's image and venv; a server that runs elsewhere is not asked.
    """
    if os.environ.get("LAB_STATIC") == "1" or os.environ.get("LAB_GRADING") == "1" or not in_jupyter_session():
        return False, None
    behind_proxy = os.environ.get("JUPYTERHUB_SERVICE_PREFIX") or os.environ.get("PYVISTA_TRAME_SERVER_PROXY_PREFIX")
    if behind_proxy and importlib.util.find_spec("jupyter_server_proxy") is None:
        return False, _("live 3D view unavailable: behind JupyterHub or a proxy the view needs jupyter-server-proxy "
                        "(pip install jupyter-server-proxy, then restart the server); showing pictures")
    return True, None


def live_view_possible():
    """Whether a live trame view can be shown here (:func:`live_view_choice`)."""
    return live_view_choice()[0]


def _main_loop():
    try:
        return asyncio.get_event_loop()
    except RuntimeError:  # pragma: no cover - no loop in this thread
        return None


def _running_loop():
    try:
        return asyncio.get_running_loop()
    except RuntimeError:
        return None


@__import__("types").coroutine
def checkpoint():
    """Let the event loop run (newer control changes arrive, a newer request cancels this one)."""
    yield


def _current_cell():
    """(cell id, execution count) of the notebook cell running now, or None outside a notebook cell."""
    try:
        from IPython import get_ipython

        shell = get_ipython()
        parent = shell.kernel.get_parent("shell") if shell is not None and hasattr(shell, "kernel") else None
        cell = (parent or {}).get("metadata", {}).get("cellId")
        return (cell, shell.execution_count) if cell else None
    except Exception:  # noqa: BLE001  # pragma: no cover - any other front end raises anything
        return None


def _replace_previous(explorer):
    """Close the explorers that an earlier run of the current cell made; remember this one."""
    where = _current_cell()
    if where is None:
        return
    cell, count = where
    previous = _BY_CELL.get(cell)
    if previous is not None and previous[0] != count:
        for ref in previous[1]:
            old = ref()
            if old is not None and old is not explorer:
                old.close()
        previous = None
    if previous is None:
        previous = _BY_CELL[cell] = (count, [])
    previous[1].append(weakref.ref(explorer))


class Explorer:
    """Base of the explorers: a plotter, a view (live or static), controls, a status line and main-thread actions.

    Parameters
    ----------
    window_size : (int, int)
        Size of the static picture in pixels; the live view takes the width of
        the notebook's output and keeps this aspect ratio.
    live : bool, optional
        Force a live or a static view; default: live when possible.
    backend : str, optional
        ``"client"`` (default: the browser renders with vtk.js), ``"server"``
        (images rendered in the kernel) or ``"trame"`` (trame's hybrid view).
    """

    title = N_("explorer")
    camera_direction = None  #: a fixed view direction for the camera; None: the lab's automatic oblique view

    def __init__(self, *, window_size=(800, 500), live=None, backend=None):
        configure_offscreen()
        self._loop = _main_loop()
        self.window_size = tuple(int(x) for x in window_size)
        self.backend = backend or os.environ.get("LAB_VIEW_BACKEND") or DEFAULT_BACKEND
        if self.backend not in BACKENDS:
            raise ValueError(f"backend must be one of {', '.join(BACKENDS)}; got {self.backend!r}")
        self.plotter = pv.Plotter(notebook=True, off_screen=True, window_size=list(self.window_size), lighting="none")
        self.plotter.set_background("white")
        # Multisampling triples the cost of a software (llvmpipe) render; explorers answer first.
        self.plotter.ren_win.SetMultiSamples(0)
        style.apply_lights(self.plotter)
        # why the view is static when it could have been live; the status line shows it whenever it has nothing else
        self.live, self._static_note = live_view_choice() if live is None else (bool(live), None)
        self.status = W.HTML(layout=W.Layout(min_height="1.4em", flex="1 1 0", min_width="0", overflow="hidden"))
        self.status.add_class("lab-status")
        self.progress = W.FloatProgress(value=0.0, min=0.0, max=1.0, bar_style="info",
                                        layout=W.Layout(width="140px", height="14px", visibility="hidden"))
        self.legend_view = W.HTML(layout=W.Layout(width="100%"))
        self.legend_view.add_class("lab-legend-view")
        self.timings = {}
        self.counts = collections.Counter()  # how often each action ran: the idle test counts them
        self.callback_threads = []  # where widget callbacks arrived (the renders always run on the main thread)
        self.last_error = None
        self._tasks = {}
        self._observers = []
        self._widgets = []
        self._view = None
        self._viewer = None
        self._widget = None
        self._syncing = False
        self._closed = False
        # "see it as a colour-blind student does": every explorer's colours, simulated where they are made
        self.vision = vision_control()
        self._vision = SceneVision()
        self._observe(self.vision, self.refresh)
        _INSTANCES.add(self)
        _replace_previous(self)

    # -- controls -------------------------------------------------------------

    def _control(self, widget):
        """Register a widget of this explorer (closed with it)."""
        self._widgets.append(widget)
        return widget

    def _observe(self, widget, action, names="value"):
        """Run ``action`` (a method, plain or async) on the main thread when ``widget`` changes."""
        handler = self._callback(action)
        widget.observe(handler, names)
        self._observers.append((widget, handler, names))

    def _callback(self, action):
        """An ipywidgets observer that requests ``action`` on the main thread (errors go to the status line)."""

        def observer(change=None):
            if self._syncing or self._closed:
                return
            self.callback_threads.append(threading.current_thread().name)
            self._on_main(self._request, action)

        return observer

    def _on_main(self, func, *args):
        """Run ``func`` on the kernel's main thread (now, if this is it)."""
        if threading.current_thread() is threading.main_thread() or self._loop is None:
            func(*args)
        else:
            self._loop.call_soon_threadsafe(func, *args)

    class _Quiet:
        def __init__(self, explorer):
            self.explorer = explorer

        def __enter__(self):
            self.explorer._syncing = True

        def __exit__(self, *exc):
            self.explorer._syncing = False

    def _quiet(self):
        """Change widget values from code without triggering the callbacks."""
        return self._Quiet(self)

    # -- actions ----------------------------------------------------------------

    def _request(self, action):
        """Start ``action``; a running request of the same action is cancelled (latest wins)."""
        if self._closed:
            return
        name = getattr(action, "__name__", "action")
        loop = _running_loop()
        if loop is None:  # no event loop (tests, scripts): run to the end now
            self._run(action)
            return
        old = self._tasks.get(name)
        if old is not None and not old.done():
            old.cancel()
        self._tasks[name] = loop.create_task(self._run_async(action))

    async def _run_async(self, action):
        await checkpoint()  # changes that are already queued arrive first; then only the latest runs
        steps = self._steps(action)
        try:
            while next(steps):
                await checkpoint()
        except StopIteration:
            pass
        finally:
            steps.close()

    def _run(self, action):
        """Run ``action`` to its end now (plain or async), timed, errors in the status line."""
        for _step in self._steps(action):
            pass

    def _steps(self, action):
        """Run ``action`` step by step (a generator: True after each step of an async action).

        Warnings are caught per step, never across a pause, so that actions that
        interleave on the event loop cannot mix up the global warning filters.
        """
        name = getattr(action, "__name__", "action")
        start = time.perf_counter()
        self.counts[name] += 1
        notes = set()

        def step(func):
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    return func()
                finally:
                    notes.update(str(w.message) for w in caught
                                 if issubclass(w.category, (DegeneratePointWarning, UserWarning)))

        coroutine = None
        try:
            result = step(action)
            if asyncio.iscoroutine(result):
                coroutine = result
                while True:
                    try:
                        step(lambda: coroutine.send(None))
                    except StopIteration:
                        break
                    yield True
            self._say(" ".join(sorted(notes)[:2]), "note" if notes else "ok")
        except GeneratorExit:  # cancelled by a newer request
            if coroutine is not None:
                coroutine.close()
            raise
        except NotImplementedError as exc:
            self._say(_("not implemented yet: {error}").format(error=exc), "note")
        except _Note as note:
            self._say(str(note), "note")
        except Exception as exc:  # noqa: BLE001 - shown to the user, never a traceback in the notebook
            self._say(f"{type(exc).__name__}: {exc}", "error")
            self.last_error = traceback.format_exc()
        finally:
            self._show_progress(None)
            self.timings[name] = time.perf_counter() - start

    def _show_progress(self, fraction, text=None):
        """Show a long action's progress (``None`` hides the bar)."""
        if fraction is None:
            if self.progress.layout.visibility != "hidden":
                self.progress.layout.visibility = "hidden"
            return
        self.progress.value = float(min(max(fraction, 0.0), 1.0))
        if self.progress.layout.visibility != "visible":
            self.progress.layout.visibility = "visible"
        if text:
            self._say(text, "busy")

    def _say(self, text, kind="ok"):
        if not text and self._static_note:
            text, kind = self._static_note, "note"
        colour = {"ok": "#57606a", "note": "#9a6700", "error": "#cf222e", "busy": "#0969da"}[kind]
        # one line: a long message ends in "…" and is shown whole as the tooltip (the line never wraps)
        value = (f'<span class="lab-status-text" title="{html.escape(text)}" style="color:{colour};display:block;'
                 f'white-space:nowrap;overflow:hidden;text-overflow:ellipsis">{html.escape(text)}</span>'
                 if text else "")
        if self.status.value != value:
            self.status.value = value

    # -- the view -----------------------------------------------------------

    def _build_scene(self):  # pragma: no cover - abstract
        raise NotImplementedError

    def _controls(self):  # pragma: no cover - abstract
        raise NotImplementedError

    def _extra_views(self):
        """Widgets shown below the 3D view (none by default)."""
        return []

    def legend(self):
        """The :class:`lab.view.legend.Legend` of the current colours, or None."""
        return

    def legend_html(self):
        """What the view's colours mean, as HTML below the view."""
        legend = self.legend()
        return legend.html() if legend is not None else ""

    def picture_title(self):
        return _(self.title)

    def _fit_mesh(self):
        """The mesh the camera is fitted to (the scene's main surface)."""
        return

    def fit_camera(self):
        """Fit the camera to the surface (the lab's oblique view) and show it."""
        mesh = self._fit_mesh()
        if mesh is not None and mesh.n_points:
            style.fit_camera(self.plotter, mesh, self.camera_direction)
        if self._viewer is not None:
            _push_camera(self._viewer)

    def refresh(self):
        """Show the current scene: push it to the live view, or render the static picture (main thread only)."""
        if self._closed:
            return
        self._vision.apply(self.plotter, deficiency(self.vision))
        if self._viewer is not None:
            start = time.perf_counter()
            _update_live(self._viewer)
            self.timings["push"] = time.perf_counter() - start
        elif isinstance(self._view, W.Image):
            self._view.value = self.png()
        value = simulate_css(self.legend_html(), deficiency(self.vision))
        if self.legend_view.value != value:
            self.legend_view.value = value

    def screenshot(self):
        """The bare 3D view as an array (height, width, 3), rendered in the kernel."""
        with _rendering(self.plotter):
            self.plotter.render()
            return np.asarray(self.plotter.screenshot(None, return_img=True))[..., :3]

    def picture_legend(self):
        """The legend beside :meth:`picture`: :meth:`legend`, or swatches where there is no colour bar."""
        return self.legend()

    def picture(self, size=None, title=None):
        """The view in the lab's picture style (title, colour bar or legend) as an RGB array."""
        legend = self.picture_legend()
        if legend is not None:
            legend = legend.simulated(deficiency(self.vision))
        title = self.picture_title() if title is None else title
        frame = style.layout(size or self.window_size, title, legend)
        old = tuple(self.plotter.window_size)
        try:
            self.plotter.window_size = list(frame.view[2:])
            if not self.live:  # the static picture: fitted to its own aspect
                mesh = self._fit_mesh()
                if mesh is not None and mesh.n_points:
                    style.fit_camera(self.plotter, mesh, self.camera_direction)
            image = self.screenshot()
        finally:
            self.plotter.window_size = list(old)
        return style.compose(image, frame, title=title, legend=legend)

    def save_picture(self, path, width=DEFAULT_WIDTH):
        """Write the current view with colour bar, legend and caption as a PNG ``width`` px wide (see
        :mod:`lab.view.explorers.saving`); returns ``(path, (width, height))``."""
        return _save_picture(self, path, width)

    def png(self):
        """The current picture (:meth:`picture`) as PNG bytes."""
        from PIL import Image

        buf = io.BytesIO()
        Image.fromarray(self.picture()).save(buf, format="PNG")
        return buf.getvalue()

    def _make_view(self):
        if self.live:
            try:
                self._view, self._viewer = _show_live(self.plotter, self.backend, aspect=self.window_size)
                self.refresh()
                return self._view
            except Exception as exc:  # noqa: BLE001 - no trame server here: fall back to pictures
                self.live = False
                self._static_note = _("live 3D view unavailable ({error}); showing pictures").format(
                    error=f"{type(exc).__name__}: {exc}")
                self._say(self._static_note, "note")
        self._view = W.Image(value=self.png(), format="png", layout=W.Layout(width="100%", height="auto"))
        self._view.add_class("lab-static-view")
        return self._view

    @property
    def widget(self):
        """The ipywidgets box: title and status, controls, the 3D view, its legend and extra views."""
        if self._widget is None:
            view = self._make_view()
            head = W.HBox([W.HTML(f"{FULL_ROW_CSS}<b>{html.escape(_(self.title))}</b>", layout=W.Layout(flex="0 0 auto",
                                                                                       margin="0 1em 0 0")),
                           self.status, self.progress],
                          layout=W.Layout(align_items="center", width="auto", padding="0 0 0 4px"))
            cells = grid_cells([*self._controls(), self.vision, save_control(self)])
            controls = W.GridBox(cells, layout=W.Layout(
                width="100%", grid_template_columns="repeat(auto-fill, minmax(250px, 1fr))",
                grid_gap="0px 14px", align_items="center"))
            controls.add_class("lab-controls")
            if self.legend_view.value == "":
                self.refresh()
            self._widget = W.VBox([head, controls, view, self.legend_view] + self._extra_views(),
                                  layout=W.Layout(width="100%", min_width="0"))
            self._widget.add_class("lab-explorer")
            self._widgets += [head, head.children[0], controls, self._widget]
        return self._widget

    def _repr_mimebundle_(self, include=None, exclude=None):
        # Without a frontend (nbconvert, nbclient, grading) the explorer shows a picture, which survives the
        # conversion: a widget view would make nbconvert's HTML depend on widget JavaScript from the network.
        # In a Jupyter session it shows the live view only: a picture would be an offscreen render in the kernel
        # (time, and a GL context whose memory stays with the process); e.png() makes one on request.
        text = {"text/plain": _("{title} (open the notebook in JupyterLab for the interactive view)").format(
            title=_(self.title))}
        if in_jupyter_session():
            return {**text, **self.widget._repr_mimebundle_(include=include, exclude=exclude)}
        return {"image/png": base64.b64encode(self.png()).decode(), **text}

    def close(self):
        """Close the explorer: cancel its work, drop its callbacks, close its live view, plotter and widgets."""
        if self._closed:
            return
        self._closed = True
        for task in self._tasks.values():
            if not task.done():
                task.cancel()
        self._tasks.clear()
        for widget, handler, names in self._observers:
            try:
                widget.unobserve(handler, names)
            except ValueError:  # pragma: no cover - already gone
                pass
        self._observers.clear()
        if self._viewer is not None:
            _release_view(self._viewer, self.plotter)
            self._viewer = None
        for widget in self._widgets + [self.status, self.progress, self.legend_view, self.vision, self._view,
                                       self._widget]:
            _close_tree(widget)
        self._widgets.clear()
        self._view = self._widget = None
        self.plotter.close()
        self.plotter.deep_clean()
        _INSTANCES.discard(self)
        self._drop_data()
        _trim_memory()

    def _drop_data(self):
        """Let the meshes and arrays go even while something (IPython's ``Out``, a variable) keeps the explorer."""
        for name, value in list(vars(self).items()):
            if isinstance(value, (pv.DataObject, np.ndarray)) or (
                    isinstance(value, dict) and any(isinstance(v, pv.DataObject) for v in value.values())) or name in ("fan", "isodistance", "_current_patches", "_base", "source", "actor", "lut", "plotter",
                                                                              "_model_meshes"):
                setattr(self, name, None)

    @property
    def closed(self):
        return self._closed

    @property
    def busy(self):
        """Whether an action is still running or waiting to run on the event loop."""
        return any(not task.done() for task in self._tasks.values())


def _trim_memory():
    """Hand freed memory back to the system (glibc keeps freed blocks of the many threads' arenas otherwise)."""
    import ctypes
    import gc

    gc.collect()
    try:
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):  # not glibc
        pass


def _close_tree(widget):
    """Close a widget with everything it made: its children, its layout and style widgets."""
    if widget is None:
        return
    for child in getattr(widget, "children", ()) or ():
        _close_tree(child)
    for part in ("layout", "style"):
        sub = getattr(widget, part, None)
        if isinstance(sub, W.Widget):
            sub.close()
    widget.close()


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
