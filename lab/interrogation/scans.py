"""Scans of parts: reading the point files scanners write, writing them, and test scans of the lab's parts.

:func:`read_scan` reads PLY, STL, OBJ and VTK/VTP files through PyVista (VTK's readers) and the text formats
XYZ, ASC, PTS, TXT and CSV with ``numpy.loadtxt`` (the first three numbers of a line: x, y, z).  A scan that is a
mesh gives its vertices.

:func:`sample_scan` makes a scan with known answers: points sampled on a part's faces (uniformly by area,
evaluated on the exact surfaces), moved along the face's normal by a scanner's noise (Gaussian, standard
deviation ``noise``), a constant ``offset`` and a deliberate dent (a smooth pit of given centre, radius and
depth).  Each point's planted normal offset is returned with it, so a deviation's values can be checked.
"""

import os
from typing import NamedTuple

import numpy as np

from ..geometry import validation as _v
from ..i18n import _
from .projection import piece_triangles, pieces

__all__ = ["SCAN_FORMATS", "Dent", "Scan", "read_scan", "sample_scan", "write_scan"]

#: File endings :func:`read_scan` reads: meshes and point clouds through PyVista, text through numpy.
MESH_FORMATS = (".ply", ".stl", ".obj", ".vtk", ".vtp")
TEXT_FORMATS = (".xyz", ".asc", ".pts", ".txt", ".csv")
SCAN_FORMATS = MESH_FORMATS + TEXT_FORMATS


def read_scan(path):
    """The points of a scan file, ``(n, 3)`` float array (a mesh's vertices).

    PLY, STL, OBJ, VTK, VTP through PyVista; XYZ, ASC, PTS, TXT, CSV as text, one point per line (x y z,
    separated by blanks or commas; more numbers on a line, such as colours or normals, are ignored; lines
    starting with ``#`` or ``//`` are comments)."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a file name (str or os.PathLike); got {type(path).__name__}")
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path}: no such file")
    ext = os.path.splitext(path)[1].lower()
    if ext in MESH_FORMATS:
        import pyvista as pv

        try:
            points = np.asarray(pv.read(path).points, dtype=float)
        except Exception as exc:  # noqa: BLE001 - VTK's readers raise many kinds: said with the file's name
            raise ValueError(f"{path}: not a readable {ext[1:].upper()} scan ({type(exc).__name__}: {exc})") from None
    elif ext in TEXT_FORMATS:
        with open(path, encoding="utf-8", errors="replace") as f:
            sample = "".join(line for _k, line in zip(range(50), f) if not line.lstrip().startswith(("#", "//")))
        delimiter = "," if "," in sample else None
        try:
            data = np.loadtxt(path, comments=("#", "//"), delimiter=delimiter, ndmin=2, usecols=(0, 1, 2))
        except ValueError as exc:
            raise ValueError(f"{path}: expected one point per line, x y z (blanks or commas between); {exc}") from None
        points = data.astype(float)
    else:
        raise ValueError(f"{path}: unsupported scan type {ext or '(no extension)'!r}; expected one of "
                         f"{', '.join(SCAN_FORMATS)}")
    if points.ndim != 2 or points.shape[1] != 3 or not len(points):
        raise ValueError(f"{path}: the scan holds no points")
    return points


def write_scan(points, path):
    """Write points as a scan file: PLY, VTK or VTP (a point cloud), XYZ/ASC/PTS/TXT (``x y z`` per line) or CSV.

    STL and OBJ hold triangles, not loose points: a point cloud is written to them as degenerate triangles,
    one per point (each point three times), which :func:`read_scan` and other readers read back as points."""
    P = _v._as_float_array(points, "points")
    if P.ndim != 2 or P.shape[1] != 3:
        raise ValueError(f"points must have shape (n, 3); got {P.shape}")
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext in TEXT_FORMATS:
        np.savetxt(path, P, fmt="%.17g", delimiter="," if ext == ".csv" else " ")
        return path
    if ext not in MESH_FORMATS:
        raise ValueError(f"{path}: unsupported scan type {ext or '(no extension)'!r}; expected one of "
                         f"{', '.join(SCAN_FORMATS)}")
    import pyvista as pv

    if ext in (".stl", ".obj"):
        k = np.arange(len(P))
        cloud = pv.PolyData(P, np.column_stack([np.full(len(P), 3), k, k, k]).ravel())
    else:
        cloud = pv.PolyData(P)
    cloud.save(path)
    return path


class Dent(NamedTuple):
    """A deliberate dent: a smooth pit of ``depth`` (into the part, against the face's normal) at ``centre``,
    falling to 0 at ``radius``: depth · (1 - (ρ/radius)²)² at distance ρ < radius from the centre."""

    centre: np.ndarray
    radius: float
    depth: float

    def profile(self, X):
        """The dent's depth at points ``X`` (k, 3): 0 outside the radius."""
        rho = np.linalg.norm(np.asarray(X, dtype=float) - self.centre, axis=-1) / self.radius
        return np.where(rho < 1, self.depth * (1 - rho**2) ** 2, 0.0)


class Scan(NamedTuple):
    """A test scan: ``points`` (n, 3) as measured, ``surface`` (n, 3) the points of the part they were sampled at,
    ``face`` (n,) and ``uv`` (n, 2) where, ``normal`` (n, 3) the face's normal there, ``offset`` (n,) how far each
    point was moved along it (noise, constant offset and dent: the signed distance the deviation should find
    while it is small against the radii of curvature), and the ``dent`` (or None)."""

    points: np.ndarray
    surface: np.ndarray
    face: np.ndarray
    uv: np.ndarray
    normal: np.ndarray
    offset: np.ndarray
    dent: object


def sample_scan(part, n, *, noise=0.0, offset=0.0, dent=None, seed=0, lines=24):
    """A scan of ``part`` with known answers: ``n`` points on its faces with noise, an offset and a dent.

    Parameters
    ----------
    part : lab.Model, lab surface or lab.TrimmedSurface
    n : int
        Number of points, spread uniformly by area over the faces (each face's trimmed region, triangulated on
        ``lines`` iso-parameter lines, then evaluated exactly at random points of the triangles).
    noise : float
        Standard deviation of the scanner's noise along the normal (a length).
    offset : float or (n,) array_like
        A constant or per-point move along the normal (a length).
    dent : (centre, radius, depth), optional
        A pit of ``depth`` at ``centre`` (a 3-D point, e.g. on the part), falling to 0 at ``radius``.
    seed : int
        Of the random generator: the same seed gives the same scan.

    Returns
    -------
    Scan
    """
    n = _v.as_positive_int(n, "n", minimum=1)
    noise = _v.as_number(noise, "noise", minimum=0)
    rng = np.random.default_rng(seed)
    parts = pieces(part)
    uvs, tris, areas, owners = [], [], [], []
    for k, piece in enumerate(parts):
        uv, tri = piece_triangles(piece, _v.as_positive_int(lines, "lines", minimum=2))
        X = piece.surface.evaluate(uv[:, 0], uv[:, 1])
        a = 0.5 * np.linalg.norm(np.cross(X[tri[:, 1]] - X[tri[:, 0]], X[tri[:, 2]] - X[tri[:, 0]]), axis=1)
        uvs.append(uv)
        tris.append(tri)
        areas.append(np.nan_to_num(a))
        owners.append(np.full(len(tri), k))
    offsets = np.cumsum([0] + [len(t) for t in tris[:-1]])
    area = np.concatenate(areas)
    if not area.sum() > 0:
        raise ValueError(_("the part has no area to sample"))
    pick = rng.choice(len(area), size=n, p=area / area.sum())
    owner = np.concatenate(owners)[pick]
    r1, r2 = np.sqrt(rng.random(n)), rng.random(n)
    bary = np.column_stack([1 - r1, r1 * (1 - r2), r1 * r2])
    uv = np.zeros((n, 2))
    for k in np.unique(owner):
        sel = owner == k
        tri = tris[k][pick[sel] - offsets[k]]
        uv[sel] = np.einsum("ij,ijk->ik", bary[sel], uvs[k][tri])
    X, N = np.zeros((n, 3)), np.zeros((n, 3))
    for k in np.unique(owner):
        sel = owner == k
        X[sel] = parts[k].surface.evaluate(uv[sel, 0], uv[sel, 1])
        N[sel] = parts[k].normal(uv[sel])
    N = np.nan_to_num(N)
    move = np.broadcast_to(np.asarray(offset, dtype=float), (n,)).copy() + noise * rng.standard_normal(n)
    found = None
    if dent is not None:
        centre, radius, depth = dent
        found = Dent(np.asarray(centre, dtype=float).reshape(3), _v.as_number(radius, "dent radius", positive=True),
                     _v.as_number(depth, "dent depth"))
        move -= found.profile(X)
    face = np.array([p.index for p in parts])[owner]
    return Scan(X + move[:, None] * N, X, face, uv, N, move, found)
