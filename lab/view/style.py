"""One picture style for the whole lab: ``render.show``, the CLI, the gallery and the explorers' first frame.

* **Camera**: fitted to the surface from an oblique view.  Unless an azimuth
  and elevation are given, the view direction is chosen among a fixed set of
  oblique directions (elevation 20° to 65° above the xy-plane, azimuth in
  steps of 30°) as the one in which the surface faces the camera most
  squarely and fills most of the picture (nearest 50° elevation when several
  come within 5%), so a graph surface is seen as a landscape from above and a
  closed surface from a slant, never edge-on.  Then the camera is moved so that the projected surface fills the
  frame up to a margin (perspective, a few fixed-point steps on the projected
  bounding box).
* **Light**: three camera lights (key from the upper left, fill from the right,
  a weak back light) and a high ambient part, so that shading shows the shape
  but never darkens a flank: the colour is the data (every visible face keeps
  at least ~65% of its colour's brightness, facing faces ~100%).
* **Frame**: white background, a title on top, the colour bar or class legend
  (:mod:`lab.view.legend`) at the right, padding all round; drawn with
  matplotlib around the offscreen 3D image, which is placed pixel for pixel.

Everything is deterministic: the same mesh and options give the same picture.
"""

import math

import numpy as np
import pyvista as pv

from ..geometry import validation as _v

__all__ = ["SURFACE_PROPERTIES", "Frame", "apply_lights", "bar_box", "compose", "fit_camera", "layout", "view_direction"]

#: Material of coloured surfaces: mostly ambient and diffuse, a hint of specular.
SURFACE_PROPERTIES = {"ambient": 0.5, "diffuse": 0.5, "specular": 0.08, "specular_power": 30.0}

# Camera lights: positions in the camera's frame (camera at (0, 0, 1) looking at the origin, y up).
_LIGHTS = (
    ((-0.6, 0.6, 1.0), 0.70),   # key: upper left, in front
    ((0.7, -0.45, 1.0), 0.50),  # fill: lower right, in front
    ((0.0, 0.8, -0.6), 0.30),   # back: above, behind (rims)
)

#: Candidate view directions (azimuth, elevation in degrees) for the automatic camera, in order of preference.
_CANDIDATES = tuple((az, el) for el in (35, 50, 20, 65) for az in (-60, -30, -90, -120, -150, 180, 150, 120, 90, 60, 30, 0))
DEFAULT_VIEW = (-60.0, 35.0)
PREFERRED_ELEVATION = 50.0


#: Depth offset (VTK's coincident-topology units) of lines drawn on a surface.  Without one most of a line hides
#: in the surface's depth buffer; too much of one draws lines from behind a closed part through it (-66000, the
#: old value, showed the teapot's far side through its body).  Measured on the hood's 12 reflection lines (dark
#: pixels: 650 without, 4279 from -500 to -66000) and the teapot's 16 (no lines from behind down to -1500).
LINE_OFFSET_UNITS = -1000


def offset_lines(actor):
    """Draw a line actor in front of the surface it lies on (:data:`LINE_OFFSET_UNITS`)."""
    actor.mapper.SetResolveCoincidentTopologyToPolygonOffset()
    actor.mapper.SetRelativeCoincidentTopologyLineOffsetParameters(0, LINE_OFFSET_UNITS)
    return actor


def add_lines_on_surface(plotter, lines, **options):
    """Add polylines lying on a surface (reflection lines, isophotes) in black, drawn in front of it.

    Without a depth offset most of each line would hide in the surface's depth buffer.  Returns the actor.
    """
    return offset_lines(plotter.add_mesh(lines, color="black", line_width=2.5, scalars=None, **options))


def apply_lights(plotter):
    """Replace the plotter's lights by the lab's three camera lights."""
    plotter.remove_all_lights()
    for position, intensity in _LIGHTS:
        light = pv.Light(position=position, focal_point=(0.0, 0.0, 0.0), color="white", intensity=intensity,
                         light_type="camera light")
        plotter.add_light(light)


def _direction(azimuth, elevation):
    a = math.radians(_v.as_number(azimuth, "azimuth"))
    e = math.radians(_v.as_number(elevation, "elevation", minimum=-90, maximum=90))
    return np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])


def _triangles(mesh, limit=20000):
    """Triangle corner points of ``mesh`` (a sample of at most ``limit`` triangles), shape (t, 3, 3)."""
    tri = mesh if mesh.is_all_triangles else mesh.triangulate()
    faces = np.asarray(tri.faces).reshape(-1, 4)[:, 1:] if tri.n_cells else np.zeros((0, 3), int)
    if len(faces) > limit:
        faces = faces[:: math.ceil(len(faces) / limit)]
    return np.asarray(tri.points)[faces]


def _fill(T, d, aspect):
    """Fraction of a viewport of ``aspect`` that the triangles ``T`` cover when seen along ``d`` and fitted
    (orthographic estimate: projected area over the area of the fitted viewport; overlaps count twice)."""
    up = np.array([0.0, 0.0, 1.0]) if abs(d[2]) < 0.98 else np.array([0.0, 1.0, 0.0])
    right = np.cross(up, d)
    right /= np.linalg.norm(right)
    P = T @ np.stack([right, np.cross(d, right)], axis=1)  # (t, 3, 2) screen coordinates
    a, b = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    area = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum()
    w, h = np.ptp(P.reshape(-1, 2), axis=0)
    if not (w > 0 and h > 0):
        return 0.0
    scale = min(aspect / w, 1.0 / h)
    return float(area * scale**2 / aspect)


def view_direction(mesh, azimuth=None, elevation=None, aspect=4 / 3):
    """The unit vector from the surface towards the camera.

    With ``azimuth`` and ``elevation`` (degrees; azimuth around z from +x,
    elevation above the xy-plane) that direction; a missing one is chosen among
    oblique views (elevation 20° to 65°): the one that maximises how squarely
    the surface faces the camera (area-weighted mean of |N·d|; 0 is edge-on)
    times how much of a viewport of ``aspect`` it fills; among views within 5%
    of the best, the one nearest 50° elevation, then the earlier candidate.
    """
    if azimuth is not None and elevation is not None:
        return _direction(azimuth, elevation)
    T = _triangles(mesh)
    if len(T) == 0:
        return _direction(*DEFAULT_VIEW)
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])  # 2 x area x unit normal
    total = float(np.linalg.norm(n, axis=1).sum()) or 1.0
    scores = {}
    for az, el in _CANDIDATES:
        if azimuth is not None and not math.isclose((az - azimuth) % 360, 0.0, abs_tol=1e-9):
            continue
        if elevation is not None and el != elevation:
            continue
        d = _direction(az, el)
        facing = float(np.abs(n @ d).sum()) / total  # 1: the surface faces the camera, 0: edge-on
        scores[(az, el)] = facing * _fill(T, d, aspect)
    if not scores:  # only one of the two given and not among the candidates
        best = (DEFAULT_VIEW[0] if azimuth is None else azimuth, DEFAULT_VIEW[1] if elevation is None else elevation)
        return _direction(*best)
    top = max(scores.values())
    if not top > 0:  # a surface of zero area (one point): every view is as good, the default one
        return _direction(*DEFAULT_VIEW)
    good = [c for c in scores if scores[c] >= 0.95 * top]
    best = min(good, key=lambda c: (abs(c[1] - PREFERRED_ELEVATION), -round(scores[c] / top, 2), _CANDIDATES.index(c)))
    return _direction(*best)


def fit_camera(plotter, mesh, direction=None, *, azimuth=None, elevation=None, margin=0.03, view_angle=30.0):
    """Point the camera at ``mesh`` from ``direction`` (or azimuth/elevation, or the automatic choice).

    The projected surface is centred and fills the viewport up to ``margin``
    (a fraction of the viewport on each side), z up on the screen.
    """
    width, height = plotter.window_size
    aspect = width / max(height, 1)
    d = view_direction(mesh, azimuth, elevation, aspect) if direction is None else np.asarray(direction, float)
    d = d / np.linalg.norm(d)
    up = np.array([0.0, 0.0, 1.0]) if abs(d[2]) < 0.98 else np.array([0.0, 1.0, 0.0])
    centre = np.asarray(mesh.center, dtype=float)
    size = max(float(mesh.length), 1e-9)
    camera = plotter.camera
    camera.view_angle = view_angle
    distance = size / (2 * math.tan(math.radians(view_angle) / 2))
    camera.position = tuple(centre + d * distance)
    camera.focal_point = tuple(centre)
    camera.up = tuple(up)
    points = np.asarray(mesh.points, dtype=float)
    if len(points) > 20000:
        points = points[:: math.ceil(len(points) / 20000)]
    renderer = plotter.renderer
    for _ in range(4):
        renderer.ResetCameraClippingRange()
        m = np.array([[camera.GetCompositeProjectionTransformMatrix(aspect, -1, 1).GetElement(i, j)
                       for j in range(4)] for i in range(4)])
        h = np.c_[points, np.ones(len(points))] @ m.T
        ndc = h[:, :2] / h[:, 3:4]
        lo, hi = ndc.min(axis=0), ndc.max(axis=0)
        # pan: move the focal point so the projected box is centred
        mid = (lo + hi) / 2
        pos, foc = np.array(camera.position), np.array(camera.focal_point)
        forward = (foc - pos) / np.linalg.norm(foc - pos)
        right = np.cross(forward, up)
        right /= np.linalg.norm(right)
        true_up = np.cross(right, forward)
        dist = np.linalg.norm(foc - pos)
        half_h = dist * math.tan(math.radians(camera.view_angle) / 2)
        shift = right * mid[0] * half_h * aspect + true_up * mid[1] * half_h
        # zoom: scale the distance so the larger relative extent fills 1 - 2 margin
        extent = max((hi[0] - lo[0]) / 2, (hi[1] - lo[1]) / 2)
        scale = extent / (1 - 2 * margin) if extent > 0 else 1.0
        foc = foc + shift
        pos = foc - forward * dist * scale
        camera.focal_point = tuple(foc)
        camera.position = tuple(pos)
    renderer.ResetCameraClippingRange()
    return d


# ------------------------------------------------------------------------- the frame around the 3D image


def _text_width(text, font_pt):
    """Rough width in pixels of ``text`` at ``font_pt`` points (100 dpi, DejaVu Sans averages ~0.6 em)."""
    return 0.6 * font_pt * 100 / 72 * len(text)


def _title_lines(legend):
    """The legend's title as (first line, second line): the name, then symbol and unit."""
    name, _, unit = legend.title.rpartition("  ")
    words = name.split(" ")
    if len(words) > 1 and len(words[-1]) <= 10:  # the symbol goes to the unit's line
        return " ".join(words[:-1]), f"{words[-1]} {unit}".strip()
    return name, unit


class Frame:
    """Where the parts of a picture go, in pixels: 3D view, title band and legend band (x, y, w, h from top left)."""

    def __init__(self, size, title, legend):
        W, H = (int(x) for x in size)
        self.size = (W, H)
        self.font = max(8.0, 12.5 * min(W / 1024, H / 768) ** 0.7)
        px = self.font * 100 / 72
        pad = round(0.02 * min(W, H)) + 2
        lines = title.count("\n") + 1 if title else 0  # a long caption wrapped: each more line 1.9 font high
        title_h = round(self.font * (2.6 + 1.9 * (lines - 1))) if title else 0
        if legend is None:
            legend_w = 0
        else:
            first, second = _title_lines(legend)
            heading = max(_text_width(first, self.font), _text_width(second, self.font))
            if legend.is_bar:
                labels = max((_text_width(label, self.font) for _, label in legend.ticks), default=0.0)
                body = 2.6 * px + labels
            else:
                body = 2.2 * px + max(_text_width(label, self.font) for label, _ in legend.classes)
            legend_w = round(min(max(heading, body) + 1.5 * px, 0.45 * W))
        self.pad = pad
        self.title = (pad, pad, W - 2 * pad, title_h)
        self.view = (pad, pad + title_h, W - 2 * pad - legend_w, H - 2 * pad - title_h)
        self.legend = (W - pad - legend_w, pad + title_h, legend_w, H - 2 * pad - title_h)


def bar_box(frame):
    """Where the colour bar goes in a frame with a bar legend: (x, y, width, height) in pixels from the top left."""
    lx, ly, _lw, lh = frame.legend
    px = frame.font * 100 / 72
    bar_h = 0.6 * lh
    return lx + 0.6 * px, ly + (lh - bar_h) / 2 + px, 1.1 * px, bar_h


def layout(size, title=None, legend=None):
    """The :class:`Frame` of a picture of ``size`` (width, height) with an optional title and legend."""
    return Frame(size, title, legend)


def compose(image, frame, *, title=None, legend=None):
    """Put the 3D ``image`` (sized ``frame.view``) into the frame with title and legend; returns RGB uint8."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    W, H = frame.size
    dpi = 100
    fig = Figure(figsize=(W / dpi, H / dpi), dpi=dpi, facecolor="white")
    canvas = FigureCanvasAgg(fig)
    x, y, _w, _h = frame.view
    img = np.asarray(image)[..., :3]
    fig.figimage(img, xo=x, yo=H - y - img.shape[0], origin="upper", zorder=0)
    fs = frame.font
    if title:
        _tx, ty, _tw, th = frame.title
        fig.text(0.5, 1 - (ty + th * 0.5) / H, title, ha="center", va="center", fontsize=fs * 1.25, color="#1f2328")
    if legend is not None:
        lx, ly, lw, lh = frame.legend
        px = fs * 100 / 72
        first, second = _title_lines(legend)
        if legend.is_bar:
            bx, by, bar_w, bar_h = bar_box(frame)
            fig.text((bx) / W, 1 - (by - 2.3 * px) / H, first, ha="left", va="bottom", fontsize=fs, color="#1f2328")
            fig.text((bx) / W, 1 - (by - 0.8 * px) / H, second, ha="left", va="bottom", fontsize=fs, color="#1f2328")
            cax = fig.add_axes([bx / W, 1 - (by + bar_h) / H, bar_w / W, bar_h / H])
            colours = legend.colors(512)[:, None, :]
            cax.imshow(colours, aspect="auto", origin="lower", extent=(0, 1, 0, 1), interpolation="nearest")
            cax.set_xticks([])
            cax.yaxis.tick_right()
            cax.set_yticks([p for p, _ in legend.ticks], [label for _, label in legend.ticks], fontsize=fs)
            cax.tick_params(axis="y", length=3, pad=2, colors="#1f2328")
            cax.set_ylim(0, 1)
            for spine in cax.spines.values():
                spine.set_color("#555555")
            if legend.note:
                import textwrap

                width = max(12, int(lw / (0.6 * 0.8 * px)))
                fig.text(bx / W, 1 - (by + bar_h + 0.8 * px) / H, textwrap.fill(legend.note, width), ha="left",
                         va="top", fontsize=fs * 0.8, color="#57606a", linespacing=1.2)
        else:
            n = len(legend.classes)
            row = 1.9 * px
            top = ly + (lh - n * row) / 2
            x0 = lx + 0.5 * px
            fig.text(x0 / W, 1 - (top - 2.0 * px) / H, first, ha="left", va="center", fontsize=fs, color="#1f2328")
            fig.text(x0 / W, 1 - (top - 0.8 * px) / H, second, ha="left", va="center", fontsize=fs, color="#1f2328")
            for k, (label, colour) in enumerate(legend.classes):
                cy = top + (k + 0.5) * row
                fig.patches.append(Rectangle((x0 / W, 1 - (cy + 0.5 * px) / H), px / W, px / H,
                                             transform=fig.transFigure, facecolor=colour, edgecolor="#555555",
                                             linewidth=0.8))
                fig.text((x0 + 1.6 * px) / W, 1 - cy / H, label, ha="left", va="center", fontsize=fs, color="#1f2328")
            if legend.note:  # wrapped to the picture's right edge (one line stays where it always was)
                import textwrap

                lines = textwrap.wrap(legend.note, max(12, int((W - x0) / (0.6 * 0.8 * px))))
                y = top + (n + 0.5) * row - (0.5 * 0.8 * px if len(lines) > 1 else 0.0)
                fig.text(x0 / W, 1 - y / H, "\n".join(lines), ha="left", va="top" if len(lines) > 1 else "center",
                         fontsize=fs * 0.8, color="#57606a", linespacing=1.2)
    canvas.draw()
    out = np.asarray(canvas.buffer_rgba())[..., :3].copy()
    return out


def add_marks(plotter, points, height, ring=15, dot=8):
    """Points as white dots in black rings (seen on every colour of every map), after the camera is set: the dots are
    moved towards the eye by a ring's radius so that they lie in front of their own ring, yet behind the surface
    where the point is on its far side."""
    points = np.asarray(points, dtype=float)
    if points.size and (points.ndim not in (1, 2) or points.shape[-1] != 3 or not np.all(np.isfinite(points))):
        raise ValueError(f"marks must be finite points of shape (n, 3); got shape {points.shape}")
    if not points.size:
        return
    points = points.reshape(-1, 3)
    cam = plotter.camera
    eye = np.asarray(cam.position, dtype=float)
    towards = eye - points
    distance = np.linalg.norm(towards, axis=1, keepdims=True)
    if cam.parallel_projection:
        pixel = 2.0 * cam.parallel_scale / height
    else:
        pixel = distance * 2.0 * np.tan(np.radians(cam.view_angle) / 2) / height
    for colour, size, shift in (("black", ring, 0.0), ("white", dot, ring / 2)):
        actor = plotter.add_points(points + towards / distance * pixel * shift, color=colour, point_size=size,
                                   render_points_as_spheres=True, lighting=False, reset_camera=False)
        actor.mapper.SetResolveCoincidentTopologyToPolygonOffset()
        actor.mapper.SetRelativeCoincidentTopologyPointOffsetParameter(LINE_OFFSET_UNITS)
