"""The curvature explorer's CAD tools: the draft-angle, minimum-radius and scan-deviation maps, curvature combs and a
point probe.

The probe is a (u, v) control (two sliders), not picking: in the browser-rendered view (PyVista's ``client``
backend, vtk.js) a pick happens in the browser and never reaches the kernel, where the exact curvature lives;
the sliders work the same in every backend and in the static picture.

On a model (a part from :func:`lab.read`) the maps colour every face (they need only the mesh's normals and
principal curvatures); the combs and the probe belong to one surface, so they work on the face chosen in the
"face" menu: the combs along its trimming loops and iso-curves cut to it, the probe at (u, v) inside it.
"""

import html

import ipywidgets as W
import numpy as np

from ...i18n import N_, _
from ...interrogation import combs as _combs
from ...interrogation import maps as _maps
from ...interrogation.probe import probe, probe_lines
from .. import legend as _legend
from .. import style
from .base import _dropdown, _layout, style_for
from .controls import float_slider, full_row_text
from .models import default_point, face_label

#: the pull directions offered (label, vector)
PULLS = (("+z", (0.0, 0.0, 1.0)), ("−z", (0.0, 0.0, -1.0)), ("+x", (1.0, 0.0, 0.0)), ("−x", (-1.0, 0.0, 0.0)),
         ("+y", (0.0, 1.0, 0.0)), ("−y", (0.0, -1.0, 0.0)))


def scan_deviation(surface, scan, tolerance, student=False):
    """The :func:`lab.deviation` of a scan given to the curvature explorer (None without one)."""
    if scan is None:
        return None
    if student:
        raise TypeError("a scan's deviation is shown on the library's surface, not with patches_class")
    from ...interrogation.deviation import deviation

    return deviation(scan, surface, tolerance)


class CurvatureTools:
    """Widgets and overlays the :class:`~lab.view.explorers.CurvatureExplorer` shows below its curvature controls.

    ``map`` chooses what colours the surface: ``"curvature"`` (the explorer's measure and map), ``"draft"`` (the
    draft angle against ``pull``, with the parting line) or ``"radius"`` (red where the smallest radius of
    curvature is below ``radius``).  ``combs`` draws curvature combs along the borders and ``comb_count``
    iso-curves in each direction; ``probe`` shows K, H, κ1, κ2, d1, d2 and the Dupin indicatrix at ``(u, v)``.
    """

    def __init__(self, explorer):
        self.e = e = explorer
        self.model = getattr(e, "model", None)
        c = e._control
        self.face = None
        if self.model is not None:  # the combs and the probe work on one face of the model
            self.face = c(W.Dropdown(options=[(face_label(f), f.index) for f in self.model.faces],
                                     value=self.model.faces[0].index, description=_("face"), style=style_for(),
                                     layout=_layout()))
            self.face.add_class("lab-face")
        self.surface = e.source if self.model is None else self.model.face(self.face.value)
        (u0, u1), (v0, v1) = self._uv_box()
        maps = [(_("curvature"), "curvature"), (_("draft angle"), "draft"), (_("radius below r"), "radius")]
        if getattr(e, "deviation", None) is not None:  # a scan was given: its deviation from the part
            maps += [(_("deviation from the scan"), "deviation"), (_("deviation: three bands"), "deviation-bands")]
        self.map = c(_dropdown(maps, "curvature", N_("map")))
        self.pull = c(W.Dropdown(options=[(label, i) for i, (label, _v) in enumerate(PULLS)], value=0,
                                 description=_("pull"), style=style_for(), layout=_layout()))
        self.radius = c(W.BoundedFloatText(value=1.0, min=1e-9, max=1e9, description=_("r"), style=style_for(),
                                           layout=_layout()))
        self.combs = c(W.Checkbox(value=False, description=_("curvature combs"), indent=False,
                                  layout=W.Layout(width="auto")))
        self.comb_scale = c(float_slider(W.FloatLogSlider, _("comb scale"), value=0.05, base=10, min=-4, max=1,
                                         continuous_update=False))
        self.comb_density = c(W.IntSlider(value=32, min=4, max=128, description=_("teeth"), continuous_update=False,
                                          style=style_for(), layout=_layout()))
        self.comb_count = c(W.IntSlider(value=2, min=0, max=8, description=_("iso-curves"), continuous_update=False,
                                        style=style_for(), layout=_layout()))
        self.probe = c(W.Checkbox(value=False, description=_("point probe"), indent=False,
                                  layout=W.Layout(width="auto")))
        self.u = c(float_slider(W.FloatSlider, "u", value=0.5 * (u0 + u1), min=u0, max=u1, step=(u1 - u0) / 200,
                                continuous_update=False))
        self.v = c(float_slider(W.FloatSlider, "v", value=0.5 * (v0 + v1), min=v0, max=v1, step=(v1 - v0) / 200,
                                continuous_update=False))
        self.readout = c(full_row_text())
        self.lines_actor = None
        self.last_probe = None
        self.mark_actor = None
        if self.model is not None:
            self._place_probe()
            self._fit_combs()
            e._observe(self.face, self.choose_face)
        self._show_map_controls()
        for w in (self.map, self.pull, self.radius):
            e._observe(w, self.recolor_map)
        for w in (self.combs, self.comb_scale, self.comb_density, self.comb_count, self.probe, self.u, self.v):
            e._observe(w, self.update_lines)

    def _show_map_controls(self):
        """``pull`` only with the draft angle, ``r`` only with the radius map."""
        self.pull.layout.display = None if self.map.value == "draft" else "none"
        self.radius.layout.display = None if self.map.value == "radius" else "none"

    @property
    def active(self):
        """True when a CAD map (not the curvature) colours the surface."""
        return self.map.value != "curvature"

    def controls(self):
        """The tools' controls, each a cell of the explorer's grid (the probe's readout a full row of it: in one
        column of its own it wrapped word by word)."""
        face = [self.face] if self.face is not None else []
        return [self.map, self.pull, self.radius, *face, self.combs, self.comb_scale, self.comb_density,
                self.comb_count, self.probe, self.u, self.v, self.readout]

    # -- the face of a model --------------------------------------------------------------------

    def _uv_box(self):
        """The (u, v) box the probe's sliders span: the surface's domain, or a face's loops' bounding box."""
        trim = getattr(self.surface, "trim", None)
        if trim is None:
            return self.surface.domain
        X = np.concatenate(trim.loops)
        lo, hi = X.min(axis=0), X.max(axis=0)
        return (float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))

    def _place_probe(self):
        """The sliders span the chosen face; the probe starts at a point inside it."""
        (u0, u1), (v0, v1) = self._uv_box()
        u, v = default_point(self.e._model_meshes.mesh(self.e.depth.value), self.face.value)
        with self.e._quiet():
            for slider, lo, hi, x in ((self.u, u0, u1, u), (self.v, v0, v1, v)):
                slider.min, slider.max = min(lo, slider.min), max(hi, slider.max)  # never min > max on the way
                slider.min, slider.max = lo, hi
                slider.step = (hi - lo) / 200 if hi > lo else 1.0
                slider.value = min(max(x, lo), hi)

    def choose_face(self):
        """Another face for the combs and the probe."""
        self.surface = self.model.face(self.face.value)
        self._place_probe()
        self._fit_combs()
        self.update_lines()

    #: On a face of a part: teeth per border, and the longest tooth as a fraction of the face's size.
    FACE_COMB_DENSITY, FACE_COMB_LENGTH = 16, 0.25

    def _fit_combs(self):
        """The combs on a face of a part: :data:`FACE_COMB_DENSITY` teeth per border (a small fillet had a black
        tangle of 32), scaled so that the longest tooth is :data:`FACE_COMB_LENGTH` of the face's size."""
        found = _combs.border_combs(self.surface, density=self.FACE_COMB_DENSITY, scale=1.0, count=0)
        kn = np.concatenate([np.abs(c.kn[np.isfinite(c.kn)]) for c in found]) if found else np.zeros(0)
        points = np.concatenate([c.points for c in found]) if found else np.zeros((0, 3))
        if not kn.size or kn.max() <= 0 or len(points) < 2:  # a plane: no teeth to scale
            return
        size = float(np.linalg.norm(np.ptp(points, axis=0)))
        scale = float(np.clip(self.FACE_COMB_LENGTH * size / kn.max(), 10.0 ** self.comb_scale.min,
                              10.0 ** self.comb_scale.max))
        with self.e._quiet():
            self.comb_density.value = self.FACE_COMB_DENSITY
            self.comb_scale.value = scale

    # -- maps ---------------------------------------------------------------------------------

    def _pull(self):
        return PULLS[self.pull.value][1]

    def recolor_map(self):
        """Colour the explorer's mesh by the chosen CAD map (or hand back to the curvature colours)."""
        e = self.e
        self.pull.disabled = self.map.value != "draft"
        self.radius.disabled = self.map.value != "radius"
        self._show_map_controls()
        if not self.active:
            e.actor.mapper.SetColorModeToMapScalars()
            e.recolor()
            self.update_lines()
            return
        m = e.mesh.point_data
        if self.map.value.startswith("deviation"):
            coloured = e.deviation.map(e.mesh, self._deviation_map())
            m["cad"], m["RGB"] = coloured.point_data["deviation"], coloured.point_data["RGB"]
        elif self.map.value == "draft":
            m["cad"] = _maps.draft_angle(np.nan_to_num(np.asarray(m["N"], dtype=float)), self._pull())
            m["RGB"] = _maps.draft_colors(m["cad"])
        else:
            m["cad"] = _maps.min_radius(m["k1"], m["k2"])
            m["RGB"] = _maps.radius_colors(_maps.below_radius(m["k1"], m["k2"], self.radius.value))
        e.actor.mapper.SetScalarModeToUsePointFieldData()
        e.actor.mapper.SelectColorArray("RGB")
        e.mesh.point_data.active_scalars_name = "RGB"
        e.actor.mapper.SetColorModeToDirectScalars()
        e.actor.mapper.ScalarVisibilityOn()
        self.update_lines()

    def _deviation_map(self):
        return "bands" if self.map.value == "deviation-bands" else "graded"

    def title(self, resolution):
        """The picture's title while a CAD map colours the surface (``resolution``: "depth 2", "16 lines per face")."""
        if self.map.value.startswith("deviation"):
            lo, hi = (_legend._minus(f"{x:.3g}") for x in self.e.deviation.tolerance)
            return _("deviation from the scan, tolerance {lo} … {hi}, {resolution}").format(
                lo=lo, hi=hi, resolution=resolution)
        if self.map.value == "draft":
            return _("draft angle, pull {pull}, {resolution}").format(pull=PULLS[self.pull.value][0],
                                                                     resolution=resolution)
        return _("radius of curvature below {r}, {resolution}").format(
            r=_legend.decimal(f"{self.radius.value:g}"), resolution=resolution)

    def legend(self):
        if self.map.value.startswith("deviation"):
            d = self.e.deviation
            top = float(np.max(np.abs(d.distance))) if len(d.distance) else None
            unscanned = bool(np.isnan(np.asarray(self.e.mesh.point_data["cad"], dtype=float)).any())
            return _legend.deviation_legend(d.tolerance, self._deviation_map(), top, unscanned=unscanned)
        return _legend.draft_legend() if self.map.value == "draft" else _legend.radius_legend(self.radius.value)

    # -- lines: parting line, combs, probe ---------------------------------------------------------

    def lines(self):
        """The overlay lines now shown (pyvista.PolyData or None)."""
        parts = []
        if self.map.value == "draft":
            mesh = self.e.mesh.copy()
            mesh.point_data["draft"] = np.asarray(mesh.point_data["cad"], dtype=float)
            parts.append(_maps.parting_line(mesh))
        if self.combs.value:
            found = _combs.border_combs(self.surface, density=self.comb_density.value, scale=self.comb_scale.value,
                                        count=self.comb_count.value)
            parts.append(_combs.comb_lines(found))
        self.last_probe = None
        if self.probe.value:
            self.last_probe = probe(self.surface, self.u.value, self.v.value)
            parts.append(probe_lines(self.last_probe))
        parts = [p for p in parts if p.n_points]
        if not parts:
            return None
        return parts[0] if len(parts) == 1 else parts[0].merge(parts[1:])

    def update_lines(self):
        e = self.e
        if self.lines_actor is not None:
            e.plotter.remove_actor(self.lines_actor)
            self.lines_actor = None
        lines = self.lines()
        if lines is not None:
            self.lines_actor = style.add_lines_on_surface(e.plotter, lines, pickable=False)
        if self.mark_actor is not None:
            e.plotter.remove_actor(self.mark_actor)
            self.mark_actor = None
        if self.last_probe is not None and np.all(np.isfinite(self.last_probe.point)):
            # the probed point as a red dot of 16 pixels at any zoom (a ball in space was lost on a small face),
            # drawn in front of the surface it lies on
            self.mark_actor = e.plotter.add_points(np.asarray(self.last_probe.point, dtype=float).reshape(1, 3),
                                                   color="#d7191c", point_size=16, render_points_as_spheres=True,
                                                   pickable=False, reset_camera=False)
            self.mark_actor.mapper.SetResolveCoincidentTopologyToPolygonOffset()
            self.mark_actor.mapper.SetRelativeCoincidentTopologyPointOffsetParameter(style.LINE_OFFSET_UNITS)
        self.readout.value = self._probe_text()
        e.refresh()

    def _probe_text(self):
        p = self.last_probe
        if p is None:
            return ""
        def num(x):
            return _legend.format_values([x], spacing=abs(x) * 1e-3 or 1e-6)[0]
        rows = [("K", p.K), ("H", p.H), ("κ1", p.k1), ("κ2", p.k2)]
        text = ", ".join(f"{name} = {num(value)}" for name, value in rows)
        if p.umbilic:
            text += "; " + _("umbilic: every direction is principal")
        else:
            text += "; " + _("d1, d2: the lines through the point; the conics: Dupin's indicatrix")
        return f"<small>{html.escape(text)}</small>"
