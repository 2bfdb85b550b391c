"""Real parts: :func:`read` a STEP, IGES, BREP, geomview or Rhino file into a :class:`Model` of NURBS faces with
trimming loops and shared edges, mesh it with exact curvature, :func:`write` surfaces back.
``model`` → ``occ`` (OpenCASCADE, imported only when a CAD file is read), ``geomview``, ``mesh``, ``models``.
"""

import os

from .model import Edge, Face, Model, Problem

__all__ = ["Edge", "Face", "Model", "Problem", "read", "write"]


def write(obj, path, *, drop_trims=False, sew=True):
    """Write a model (trimmed faces with their loops), a lab.TrimmedSurface or a lab surface as ``.brep``,
    ``.step`` or ``.3dm``: see :func:`.writer.write`."""
    from .writer import write as _write

    return _write(obj, path, drop_trims=drop_trims, sew=sew)


def read(path, *, name=None, sew=None, orient=False):
    """Read a part: STEP (``.step``, ``.stp``), IGES (``.iges``, ``.igs``), BREP (``.brep``) or geomview's Bézier
    files (``.bez``, ``.bbp``: ``BEZuvn``, ``BBP``, ``CBEZuvn``, rational ``BEZuv4``, pure Python) or Rhino
    (``.3dm``, through rhino3dm).

    Parameters
    ----------
    path : str or os.PathLike
    name : str, optional
        A name for pictures and tables (default: the file's name).
    sew : bool or None
        STEP, IGES and BREP files: find the edges that faces share by sewing them (``BRepBuilderAPI_Sewing``):
        ``None`` (default) when the file's faces have free edges (an IGES file's usually do), ``True``
        always, ``False`` never.  Sewing only finds edges; the faces stay the file's.  See
        :func:`lab.interrogation.cad.occ.read_occ`.
    orient : bool
        STEP, IGES and BREP files: orient the faces as a CAD system orients a joined part (the faces of each
        sewn shell consistently, a closed shell outwards, an open one as most of its faces are in the file),
        so that H has one sign over the part.  Meant for IGES files, whose faces carry no orientation: it sews
        during the read.  ``model.turned`` says how many faces it turned.

    Returns
    -------
    Model
        ``faces`` in the file's order, ``edges`` shared by two faces, ``problems``
        (faces that could not be converted, by index and kind).

    Raises
    ------
    FileNotFoundError
        No such file.
    ValueError
        An empty, corrupt or unsupported file, named with what is wrong.
    ImportError
        A CAD file without OpenCASCADE installed (``pip install -e '.[cad]'``).
    """
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a file name (str or os.PathLike); got {type(path).__name__}")
    path = os.fspath(path)
    if os.path.isdir(path):
        raise ValueError(f"{path}: is a folder, not a file")
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path}: no such file")
    if os.path.getsize(path) == 0:  # said before OpenCASCADE is imported (seconds)
        from .occ import EXTENSIONS as _FORMATS

        kind = {**_FORMATS, ".bez": "geomview Bézier", ".bbp": "geomview Bézier", ".3dm": "Rhino"}.get(
            os.path.splitext(path)[1].lower(), "CAD")
        raise ValueError(f"{path}: the file is empty; expected a {kind} file")
    ext = os.path.splitext(path)[1].lower()
    name = name or os.path.basename(path)
    from .occ import EXTENSIONS

    if ext in EXTENSIONS:
        from .occ import read_occ

        return read_occ(path, name=name, sew=sew, orient=orient)
    if orient is not False:
        raise ValueError(f"{path}: orient=True is for STEP, IGES and BREP files; a {ext} file's surfaces have no shells to "
                         "orient")
    if ext in (".bez", ".bbp"):
        from .geomview import read_geomview

        return read_geomview(path, name=name)
    if ext == ".3dm":
        from .rhino import read_3dm

        return read_3dm(path, name=name)
    known = sorted(set(EXTENSIONS) | {".bez", ".bbp", ".3dm"})
    raise ValueError(f"{path}: unsupported file type {ext or '(no extension)'!r}; expected one of {', '.join(known)}")
