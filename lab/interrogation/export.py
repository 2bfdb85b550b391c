"""Numbers for the report: every analysis result as CSV (``result.to_csv(path)``) or a pandas table
(``result.to_pandas()``), one implementation for all.

A result class gives its table by a method ``_table()`` returning a :class:`Table` and takes the two methods
from here (``to_csv = export.to_csv``, ``to_pandas = export.to_pandas`` in its body), so that the continuity
report, a deviation, the probe's readout, the umbilics and the geodesics all write the same kind of file.

**The file** (plain CSV, comma-separated, a point as decimal separator in every language, UTF-8):

* comment lines first, each starting with ``# ``: the title, then ``key: value`` lines, among them ``units:``
  (each column's unit, ``column [unit]``, separated by ``;``) and, where the result has one, ``tolerance:``;
* one header line with the column names;
* one row per item.  Numbers are written with Python's ``repr`` (the shortest text that reads back to the same
  float), so a table read back is equal to the result, not close to it; ``nan`` for a missing value,
  ``True``/``False`` for flags.

``pandas.read_csv(path, comment="#")`` reads the rows; :func:`read_csv` also the comments.  pandas is optional:
:func:`to_pandas` imports it when called and says how to install it when it is missing.
"""

import csv
import math
import os
from typing import NamedTuple

import numpy as np

from ..i18n import _

__all__ = ["Table", "read_csv", "to_csv", "to_pandas", "write_csv"]


class Table(NamedTuple):
    """A result as a table: ``title`` (one line), ``columns`` (name -> 1-D values, all of one length),
    ``units`` (name -> unit, for the columns that have one), ``meta`` (key -> text: tolerance, part, …)."""

    title: str
    columns: dict
    units: dict = None
    meta: dict = None


def _cell(x):
    if isinstance(x, (bool, np.bool_)):
        return "True" if x else "False"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (float, np.floating)):
        x = float(x)
        return "nan" if math.isnan(x) else repr(x)
    return "" if x is None else str(x)


def _check(table):
    if not isinstance(table, Table):
        raise TypeError(f"_table() must return a lab.interrogation.export.Table; got {type(table).__name__}")
    lengths = {name: len(values) for name, values in table.columns.items()}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"the columns of a table must have one length; got {lengths}")
    for name in table.columns:
        if not name or any(c in name for c in ",\n#"):
            raise ValueError(f"a column name must be plain text without ',', '#' or a line break; got {name!r}")


def write_csv(path, table):
    """Write ``table`` (a :class:`Table`) to ``path`` as described in the module docstring; returns the path."""
    _check(table)
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a file name (str or os.PathLike); got {type(path).__name__}")
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FileNotFoundError(f"{path}: the folder {folder} does not exist")
    names = list(table.columns)
    with open(path, "w", newline="", encoding="utf-8") as f:
        f.write(f"# {table.title}\n")
        f.writelines(f"# {key}: {value}\n" for key, value in (table.meta or {}).items())
        if table.units:
            f.write("# units: " + "; ".join(f"{name} [{unit}]" for name, unit in table.units.items()) + "\n")
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(names)
        columns = [list(table.columns[name]) for name in names]
        for row in zip(*columns):
            writer.writerow([_cell(x) for x in row])
    return path


def _parse(texts):
    """A column read back: ints, floats, flags or text, whichever all its cells are."""
    if texts and all(t in ("True", "False") for t in texts):
        return np.array([t == "True" for t in texts])
    for kind in (int, float):
        try:
            return np.array([kind(t) for t in texts], dtype=kind)
        except ValueError:
            continue
    return np.array(texts, dtype=object)


def read_csv(path):
    """A file written by :func:`write_csv` (or any ``to_csv``) read back as a :class:`Table`.

    Columns come back as numpy arrays: integers, floats, booleans or text (object arrays), whichever all
    of the column's cells are; ``units`` and ``meta`` from the comment lines."""
    path = os.fspath(path)
    with open(path, encoding="utf-8", newline="") as f:
        lines = f.read().splitlines()
    comments = [line[2:] if line.startswith("# ") else line[1:] for line in lines if line.startswith("#")]
    body = [line for line in lines if not line.startswith("#")]
    if not body:
        raise ValueError(f"{path}: no header line; expected a CSV file written by to_csv")
    title, meta, units = (comments[0] if comments else ""), {}, {}
    for line in comments[1:]:
        key, sep, value = line.partition(": ")
        if not sep:
            continue
        if key == "units":
            for item in value.split("; "):
                name, _sep, unit = item.rpartition(" [")
                units[name] = unit[:-1]
        else:
            meta[key] = value
    rows = list(csv.reader(body))
    names, rows = rows[0], rows[1:]
    columns = {name: _parse([row[k] for row in rows]) for k, name in enumerate(names)}
    return Table(title, columns, units, meta)


def to_csv(self, path):
    """Write this result as CSV to ``path`` (units and tolerance in ``#`` comment lines; see
    :mod:`lab.interrogation.export`); returns the path."""
    return write_csv(path, self._table())


def to_pandas(self):
    """This result as a ``pandas.DataFrame`` (needs pandas); units and the other header lines in ``df.attrs``."""
    try:
        import pandas as pd
    except ImportError:
        raise ImportError(_("to_pandas needs the package pandas (pip install pandas); to_csv(path) needs nothing")) \
            from None
    table = self._table()
    _check(table)
    frame = pd.DataFrame({name: list(values) if np.asarray(values).dtype == object else np.asarray(values)
                          for name, values in table.columns.items()})
    frame.attrs.update({"title": table.title, "units": dict(table.units or {}), **(table.meta or {})})
    return frame
