"""The live 3D view of an explorer: a PyVista plotter shown through trame in an iframe that fills the cell.

Three rendering modes (``backend``), all through PyVista's trame integration:

* ``client``: the browser renders the geometry with vtk.js (trame's local
  view); the kernel serialises the changed arrays only, the camera turns in
  the browser without a kernel round trip;
* ``server``: the kernel renders (offscreen, software OpenGL here) and streams
  images (trame's remote view); every camera move is a kernel round trip;
* ``trame``: trame's hybrid view (remote rendering by default, geometry kept
  in sync for a switch to local rendering), what PyVista's ``trame`` backend shows.

The view is built without PyVista's floating menu (its buttons and state
callbacks would keep every plotter alive in the shared trame server); the
explorer has its own "fit view" control.  :func:`release` undoes everything
:func:`show` registered, so a closed explorer frees its render window.
"""

import contextlib
import sys

import ipywidgets as W

__all__ = ["push_camera", "release", "rendering", "show", "update"]

_MODES = {"client": "client", "server": "server", "trame": "trame"}


def _block_vtklocal():
    # trame-vtklocal (pulled in by trame-pyvista) downloads a WASM bundle from gitlab.kitware.com when the server
    # starts; offline this prints a traceback into the notebook.  No view here uses it: keep PyVista from loading
    # it (it imports it inside contextlib.suppress(ImportError)).
    if "trame.widgets.vtklocal" not in sys.modules:
        sys.modules["trame.widgets.vtklocal"] = None


# Software WebGL (SwiftShader, llvmpipe: a browser without a GPU, as on many hub machines and in headless tests)
# pays 4x multisampling in full for every picture; there, turn it off, which roughly doubles the frames per
# second while the camera turns.  Browsers with a GPU keep their antialiasing.  Runs in the view's page before
# vtk.js creates its WebGL context.
_SOFTWARE_GL_JS = """
(() => {
  try {
    const probe = document.createElement('canvas');
    const gl = probe.getContext('webgl2') || probe.getContext('webgl');
    if (!gl) return;
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    const renderer = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
    const lose = gl.getExtension('WEBGL_lose_context');
    if (lose) lose.loseContext();
    if (!/swiftshader|llvmpipe|softpipe|software/i.test(renderer)) return;
    const getContext = HTMLCanvasElement.prototype.getContext;
    HTMLCanvasElement.prototype.getContext = function (type, attributes) {
      if (typeof type === 'string' && type.startsWith('webgl')) attributes = Object.assign({}, attributes, {antialias: false});
      return getContext.call(this, type, attributes);
    };
    window.__labSoftwareGL = renderer;
  } catch (error) { /* keep the defaults */ }
})();
"""


def _prepare_server():
    """Add the lab's page script to PyVista's trame server before it starts (once per kernel)."""
    import base64

    import pyvista as pv
    from trame_pyvista.widgets import get_server

    server = get_server(name=pv.global_theme.trame.jupyter_server_name)
    if not server.running and not getattr(server, "_lab_prepared", False):
        url = "data:text/javascript;base64," + base64.b64encode(_SOFTWARE_GL_JS.encode()).decode()
        server.enable_module({"scripts": [url]})
        server._lab_prepared = True


def _iframe(src, aspect):
    w, h = aspect
    style = (f"width:100%;aspect-ratio:{int(w)} / {int(h)};height:auto;border:1px solid #d0d7de;"
             "box-sizing:border-box;display:block")
    return W.HTML(f'<iframe src="{src}" class="pyvista" scrolling="no" style="{style}"></iframe>',
                  layout=W.Layout(width="100%"))


def show(plotter, backend, *, aspect=(16, 10)):
    """Start (or reuse) the kernel's trame server and return ``(widget, viewer)`` for ``plotter``.

    The widget is an iframe 100% wide with the given aspect ratio.  Renders
    of the plotter no longer push to the view by themselves: call :func:`update`.
    """
    _block_vtklocal()
    _prepare_server()
    captured = {}

    def handler(viewer, src, **_kwargs):
        captured["viewer"] = viewer
        return _iframe(src, aspect)

    # the mode is passed explicitly: PyVista calls the entry-point handler without it (it would show "trame")
    widget = plotter.show(jupyter_backend=_MODES[backend], return_viewer=True, auto_close=False,
                          jupyter_kwargs={"handler": handler, "add_menu": False, "mode": _MODES[backend]})
    viewer = captured["viewer"]
    # PyVista pushes the view on every plotter.render(); the explorers push once per change themselves.
    for view in viewer.views:
        plotter._on_render_callbacks.discard(getattr(view, "_plotter_render_callback", None))
    return widget, viewer


def update(viewer):
    """Push the current scene to the browser (client: changed arrays; server: a new image)."""
    for view in list(viewer.views):
        view.update()
    # The views also put the full scene into the trame state, which trame only sends at its next flush (the
    # next message from the browser, often half a second later): send it now.
    viewer.server.state.flush()


def push_camera(viewer):
    """Send the plotter's camera to the browser (client) or render with it (server)."""
    for view in list(viewer.views):
        if hasattr(view, "push_camera"):
            with contextlib.suppress(Exception):
                view.push_camera()
        view.update()


def _helper(view):
    return getattr(view, "_helper", None)


def release(viewer, plotter):
    """Undo what :func:`show` registered in the shared trame server, so the plotter can be freed."""
    from trame_pyvista import ui as pv_ui

    server = viewer.server
    render_window = plotter.render_window
    for view in list(viewer.views):
        with contextlib.suppress(Exception):
            server.controller.on_server_ready.discard(view.update)
        for name in ("update_geometry",):
            method = getattr(view, name, None)
            if method is not None:
                with contextlib.suppress(Exception):
                    server.controller.on_server_ready.discard(method)
        helper = _helper(view)
        with contextlib.suppress(Exception):
            view.release_resources()
        if helper is not None and render_window is not None:
            with contextlib.suppress(Exception):
                helper.remove_hybrid_view(plotter._id_name)
            with contextlib.suppress(Exception):
                helper._vtk_core.GetObjectIdMap().FreeObject(render_window)
    viewer.views.clear()
    pv_ui._VIEWERS.pop(plotter._id_name, None)
    # the view's scene and the layout's template stay in the shared trame state under the plotter's name: empty them
    with contextlib.suppress(Exception):
        state = server.state
        for key, value in list(state.to_dict().items()):
            if plotter._id_name in key and isinstance(value, (dict, list, str)) and len(value) > 0:
                state[key] = None
        state.flush()
    viewer.layout = None
    viewer.plotter = None


@contextlib.contextmanager
def rendering(plotter):
    """Let the plotter render for a picture even while a client-side view suppresses its renders."""
    suppressed = getattr(plotter, "suppress_rendering", False)
    try:
        plotter.suppress_rendering = False
        yield
    finally:
        plotter.suppress_rendering = suppressed
