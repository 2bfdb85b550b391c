"""Geomview export and import: coloured Bézier patches (``CBEZ333``, the practical's format) and (coloured) OFF."""

import os

import numpy as np
import pyvista as pv

from ..geometry import bezier
from ..i18n import _
from .build import _bilinear, _faces, grid_mesh

__all__ = ["read_cbez", "read_geomview", "read_off", "write_cbez", "write_off"]


def write_off(mesh, path):
    """Write a mesh as geomview OFF; with ``RGB`` point data as ``COFF`` (per-vertex RGBA in [0, 1]).

    Parameters
    ----------
    mesh : pyvista.PolyData
    path : str or os.PathLike
    """
    points = np.asarray(mesh.points, dtype=float)
    faces = _faces(mesh)
    rgb = mesh.point_data["RGB"] / 255.0 if "RGB" in mesh.point_data else None
    lines = ["COFF" if rgb is not None else "OFF", f"{len(points)} {len(faces)} 0"]
    for i, p in enumerate(points):
        row = f"{p[0]:.17g} {p[1]:.17g} {p[2]:.17g}"
        if rgb is not None:
            row += " " + " ".join(f"{c:.6g}" for c in rgb[i]) + " 1"
        lines.append(row)
    lines.extend(f"{len(f)} " + " ".join(str(int(j)) for j in f) for f in faces)
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


def _tokens(path):
    with open(path) as fh:
        text = [line.split("#", 1)[0] for line in fh]
    return " ".join(text).split()


def read_off(path):
    """Read a geomview ``OFF`` / ``COFF`` file.

    Returns
    -------
    points : (k, 3) ndarray
    faces : list of int ndarrays
    colors : (k, 4) ndarray or None
        RGBA per vertex for COFF.
    """
    tok = _tokens(path)
    if not tok or tok[0] not in ("OFF", "COFF"):
        raise ValueError(f"{path}: not an OFF file (expected header OFF or COFF; got {tok[:1]})")
    colored = tok[0] == "COFF"
    nv, nf = int(tok[1]), int(tok[2])
    per = 7 if colored else 3
    pos = 4
    verts = np.array(tok[pos : pos + nv * per], dtype=float).reshape(nv, per)
    pos += nv * per
    faces = []
    for _face in range(nf):
        k = int(tok[pos])
        faces.append(np.array(tok[pos + 1 : pos + 1 + k], dtype=int))
        pos += k + 1
    return verts[:, :3], faces, (verts[:, 3:] if colored else None)


def write_cbez(patches, path):
    """Write coloured Bézier patches for geomview (``CBEZ<m><n><d>``; ``CBEZ333`` for bicubic).

    Per patch the control points with u varying fastest, then the corner
    colours RGBA(0,0) RGBA(0,n) RGBA(m,0) RGBA(m,n), i.e. c00, c01, c10, c11
    (geomview manual, "BBP and BEZ").  Rational patches are written with
    homogeneous 4-D vertices ``(w x, w y, w z, w)``.
    """
    m, n = patches.degree
    if not (1 <= m <= 6 and 1 <= n <= 6):
        raise ValueError(f"geomview BEZ patches need degrees 1..6 in u and v; got {(m, n)}")
    colors = patches.colors
    if not np.all(np.isfinite(colors)):
        raise ValueError("the patches have no colours yet: call visualize_curvature (or set_colors) before write_cbez")
    P = patches.control_points
    if patches.weights is not None:
        w = patches.weights[..., None]
        P = np.concatenate([P * w, w], axis=-1)
    d = P.shape[-1]
    lines = [f"CBEZ{m}{n}{d}"]
    for net, col in zip(P, colors):
        for j in range(n + 1):
            for i in range(m + 1):
                lines.append(" ".join(f"{x:.17g}" for x in net[i, j]))
        for a, b in ((0, 0), (0, 1), (1, 0), (1, 1)):
            lines.append(" ".join(f"{x:.6g}" for x in col[a, b]) + " 1")
        lines.append("")
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


def read_cbez(path):
    """Read a geomview ``CBEZ<m><n><d>`` file written by :func:`write_cbez`.

    Returns
    -------
    nets : (N, m+1, n+1, 3) ndarray
    weights : (N, m+1, n+1) ndarray or None
    colors : (N, 2, 2, 4) ndarray
        RGBA indexed ``[patch, u, v]``.
    """
    tok = _tokens(path)
    head = tok[0] if tok else ""
    if not (len(head) == 7 and head.startswith("CBEZ") and head[4:].isdigit()):
        raise ValueError(f"{path}: expected a CBEZ<m><n><d> header; got {head!r}")
    m, n, d = (int(c) for c in head[4:])
    values = np.array(tok[1:], dtype=float)
    per = (m + 1) * (n + 1) * d + 16
    if values.size % per:
        raise ValueError(f"{path}: {values.size} numbers is not a whole number of {head} patches ({per} each)")
    rec = values.reshape(-1, per)
    nets = rec[:, : per - 16].reshape(-1, n + 1, m + 1, d).transpose(0, 2, 1, 3)
    colors = rec[:, per - 16 :].reshape(-1, 2, 2, 4)  # c00, c01, c10, c11
    if d == 4:
        w = nets[..., 3]
        return nets[..., :3] / w[..., None], w, colors
    return nets, None, colors


def read_geomview(path, resolution=8):
    """A file written for geomview (``CBEZ<m><n><d>`` or ``OFF``/``COFF``), read back as a mesh to look at.

    The practical's last step ("kann dann mit geomview betrachtet werden") in the notebook: the patches of a
    ``CBEZ`` file are sampled on a ``resolution x resolution`` grid each, their corner colours interpolated
    bilinearly (as geomview shades them); an OFF file gives its polygons and, for ``COFF``, its vertex colours.

    Parameters
    ----------
    path : str or os.PathLike
    resolution : int
        Quads per patch edge for ``CBEZ`` files.

    Returns
    -------
    pyvista.PolyData
        ``RGB`` point data (uint8) when the file has colours; field data ``geomview_format`` (the header).
    """
    path = os.fspath(path)
    tok = _tokens(path)
    head = tok[0] if tok else ""
    if head.startswith("CBEZ"):
        nets, weights, colors = read_cbez(path)
        s = np.linspace(0.0, 1.0, int(resolution) + 1)
        U, V = np.meshgrid(s, s, indexing="ij")
        points = bezier.evaluate(nets, U, V, weights)
        mesh = grid_mesh(points, {"colors": _bilinear(colors[..., :3], s)})
        rgb = mesh.point_data.pop("colors")
    elif head in ("OFF", "COFF"):
        points, faces, colors = read_off(path)
        cells = np.concatenate([np.r_[len(f), f] for f in faces]) if faces else np.zeros(0, dtype=int)
        mesh = pv.PolyData(points, cells)
        rgb = None if colors is None else colors[:, :3]
    else:
        raise ValueError(_("{path}: not a geomview file the lab writes (expected a CBEZ<m><n><d>, OFF or COFF "
                           "header; got {head!r})").format(path=path, head=head))
    if rgb is not None:
        mesh.point_data["RGB"] = np.round(255 * np.clip(rgb, 0, 1)).astype(np.uint8)
    mesh.field_data["geomview_format"] = [head]
    return mesh
