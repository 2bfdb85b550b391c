"""Statements in the notebooks' text that executed cells back up (issue 11): the cells are run and their output read.

Only the cells named here (after the notebook's first code cell, its imports) are executed, in notebook order,
so the tests read exactly the code and output a student sees.
"""

import re
import tempfile
from pathlib import Path

import nbformat

from lab.teaching.kernel.notebook_client import NotebookRunner

ROOT = Path(__file__).resolve().parent.parent


def run_cells(name, ids):
    """Execute the first code cell and the cells ``ids`` of ``solutions/en/name``; their text output by id."""
    nb = nbformat.read(ROOT / "solutions" / "en" / name, as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    missing = set(ids) - {c.id for c in code}
    assert not missing, f"{name} has no code cells {missing}"
    nb.cells = [code[0]] + [c for c in code[1:] if c.id in ids]
    with tempfile.TemporaryDirectory() as tmp:
        NotebookRunner(nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": tmp}}).execute()
    out = {}
    for c in nb.cells[1:]:
        text = []
        for o in c.outputs:
            if o.output_type == "stream":
                text.append(o.text)
            elif o.output_type == "execute_result" and "text/plain" in o.data and "image/png" not in o.data:
                text.append(o.data["text/plain"])
        out[c.id] = "".join(text)
    return out


def number(pattern, text):
    match = re.search(pattern, text)
    assert match, f"{pattern!r} not in:\n{text}"
    return float(match.group(1))


def test_00_the_first_picture_is_mostly_blue_and_values_are_plain_numbers():
    out = run_cells("00_start.ipynb", ["14670f25", "8fce7930"])
    assert number(r"K < 0 \(blue\) at (\d+)%", out["14670f25"]) > 50  # "most of the surface is blue"
    assert number(r"K > 0 \(red\) at (\d+)%", out["14670f25"]) > 0  # the bump's top and two spots are red
    assert "np.float64" not in out["8fce7930"] and out["8fce7930"].startswith("Curvature(K=-0.70732")


def test_02_the_practicals_normal_points_down_and_h_is_positive_at_the_top():
    out = run_cells("02_fundamental_forms.ipynb", ["c7e6c6d6", "aa544345", "8894f39d", "0a2e0002"])["0a2e0002"]
    course, transposed = out.splitlines()
    assert "u along y: N_z = -0.89, H = +6.08, k1 = +6.64, k2 = +5.53, K = 36.68" in course
    assert "u along x: N_z = +0.89, H = -6.08, k1 = -5.53, k2 = -6.64, K = 36.68" in transposed


def test_04_a_cylinders_k_is_exactly_zero_only_when_it_is_not_tilted():
    out = run_cells("04_color_maps.ipynb", ["5e3ced60", "04c0a002"])["04c0a002"]
    upright, tilted = out.splitlines()
    assert upright.startswith("cylinder along z: 0 of 256 corner values differ from 0")
    assert number(r"tilted cylinder: (\d+) of 256", tilted) > 100  # rounding noise, of either sign
    assert "your f3 paints 256 of them green" in tilted


def test_05_refine_works_in_place():
    out = run_cells("05_visualize_curvature.ipynb", ["53d32008"])["53d32008"]
    assert out.splitlines() == ["49 patches", "196 patches after refine(1); refine returned the same collection: True"]


def test_05_the_ranges_the_text_and_the_readme_state():
    """05: the bump's top is the largest H and K at the corners of depth 1 and 3, not from depth 4 on (the
    surface's maximum lies between those corners); the picture's caption (lab.view.gallery: the README's and the
    site's) states the depth-1 range."""
    out = run_cells("05_visualize_curvature.ipynb", ["53d32008", "5ca1e5d0"])["5ca1e5d0"]
    ranges = {}
    for line in out.splitlines():
        depth, kmin, kmax, hmin, hmax = re.match(
            r"depth (\d): K from (\S+) to (\S+), H from (\S+) to (\S+)$", line).groups()
        ranges[int(depth)] = tuple(float(x) for x in (kmin, kmax, hmin, hmax))
    top_h = 6.08  # the practical's value at the bump's top (the practical's course program), the intro's H ≈ +6.08
    assert abs(ranges[1][3] - top_h) < 0.01 and abs(ranges[3][3] - top_h) < 0.01
    assert ranges[1][1] == ranges[3][1] and ranges[4][1] > ranges[3][1] + 10 and ranges[4][3] > top_h + 1
    from lab.view.gallery import PICTURES

    text = next(caption for name, _options, caption in PICTURES if name == "practical_gaussian_linear.png")
    caption = re.search(r"[Tt]he bump's top \(K ≈ (\d+) at the corners\).*?K\s+from (\S+) to (\S+), is blue", text,
                        re.DOTALL)
    assert caption, "the caption of the practical's picture"
    assert int(caption.group(1)) == round(ranges[1][1])
    assert float(caption.group(2).replace("−", "-")) == round(ranges[1][0], 1)

    import lab

    K = lab.surfaces.practical().to_bezier_patches().refine(1).corner_curvature().K
    rest = K[K < K.max() / 2]  # "everything else": the corners beside the top
    assert float(caption.group(3)) == round(float(rest.max()), 2)


def test_06_cylinder_sheets_and_dropped_rims():
    out = run_cells("06_focal_surfaces.ipynb", ["6c1f0a01", "9dd9011d"])
    cyl, torus = out["6c1f0a01"], out["9dd9011d"]
    assert "k1 = +0, k2 = -1" in cyl
    assert "warning: focal sheet of k1: dropped 240 of 240 vertices" in cyl
    assert "first sheet: 0 points left" in cyl  # at infinity
    assert number(r"second sheet: 240 points, largest distance from the axis (\S+):", cyl) < 1e-12  # the axis
    assert "warning: focal sheet of k2: dropped 96 of 2304 vertices" in torus  # the two rims, 48 vertices each
    assert "0 and 96 vertices dropped" in torus
    assert "first sheet: distance from the axis 2.000000 ... 2.000000" in torus


def test_07_the_papers_stripes_against_the_exact_split():
    out = run_cells("07_reflection_lines.ipynb", ["b57a6a34", "07a1b002"])["07a1b002"]
    assert number(r"plane .*colours differ on ([\d.]+) %", out) < 0.2
    assert number(r"hood .*colours differ on ([\d.]+) %", out) < 1.0
    coarse, fine = (number(rf"torus {n}: colours differ on ([\d.]+) %", out) for n in (96, 192))
    assert coarse > 5 and fine < 1  # the text: about 10 % drops to under 1 %


def test_08_figure_1_closes_as_many_curves_as_the_paper_from_an_edge_point():
    out = run_cells("08_geodesics_isodistance.ipynb", ["08f10002"])["08f10002"]
    assert "start (0.1, 0.5): 2 of 15 curves closed (s_L = 0.3, 0.6)" in out
    assert "start (0.5, 0.4): 10 of 15 curves closed" in out
    assert "paper, figure 1: 2 of 15 closed (s_L = 0.3, 0.6)" in out


def test_09_dills_colours_at_named_points():
    out = run_cells("09_dill_gallery.ipynb", ["edd5e251", "ddf0ebc7", "194357a0"])
    torus, catenoid, hood = out["edd5e251"], out["ddf0ebc7"], out["194357a0"]
    assert re.search(r"outer equator .*K = \+0\.3333 -> red", torus)
    assert re.search(r"top rim .*K = [+-]0\.0000 -> yellow", torus)  # K = 0 is yellow, not red
    assert re.search(r"inner equator .*K = -1\.0000 -> blue", torus)
    lines = catenoid.splitlines()
    assert lines[0].endswith("-> blue") and lines[-1].endswith("-> yellow")  # waist -1, ends near 0
    assert all(number(r"H = ([\d.e+-]+)", line) < 1e-12 for line in lines)  # a minimal surface
    assert re.search(r"crown .*-> red", hood) and re.search(r"flank of the crease .*-> blue", hood)
    assert re.search(r"flat spot \(back outside\) +K = [+-]0\.00000 1/m² -> yellow", hood)


def test_10_trimming_statements():
    out = run_cells("10_trimmed_surfaces.ipynb", ["10a00004", "10a00006", "10a00009", "10a0000b", "10a0000e"])
    areas = [float(a) for a in re.findall(r"[+-][\d.]+", out["10a00009"].splitlines()[0])]
    assert areas[0] > 0 and all(a < 0 for a in areas[1:])  # outer counter-clockwise, holes clockwise
    assert "ValueError: outer loop runs clockwise" in out["10a00009"]
    assert number(r"smallest angle ([\d.]+)°", out["10a0000b"]) >= 20.0
    covered = re.search(r"cover ([\d.]+) of the region's ([\d.]+)", out["10a0000b"])
    assert covered.group(1) == covered.group(2)
    assert number(r"largest \|K\(mesh\) - K\(surface\)\| = (\S+)\n", out["10a0000e"]) == 0.0


def test_13_what_the_triangulation_skinny_triangles_and_the_estimators_do():
    out = run_cells("13_meshes_and_scans.ipynb", ["13a00009", "13a0000b", "13a0000f"])
    orders = {(s, d): (float(k), float(h)) for s, d, k, h in re.findall(
        r"(torus|saddle) +(\w+) *: inside, order of K (\S+), of H (\S+);", out["13a00009"])}
    assert len(orders) == 6 and all(abs(p - 2) < 0.15 for p in orders["torus", "regular"] + orders["saddle", "regular"])
    for d in ("alternating", "random"):  # "on the torus the order falls to about 1; on the saddle ... about 0"
        assert all(abs(p - 1) < 0.2 for p in orders["torus", d]) and all(abs(p) < 0.2 for p in orders["saddle", d])
    # "the mean curvature can change its sign" on the thinnest triangles, not on the square grid
    flips = [int(n) for n in re.findall(r"H of the wrong sign at (\d+) of", out["13a0000b"])]
    assert flips[0] == 0 and flips[-1] > 0
    tables = out["13a0000f"].split("saddle")
    random = tables[-1]  # "on the mesh with random diagonals VTK's K is off by almost half"
    assert 0.35 < number(r"\nVTK +(\S+)", random) < 0.5
    regular = tables[1]  # "the quadric fit ... stays within a few per cent" at the boundary; VTK's, libigl's 2π worse
    quadric = re.search(r"libigl quadric +\S+ +(\S+) +\S+ +(\S+)", regular).groups()
    assert all(float(x) < 0.05 for x in quadric)
    lab_k, vtk_k, igl_k = (number(rf"\n{name} +\S+ +(\S+)", regular) for name in ("lab", "VTK", "libigl"))
    assert vtk_k > 3 * lab_k and igl_k > 3 * lab_k
