"""What the explorers need of a model (a part from :func:`lab.read`): its mesh per resolution, built face by face
once and kept; the borders of its faces; the face a tool works on.

A model's resolution is the number of iso-parameter lines per face (``model.to_mesh(n, n)``): a subdivision
depth means nothing for trimmed faces of different sizes.  The mesh is built one face at a time, so a long
build shows its progress and a newer request cancels it between two faces.
"""

import numpy as np
import pyvista as pv

from ...geometry import validation as _v
from ...i18n import _
from ...interrogation.cad.mesh import face_arrays
from ...interrogation.cad.model import kind_name
from ...interrogation.faces import fill_normals, is_model
from ..render import face_borders

__all__ = ["ModelMeshes", "default_point", "face_borders", "face_label", "face_mesh", "is_model"]

#: point data of a model's mesh, as lab.Model.to_mesh makes it
FIELDS = ("K", "H", "k1", "k2", "degenerate", "N", "uv")


class ModelMeshes:
    """A model's meshes by lines per face, each built once (:meth:`steps`, :meth:`mesh`) with the arrays of
    :meth:`lab.Model.to_mesh`: exact K, H, k1, k2, N with each face's orientation, ``uv``, ``face`` ids."""

    def __init__(self, model):
        self.model = model
        self._meshes = {}

    def cached(self, n):
        """The mesh at ``n`` lines per face if it was built, else None."""
        return self._meshes.get(int(n))

    def steps(self, n):
        """Build the mesh at ``n`` lines per face one face at a time: yields the fraction done after each face,
        returns the mesh (``StopIteration.value``; use :meth:`mesh` to run it to the end)."""
        n = _v.as_positive_int(n, "lines per face", minimum=2)
        if n in self._meshes:
            return self._meshes[n]
        limit = _v.memory_limit()[0]
        faces = self.model.faces
        parts = []
        for k, face in enumerate(faces):
            parts.append(face_arrays(face, n, n, None, limit))
            yield (k + 1) / len(faces)
        mesh = _assemble(faces, parts)
        self._meshes[n] = mesh
        return mesh

    def mesh(self, n):
        """The mesh at ``n`` lines per face (built now if needed)."""
        steps = self.steps(n)
        while True:
            try:
                next(steps)
            except StopIteration as done:
                return done.value


def _assemble(faces, parts):
    """One PolyData of the faces' arrays (as :func:`lab.interrogation.cad.mesh.model_mesh` joins them)."""
    counts = np.array([len(p[0]) for p in parts])
    offsets = np.r_[0, np.cumsum(counts)[:-1]]
    tris = [p[1] + o for p, o in zip(parts, offsets)]
    tri = np.concatenate(tris)
    mesh = pv.PolyData(np.concatenate([p[0] for p in parts]), np.hstack([np.full((len(tri), 1), 3), tri]).ravel())
    for key in FIELDS:
        mesh.point_data[key] = np.concatenate([p[2][key] for p in parts])
    ids = np.array([f.index for f in faces])
    mesh.point_data["face"] = np.repeat(ids, counts)
    mesh.cell_data["face"] = np.repeat(ids, [len(t) for t in tris])
    return fill_normals(mesh)


def face_mesh(face, n=32):
    """One face of a model on ``n`` lines in its trimmed region, with the arrays of a model's mesh."""
    return _assemble([face], [face_arrays(face, n, n)])


def face_label(face):
    """How the face menu names a face: its index in the file and what the file stores, in the lab's language."""
    side = _(", reversed") if face.reversed else ""
    return f"{face.index}: {kind_name(face.kind)}{side}"


def default_point(mesh, index):
    """A point (u, v) inside face ``index``: its mesh vertex nearest the median of the face's vertices' (u, v)."""
    face = np.asarray(mesh.point_data["face"])
    uv = np.asarray(mesh.point_data["uv"], dtype=float)[face == index]
    if not len(uv):
        raise ValueError(f"the model's mesh has no face with index {index}")
    k = int(np.argmin(np.linalg.norm(uv - np.median(uv, axis=0), axis=1)))
    return float(uv[k, 0]), float(uv[k, 1])
