"""A real part: faces (a NURBS surface each, its trimming loops, its orientation) and the edges two faces share.

:func:`lab.read` builds a :class:`Model` from a STEP, IGES, BREP, geomview or
Rhino file.  Nothing here needs OpenCASCADE: a model is plain arrays and lab
surfaces, so it can be meshed, interrogated and pickled without ``OCP``.
"""

import os
from typing import NamedTuple

import numpy as np

from ...i18n import N_, _
from ...model.surface import CLASS_NAMES
from .orientation import flip

__all__ = ["Edge", "Face", "Model", "Problem"]


class Problem(NamedTuple):
    """A face of the file that the lab could not take over (``index`` in the file's face order)."""

    index: int
    kind: str
    reason: str

    def __str__(self):
        return f"face {self.index} ({self.kind}): {self.reason}"


class Edge(NamedTuple):
    """An edge of the file shared by two faces, sampled at the same curve parameters ``t`` on both.

    ``faces`` : (i, j), indices in the file's face order (``i == j`` for a seam of one face).
    ``points`` : (k, 3) ndarray, the 3-D edge curve at ``t``.
    ``uv`` : ((k, 2) ndarray, (k, 2) ndarray), the edge's pcurve on each face at ``t``
    (in that face's parameters), so that both surfaces can be evaluated along the edge.
    ``t`` : (k,) ndarray, parameters of the 3-D edge curve.
    ``tangents`` : (k, 3) ndarray or None, the 3-D edge curve's derivative at ``t`` (exact, from the file's curve).
    ``tolerance`` : float or None, the file's tolerance of the edge (``BRep_Tool.Tolerance``): how far the
    faces' surfaces at ``uv`` may lie from ``points``.
    ``reversed`` : (bool, bool) or None, the two faces' orientations in the shell the edge was found in: the
    faces' own (``Face.reversed``) unless the faces were sewn, where sewing orients the faces of a shell
    consistently (an IGES file's faces carry no orientation of their own; :func:`lab.continuity` uses these).
    """

    index: int
    faces: tuple
    points: np.ndarray
    uv: tuple
    t: np.ndarray
    tangents: object = None
    tolerance: object = None
    reversed: object = None


class Face:
    """One face of a model: its surface in the file's parameters, its trimming loops and its orientation.

    Attributes
    ----------
    index : int
        Position in the file's face order (``TopExp_Explorer`` over faces).
    kind : str
        What the file stores: ``"BSplineSurface"``, ``"Plane"``, ``"Cylinder"``, ``"Cone"``, ``"Sphere"``,
        ``"Torus"``, ``"SurfaceOfRevolution"``, ``"SurfaceOfExtrusion"``, ``"OffsetSurface"``, ``"BezierSurface"``.
    surface : lab.BSplineSurface or lab.BezierSurface
        The face's surface as NURBS: B-spline faces keep the file's poles, knots, weights and parameters;
        analytic faces are OpenCASCADE's exact NURBS form (``GeomConvert``), which runs in its own
        parameters (a circle's angle becomes a rational parameter).
    file_surface : lab.Surface
        The same surface in the file's parameters: ``surface`` itself where the parameters agree, else a
        :class:`lab.ReparametrizedSurface` over it (exact maps per direction, ``maps``).  :meth:`curvature`,
        :meth:`evaluate`, :attr:`trim`, ``model.edges[i].uv`` and meshes use it.
    maps : (ParameterMap, ParameterMap) or None
        The maps from the file's u and v to the NURBS's (None: the identity).
    trim : lab.trimming.TrimmedSurface or None
        The face's loops, outer first, in the file's (u, v) (on :attr:`file_surface`); ``None`` for an
        untrimmed patch.
    reversed : bool
        The face's normal is ``-(x_u x x_v)`` (``TopAbs_REVERSED``): :meth:`curvature` flips H, k1, k2.
    domain : ((float, float), (float, float))
        The file's (u, v) bounds of the face (``BRepTools.UVBounds_s``, within the surface's domain).
    exact : bool
        False where the NURBS is an approximation (an offset of a B-spline surface): ``deviation`` says
        how far it lies from the file's surface at 25 sample points (in the file's length unit).
    """

    def __init__(self, index, kind, surface, trim=None, reversed=False, name=None, *, file_surface=None,
                 domain=None, maps=None, exact=True, deviation=0.0):
        self.index = int(index)
        self.kind = str(kind)
        self.surface = surface
        self.file_surface = surface if file_surface is None else file_surface
        self.maps = maps
        self.trim = trim
        self.reversed = bool(reversed)
        self.name = name
        self._domain = None if domain is None else tuple(tuple(float(x) for x in pair) for pair in domain)
        self.exact = bool(exact)
        self.deviation = float(deviation)

    @property
    def domain(self):
        """The file's (u, v) bounds of the face ``((u0, u1), (v0, v1))`` (the surface's domain if not given)."""
        return self.file_surface.domain if self._domain is None else self._domain

    def evaluate(self, u, v):
        """Points of the face's surface at the file's ``(u, v)``, shape ``broadcast(u, v).shape + (3,)``."""
        return self.file_surface.evaluate(u, v)

    def derivatives(self, u, v):
        """Point and partial derivatives ``b, bu, bv, buu, buv, bvv`` with respect to the file's ``(u, v)``."""
        return self.file_surface.derivatives(u, v)

    def curvature(self, u, v, *, directions=False):
        """K, H, k1, k2 (k1 >= k2) and ``degenerate`` at the file's ``(u, v)`` with the face's normal.

        On a reversed face the normal is ``-(x_u x x_v)``: K stays, H changes sign and the principal
        curvatures change sign and order (with ``directions=True`` also ``d1`` and ``d2``, see
        :meth:`lab.Surface.curvature`).
        """
        c = self.file_surface.curvature(u, v, directions=directions)
        return flip(c) if self.reversed else c

    def normal(self, u, v):
        """The face's unit normal at the file's ``(u, v)`` (``-(x_u x x_v)/|x_u x x_v|`` on a reversed face)."""
        N = self.file_surface.normal(u, v)
        return -N if self.reversed else N

    def __repr__(self):
        side = ", reversed" if self.reversed else ""
        trim = "" if self.trim is None else f", {len(self.trim.loops)} loops"
        approx = "" if self.exact else f", approximate ({self.deviation:.2g})"
        return f"Face({self.index}, {self.kind}, {self.surface!r}{trim}{side}{approx})"


#: What a file stores (:attr:`Face.kind`, OpenCASCADE's type names) as people read it, in the lab's language.
KIND_NAMES = {"Plane": N_("plane"), "Cylinder": N_("cylinder"), "Cone": N_("cone"), "Sphere": N_("sphere"),
              "Torus": N_("torus"), "BezierSurface": CLASS_NAMES["BezierSurface"],
              "BSplineSurface": CLASS_NAMES["BSplineSurface"],
              "SurfaceOfRevolution": N_("surface of revolution"), "SurfaceOfExtrusion": N_("extrusion"),
              "OffsetSurface": N_("offset surface"), "OtherSurface": N_("other surface")}


def kind_name(kind):
    """A face's ``kind`` as people read it, in the current language (the code name if it is not known)."""
    return _(KIND_NAMES[kind]) if kind in KIND_NAMES else kind


class Model:
    """A part read from a file: its faces in the file's order, the edges they share and what could not be read.

    Attributes
    ----------
    faces : list of Face
        In the file's face order; a face that could not be converted is
        missing here and listed in :attr:`problems` with its index and kind.
    edges : list of Edge
        Edges shared by two faces, with both faces' pcurves in the file's parameters.  A reader may pass
        a function that finds them instead of the list: they are then found when first used (sewing an
        IGES file's faces takes longer than reading it; a mesh does not need the edges).
    problems : list of Problem
    path : str or None
        The file read.
    sewn : float or None
        The tolerance the file's faces were sewn with to find the shared edges (None: not sewn), known
        once :attr:`edges` is.
    turned : int or None
        How many faces ``lab.read(path, orient=True)`` turned to orient the part (None: read as the file
        orients its faces).
    """

    def __init__(self, faces, edges=(), problems=(), path=None, name=None):
        self.faces = list(faces)
        self._edges = edges if callable(edges) else list(edges)
        self.problems = list(problems)
        self.path = None if path is None else str(path)
        self.name = name
        self.sewn = None
        self.turned = None

    @property
    def edges(self):
        """The edges two faces share (found on first use if the reader deferred them)."""
        if callable(self._edges):
            found = self._edges()
            self._edges, self.sewn = (found, None) if isinstance(found, list) else (list(found[0]), found[1])
        return self._edges

    @edges.setter
    def edges(self, value):
        self._edges = list(value)

    def __getstate__(self):
        """A model pickles as plain arrays: deferred edges are found first (the finder holds OpenCASCADE shapes)."""
        state = dict(self.__dict__)
        state["_edges"] = self.edges
        state["sewn"] = self.sewn
        return state

    def __len__(self):
        return len(self.faces)

    def __iter__(self):
        return iter(self.faces)

    def __getitem__(self, i):
        return self.faces[i]

    def face(self, index):
        """The face with the file index ``index`` (``KeyError`` if it is missing; see :attr:`problems`)."""
        for f in self.faces:
            if f.index == index:
                return f
        raise KeyError(f"the model has no face with file index {index}; problems: {[str(p) for p in self.problems]}")

    def neighbours(self, index):
        """File indices of the faces that share an edge with face ``index``."""
        out = set()
        for e in self.edges:
            if index in e.faces:
                out.update(e.faces)
        out.discard(index)
        return sorted(out)

    def kinds(self):
        """``{kind: number of faces}``."""
        out = {}
        for f in self.faces:
            out[f.kind] = out.get(f.kind, 0) + 1
        return out

    def bounds(self):
        """Axis-aligned box of all control points, ``(min xyz, max xyz)``."""
        P = np.concatenate([f.surface.control_points.reshape(-1, 3) for f in self.faces])
        return P.min(axis=0), P.max(axis=0)

    def to_mesh(self, *args, **kwargs):
        """A triangle mesh of every face with exact curvature: see :func:`lab.interrogation.cad.mesh.model_mesh`."""
        from .mesh import model_mesh

        return model_mesh(self, *args, **kwargs)

    def __repr__(self):
        kinds = ", ".join(f"{n} {k}" for k, n in sorted(self.kinds().items()))
        bad = _(", {n} problems").format(n=len(self.problems)) if self.problems else ""
        where = _(" from {path}").format(path=os.path.basename(self.path)) if self.path else ""  # no machine paths
        edges = (_("shared edges found on first use") if callable(self._edges)
                 else _("{n} shared edges").format(n=len(self._edges)))
        return _("Model({n} faces: {kinds}; {edges}{problems}{where})").format(
            n=len(self.faces), kinds=kinds, edges=edges, problems=bad, where=where)

    def __str__(self):
        """The part for people, in the lab's language: the file's name, the faces by kind, the edges, the problems."""
        kinds = ", ".join(f"{kind_name(k)} × {n}" for k, n in sorted(self.kinds().items()))
        name = os.path.basename(self.path) if self.path else _("a part")
        edges = (_("shared edges found on first use") if callable(self._edges)
                 else _("{n} shared edges").format(n=len(self._edges)))
        bad = _(", {n} problems").format(n=len(self.problems)) if self.problems else ""
        return _("{name}: {n} faces ({kinds}); {edges}{problems}").format(name=name, n=len(self.faces), kinds=kinds,
                                                                          edges=edges, problems=bad)
