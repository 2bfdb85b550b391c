"""Offscreen pictures and HTML scenes of meshes with curvature colours (PyVista)."""

import os

import numpy as np
import pyvista as pv

__all__ = ["configure_offscreen", "plot_mesh", "set_camera", "screenshot", "export_html", "VIEW_DIRECTION"]


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
    if scalars is None and "RGB" in mesh.point_data:
        return plotter.add_mesh(mesh, scalars="RGB", rgb=True, show_edges=show_edges, smooth_shading=True, **kwargs)
    return plotter.add_mesh(mesh, scalars=scalars, cmap=cmap, show_edges=show_edges, smooth_shading=True, **kwargs)


#: Default viewing direction (from the focal point towards the camera): from the front left, above.
VIEW_DIRECTION = (-1.0, -1.2, 1.6)


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
