"""Offscreen pictures and HTML scenes of meshes with curvature colours (PyVista)."""

import os

import numpy as np
import pyvista as pv

from ..interrogation.reflection import VIEW_DIRECTION

__all__ = ["configure_offscreen", "plot_mesh", "set_camera", "screenshot", "export_html", "show", "VIEW_DIRECTION"]


def configure_offscreen():
    """Render without a display when there is none (EGL, no X server).

    Sets ``pyvista.OFF_SCREEN`` and ``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``
    (which silences VTK's "bad X server connection" warning) when ``DISPLAY`` is unset.
    """
    if not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
        pv.OFF_SCREEN = True


def plot_mesh(mesh, plotter, *, show_edges=False, scalars=None, cmap="viridis", **kwargs):
    """Add a curvature mesh to ``plotter``: its ``RGB`` colours if present, else ``scalars`` with ``cmap``."""
    if scalars is None and "RGB" in mesh.cell_data:  # e.g. stripe mappings: one colour per facet
        lit = "lit" in mesh.field_data  # colours that already contain their shading (the paper's colour plate 1)
        return plotter.add_mesh(mesh, scalars="RGB", rgb=True, preference="cell", show_edges=show_edges,
                                **({"lighting": False} if lit else {}), **kwargs)
    if scalars is None and "RGB" in mesh.point_data:
        return plotter.add_mesh(mesh, scalars="RGB", rgb=True, show_edges=show_edges, smooth_shading=True, **kwargs)
    return plotter.add_mesh(mesh, scalars=scalars, cmap=cmap, show_edges=show_edges, smooth_shading=True, **kwargs)


#: Default viewing direction (from the focal point towards the camera): from the front left, above.


def set_camera(plotter, mesh, direction=VIEW_DIRECTION, zoom=1.0):
    """Look at ``mesh`` from ``direction`` with z up; ``zoom`` > 1 fills more of the view than the bounding sphere."""
    centre = np.asarray(mesh.center, dtype=float)
    d = np.asarray(direction, dtype=float)
    d /= np.linalg.norm(d)
    plotter.camera_position = [tuple(centre + d * max(mesh.length, 1e-9)), tuple(centre), (0.0, 0.0, 1.0)]
    plotter.reset_camera()
    plotter.camera.zoom(zoom)


def screenshot(mesh, path, *, window_size=(1024, 768), show_edges=False, title=None):
    """Render ``mesh`` offscreen to a PNG file and return the image as an array."""
    configure_offscreen()
    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    plot_mesh(mesh, plotter, show_edges=show_edges)
    if title:
        plotter.add_text(title, font_size=12, color="black")
    set_camera(plotter, mesh)
    image = plotter.screenshot(str(path), return_img=True)
    plotter.close()
    return np.asarray(image)


def export_html(mesh, path, *, show_edges=False):
    """Write an interactive HTML scene (vtk.js via trame) of ``mesh``."""
    configure_offscreen()
    plotter = pv.Plotter(off_screen=True)
    plot_mesh(mesh, plotter, show_edges=show_edges)
    set_camera(plotter, mesh)
    plotter.export_html(str(path))
    plotter.close()


def _as_mesh(obj, curvature, color_map, resolution, n, map_options=None):
    """A curvature mesh for patches, a surface or a mesh (see :func:`show`)."""
    from .. import mesh as _mesh
    from ..model.patches import BezierPatches

    if isinstance(obj, pv.PolyData):
        return obj
    if isinstance(obj, BezierPatches):
        if curvature is not None and color_map is not None:
            obj = obj.copy()
            BezierPatches.visualize_curvature(obj, curvature, color_map, **(map_options or {}))
        return _mesh.patches_mesh(obj, resolution=resolution)
    if hasattr(obj, "derivatives") and hasattr(obj, "domain"):
        return _mesh.surface_mesh(obj, n, n, curvature, color_map, **(map_options or {}))
    raise TypeError(f"show expects BezierPatches, a lab surface or a pyvista.PolyData; got {type(obj).__name__}")


def _add_flat(plotter, mesh, curvature, color_map, map_options, edges):
    """Dill's drawing (``seeds/000``): one colour per polygon (:func:`lab.mesh.color_cells`), one light at the eye."""
    from .. import mesh as _mesh

    if curvature is not None and color_map is not None:
        mesh = _mesh.color_cells(mesh, curvature, color_map, **(map_options or {}))
    elif "RGB" in mesh.point_data:
        mesh = _mesh.color_cells(mesh)
    plotter.remove_all_lights()
    plotter.add_light(pv.Light(light_type="headlight"))
    colors = {"scalars": "RGB", "rgb": True, "preference": "cell"} if "RGB" in mesh.cell_data else {"color": "#d9d9d9"}
    plotter.add_mesh(mesh, show_edges=edges, ambient=0.3, diffuse=0.7, smooth_shading=False, **colors)


def show(obj, curvature=None, color_map=None, *, window_size=(640, 480), edges=False, net=False, title=None,
         resolution=1, n=64, direction=VIEW_DIRECTION, map_options=None, shading="smooth"):
    """A picture of patches, a surface or a mesh for a notebook (an ``IPython.display.Image``, PNG).

    Parameters
    ----------
    obj : BezierPatches, lab surface or pyvista.PolyData
        Patches are shown with the colours their ``visualize_curvature`` stored
        (or, with ``curvature`` and ``color_map``, coloured by the library).
    curvature, color_map : str, optional
        Colour a surface (or patches) by this curvature and map.
    edges : bool
        Draw mesh edges (for patches at resolution 1: the patch borders).
    net : bool
        Draw the control nets of patches.
    map_options : dict, optional
        Options of the colour map, e.g. ``{"vmin": -1, "vmax": 0.5}`` for Dill's bands.
    shading : {"smooth", "flat"}
        ``"flat"`` draws as Dill did (``seeds/000``, "Image generation"): every
        polygon in one colour, that of the mean of its vertices' values, and one
        uniform shade from a single light at the eye (ambient plus Lambert), so
        band edges follow the polygons as in his figures.
    """
    from IPython.display import Image

    if shading not in ("smooth", "flat"):
        raise ValueError(f"shading must be 'smooth' or 'flat'; got {shading!r}")
    configure_offscreen()
    mesh = _as_mesh(obj, curvature, color_map, resolution, n, map_options)
    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    if shading == "flat":
        _add_flat(plotter, mesh, curvature, color_map, map_options, edges)
    elif "RGB" in mesh.point_data or "RGB" in mesh.cell_data:
        plot_mesh(mesh, plotter, show_edges=edges)
    else:
        plotter.add_mesh(mesh, color="#d9d9d9", show_edges=edges, smooth_shading=True)
    if net and hasattr(obj, "control_points"):
        P = np.asarray(obj.control_points)
        P = P[None] if P.ndim == 3 else P
        lines = []
        for net_ in P:
            lines += [pv.lines_from_points(row) for row in net_] + [pv.lines_from_points(col) for col in net_.transpose(1, 0, 2)]
        plotter.add_mesh(pv.merge(lines), color="black", line_width=1)
        plotter.add_points(P.reshape(-1, 3), color="black", point_size=5, render_points_as_spheres=True)
    if title:
        plotter.add_text(title, font_size=11, color="black")
    set_camera(plotter, mesh, direction)
    png = plotter.screenshot(None, return_img=True)
    plotter.close()
    import io

    from PIL import Image as PILImage

    buf = io.BytesIO()
    PILImage.fromarray(np.asarray(png)).save(buf, format="PNG")
    return Image(data=buf.getvalue(), format="png")
