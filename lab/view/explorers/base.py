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

from ...geometry.curvature import DegeneratePointWarning
from ..render import configure_offscreen

__all__ = ["Explorer", "live_view_possible", "in_jupyter_session", "callback_threads"]

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
