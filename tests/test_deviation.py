"""lab.deviation: signed distances of scanned points to a part, against closed forms and OpenCASCADE; statistics,
bands and colours; a planted dent found; scans read from PLY, STL, OBJ and XYZ files."""

import numpy as np
import pytest

import lab
from lab.interrogation.deviation import DeviationStats, deviation_colors, tolerance_band
from lab.interrogation.projection import closest_points
from lab.interrogation.scans import read_scan, sample_scan, write_scan

pytest.importorskip("OCP", reason="OpenCASCADE (the cad extra) gives the reference projections")


@pytest.fixture(scope="module")
def linkrods():
    return lab.models.linkrods()


@pytest.fixture(scope="module")
def size(linkrods):
    mesh = linkrods.to_mesh(8, 8)
    return float(np.linalg.norm(np.ptp(np.asarray(mesh.points), axis=0)))


@pytest.fixture(scope="module")
def clean(linkrods, size):
    """2000 noise-free points: each on a face, moved along its normal by a known amount up to 0.1 % of the size."""
    rng = np.random.default_rng(11)
    offset = rng.uniform(-1e-3, 1e-3, 2000) * size
    scan = sample_scan(linkrods, 2000, offset=offset, seed=4)
    return scan, lab.deviation(scan.points, linkrods, tolerance=5e-4 * size)


def test_sphere_closed_form():
    """On the unit sphere (a NURBS) the signed distance of p is |p| - 1, the foot p/|p|."""
    rng = np.random.default_rng(0)
    direction = rng.normal(size=(500, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    radius = rng.uniform(0.7, 1.3, 500)
    sphere = lab.surfaces.sphere()
    d = lab.deviation(direction * radius[:, None], sphere, tolerance=0.1)
    outward = np.sign(np.einsum("ij,ij->i", sphere.normal(d.uv[:, 0], d.uv[:, 1]), direction))
    assert np.all(outward == outward[0])  # the surface's normal points one way everywhere
    assert np.max(np.abs(d.distance - outward[0] * (radius - 1))) < 1e-12
    assert np.max(np.abs(d.foot - direction)) < 1e-12
    assert np.all(d.face == 0) and not d.border.any()


def test_plane_border_foot():
    """Beside a plane patch the nearest point is on its border: found there and flagged."""
    plane = lab.surfaces.plane()
    (u0, u1), (_v0, v1) = plane.domain
    corner = plane.evaluate(u1, v1)
    p = corner + np.array([0.3, 0.4, 0.0]) * (u1 - u0)
    d = lab.deviation([p], plane, tolerance=0.01)
    assert d.border[0] and abs(abs(d.distance[0]) - 0.5 * (u1 - u0)) < 1e-12
    assert np.max(np.abs(d.foot[0] - corner)) < 1e-12


def test_planted_offsets(clean, size):
    """Away from the edges every distance is the planted offset (signed by the face's normal, reversed faces too)."""
    scan, d = clean
    same = d.face == scan.face
    assert same.mean() > 0.99
    assert np.max(np.abs(d.distance - scan.offset)[same]) < 1e-12 * size


def test_against_occ_surface_projection(linkrods, clean, size):
    """GeomAPI_ProjectPointOnSurf on the face: the same distance and (u, v) to 1e-8 (where the foot is inside)."""
    from lab.interrogation.cad.kernel import occ_projection

    scan, d = clean
    inside = (d.face == scan.face) & ~d.border
    distance, feet, _uv = occ_projection(linkrods, scan.points[inside], faces=scan.face[inside])
    assert np.max(np.abs(np.abs(d.distance[inside]) - distance)) < 1e-8
    assert np.max(np.linalg.norm(d.foot[inside] - feet, axis=1)) < 1e-8


def test_against_occ_whole_part(linkrods, clean):
    """BRepExtrema_DistShapeShape against all faces (trims respected): the same distance to 1e-8."""
    from lab.interrogation.cad.kernel import occ_projection

    scan, d = clean
    some = np.random.default_rng(2).choice(len(scan.points), 300, replace=False)
    distance, _feet, _uv = occ_projection(linkrods, scan.points[some])
    inside = ~d.border[some]
    assert inside.mean() > 0.98
    assert np.max(np.abs(np.abs(d.distance[some]) - distance)[inside]) < 1e-8
    # on all 2000 points (measured) one differs, by 2.4e-7: its foot is at an edge between faces, where the lab's
    # trims (polylines of the pcurves) and OCC's exact edges part; on these 300 the lab is never the farther
    assert np.all(np.abs(d.distance[some]) <= distance + 1e-12)


@pytest.fixture(scope="module")
def dented(linkrods, size):
    """A scan with a scanner's noise (sigma 2e-5 of the size) and a dent of depth 0.4 % of the size."""
    centre = linkrods.face(6).evaluate(2.2, 1.13)  # on the outside of the large cylinder (radius ~1.1), inside its trims
    scan = sample_scan(linkrods, 20000, noise=2e-5 * size, dent=(centre, 0.05 * size, 4e-3 * size), seed=7)
    return scan, lab.deviation(scan.points, linkrods, tolerance=1e-3 * size)


def test_dent_found(dented, size):
    """The points below the tolerance are the dent's: their deepest lies at the planted centre, as deep as planted."""
    scan, d = dented
    dent = scan.dent
    below = d.band < 0
    assert below.sum() > 20
    assert np.all(np.linalg.norm(d.points[below] - dent.centre, axis=1) < dent.radius)
    deepest = np.argmin(d.distance)
    assert np.linalg.norm(d.foot[deepest] - dent.centre) < 0.2 * dent.radius
    assert abs(-d.distance[deepest] - dent.depth) < 0.1 * dent.depth
    # each point's distance is its planted offset (dent and noise) up to the dent's curvature's effect
    assert np.max(np.abs(d.distance - scan.offset)) < 2e-2 * dent.depth


def test_stats(dented):
    _scan, d = dented
    s = d.stats
    x = d.distance
    assert isinstance(s, DeviationStats) and s.count == len(x)
    assert s.mean == pytest.approx(x.mean(), abs=0) and s.median == pytest.approx(np.median(x), abs=0)
    assert s.std == pytest.approx(x.std(), abs=0) and s.rms == pytest.approx(np.sqrt((x * x).mean()), rel=1e-15)
    assert s.max_above == x.max() and s.max_below == x.min()
    lo, hi = d.tolerance
    assert s.within == np.mean((x >= lo) & (x <= hi)) and s.above + s.below + s.within == pytest.approx(1.0)
    assert "share within tolerance" in s.table() and len(d.outside()) == round((1 - s.within) * s.count)
    with lab.i18n.using("de"):  # in German: the names translated, decimal commas, the columns aligned
        rows = s.table().splitlines()
    assert rows[8].startswith("Anteil innerhalb der Toleranz") and "," in rows[1]
    assert len({len(row) for row in rows[:-1]}) == 1


def test_tolerance_and_colours():
    assert tolerance_band(0.1) == (-0.1, 0.1) and tolerance_band((-0.05, 0.2)) == (-0.05, 0.2)
    with pytest.raises(ValueError, match="tolerance"):
        tolerance_band((0.1, 0.2))
    with pytest.raises(ValueError, match="tolerance must be"):
        tolerance_band(-1)
    d = np.array([-1.0, -0.2, 0.0, 0.05, 0.2, 1.0])
    bands = deviation_colors(d, 0.1, "bands")
    assert np.allclose(bands[0], bands[1]) and np.allclose(bands[2], bands[3]) and np.allclose(bands[4], bands[5])
    graded = deviation_colors(d, 0.1, "graded")
    assert np.allclose(graded[2], bands[2]) and np.allclose(graded[0], lab.geometry.palettes.ramp("vik", 0.0))
    assert np.allclose(graded[5], lab.geometry.palettes.ramp("vik", 1.0))
    assert graded[1].sum() > graded[0].sum()  # lighter near the band's border than at the far end
    with pytest.raises(ValueError, match="color_map must be one of bands, graded"):
        deviation_colors(d, 0.1, "rainbow")


def test_bad_input():
    plane = lab.surfaces.plane()
    with pytest.raises(ValueError, match=r"points must have shape \(n, 3\); got \(4, 2\)"):
        lab.deviation(np.zeros((4, 2)), plane, tolerance=0.1)
    with pytest.raises(ValueError, match="points must be finite"):
        lab.deviation([[0, 0, np.nan]], plane, tolerance=0.1)
    with pytest.raises(TypeError, match="the part must be a lab.Model"):
        lab.deviation([[0, 0, 0]], "plane", tolerance=0.1)


@pytest.mark.parametrize("suffix", [".ply", ".stl", ".obj", ".xyz", ".csv", ".vtp"])
def test_scan_files(tmp_path, suffix):
    """A scan written and read back in the formats scanners write gives the same points (text to 17 digits)."""
    points = np.random.default_rng(3).normal(size=(50, 3))
    path = write_scan(points, tmp_path / f"scan{suffix}")
    back = read_scan(path)
    if suffix in (".stl",):  # STL stores single precision
        assert np.allclose(back, points, atol=1e-6) and len(back) == 50
    else:
        tol = 0 if suffix in (".xyz", ".csv") else 1e-6
        assert back.shape == (50, 3) and np.max(np.abs(back - points)) <= tol


def test_scan_file_through_trimesh(tmp_path):
    """A PLY point cloud that trimesh (another library) writes reads back: the lab parses no format itself."""
    trimesh = pytest.importorskip("trimesh")
    points = np.random.default_rng(4).normal(size=(30, 3))
    path = tmp_path / "cloud.ply"
    trimesh.PointCloud(points).export(path)
    assert np.allclose(read_scan(path), points)
    d = lab.deviation(path, lab.surfaces.plane(), tolerance=0.1)
    assert len(d.distance) == 30


def test_scan_file_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        read_scan(tmp_path / "missing.ply")
    bad = tmp_path / "scan.dat"
    bad.write_text("1 2 3\n")
    with pytest.raises(ValueError, match="unsupported scan type '.dat'"):
        read_scan(bad)
    text = tmp_path / "scan.xyz"
    text.write_text("1 2\n3 4\n")
    with pytest.raises(ValueError, match="expected one point per line"):
        read_scan(text)


def test_seeds_reused(linkrods, clean):
    """A start mesh built once serves another call with the same answer."""
    scan, d = clean
    seeds = closest_points.seeds(linkrods)
    again = closest_points(scan.points[:100], linkrods, seeds=seeds)
    assert np.array_equal(again.face, d.face[:100])
    assert np.max(np.abs(again.distance - d.distance[:100])) < 1e-14 * np.ptp(seeds.points, axis=0).max()


def test_map_on_the_part(linkrods, dented, size):
    """The part's mesh coloured by the scan: each vertex takes the nearest foot's distance (the dent's vertices
    its depth), grey where no scanned point is near, vik's colours elsewhere."""
    from lab.interrogation.deviation import NO_SCAN

    _scan, d = dented
    mesh = linkrods.to_mesh(33, 33)
    coloured = d.map(mesh, "bands")
    values = np.asarray(coloured.point_data["deviation"])
    X = np.asarray(mesh.points, dtype=float)
    from scipy.spatial import cKDTree

    gap, nearest = cKDTree(d.foot).query(X)
    scanned = np.isfinite(values)
    assert scanned.mean() > 0.95
    assert np.array_equal(values[scanned], d.distance[nearest[scanned]])
    assert np.all(gap[~scanned] > 0)  # unscanned: no foot within reach
    rgb = np.asarray(coloured.point_data["RGB"])
    assert rgb.dtype == np.uint8 and np.all(rgb[~scanned] == np.round(255 * np.array(NO_SCAN)))
    assert (values < d.tolerance[0]).any()  # the dent's vertices are below the tolerance, coloured navy
    navy = np.round(255 * lab.geometry.palettes.ramp("vik", 0.0))
    assert np.all(rgb[values < d.tolerance[0]] == navy)


def test_legend():
    from lab.view.legend import deviation_legend

    bands = deviation_legend(0.01, "bands", unscanned=True)
    labels = [label for label, _c in bands.classes]
    assert labels == ["below −0.01", "within −0.01 … 0.01", "above 0.01", "not scanned"]
    graded = deviation_legend((-0.01, 0.02), "graded", 0.05)
    assert graded.clim == (-0.05, 0.05) and graded.levels == (-0.01, 0.02)
    # the bar's colours are the points' colours: sampled at a distance, it shows deviation_colors' colour there
    bar = graded.colors(1000)
    for x in (-0.04, 0.0, 0.015, 0.035):
        k = int((x + 0.05) / 0.1 * 1000)
        assert np.allclose(bar[k], deviation_colors(np.array([x]), (-0.01, 0.02), vmax=0.05)[0], atol=0.02)


def test_render_deviation(tmp_path, dented, capsys):
    """curvature-lab render --deviation SCAN: the part's mesh with the deviation at its vertices, the table printed."""
    import pyvista as pv

    from lab import cli

    scan, d = dented
    path = write_scan(scan.points, tmp_path / "scan.ply")
    out = tmp_path / "deviation.vtp"
    assert cli.main(["render", "--model", "linkrods", "--deviation", str(path), "--tolerance",
                     repr(d.tolerance[1]), "--quiet", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "share within tolerance" in printed and f"{len(scan.points)} points against linkrods" in printed
    values = np.asarray(pv.read(out).point_data["deviation"])
    # at 17 lines per face the dent (radius 0.28, on a cylinder of circumference ~7) falls between vertices:
    # the deepest vertex shows part of its depth, none more than all of it
    assert -1.01 * scan.dent.depth < np.nanmin(values) < -0.5 * scan.dent.depth
    assert np.isfinite(values).mean() > 0.9
    with pytest.raises(SystemExit):
        cli.main(["render", "--model", "linkrods", "--deviation", str(path), "--draft", "0,0,1", "-o", str(out)])
    assert "different colourings" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        cli.main(["render", "--model", "linkrods", "--tolerance", "0.1", "-o", str(out)])
    assert "--tolerance belongs to --deviation" in capsys.readouterr().err


def test_explorer_shows_the_deviation(linkrods, dented):
    """The curvature explorer given a scan offers its deviation as a map: the mesh's vertices take
    Deviation.on_points, the legend and title say so, and the curvature comes back."""
    from lab.view.explorers import CurvatureExplorer

    scan, d = dented
    e = CurvatureExplorer(linkrods, live=False, lines=8, scan=scan.points, tolerance=d.tolerance)
    try:
        t = e.tools
        assert np.array_equal(e.deviation.distance, d.distance)
        t.map.value = "deviation"
        shown = np.asarray(e.mesh.point_data["cad"], dtype=float)
        expected = d.on_points(np.asarray(e.mesh.points))
        assert np.array_equal(np.isnan(shown), np.isnan(expected))
        assert np.array_equal(shown[np.isfinite(shown)], expected[np.isfinite(expected)])
        assert e.legend().title.startswith("signed distance to the part") and e.legend().is_bar
        assert e.picture_title().startswith("deviation from the scan, tolerance −0.0056 … 0.0056")
        t.map.value = "deviation-bands"
        assert [label for label, _c in e.legend().classes][:3] == ["below −0.0056", "within −0.0056 … 0.0056",
                                                                   "above 0.0056"]
        image = e.picture()
        assert image.ndim == 3 and image.shape[2] == 3
        t.map.value = "curvature"
        assert not e.legend().title.startswith("signed distance")
    finally:
        e.close()
    with pytest.raises(TypeError, match="the part must be a lab.Model"):
        CurvatureExplorer(lab.surfaces.practical().to_bezier_patches(), live=False, depth=0, scan=scan.points)


def test_csv_reads_back_equal(dented, tmp_path):
    """Per-point values and statistics to CSV for the report: read back equal, with the tolerance in the header."""
    from lab.interrogation.export import read_csv

    _scan, d = dented
    back = read_csv(d.to_csv(tmp_path / "deviation.csv") or tmp_path / "deviation.csv")
    assert np.array_equal(back.columns["distance"], d.distance) and np.array_equal(back.columns["face"], d.face)
    assert np.array_equal(back.columns["u"], d.uv[:, 0]) and np.array_equal(back.columns["band"], d.band)
    assert repr(d.tolerance[1]) in back.meta["tolerance"]
    stats = read_csv(d.stats.to_csv(tmp_path / "stats.csv") or tmp_path / "stats.csv")
    values = dict(zip(stats.columns["statistic"], stats.columns["value"]))
    assert values["mean"] == d.stats.mean and values["max_below"] == d.stats.max_below
