"""Numbers for the report: every analysis result writes CSV with one method, ``result.to_csv(path)`` (and
``result.to_pandas()`` where pandas is installed), and the file reads back equal (lab.interrogation.export).

One set-up for the module (the results of each kind, made once); each kind's file is read back with the module's
own reader and with the standard library's csv module, and its numbers compared with the result's attributes
exactly (the file holds each float's repr, the shortest text that reads back to the same float)."""

import csv

import numpy as np
import pytest

import lab
from lab.interrogation import export
from lab.interrogation.export import read_csv
from lab.mesh import triangle_mesh


@pytest.fixture(scope="module")
def results():
    """One result of each kind that exports (deviation's: tests/test_deviation.py)."""
    torus, practical = lab.surfaces.torus(), lab.surfaces.practical()
    mesh = triangle_mesh(torus, 9)
    fan = lab.geodesic_fan(torus, (0.3, 0.2), 6, 1.5)
    return {"continuity": lab.continuity(lab.surfaces.hood()), "probe": lab.probe(torus, 0.3, 0.2),
            "umbilics": lab.umbilics(practical), "fan": fan, "path": fan[1],
            "estimators": lab.compare_estimators(mesh, estimators=("lab", "VTK")),
            "convergence": lab.convergence(torus, sizes=(9, 13, 17))}


KINDS = ("continuity", "probe", "umbilics", "fan", "path", "estimators", "convergence")


def same(a, b):
    """Equal arrays, NaN equal to NaN, text to text."""
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind in "fc" or b.dtype.kind in "fc":
        return a.shape == b.shape and bool(np.all((a == b) | (np.isnan(a.astype(float)) & np.isnan(b.astype(float)))))
    return a.tolist() == b.tolist()


@pytest.mark.parametrize("kind", KINDS)
def test_every_result_reads_back_equal(results, kind, tmp_path):
    result = results[kind]
    assert type(result).to_csv is export.to_csv and type(result).to_pandas is export.to_pandas  # one method
    table = result._table()
    path = result.to_csv(tmp_path / f"{kind}.csv")
    back = read_csv(path)
    assert back.title == table.title and list(back.columns) == list(table.columns)
    for name, values in table.columns.items():
        assert same(back.columns[name], values), (kind, name)
    assert back.units == {k: str(v) for k, v in (table.units or {}).items()}
    assert back.meta == {k: str(v) for k, v in (table.meta or {}).items()}
    with open(path, newline="", encoding="utf-8") as f:  # a plain CSV reader sees the same header and rows
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    assert rows[0] == list(table.columns) and len(rows) - 1 == len(next(iter(table.columns.values())))


def test_the_numbers_are_the_results_own(results, tmp_path):
    """Each file against the result's attributes, not only against its own table; units and tolerance stated."""
    p = read_csv(results["probe"].to_csv(tmp_path / "probe.csv"))
    probe = results["probe"]
    assert [p.columns[k][0] for k in ("K", "H", "k1", "k2")] == [probe.K, probe.H, probe.k1, probe.k2]
    assert p.columns["x"][0] == probe.point[0] and p.units["K"] == "1/length²"

    u = read_csv(results["umbilics"].to_csv(tmp_path / "umbilics.csv"))
    assert len(results["umbilics"]) == 4 and list(u.columns["kind"]) == [x.kind for x in results["umbilics"]]
    assert list(u.columns["k"]) == [x.k for x in results["umbilics"]] and "1e-08" in u.meta["tolerance"]

    f = read_csv(results["fan"].to_csv(tmp_path / "fan.csv"))
    assert list(f.columns["length"]) == [path.length for path in results["fan"]] == [1.5] * 6
    path = read_csv(results["path"].to_csv(tmp_path / "path.csv"))
    assert list(path.columns["s"]) == list(results["path"].s) and path.meta["length"] == "1.5"

    e = read_csv(results["estimators"].to_csv(tmp_path / "estimators.csv"))
    assert e.columns["K_inside"][1] == results["estimators"].error("VTK", "K", "inside")
    c = read_csv(results["convergence"].to_csv(tmp_path / "convergence.csv"))
    conv = results["convergence"]
    assert list(c.columns["h"]) == list(conv.h) and float(c.meta["order K_inside"]) == conv.orders["K", "inside"]


def test_pandas_is_optional(results):
    try:
        import pandas as pd
    except ImportError:
        with pytest.raises(ImportError, match="pip install pandas"):
            results["probe"].to_pandas()
        return
    frame = results["convergence"].to_pandas()
    assert isinstance(frame, pd.DataFrame) and list(frame["h"]) == list(results["convergence"].h)


def test_bad_paths_are_refused(results, tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        results["probe"].to_csv(tmp_path / "no" / "such" / "folder.csv")
    with pytest.raises(TypeError, match="file name"):
        results["probe"].to_csv(3)
