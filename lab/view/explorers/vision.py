"""See it as a colour-blind student does: every explorer's scene and legend as simulated for a colour-vision deficiency.

The "colour vision" control of every explorer (:class:`lab.view.explorers.base.Explorer`) simulates protanopia,
deuteranopia or tritanopia (Machado, Oliveira & Fernandes 2009, :func:`lab.vision.simulate`) where the colours
are made, not on a picture of them, so that the live view (drawn by the browser) shows it too: the lookup table of
every actor coloured through one, the colour arrays of actors with direct colours (a student's own
``visualize_curvature``, stripes, the draft map, the edges), the plain colour of the others (the control net,
the geodesics), and the CSS colours of the legend below the view.  The originals are kept: whatever the explorer
recolours afterwards is simulated again at the next refresh, and "normal" restores them.
"""

import re

import ipywidgets as W
import numpy as np
import pyvista as pv
from vtkmodules.util.numpy_support import vtk_to_numpy

from ...geometry import vision
from ...i18n import N_, _
from .controls import _dropdown

__all__ = ["SceneVision", "simulate_css", "vision_control"]

#: The control's choices: label -> deficiency ("normal": none).
CHOICES = {N_("normal"): "normal", N_("protanopia"): "protanopia", N_("deuteranopia"): "deuteranopia",
           N_("tritanopia"): "tritanopia"}
#: Suffix of the simulated copy of a colour array.
SUFFIX = "_cvd"
#: VTK's scalar modes that colour by cell data (VTK_SCALAR_MODE_USE_CELL_DATA, ..._USE_CELL_FIELD_DATA).
_CELL_MODES = (2, 4)


def vision_control():
    """The dropdown "colour vision": normal, protanopia, deuteranopia, tritanopia (simulated)."""
    control = _dropdown(list(CHOICES.items()), "normal", N_("colour vision"))
    control.tooltip = _("the view as a student with this colour-vision deficiency sees it (simulated after "
                        "Machado et al. 2009)")
    control.add_class("lab-vision")
    return control


def deficiency(control):
    """The deficiency a control chooses, or None for normal vision."""
    value = control.value if isinstance(control, W.Widget) else control
    return None if value in (None, "normal") else value


_CSS = re.compile(r"#[0-9a-fA-F]{6}\b|rgb\(\s*\d+\s*,\s*\d+\s*,\s*\d+\s*\)")


def _parse(text):
    if text.startswith("#"):
        return [int(text[k:k + 2], 16) for k in (1, 3, 5)]
    return [int(x) for x in re.findall(r"\d+", text)]


def simulate_css(html, deficiency_):
    """``html`` with every CSS colour (``#rrggbb``, ``rgb(r,g,b)``) as seen with ``deficiency_`` (None: as it is)."""
    if vision.check_deficiency(deficiency_) is None or not html:
        return html
    found = sorted(set(_CSS.findall(html)))
    if not found:
        return html
    seen = vision.simulate(np.array([_parse(c) for c in found]) / 255.0, deficiency_)
    table = {c: "rgb({},{},{})".format(*(round(255 * x) for x in s)) for c, s in zip(found, seen)}
    return _CSS.sub(lambda m: table[m.group(0)], html)


def _input(mapper):
    """The dataset a mapper draws (wrapped by PyVista), or None."""
    data = mapper.GetInputDataObject(0, 0) if mapper.GetNumberOfInputPorts() else None
    return pv.wrap(data) if data is not None and hasattr(data, "GetPointData") else None


class SceneVision:
    """The simulated colours of a plotter's actors, with the originals to go back to."""

    def __init__(self):
        self._tables = {}  # id(lookup table) -> (original, simulated) RGBA uint8
        self._props = {}  # id(actor) -> (original, simulated) RGB float
        self._arrays = {}  # id(actor) -> (array name, fingerprint of the original)

    def apply(self, plotter, deficiency_):
        """Simulate ``deficiency_`` on every actor of ``plotter`` (None: restore the original colours)."""
        for actor in list(plotter.renderer.actors.values()):
            mapper = actor.GetMapper() if hasattr(actor, "GetMapper") else None
            if mapper is None:
                continue
            direct = self._direct_array(mapper)
            if direct is not None:
                self._array(actor, mapper, direct, deficiency_)
            elif mapper.GetScalarVisibility() and mapper.GetLookupTable() is not None and self._has_scalars(mapper):
                self._table(mapper.GetLookupTable(), deficiency_)
            self._prop(actor, deficiency_)

    @staticmethod
    def _has_scalars(mapper):
        data = _input(mapper)
        return data is not None and bool(data.point_data.keys() or data.cell_data.keys())

    @staticmethod
    def _direct_array(mapper):
        """``(data, name)`` of the colours an actor shows directly (RGB uint8, or colour mode direct), or None."""
        data = _input(mapper)
        if not mapper.GetScalarVisibility() or data is None:
            return None
        attrs = data.cell_data if mapper.GetScalarMode() in _CELL_MODES else data.point_data
        name = mapper.GetArrayName() or (attrs.active_scalars_name or "")
        source = name.removesuffix(SUFFIX)
        if source not in attrs:
            return None
        array = np.asarray(attrs[source])
        direct = mapper.GetColorMode() == 2 or (array.dtype == np.uint8 and array.ndim == 2 and array.shape[1] in (3, 4))
        return (attrs, source) if direct and array.ndim == 2 and array.shape[1] in (3, 4) else None

    def _array(self, actor, mapper, found, deficiency_):
        attrs, source = found
        array = np.asarray(attrs[source])
        if deficiency_ is None:
            if mapper.GetArrayName() != source:
                mapper.SelectColorArray(source)
            if source + SUFFIX in attrs:
                attrs.remove(source + SUFFIX)
            self._arrays.pop(id(actor), None)
            return
        key = (source, deficiency_, array.shape, hash(array.tobytes()))
        if self._arrays.get(id(actor)) == key and source + SUFFIX in attrs and mapper.GetArrayName() == source + SUFFIX:
            return
        scale = 255.0 if array.dtype == np.uint8 else 1.0
        rgb = np.clip(array[:, :3] / scale, 0.0, 1.0)
        seen = vision.simulate(np.nan_to_num(rgb, nan=0.5), deficiency_) * scale
        out = array.copy()
        out[:, :3] = np.rint(seen).astype(array.dtype) if array.dtype == np.uint8 else seen
        attrs[source + SUFFIX] = out
        mapper.SelectColorArray(source + SUFFIX)
        self._arrays[id(actor)] = key

    def _table(self, lut, deficiency_):
        table = vtk_to_numpy(lut.GetTable())  # a view of the table's RGBA bytes
        old = self._tables.get(id(lut))
        if old is not None and np.array_equal(table, old[1]):
            if deficiency_ is None:
                table[:] = old[0]
                lut.Modified()
                del self._tables[id(lut)]
            elif old[2] != deficiency_:
                self._write(lut, table, old[0], deficiency_)
            return
        if deficiency_ is not None:  # a table the explorer made or changed since: its colours are the originals now
            self._write(lut, table, table.copy(), deficiency_)
        else:
            self._tables.pop(id(lut), None)

    def _write(self, lut, table, original, deficiency_):
        seen = original.copy()
        seen[:, :3] = np.rint(vision.simulate(original[:, :3] / 255.0, deficiency_) * 255).astype(np.uint8)
        table[:] = seen
        lut.Modified()
        self._tables[id(lut)] = (original, seen.copy(), deficiency_)

    def _prop(self, actor, deficiency_):
        prop = actor.GetProperty() if hasattr(actor, "GetProperty") else None
        if prop is None or not hasattr(prop, "GetColor"):
            return
        now = tuple(prop.GetColor())
        old = self._props.get(id(actor))
        if old is not None and np.allclose(now, old[1]):
            if deficiency_ is None:
                prop.SetColor(*old[0])
                del self._props[id(actor)]
                return
            original = old[0]
        else:
            original = now
        if deficiency_ is None:
            self._props.pop(id(actor), None)
            return
        seen = tuple(float(x) for x in vision.simulate(np.array(original), deficiency_))
        prop.SetColor(*seen)
        self._props[id(actor)] = (original, seen)
