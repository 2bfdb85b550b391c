"""Offscreen pictures and HTML scenes of meshes with curvature colours (PyVista), in the lab's one style.

:func:`picture` (an RGB array), :func:`show` (for a notebook) and :func:`save`
(a PNG file, used by the CLI and the gallery) draw a surface the way
:mod:`lab.view.style` describes: fitted oblique camera, three-point light that
keeps the colours true, a title, the colour bar or class legend in curvature
units (:mod:`lab.view.legend`), padding, optional patch borders.

How pictures are drawn without a window (:func:`configure_offscreen`, called before every picture, scene and
explorer; the choice is :func:`choose_backend`'s):

* **Windows, macOS, and Linux with a display** (``DISPLAY`` or ``WAYLAND_DISPLAY`` set): VTK's own choice
  (WGL on Windows, Cocoa on macOS, X on a Linux desktop); nothing is forced.  The Windows wheel has no EGL.
* **Linux without a display**: EGL (``vtkEGLRenderWindow``) if it works here, else OSMesa
  (``vtkOSOpenGLRenderWindow``: VTK 9.7's Linux wheel has it and loads ``libOSMesa.so.8``, ``.so.6`` or ``.so``
  when it is first used; PyPI has no OSMesa build of VTK, the library comes from the system, e.g.
  ``apt install libosmesa6``).  An explicit ``VTK_DEFAULT_OPENGL_WINDOW`` naming one of the two is tried first;
  one naming another window is left alone.  Whether a backend works is tested once per process in a child
  process (load the library with ctypes, then draw an 8 x 8 picture with that window class), because a
  missing ``libEGL`` or an EGL without a usable driver ends the process that tries it with a segmentation
  fault (VTK 9.7: "Failed to load EGL!", exit 139; a notebook's kernel dies): a crash of the child is a
  verdict, never a dead kernel.  The test costs about half a second, once; a backend found working is
  remembered, one found wanting is tested again next time (install the library, run the cell again).
* When neither works, :class:`RenderingUnavailable` (a ``RuntimeError``) says so and names what to install
  (``libegl1 libgl1-mesa-dri`` or ``libosmesa6`` on Debian/Ubuntu, ``mesa-libEGL mesa-dri-drivers`` on
  Fedora) or to work with a display; the command line prints it as ``curvature-lab: error: …`` and exits 1.
  :func:`export_html` needs no drawing (vtk.js draws the scene in the browser) and goes on without one.
"""

import io
import os
import re
import signal
import subprocess
import sys

import numpy as np
import pyvista as pv

from ..geometry import validation as _v
from ..i18n import _
from ..interrogation.faces import is_model
from ..interrogation.reflection import VIEW_DIRECTION
from ..model.patches import BezierPatches
from . import style
from .legend import Legend, simulated_note, stored_legend
from .legend import legend as make_legend

__all__ = [
    "VIEW_DIRECTION",
    "RenderingUnavailable",
    "choose_backend",
    "configure_offscreen",
    "export_html",
    "face_borders",
    "picture",
    "plot_mesh",
    "probe_backend",
    "save",
    "screenshot",
    "set_camera",
    "show",
    "show_row",
    "stored_legend",
]


class RenderingUnavailable(RuntimeError):
    """No way to draw a picture on this machine (Linux without a display, neither EGL nor OSMesa working); the
    message says why and what to install."""


#: the offscreen backends that can be forced on Linux without a display: VTK's window class for each
WINDOWS = {"egl": "vtkEGLRenderWindow", "osmesa": "vtkOSOpenGLRenderWindow"}
#: the libraries VTK 9.7 loads for each, in its order (glad for EGL; vtkOSOpenGLRenderWindow for OSMesa)
LIBRARIES = {"egl": ("libEGL.so.1", "libEGL.so"), "osmesa": ("libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so")}
NAMES = {"egl": "EGL", "osmesa": "OSMesa"}
#: seconds a test render may take (about 0.5 s on an idle machine, several on a loaded one)
PROBE_TIMEOUT = 60.0


def choose_backend(platform, environ, probe):
    """How VTK should draw offscreen: ``"native"`` (VTK's own choice, nothing forced), ``"egl"`` or ``"osmesa"``.

    ``platform`` is a ``sys.platform`` value, ``environ`` a mapping like ``os.environ``, ``probe(backend)`` answers
    ``(works, why)`` for ``"egl"`` and ``"osmesa"`` (:func:`probe_backend`), and is asked only on Linux without a
    display, EGL first unless ``VTK_DEFAULT_OPENGL_WINDOW`` names OSMesa's window.  Raises
    :class:`RenderingUnavailable` when no backend works.
    """
    if not str(platform).startswith("linux"):
        return "native"  # Windows (WGL), macOS (Cocoa), others: VTK knows best; the Windows wheel has no EGL
    if environ.get("DISPLAY") or environ.get("WAYLAND_DISPLAY"):
        return "native"  # a desktop: VTK's X window draws the same picture
    asked = environ.get("VTK_DEFAULT_OPENGL_WINDOW") or ""
    order = ["egl", "osmesa"]
    if asked == WINDOWS["osmesa"]:
        order.reverse()
    elif asked and asked != WINDOWS["egl"]:
        return "native"  # someone chose another window on purpose
    reasons = {}
    for backend in order:
        works, why = probe(backend)
        if works:
            return backend
        reasons[backend] = why
    raise RenderingUnavailable(_unavailable(reasons))


def _unavailable(reasons):
    found = " ".join(f"{NAMES[b]}: {why}." for b, why in reasons.items())
    return (f"cannot draw pictures on this machine: it is Linux without a display (neither DISPLAY nor "
            f"WAYLAND_DISPLAY is set), so VTK must draw offscreen with EGL or OSMesa, and neither works. {found} "
            f"Install EGL with Mesa's drivers (Debian/Ubuntu: sudo apt install libegl1 libgl1-mesa-dri; "
            f"Fedora: sudo dnf install mesa-libEGL mesa-dri-drivers) or OSMesa (Debian/Ubuntu: "
            f"sudo apt install libosmesa6), or work in a desktop session with a display; then run it again.")


#: the child process of :func:`probe_backend`: argv = window class, library names to try
_PROBE = """
import ctypes, sys
error = None
for name in sys.argv[2:]:
    try:
        ctypes.CDLL(name)
        break
    except OSError as exc:
        error = error or exc
else:
    print("missing:", error, flush=True)
    sys.exit(3)
print("loaded:", name, flush=True)
import vtkmodules.vtkRenderingOpenGL2 as gl
from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
from vtkmodules.vtkRenderingCore import vtkRenderer
if not hasattr(gl, sys.argv[1]):
    print("no-class:", flush=True)
    sys.exit(4)
window = getattr(gl, sys.argv[1])()
window.SetOffScreenRendering(1)
window.SetSize(8, 8)
renderer = vtkRenderer()
renderer.SetBackground(1.0, 0.0, 0.0)
window.AddRenderer(renderer)
window.Render()
pixels = vtkUnsignedCharArray()
window.GetPixelData(0, 0, 7, 7, 1, pixels, 0)
red = (pixels.GetValue(0), pixels.GetValue(1), pixels.GetValue(2)) == (255, 0, 0)
window.Finalize()
print("drew:" if red else "blank:", flush=True)
"""


def _vtk_said(stderr):
    """VTK's first warning or error in a child's stderr, without colours and log prefix (or "")."""
    for line in re.sub(r"\x1b\[[0-9;]*m", "", stderr or "").splitlines():
        if "WARN|" in line or "ERR|" in line:
            return line.split("|", 1)[1].strip()
    return ""


def probe_backend(backend, *, timeout=PROBE_TIMEOUT):
    """``(works, why)``: whether VTK draws with ``backend`` (``"egl"`` or ``"osmesa"``) here, tested in a child
    process (load the library, draw an 8 x 8 red picture, read it back), so that a crash is the child's."""
    library = LIBRARIES[backend][0]
    env = {k: v for k, v in os.environ.items() if k != "VTK_DEFAULT_OPENGL_WINDOW"}
    try:
        done = subprocess.run([sys.executable, "-c", _PROBE, WINDOWS[backend], *LIBRARIES[backend]], check=False,
                              env=env, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return False, f"a test render took longer than {timeout:g} s"
    except OSError as exc:
        return False, f"could not start a test process ({exc})"
    out, code, said = done.stdout, done.returncode, _vtk_said(done.stderr)
    said = f"; VTK said: {said}" if said else ""
    if code == 0 and "drew:" in out:
        return True, "drew a test picture"
    if "missing:" in out:
        detail = out.split("missing:", 1)[1].strip().splitlines()[0]
        return False, f"{library} cannot be loaded ({detail})"
    if "no-class:" in out:
        return False, f"this VTK has no {WINDOWS[backend]}"
    if "blank:" in out:
        return False, f"{library} loads, but a test picture came back blank{said}"
    if "loaded:" in out and code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return False, f"{library} loads, but a test render crashed with {name}{said}"
    last = (done.stderr or "").strip().splitlines()[-1:] or [""]
    return False, f"a test render failed with exit code {code}{said or ('; ' + last[0] if last[0] else '')}"


#: backends that drew in this process's lifetime (a failure is not remembered: install, then try again)
_WORKING = set()


def _probe_once(backend):
    if backend in _WORKING:
        return True, "drew a test picture"
    works, why = probe_backend(backend)
    if works:
        _WORKING.add(backend)
    return works, why


def configure_offscreen():
    """Prepare VTK to draw without a window, as :func:`choose_backend` decides for this machine; returns its answer.

    On Linux without a display, sets ``VTK_DEFAULT_OPENGL_WINDOW`` to the window of the backend that works
    (EGL before OSMesa) or raises :class:`RenderingUnavailable`; elsewhere leaves VTK its own choice.  Sets
    ``pyvista.OFF_SCREEN`` when ``DISPLAY`` is unset.
    """
    backend = choose_backend(sys.platform, os.environ, _probe_once)
    if backend in WINDOWS:
        os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = WINDOWS[backend]
    if not os.environ.get("DISPLAY"):
        pv.OFF_SCREEN = True
    return backend


def plot_mesh(mesh, plotter, *, show_edges=False, scalars=None, cmap="viridis", **kwargs):
    """Add a curvature mesh to ``plotter``: its ``RGB`` colours if present, else ``scalars`` with ``cmap``."""
    kwargs = {**style.SURFACE_PROPERTIES, **kwargs}
    if show_edges:
        kwargs.setdefault("edge_color", "#3a3a3a")
        kwargs.setdefault("line_width", 0.8)
    if scalars is None and "RGB" in mesh.cell_data:  # e.g. stripe mappings: one colour per facet
        if "lit" in mesh.field_data:  # colours that already contain their shading (the paper's colour plate 1)
            kwargs["lighting"] = False
        return plotter.add_mesh(mesh, scalars="RGB", rgb=True, preference="cell", show_edges=show_edges, **kwargs)
    if scalars is None and "RGB" in mesh.point_data:
        return plotter.add_mesh(mesh, scalars="RGB", rgb=True, show_edges=show_edges, smooth_shading=True, **kwargs)
    return plotter.add_mesh(mesh, scalars=scalars, cmap=cmap, show_edges=show_edges, smooth_shading=True,
                            show_scalar_bar=False, **kwargs)


def set_camera(plotter, mesh, direction=None, zoom=1.0):
    """Look at ``mesh`` from ``direction`` (default: the automatic oblique view) with z up, fitted to the view."""
    style.fit_camera(plotter, mesh, direction)
    if zoom != 1.0:
        plotter.camera.zoom(zoom)


#: Lines per direction of a surface's grid, and per face of a model, unless a picture's ``n`` says otherwise.
SURFACE_LINES, MODEL_LINES = 64, 16


def _as_mesh(obj, curvature, color_map, resolution, n, map_options=None):
    """A curvature mesh for patches, a surface, a model or a mesh, and the legend its colours have (or None)."""
    from .. import mesh as _mesh
    from ..geometry.curvature import CurvatureMode, zero_tolerance
    _v.refuse_class(obj, "BezierPatches, a lab surface, a lab.Model, a pyvista.PolyData or a geomview file")
    options = dict(map_options or {})
    coloured = curvature is not None and color_map is not None
    if isinstance(obj, (str, os.PathLike)):  # a file written for geomview, read back with its colours
        obj = _mesh.read_geomview(obj, resolution=max(int(resolution), 8))
    if isinstance(obj, pv.PolyData):
        mesh = obj
        if coloured and "K" in mesh.point_data:
            mesh = _mesh.color_curvature(mesh.copy(), curvature, color_map, **options)
    elif isinstance(obj, BezierPatches):
        if coloured:
            obj = obj.copy()
            BezierPatches.visualize_curvature(obj, curvature, color_map, **options)
        mesh = _mesh.patches_mesh(obj, resolution=resolution)
    elif hasattr(obj, "derivatives") and hasattr(obj, "domain"):
        mesh = _mesh.surface_mesh(obj, n or SURFACE_LINES, n or SURFACE_LINES, curvature, color_map, **options)
    elif is_model(obj):  # a part from lab.read: every face on n lines, one colour range over all faces
        if not obj.faces:
            raise ValueError(f"the model has no faces to show; problems: {[str(p) for p in obj.problems]}")
        lines = n or MODEL_LINES
        mesh = (obj.to_mesh(lines, lines, curvature_mode=curvature, color_map=color_map, **options) if coloured
                else obj.to_mesh(lines, lines))
    else:
        raise TypeError(f"show expects BezierPatches, a lab surface, a lab.Model, a pyvista.PolyData or a geomview "
                        f"file; got {type(obj).__name__}")
    legend = stored_legend(obj) if isinstance(obj, BezierPatches) and not coloured else None
    if coloured and "values" in mesh.point_data:
        mode = CurvatureMode(curvature).value
        name = color_map.value if hasattr(color_map, "value") else str(color_map)
        size = float(np.linalg.norm(np.ptp(np.asarray(mesh.points), axis=0)))
        legend = make_legend(mode, name, np.asarray(mesh.point_data["values"]), options=options,
                             tol=zero_tolerance(mode, size))
    return mesh, legend


def _net_lines(obj):
    P = np.asarray(obj.control_points)
    P = P[None] if P.ndim == 3 else P
    lines = []
    for net_ in P:
        lines += [pv.lines_from_points(row) for row in net_] + [pv.lines_from_points(col) for col in net_.transpose(1, 0, 2)]
    return pv.merge(lines), P.reshape(-1, 3)


def face_borders(mesh):
    """The border of every face of a model's mesh (:meth:`lab.Model.to_mesh`) as lines: its faces are not welded
    to each other, so each face's own border; an empty PolyData for a mesh without point data ``face``."""
    if mesh.n_cells == 0 or "face" not in mesh.point_data:
        return pv.PolyData()
    return mesh.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                      non_manifold_edges=False)


def _add_flat(plotter, mesh, edges):
    """Dill's drawing (Dill 1981): one colour per polygon (cell ``RGB``, :func:`lab.mesh.color_cells`), one light
    at the eye (ambient plus Lambert)."""
    plotter.add_light(pv.Light(light_type="headlight"))
    colors = {"scalars": "RGB", "rgb": True, "preference": "cell"} if "RGB" in mesh.cell_data else {"color": "#d9d9d9"}
    plotter.add_mesh(mesh, show_edges=edges, ambient=0.3, diffuse=0.7, specular=0.0, smooth_shading=False, **colors)


#: A picture's memory per pixel: VTK's colour and depth buffers, the RGB copy read back, the composed frame and
#: the PNG encoder's copy (a 100000 x 100000 window ended in std::bad_alloc inside VTK).
PICTURE_BYTES_PER_PIXEL = 24


def _window(size, name="window_size"):
    """``size`` as (width, height) of at least 16 pixels each, refused before VTK allocates if too big."""
    if isinstance(size, (str, bytes)) or np.ndim(size) != 1 or len(size) != 2:
        raise TypeError(f"{name} must be (width, height) in pixels; got {size!r}")
    w, h = (int(_v.as_number(x, f"{name} entry", minimum=16)) for x in size)
    _v.check_memory(PICTURE_BYTES_PER_PIXEL * w * h, f"a {w} x {h} picture ({name})")
    return w, h


def render_view(mesh, size, *, edges=False, net=None, lines=None, direction=None, camera=None, background="white",
                shading="smooth", borders=None, marks=None):
    """The bare 3D view of ``mesh`` in the lab's style (no frame), ``size`` = (width, height); RGB array.

    ``shading="flat"`` draws ``mesh`` (with cell colours) as Dill did: flat polygons lit by one light at the eye.
    ``lines`` (polylines, e.g. reflection lines) are drawn in black over the surface, ``borders`` (a model's
    face borders) in dark grey, ``marks`` (points, e.g. umbilics) as white dots in black rings in front of the surface.
    """
    size = _window(size, "size")
    configure_offscreen()
    plotter = pv.Plotter(off_screen=True, window_size=list(size), lighting="none")
    try:
        plotter.set_background(background)
        if shading == "flat":
            _add_flat(plotter, mesh, edges)
        elif "RGB" in mesh.point_data or "RGB" in mesh.cell_data:
            plot_mesh(mesh, plotter, show_edges=edges)
        else:
            plotter.add_mesh(mesh, color="#d9d9d9", show_edges=edges, smooth_shading=True, **style.SURFACE_PROPERTIES,
                             **({"edge_color": "#3a3a3a", "line_width": 0.8} if edges else {}))
        if net is not None:
            net_lines, net_points = net
            plotter.add_mesh(net_lines, color="black", line_width=1)
            plotter.add_points(net_points, color="black", point_size=5, render_points_as_spheres=True)
        if borders is not None and borders.n_points:
            style.offset_lines(plotter.add_mesh(borders, color="#3a3a3a", line_width=1.2, scalars=None,
                                                lighting=False))
        if lines is not None and lines.n_points:
            style.add_lines_on_surface(plotter, lines)
        if shading != "flat":
            style.apply_lights(plotter)
        azimuth, elevation = camera if camera is not None else (None, None)
        fit_to = mesh if net is None else mesh.merge(pv.PolyData(net[1])) if mesh.n_points else pv.PolyData(net[1])
        style.fit_camera(plotter, fit_to, direction, azimuth=azimuth, elevation=elevation)
        if marks is not None:
            style.add_marks(plotter, marks, size[1])
        return np.asarray(plotter.screenshot(None, return_img=True))[..., :3]
    finally:
        plotter.close()


def picture(obj, curvature=None, color_map=None, *, window_size=(800, 600), edges=False, net=False, title=None,
            resolution=1, n=None, direction=None, camera=None, map_options=None, legend=True, shading="smooth",
            lines=None, band_lines=False, simulate=None, marks=None):
    """A picture of patches, a surface, a model or a mesh in the lab's style, as an RGB array (height, width, 3).

    Parameters
    ----------
    obj : BezierPatches, lab surface, lab.Model, pyvista.PolyData or path
        Patches are shown with the colours their ``visualize_curvature`` stored
        (or, with ``curvature`` and ``color_map``, coloured by the library).  A model (a part from
        :func:`lab.read`) is drawn face by face (:meth:`lab.Model.to_mesh`) with one colour range and one
        legend over all faces; the sign of H follows each face's normal (outward on a closed solid from a
        STEP, IGES or BREP file).  A path is a file written for
        geomview (``write_cbez``, ``write_off``), read back with its colours (:func:`lab.mesh.read_geomview`).
    curvature, color_map : str, optional
        Colour by this curvature and map; the picture then has a colour bar
        (or the classification legend) in curvature units.
    window_size : (int, int)
        Size of the whole picture in pixels.
    edges : bool
        Draw mesh edges (for patches at resolution 1: the patch borders); on a model, or a model's mesh (point
        data ``face``), the faces' borders instead.
    net : bool
        Draw the control nets of patches.
    lines : pyvista.PolyData, optional
        Polylines drawn in black over the surface, e.g. :func:`lab.reflection_lines` or :func:`lab.isophotes`.
    marks : (n, 3) array_like, optional
        Points marked as white dots in black rings, e.g. the umbilics (:func:`lab.umbilics`) where lines of curvature end.
    title : str, optional
    n : int, optional
        Lines per direction of a surface's grid (default 64) or per face of a model (default 16).
    camera : (float, float), optional
        Azimuth and elevation in degrees (azimuth around z from +x, elevation
        above the xy-plane); default: the automatic oblique view (see :mod:`lab.view.style`).
    direction : (3,) array_like, optional
        A view direction (from the surface towards the eye) instead of ``camera``.  Stripe mappings and
        reflection lines (view-dependent) are shown from :data:`VIEW_DIRECTION`, the eye they are computed
        for by default, unless ``camera`` or ``direction`` is given.
    map_options : dict, optional
        Options of the colour map, e.g. ``{"vmin": -1, "vmax": 0.5}`` for Dill's bands.
    legend : bool or Legend
        Draw the colour bar or legend when the colours' meaning is known (True: coloured here by
        ``curvature`` and ``color_map``), never (False), or this one.  A mesh without colours is grey.
    shading : {"smooth", "flat"}
        ``"flat"`` draws as Dill did (Dill 1981, "Image generation"): every
        polygon in one colour, that of the mean of its vertices' values, and one
        uniform shade from a single light at the eye (ambient plus Lambert), so
        band edges follow the polygons as in his figures.
    band_lines : bool
        Draw level lines at the borders of the colour bands (:func:`lab.interrogation.bands.band_lines` at the
        legend's ``levels``: the parabolic lines of a classification, Dill's band edges, a bar's ticks).
    simulate : {None, "protanopia", "deuteranopia", "tritanopia"}
        The whole picture as a student with this colour-vision deficiency sees it (:func:`lab.vision.simulate`).
    """
    if shading not in ("smooth", "flat"):
        raise ValueError(f"shading must be 'smooth' or 'flat'; got {shading!r}")
    if (curvature is None) != (color_map is None):  # one without the other would colour nothing
        given, missing = ("color_map", "curvature") if curvature is None else ("curvature", "color_map")
        raise ValueError(_("{given} needs {missing}: a colour map colours a curvature measure; give both "
                           "(e.g. curvature='gaussian', color_map='linear') or neither").format(
            given=given, missing=missing))
    if lines is not None and not isinstance(lines, pv.PolyData):
        raise TypeError(f"lines must be a pyvista.PolyData of polylines (e.g. lab.reflection_lines); "
                        f"got {type(lines).__name__}")
    from ..geometry import vision

    vision.check_deficiency(simulate)
    mesh, known = _as_mesh(obj, curvature, color_map, resolution, n, map_options)
    if band_lines:
        lines = _with_band_lines(mesh, known, curvature, color_map, lines)
    if shading == "flat":
        from .. import mesh as _mesh

        if curvature is not None and color_map is not None and "K" in mesh.point_data:
            mesh = _mesh.color_cells(mesh, curvature, color_map, **(map_options or {}))
        elif "RGB" in mesh.point_data:
            mesh = _mesh.color_cells(mesh)
    view_dependent = [m for m in (mesh, lines) if m is not None]
    if direction is None and camera is None and any("box_lo" in m.field_data or "light_origin" in m.field_data
                                                    for m in view_dependent):
        # stripe mappings and reflection lines depend on the eye: show them from the one they were computed for
        direction = VIEW_DIRECTION
    if isinstance(legend, Legend):
        chosen = legend
    elif legend:
        chosen = known
    else:
        chosen = None
    if simulate and chosen is not None:  # the picture says what it shows
        chosen = simulated_note(chosen, simulate)
    frame = style.layout(_window(window_size), title, chosen)
    net_data = _net_lines(obj) if net and hasattr(obj, "control_points") else None
    borders = face_borders(mesh) if edges else None
    if borders is not None and borders.n_points:
        edges = False  # a model's triangles mean nothing: its faces' borders instead
    view = render_view(mesh, frame.view[2:], edges=edges, net=net_data, lines=lines, direction=direction,
                       camera=camera, shading=shading, borders=borders, marks=marks)
    return vision.simulate_image(style.compose(view, frame, title=title, legend=chosen), simulate)


def _with_band_lines(mesh, known, curvature, color_map, lines):
    """``lines`` and the level lines at the borders of the colour bands of ``known`` (the picture's legend)."""
    from ..geometry.colormaps import normalisation
    from ..geometry.curvature import CurvatureMode, zero_tolerance
    from ..interrogation.bands import band_lines

    if known is None or not known.levels or "values" not in mesh.point_data:
        raise ValueError("band_lines needs a picture coloured by curvature and a colour map of the lab (curvature= "
                         "and color_map=); its legend's bands say where the lines go")
    tol = 0.0
    if color_map is not None and normalisation(color_map) == "classification":
        size = float(np.linalg.norm(np.ptp(np.asarray(mesh.points), axis=0)))
        tol = zero_tolerance(CurvatureMode(curvature).value, size)
    found = band_lines(mesh, "values", known.levels, tol=tol)
    if lines is None or not lines.n_points:
        return found
    return lines.merge(found) if found.n_points else lines


def save(obj, path, curvature=None, color_map=None, **options):
    """Write :func:`picture` to a PNG file and return the image."""
    from PIL import Image

    image = picture(obj, curvature, color_map, **options)
    Image.fromarray(image).save(str(path), format="PNG", optimize=True)
    return image


#: the size of a notebook picture: as wide as a JupyterLab cell on a laptop (wider pictures shrink to the cell)
SHOW_SIZE = (960, 600)


def _image(array):
    from IPython.display import Image
    from PIL import Image as PILImage

    buf = io.BytesIO()
    PILImage.fromarray(array).save(buf, format="PNG")
    return Image(data=buf.getvalue(), format="png")


def show(obj, curvature=None, color_map=None, *, window_size=SHOW_SIZE, **options):
    """A picture of patches, a surface or a mesh for a notebook (an ``IPython.display.Image``, PNG).

    Takes the arguments of :func:`picture`; the picture is :data:`SHOW_SIZE` unless ``window_size`` says otherwise.
    """
    return _image(picture(obj, curvature, color_map, window_size=window_size, **options))


def show_row(objects, titles=None, *, window_size=(1200, 420), **options):
    """Pictures side by side in one image (wider than the cell, so that it shrinks to fill it), each with its own
    title and legend.

    ``objects`` are what :func:`picture` takes; ``titles`` one per object; ``options`` (``curvature``,
    ``color_map``, ``direction``, ``camera`` …) apply to all, except a list of ``color_map`` or of ``lines`` (one
    per object).  Without ``direction`` or ``camera`` all pictures
    look from the direction the first one is drawn from: one camera for the row.
    """
    objects = list(objects)
    if not objects:
        raise ValueError("show_row needs at least one object to show; got none")
    titles = _per_object(titles, len(objects), "titles must give one title per object ({n}); got {got}")
    width = int(window_size[0]) // len(objects)
    if options.get("direction") is None and options.get("camera") is None:
        meshes = [o for o in objects if isinstance(o, pv.PolyData)]
        if any("box_lo" in m.field_data or "light_origin" in m.field_data for m in meshes):
            options["direction"] = VIEW_DIRECTION  # a view-dependent picture in the row: its eye for all
        else:
            first = (pv.PolyData(np.asarray(objects[0].control_points, dtype=float).reshape(-1, 3))
                     if isinstance(objects[0], BezierPatches) else _as_mesh(objects[0], None, None, 1, 16)[0])
            options["direction"] = style.view_direction(first, None, None, width / int(window_size[1]))
    maps, lines = (_per_object(options.pop(key, None), len(objects), key + " must be one or one per object ({n}); got {got}")
                   for key in ("color_map", "lines"))
    parts = [picture(obj, window_size=(width, int(window_size[1])), title=title, color_map=cmap, lines=drawn,
                     **options)
             for obj, title, cmap, drawn in zip(objects, titles, maps, lines)]
    return _image(np.hstack(parts))


def _per_object(value, n, message):
    """``value`` for each of ``n`` pictures: a list or tuple of one per picture, anything else for all."""
    values = list(value) if isinstance(value, (list, tuple)) else [value] * n
    if len(values) != n:
        raise ValueError(message.format(n=n, got=len(values)))
    return values


def screenshot(mesh, path, *, window_size=(1024, 768), show_edges=False, title=None):
    """The bare offscreen rendering of ``mesh`` (no frame, no legend) to a PNG file; returns the image.

    Kept for image references of the mesh colours alone; pictures for people come from :func:`picture`.
    """
    window_size = _window(window_size)
    configure_offscreen()
    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    if "RGB" in mesh.cell_data:
        plotter.add_mesh(mesh, scalars="RGB", rgb=True, preference="cell", show_edges=show_edges)
    elif "RGB" in mesh.point_data:
        plotter.add_mesh(mesh, scalars="RGB", rgb=True, show_edges=show_edges, smooth_shading=True)
    else:
        plotter.add_mesh(mesh, cmap="viridis", show_edges=show_edges, smooth_shading=True)
    if title:
        plotter.add_text(title, font_size=12, color="black")
    centre = np.asarray(mesh.center, dtype=float)
    d = np.asarray(VIEW_DIRECTION, dtype=float)
    d /= np.linalg.norm(d)
    plotter.camera_position = [tuple(centre + d * max(mesh.length, 1e-9)), tuple(centre), (0.0, 0.0, 1.0)]
    plotter.reset_camera()
    image = plotter.screenshot(str(path), return_img=True)
    plotter.close()
    return np.asarray(image)


def export_html(mesh, path, *, show_edges=False, camera=None):
    """Write an interactive HTML scene (vtk.js via trame) of ``mesh``, with the lab's camera and light."""
    try:
        configure_offscreen()
    except RenderingUnavailable:
        pass  # the scene is drawn by vtk.js in the browser: nothing is drawn here
    plotter = pv.Plotter(off_screen=True, lighting="none")
    plot_mesh(mesh, plotter, show_edges=show_edges)
    style.apply_lights(plotter)
    azimuth, elevation = camera if camera is not None else (None, None)
    style.fit_camera(plotter, mesh, azimuth=azimuth, elevation=elevation)
    try:  # PyVista 0.49+: trame-pyvista's exporter (pyvista[jupyter] brings it); Plotter.export_html is deprecated
        exporter = plotter.trame.export_html
    except (AttributeError, ImportError):  # an older PyVista
        exporter = plotter.export_html
    exporter(str(path))
    plotter.close()
