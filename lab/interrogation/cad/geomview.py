"""geomview's Bézier patch files, the practical viewer's own format, read in pure Python into a :class:`Model`.

Headers (geomview manual, "BBP and BEZ"): ``BEZuvn`` (degrees u, v; n = 3 coordinates, or 4 for homogeneous
``x y z w``, a rational patch), ``BBP`` (= ``BEZ333``), ``CBEZuvn`` (four corner colours follow each patch), a
suffix ``_ST`` (four texture pairs follow). A header may appear again between patches and changes the format
from there on. Control points are listed with u varying fastest, as :func:`lab.mesh.read_cbez` reads them.
"""

import os
import re

import numpy as np

from ...mesh.geomview import _tokens
from ...model.surface import BezierSurface
from .model import Face, Model, Problem

__all__ = ["parse_header", "read_geomview"]

_HEADER = re.compile(r"^(C?)(?:BEZ(\d)(\d)(\d)|(BBP))(_ST)?$")


def parse_header(token):
    """``(m, n, d, colours, texture)`` of a header such as ``BEZ333``, ``CBEZ224``, ``BBP``, ``BEZ334_ST``; or None."""
    match = _HEADER.match(token)
    if not match:
        return None
    colours, m, n, d, bbp, st = match.groups()
    if bbp:
        m, n, d = 3, 3, 3
    m, n, d = int(m), int(n), int(d)
    if d not in (3, 4) or m < 1 or n < 1:
        return None
    return m, n, d, bool(colours), bool(st)


def read_geomview(path, name=None):
    """A :class:`Model` of a geomview Bézier file: one face per patch, no trims, no shared edges.

    A patch the lab cannot take (a rational patch with a weight that is not positive, e.g. the ``w = 0``
    control points of geomview's ``torus.bez``) is listed in ``problems`` with its index.
    """
    path = os.fspath(path)
    tok = _tokens(path)
    if not tok:
        raise ValueError(f"{path}: the file is empty; expected a geomview Bézier file (BEZuvn, BBP, CBEZuvn)")
    fmt = parse_header(tok[0])
    if fmt is None:
        raise ValueError(f"{path}: expected a geomview Bézier header (BEZuvn, BBP, CBEZuvn, with _ST); got {tok[0]!r}")
    faces, problems, k, index = [], [], 1, 0
    while k < len(tok):
        header = parse_header(tok[k])
        if header is not None:
            fmt, k = header, k + 1
            continue
        m, n, d, colours, st = fmt
        count = (m + 1) * (n + 1) * d + (8 if st else 0) + (16 if colours else 0)
        chunk = tok[k:k + count]
        if len(chunk) < count:
            raise ValueError(f"{path}: patch {index} is cut short: {len(chunk)} of its {count} numbers are there")
        try:
            values = np.array(chunk, dtype=float)
        except ValueError:
            bad = next(t for t in chunk if not _is_number(t))
            raise ValueError(f"{path}: patch {index}: {bad!r} is not a number") from None
        net = values[: (m + 1) * (n + 1) * d].reshape(n + 1, m + 1, d).transpose(1, 0, 2)
        try:
            if d == 4:
                w = net[..., 3]
                if np.any(w <= 0):
                    raise ValueError(f"weights must be positive; got {w.min():g} (a control point at infinity)")
                surface = BezierSurface(net[..., :3] / w[..., None], w)
            else:
                surface = BezierSurface(net)
            faces.append(Face(index, "BezierSurface", surface))
        except ValueError as exc:
            problems.append(Problem(index, "BezierSurface", str(exc)))
        index, k = index + 1, k + count
    if index == 0:
        raise ValueError(f"{path}: the file holds a header but no patches")
    return Model(faces, (), problems, path=path, name=name)


def _is_number(text):
    try:
        float(text)
    except ValueError:
        return False
    return True
