"""Meshes with exact curvature point data, geomview export and rendering (lab.mesh, lab.render)."""

from pathlib import Path

import numpy as np
import pytest

import lab
from lab import mesh as M
from lab import render, surfaces
from tests.picture_support import assert_like_reference

DATA = Path(__file__).parent / "data"


def test_practical_mesh_is_welded_with_exact_curvature():
    s = surfaces.practical()
    for depth in (0, 2):
        p = s.to_bezier_patches().refine(depth)
        m = p.to_mesh()
        k = 7 * 2**depth
        assert m.n_points == (k + 1) ** 2 and m.n_cells == k * k
        # each welded vertex is a grid point of the B-spline: compare with the B-spline's own curvature
        grid = np.linspace(0, 7, k + 1)
        U, V = np.meshgrid(grid, grid, indexing="ij")
        pts = s.evaluate(U, V).reshape(-1, 3)
        c = s.curvature(U, V)
        order = np.argmin(np.linalg.norm(m.points[:, None, :] - pts[None], axis=-1), axis=1)
        np.testing.assert_allclose(m.points, pts[order], atol=1e-12)
        np.testing.assert_allclose(m.point_data["K"], c.K.ravel()[order], rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(m.point_data["H"], c.H.ravel()[order], rtol=1e-10, atol=1e-12)
    # no boundary edges inside: only the outer rim of the square domain is boundary
    edges = m.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                    non_manifold_edges=False)
    assert edges.n_cells == 4 * k


def test_finer_resolution_samples_exactly():
    p = surfaces.saddle().to_bezier_patches()
    m = M.patches_mesh(p, resolution=4)
    assert m.n_points == 25
    np.testing.assert_allclose(m.point_data["K"], -4 / (1 + 4 * m.points[:, 0] ** 2 + 4 * m.points[:, 1] ** 2) ** 2,
                               rtol=1e-12)


def test_closed_surfaces_weld_their_seams():
    t = M.surface_mesh(surfaces.torus(), 17, 13)
    assert t.n_points == 16 * 12
    edges = t.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                    non_manifold_edges=False)
    assert edges.n_cells == 0  # a closed torus
    with pytest.warns(lab.DegeneratePointWarning):
        s = M.surface_mesh(surfaces.sphere(1.0), 9, 7)
    assert s.n_points == 8 * 5 + 2  # each pole is one point
    np.testing.assert_allclose(s.point_data["K"], 1.0, rtol=1e-9)
    assert s.point_data["degenerate"].sum() == 2


def test_off_round_trip(tmp_path):
    p = surfaces.practical().to_bezier_patches().refine(1)
    p.visualize_curvature("gaussian", "linear")
    m = p.to_mesh()
    path = tmp_path / "practical.off"
    M.write_off(m, path)
    lines = path.read_text().splitlines()
    assert lines[0] == "COFF" and lines[1] == f"{m.n_points} {m.n_cells} 0"
    points, faces, colors = M.read_off(path)
    np.testing.assert_array_equal(points, m.points)
    np.testing.assert_array_equal(np.array(faces), m.faces.reshape(-1, 5)[:, 1:])
    np.testing.assert_allclose(colors[:, :3], m.point_data["RGB"] / 255, atol=1e-6)
    np.testing.assert_array_equal(colors[:, 3], 1.0)
    plain = m.copy()
    del plain.point_data["RGB"]
    M.write_off(plain, tmp_path / "plain.off")
    points, faces, colors = M.read_off(tmp_path / "plain.off")
    assert colors is None and len(faces) == m.n_cells
    with pytest.raises(ValueError, match="not an OFF file"):
        (tmp_path / "x.off").write_text("PLY\n")
        M.read_off(tmp_path / "x.off")


@pytest.mark.parametrize("rational", [False, True])
def test_cbez_round_trip(tmp_path, rng, rational):
    nets = rng.normal(size=(5, 4, 4, 3))
    w = rng.uniform(0.5, 2, size=(5, 4, 4)) if rational else None
    p = lab.BezierPatches(nets, w)
    p.visualize_curvature("mean", "linear")
    path = tmp_path / "p.bez"
    p.write_cbez(path)
    assert path.read_text().splitlines()[0] == ("CBEZ334" if rational else "CBEZ333")
    got, gw, colors = M.read_cbez(path)
    np.testing.assert_allclose(got, nets, rtol=1e-15, atol=1e-15)
    if rational:
        np.testing.assert_allclose(gw, w, rtol=1e-15)
    np.testing.assert_allclose(colors[..., :3], p.colors, atol=1e-6)  # c00, c01, c10, c11 in geomview's order


def test_cbez_layout_u_fastest_and_corner_colours(tmp_path):
    net = np.arange(2 * 3 * 3, dtype=float).reshape(2, 3, 3)  # degree (1, 2)
    p = lab.BezierPatches(net)
    p[0].set_colors((1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1))
    p.write_cbez(tmp_path / "one.bez")
    lines = (tmp_path / "one.bez").read_text().split("\n")
    assert lines[0] == "CBEZ123"
    # vertex(u=0,v=0) vertex(1,0) then vertex(0,1) ...
    assert [list(map(float, x.split())) for x in lines[1:4]] == [list(net[0, 0]), list(net[1, 0]), list(net[0, 1])]
    # RGBA(0,0) RGBA(0,Nv) RGBA(Nu,0) RGBA(Nu,Nv)
    assert lines[7:11] == ["1 0 0 1", "0 1 0 1", "0 0 1 1", "1 1 1 1"]


def test_cbez_errors(tmp_path):
    p = lab.BezierPatches(np.zeros((1, 8, 2, 3)))
    with pytest.raises(ValueError, match=r"geomview BEZ patches need degrees 1..6 in u and v; got \(7, 1\)"):
        p.write_cbez(tmp_path / "x.bez")
    q = lab.BezierPatches(np.zeros((1, 2, 2, 3)))
    with pytest.raises(ValueError, match="call visualize_curvature \\(or set_colors\\) before write_cbez"):
        q.write_cbez(tmp_path / "x.bez")


def test_render_matches_stored_reference(tmp_path):
    """The practical's surface, Gaussian curvature, linear map, depth 2, against a stored picture."""

    p = surfaces.practical().to_bezier_patches().refine(2)
    p.visualize_curvature("gaussian", "signed-log")
    image = render.screenshot(p.to_mesh(), tmp_path / "practical.png", window_size=(320, 240))
    assert image.shape == (240, 320, 3)
    assert_like_reference(image, DATA / "practical_gaussian_signed_log.png", tmp_path)
    # and it is not blank: the surface covers a good part of the picture and is coloured
    assert np.mean(np.any(image < 250, axis=-1)) > 0.1


def test_mesh_normals_and_parameters():
    with pytest.warns(lab.DegeneratePointWarning):
        m = M.surface_mesh(surfaces.sphere(2.0), 9, 7)
    N = m.point_data["N"]
    np.testing.assert_allclose(np.linalg.norm(N, axis=1), 1.0, rtol=1e-12)
    # outward normals on this sphere, including the poles (filled from the mesh there)
    np.testing.assert_allclose(np.einsum("ij,ij->i", N, m.points / 2.0), 1.0, atol=0.05)
    interior = ~m.point_data["degenerate"]
    np.testing.assert_allclose(np.einsum("ij,ij->i", N, m.points / 2.0)[interior], 1.0, atol=1e-12)
    t = M.surface_mesh(surfaces.torus(), 9, 9)
    uv = t.point_data["uv"]
    assert uv.shape == (64, 2) and uv.min() == 0 and uv.max() < 1  # the seam keeps u = 0, not an average
    np.testing.assert_allclose(t.points, surfaces.torus().evaluate(uv[:, 0], uv[:, 1]), atol=1e-12)
    assert surfaces.torus().periodic == (True, True) and surfaces.practical().periodic == (False, False)


def _sine_wave_mesh():
    with pytest.warns(lab.DegeneratePointWarning):  # the centre rho = 0 is a collapsed edge
        return M.surface_mesh(surfaces.sine_wave(), 96, 96)


def test_collapsed_edges_become_triangles_and_vtk_normals_agree_with_the_exact_ones():
    """Dill's sine wave of revolution: its edge rho = 0 collapses to the centre.

    Welded quads (c, c, a, b) there used to reach VTK as quads; its normal
    filter (run by PyVista for smooth shading) then flipped all cells but a
    strip at the seam, and the vertex normals on the strip's borders nearly
    cancelled: the dark streak from the centre outwards.
    """
    m = _sine_wave_mesh()
    faces = M.build._faces(m)
    assert sum(len(f) == 3 for f in faces) == 95 and all(len(set(f)) == len(f) for f in faces)
    assert m.n_cells == 95 * 95
    shaded = m.compute_normals(cell_normals=True, split_vertices=False)  # what smooth shading computes
    assert np.all(np.asarray(shaded.cell_data["Normals"])[:, 2] > 0)  # one orientation: up, as b_u x b_v
    cos = np.einsum("ij,ij->i", shaded.point_data["Normals"], m.point_data["N"])
    assert cos.min() > 0.99  # before the fix: 8836 of 9026 vertices below 0.9 (flipped or cancelled)
    with pytest.warns(lab.DegeneratePointWarning):
        s = M.surface_mesh(surfaces.sphere(1.0), 9, 7)
    assert sum(len(f) == 3 for f in M.build._faces(s)) == 2 * 8  # a fan of triangles at each pole
    assert s.n_cells == 8 * 6


def test_sine_wave_is_shaded_without_a_streak():
    """A uniformly coloured sine wave seen from above with a headlight is rotationally symmetric in brightness."""
    import pyvista as pv

    render.configure_offscreen()
    m = _sine_wave_mesh()
    plotter = pv.Plotter(off_screen=True, window_size=[400, 400], lighting="none")
    plotter.add_light(pv.Light(light_type="headlight"))
    plotter.set_background("black")
    plotter.add_mesh(m, color="white", smooth_shading=True)  # smooth shading as render.show and the CLI draw it
    plotter.camera_position = [(0, 0, 40), (0, 0, 0), (0, 1, 0)]
    plotter.camera.parallel_projection = True
    plotter.reset_camera()
    image = np.asarray(plotter.screenshot(None, return_img=True), dtype=float).mean(axis=-1)
    plotter.close()
    # compare each pixel with its mirror image across the centre: the seam (phi = 0, +x) against phi = pi
    ys, xs = np.nonzero(image > 0)
    cy, cx = (ys.min() + ys.max()) / 2, (xs.min() + xs.max()) / 2
    h, w = image.shape
    yy, xx = np.mgrid[0:h, 0:w]
    r = np.hypot(yy - cy, xx - cx)
    disc = r < 0.9 * min(cy - ys.min(), cx - xs.min())
    mirror = image[np.clip(np.round(2 * cy - yy).astype(int), 0, h - 1), np.clip(np.round(2 * cx - xx).astype(int), 0, w - 1)]
    diff = np.abs(image - mirror)[disc]
    # measured: mirrored pixels differ by at most 1 grey level; with the streak 5.1 % of the disc
    # differed by more than 40 (a light position or driver change moves pixels by a few levels only)
    assert np.mean(diff > 40) < 0.002, f"{np.mean(diff > 40):.2%} of the disc differs from its mirror image"


def test_color_cells_colours_each_polygon_by_the_mean_of_its_vertices():
    """Dill's polygons (Dill 1981, "Image generation"): values averaged over the vertices, then the colour table."""
    t = surfaces.torus(2.0, 1.0)
    m = M.surface_mesh(t, 67, 67)  # 66 cells around the tube: the rims u = 1/4, 3/4 run through cell centres
    flat = M.color_cells(m, "gaussian", "dill")
    faces = M.build._faces(m)
    expected = np.array([m.point_data["K"][f].mean() for f in faces])
    np.testing.assert_allclose(flat.cell_data["values"], expected, rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(flat.cell_data["RGB"], np.round(255 * lab.colormaps.dill(expected)))
    assert "RGB" not in flat.point_data and "RGB" not in m.cell_data  # a copy
    # named cells: outside red (K = 1/3), inside blue (K = -1), on the rims yellow (K ~ 0)
    centre = np.array([m.points[f].mean(axis=0) for f in faces])
    rho = np.hypot(centre[:, 0], centre[:, 1])
    names = lab.colormaps.dill_names(expected)
    on_rim = np.abs(rho - 2.0) < 0.05
    assert on_rim.sum() == 2 * 66 and set(names[on_rim]) == {"yellow"}
    assert set(names[rho > 2.5]) == {"red"} and set(names[rho < 1.5]) == {"blue"}
    # without a map: the mean of the vertices' colours
    m.point_data["RGB"] = np.tile(np.array([[255, 0, 0], [0, 0, 255]], np.uint8), (m.n_points // 2 + 1, 1))[: m.n_points]
    plain = M.color_cells(m)
    np.testing.assert_allclose(plain.cell_data["RGB"], [np.round(m.point_data["RGB"][f].mean(axis=0)) for f in faces], atol=0.5)
    with pytest.raises(ValueError, match="needs a curvature mode and a colour map, or a mesh with RGB point colours"):
        M.color_cells(M.surface_mesh(t, 5, 5))


def _hue_outliers(image, colours):
    """Fraction of surface pixels (away from its silhouette) whose colour is no shade of one of ``colours``."""
    from scipy.ndimage import binary_erosion

    img = np.asarray(image, dtype=float)[..., :3]
    surface = binary_erosion(np.any(np.abs(img - 255) > 8, axis=-1), iterations=2)  # not the background
    img = img[surface & (img.max(axis=-1) > 40)]
    unit = img / np.linalg.norm(img, axis=1, keepdims=True)
    c = np.asarray(colours, float) / np.linalg.norm(colours, axis=1, keepdims=True)
    return np.mean((unit @ c.T).max(axis=1) < 0.995)


def _distinct_colours(image):
    img = np.asarray(image)[..., :3]
    return len(np.unique(img[np.any(img < 247, axis=-1)].reshape(-1, 3), axis=0))


def test_flat_shading_draws_each_polygon_in_one_of_dills_colours():
    import io

    from PIL import Image

    t = surfaces.torus(2.0, 1.0)
    kwargs = {"curvature": "gaussian", "color_map": "dill", "n": 19, "window_size": (640, 480)}  # 18 x 18 big polygons
    flat = np.asarray(Image.open(io.BytesIO(render.show(t, shading="flat", **kwargs).data)))
    smooth = np.asarray(Image.open(io.BytesIO(render.show(t, **kwargs).data)))
    # a light at the eye with ambient + Lambert only scales a polygon's one colour: every pixel is a shade
    # of one of the five colours, except anti-aliased polygon borders (measured 1.2 % of the pixels);
    # smooth shading blends neighbouring colours (measured 11.7 %)
    assert _hue_outliers(flat, lab.colormaps.DILL_COLORS) < 0.03
    assert _hue_outliers(smooth, lab.colormaps.DILL_COLORS) > 0.06
    # and one shade per polygon: few distinct colours (measured 339 flat, 1870 smooth)
    assert _distinct_colours(flat) < _distinct_colours(smooth) / 3
    with pytest.raises(ValueError, match="shading must be 'smooth' or 'flat'; got 'phong'"):
        render.show(t, shading="phong")


def test_welding_is_by_index_never_by_distance():
    # a cylinder whose seam is declared periodic is welded there; the same geometry declared open is not,
    # although the seam's points coincide exactly: welding follows the parameter grid, not distances
    closed = surfaces.cylinder(1.0, 2.0)
    assert closed.seams.periodic == (True, False)
    m = M.surface_mesh(closed, 13, 5)
    assert m.n_points == 12 * 5
    opened = surfaces.cylinder(1.0, 2.0)
    opened.periodic = (False, False)
    m = M.surface_mesh(opened, 13, 5)
    assert m.n_points == 13 * 5
    assert np.isclose(np.linalg.norm(m.points[:5] - m.points[-5:], axis=1).max(), 0.0, atol=1e-12)
    # nodes that come close without being the same parameter stay apart: a grid finer than the weld tolerance
    fine = M.surface_mesh(surfaces.practical(), 3, 3)
    tiny = surfaces.plane(1e-11)
    assert M.surface_mesh(tiny, 4, 4).n_points == 16 and fine.n_points == 9


def test_seams_come_from_the_structure():
    assert surfaces.sphere().seams == ((True, False), ((False, False), (True, True)))
    assert surfaces.torus().seams == ((True, True), ((False, False), (False, False)))
    assert surfaces.cone().seams.collapsed == ((False, False), (False, True))  # the apex edge v = 1
    assert surfaces.sine_wave().seams == ((False, True), ((True, False), (False, False)))  # the centre, analytic
    assert surfaces.practical().seams == ((False, False), ((False, False), (False, False)))
    p = surfaces.sphere().to_bezier_patches()
    assert p.seams == surfaces.sphere().seams and p.refine(1).seams == p.seams
    with pytest.warns(lab.DegeneratePointWarning):
        m = p.to_mesh(resolution=2)
    edges = m.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                    non_manifold_edges=False)
    assert edges.n_cells == 0  # closed: the seam and both poles are welded
    # 4 x 2 patches refined once: 8 x 4, at resolution 2 a grid of 17 x 9 nodes: 16 around, 7 inner rows, 2 poles
    assert p.grid_shape == (8, 4) and m.n_points == 16 * 7 + 2


def test_large_mesh_is_welded_with_exact_curvature():
    s = surfaces.practical()
    m = M.surface_mesh(s, 449, 449)
    assert m.n_points == 449 * 449 and m.n_cells == 448 * 448
    uv = m.point_data["uv"]
    pick = np.random.default_rng(3).integers(0, m.n_points, 50)
    c = s.curvature(uv[pick, 0], uv[pick, 1])
    np.testing.assert_allclose(m.point_data["K"][pick], c.K, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(m.points[pick], s.evaluate(uv[pick, 0], uv[pick, 1]), atol=1e-13)
