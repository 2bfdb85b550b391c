"""A real part: faces (a NURBS surface each, its trimming loops, its orientation) and the edges two faces share.

:func:`lab.read` builds a :class:`Model` from a STEP, IGES, BREP, geomview or
Rhino file.  Nothing here needs OpenCASCADE: a model is plain arrays and lab
surfaces, so it can be meshed, interrogated and pickled without ``OCP``.
"""

from typing import NamedTuple

import numpy as np

from ...i18n import _
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
    """

    index: int
    faces: tuple
    points: np.ndarray
    uv: tuple
    t: np.ndarray
    tangents: object = None


class Face:
    """One face of a model: a NURBS surface in the file's parameters, its trimming loops and its orientation.

    Attributes
    ----------
    index : int
        Position in the file's face order (``TopExp_Explorer`` over faces).
    kind : str
        What the file stores: ``"BSplineSurface"``, ``"Plane"``, ``"Cylinder"``, ``"Cone"``, ``"Sphere"``,
        ``"Torus"``, ``"SurfaceOfRevolution"``, ``"SurfaceOfExtrusion"``, ``"OffsetSurface"``, ``"BezierSurface"``.
    surface : lab.BSplineSurface or lab.BezierSurface
        B-spline faces keep the file's poles, knots, weights and parameters;
        analytic faces are OpenCASCADE's exact NURBS form (``GeomConvert``), in its parameters.
    trim : lab.trimming.TrimmedSurface or None
        The face's loops, outer first, in the surface's parameters; ``None`` for an untrimmed patch.
    reversed : bool
        The face's normal is ``-(b_u x b_v)`` (``TopAbs_REVERSED``): :meth:`curvature` flips H, k1, k2.
    """

    def __init__(self, index, kind, surface, trim=None, reversed=False, name=None):
        self.index = int(index)
        self.kind = str(kind)
        self.surface = surface
        self.trim = trim
        self.reversed = bool(reversed)
        self.name = name

    @property
    def domain(self):
        """The surface's parameter domain ``((u0, u1), (v0, v1))``."""
        return self.surface.domain

    def curvature(self, u, v):
        """K, H, k1, k2 (k1 >= k2) and ``degenerate`` at ``(u, v)`` with the face's normal.

        On a reversed face the normal is ``-(b_u x b_v)``: K stays, H changes
        sign and the principal curvatures change sign and order.
        """
        c = self.surface.curvature(u, v)
        return flip(c) if self.reversed else c

    def normal(self, u, v):
        """The face's unit normal at ``(u, v)`` (``-(b_u x b_v)/|b_u x b_v|`` on a reversed face)."""
        N = self.surface.normal(u, v)
        return -N if self.reversed else N

    def __repr__(self):
        side = ", reversed" if self.reversed else ""
        trim = "" if self.trim is None else f", {len(self.trim.loops)} loops"
        return f"Face({self.index}, {self.kind}, {self.surface!r}{trim}{side})"


class Model:
    """A part read from a file: its faces in the file's order, the edges they share and what could not be read.

    Attributes
    ----------
    faces : list of Face
        In the file's face order; a face that could not be converted is
        missing here and listed in :attr:`problems` with its index and kind.
    edges : list of Edge
        Edges shared by two faces (or a seam of one), with both faces' pcurves.
    problems : list of Problem
    path : str or None
        The file read.
    """

    def __init__(self, faces, edges=(), problems=(), path=None, name=None):
        self.faces = list(faces)
        self.edges = list(edges)
        self.problems = list(problems)
        self.path = None if path is None else str(path)
        self.name = name

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
        where = _(" from {path}").format(path=self.path) if self.path else ""
        return _("Model({n} faces: {kinds}; {edges} shared edges{problems}{where})").format(
            n=len(self.faces), kinds=kinds, edges=len(self.edges), problems=bad, where=where)
