"""Focal surfaces, focal sheets and parabolic lines (lab.focal, lab.interrogation; Choi & Lee, §4)."""

import warnings

import numpy as np
import pytest
import pyvista

import lab
from lab import focal, surfaces
from lab.interrogation import meshes as I
from lab.mesh import surface_mesh


@pytest.fixture(scope="module")
def sphere_mesh():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", lab.DegeneratePointWarning)  # the poles
        return surface_mesh(surfaces.sphere(2.0), 33, 33)


# -- generalized focal surface F = X + a f(k1, k2) N (eq. 9) -------------------------------------------


@pytest.mark.parametrize(
    "function, f_expected",
    [("mean", -1 / 2), ("gaussian", 1 / 4), ("strain-energy", 2 / 4), ("k1", -1 / 2), ("k2", -1 / 2)],
)
def test_sphere_focal_surface_moves_every_point_by_a_f_along_the_normal(sphere_mesh, function, f_expected):
    # sphere r = 2, outward N: H = k1 = k2 = -1/r, K = 1/r^2; F = X + a f X / r exactly
    a = 0.5
    F = I.focal_surface(sphere_mesh, scale=a, function=function)
    X = sphere_mesh.points
    np.testing.assert_allclose(F.point_data["f"], f_expected, rtol=1e-10)
    ok = ~sphere_mesh.point_data["degenerate"]
    np.testing.assert_allclose(F.points[ok], X[ok] * (1 + a * f_expected / 2), atol=1e-12)
    # the two poles: lab.mesh takes N from VTK's float32 mesh normals there, ~6e-10 rad off
    np.testing.assert_allclose(F.points[~ok], X[~ok] * (1 + a * f_expected / 2), atol=1e-8)
    np.testing.assert_allclose(F.point_data["displacement"], a * f_expected, rtol=1e-10)
    assert F.n_cells == sphere_mesh.n_cells and np.array_equal(F.faces, sphere_mesh.faces)  # same connectivity


def test_mean_focal_surface_of_sphere_lies_a_over_r_inside(sphere_mesh):
    a, r = 0.3, 2.0
    F = I.focal_surface(sphere_mesh, a, "mean")
    moved = np.linalg.norm(F.points - sphere_mesh.points, axis=1)
    np.testing.assert_allclose(moved, a / r, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(F.points, axis=1), r - a / r, rtol=1e-12)  # inwards


def test_focal_surface_of_plane_is_the_plane():
    for function in ("gaussian", "mean", "strain-energy", "k1", "k2"):
        F = I.focal_surface(surfaces.plane(2.0), scale=10.0, function=function, resolution=9)
        np.testing.assert_array_equal(F.points, F.point_data["X"])


def test_callable_and_curvature_mode_functions(sphere_mesh):
    F = I.focal_surface(sphere_mesh, 1.0, lambda k1, k2: k1 - k2)  # umbilic: no offset
    np.testing.assert_allclose(F.points, sphere_mesh.points, atol=1e-12)
    G = I.focal_surface(sphere_mesh, 1.0, lab.CurvatureMode.GAUSSIAN)
    np.testing.assert_allclose(G.point_data["f"], 0.25, rtol=1e-10)
    assert G.field_data["function"][0] == "gaussian"


def test_focal_surface_accepts_bezier_patches_and_does_not_modify_the_mesh():
    p = surfaces.saddle().to_bezier_patches()
    F = I.focal_surface(p, 0.1, "gaussian", resolution=4)
    m = p.to_mesh(4)
    np.testing.assert_allclose(F.point_data["X"], m.points)
    # z = x^2 - y^2: K = -4 / (1 + 4x^2 + 4y^2)^2 < 0, so every point moves against N
    np.testing.assert_allclose(F.point_data["f"], m.point_data["K"], rtol=1e-12)
    before = m.points.copy()
    I.focal_surface(m, 1.0, "mean")
    np.testing.assert_array_equal(m.points, before)


# -- classical focal sheets X + N / k_i --------------------------------------------------------------


def test_sphere_focal_sheets_collapse_to_the_centre(sphere_mesh):
    with warnings.catch_warnings():
        warnings.simplefilter("error", I.FocalSheetWarning)
        s1, s2 = I.focal_sheets(sphere_mesh)
    ok = ~sphere_mesh.point_data["degenerate"]
    for s in (s1, s2):
        assert s.field_data["dropped"][0] == 0 and s.n_points == sphere_mesh.n_points
        assert np.abs(s.points[ok]).max() < 1e-12
        assert np.abs(s.points[~ok]).max() < 1e-8  # the poles' float32 mesh normals (see above)
        np.testing.assert_allclose(s.point_data["radius"], -2.0, rtol=1e-10)


def test_cylinder_sheets_are_the_axis_and_a_dropped_sheet():
    r, h = 1.5, 2.0
    with pytest.warns(I.FocalSheetWarning, match=r"focal sheet of k1: dropped 272 of 272 vertices"):
        s1, s2 = I.focal_sheets(surfaces.cylinder(r, h), resolution=17)
    # k1 = 0 everywhere: centres at infinity, all dropped (and said so)
    assert s1.n_points == 0 and s1.field_data["dropped"][0] == 272
    # k2 = -1/r: the centres of curvature are on the axis, at the height of the surface point
    assert s2.field_data["dropped"][0] == 0 and s2.n_points == 272
    assert np.abs(s2.points[:, :2]).max() < 1e-12
    np.testing.assert_allclose(s2.points[:, 2], s2.point_data["X"][:, 2], atol=1e-12)


def test_torus_sheets_are_the_core_circle_and_the_axis():
    R, r = 2.0, 0.5
    with pytest.warns(I.FocalSheetWarning, match="focal sheet of k2: dropped 32 of 256"):
        s1, s2 = I.focal_sheets(surfaces.torus(R, r), resolution=17)
    # the tube's centres of curvature: the core circle rho = R, z = 0
    np.testing.assert_allclose(np.hypot(s1.points[:, 0], s1.points[:, 1]), R, rtol=1e-10)
    assert np.abs(s1.points[:, 2]).max() < 1e-10
    # the other centres lie on the axis of revolution; dropped: the two rims where k2 = 0 (2 x 16 vertices)
    assert np.hypot(s2.points[:, 0], s2.points[:, 1]).max() < 1e-9
    dropped_z = np.setdiff1d(np.round(s1.point_data["X"][:, 2], 9), np.round(s2.point_data["X"][:, 2], 9))
    np.testing.assert_allclose(np.sort(dropped_z), [-r, r], rtol=1e-9)
    # cells touching a dropped vertex are gone: 2 rims x 16 vertices, each in 4 quads, 2 rows of 16 quads per rim
    assert s2.n_cells == 256 - 2 * 2 * 16


def test_focal_sheet_keeps_by_tolerance():
    X = np.zeros((3, 3))
    N = np.tile([0.0, 0.0, 1.0], (3, 1))
    F, keep = focal.focal_sheet(X, N, np.array([2.0, 1e-3, -0.5]), tol=1e-2)
    np.testing.assert_array_equal(keep, [True, False, True])
    np.testing.assert_allclose(F[[0, 2], 2], [0.5, -2.0])
    assert np.all(np.isnan(F[1]))


# -- parabolic lines: K changes sign ---------------------------------------------------------------


def test_torus_parabolic_lines_are_the_rims_through_grid_nodes():
    # 17 x 17 grid: the rims t = +-pi/2 are grid rows where K = 0 up to rounding; the lines run through them
    R, r = 2.0, 0.5
    lines = I.polylines(I.parabolic_lines(surfaces.torus(R, r), resolution=17))
    assert len(lines) == 2
    for p in lines:
        assert np.array_equal(p[0], p[-1]) and len(p) == 17  # closed, through the 16 rim vertices
        np.testing.assert_allclose(np.abs(p[:, 2]), r, rtol=1e-12)
        np.testing.assert_allclose(np.hypot(p[:, 0], p[:, 1]), R, rtol=1e-12)
    assert sorted(np.sign(p[0, 2]) for p in lines) == [-1, 1]


def test_torus_parabolic_lines_between_grid_nodes():
    # 20 x 20 grid: the rims fall between grid rows; the zero of the linearly interpolated K lies within
    # one grid step (2 pi r / 19 ~ 0.17) of the true rim and on its chordal approximation
    R, r = 2.0, 0.5
    lines = I.polylines(I.parabolic_lines(surfaces.torus(R, r), resolution=20))
    assert len(lines) == 2
    for p in lines:
        assert np.array_equal(p[0], p[-1])
        t = np.arctan2(np.abs(p[:, 2]), np.hypot(p[:, 0], p[:, 1]) - R)  # angle around the tube
        assert np.abs(t - np.pi / 2).max() < 2 * np.pi / 19


def test_no_parabolic_lines_where_K_has_one_sign_or_vanishes_over_an_area(sphere_mesh):
    for s in (surfaces.plane(), surfaces.cylinder(), surfaces.saddle()):
        assert I.parabolic_lines(s, resolution=17).n_cells == 0
    assert I.parabolic_lines(sphere_mesh).n_cells == 0


def test_zero_rule_of_the_level_set():
    # a flat 7 x 3 grid with hand-made K: a row of zeros between + and - is a line through those vertices;
    # a zero area bordering one sign only (a flat spot) is no line
    x, y = np.meshgrid(np.arange(7.0), np.arange(3.0), indexing="ij")
    X = np.stack([x, y, 0 * x], -1).reshape(-1, 3)
    idx = np.arange(21).reshape(7, 3)
    T = np.concatenate([
        np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:]], -1).reshape(-1, 3),
        np.stack([idx[:-1, :-1], idx[1:, 1:], idx[:-1, 1:]], -1).reshape(-1, 3),
    ])
    K = np.repeat([1.0, 1.0, 0.0, -1.0, -1.0, -1.0, -1.0], 3)
    lines = focal.parabolic_lines(X, T, K, tol=0.0)
    assert len(lines) == 1
    np.testing.assert_array_equal(lines[0][:, 0], 2.0)  # along the zero row x = 2
    assert np.ptp(lines[0][:, 1]) == 2.0
    K_flat = np.repeat([0.0, 0.0, 0.0, -1.0, -1.0, -1.0, -1.0], 3)  # flat spot next to K < 0
    assert focal.parabolic_lines(X, T, K_flat, tol=0.0) == []
    K_noise = K_flat + 1e-20 * np.sin(np.arange(21.0))  # rounding noise below tol counts as zero
    assert focal.parabolic_lines(X, T, K_noise, tol=1e-15) == []
    K_cross = np.repeat([1.0, 1.0, 0.5, -0.5, -1.0, -1.0, -1.0], 3)  # crossing between rows: at x = 2.5
    (line,) = focal.parabolic_lines(X, T, K_cross, tol=0.0)
    np.testing.assert_allclose(line[:, 0], 2.5)


def test_parabolic_lines_are_where_the_gaussian_focal_surface_meets_the_surface():
    # practical(): K changes sign.  Every line point lies on a mesh edge whose ends the focal surface of K
    # (displacement a K along N) moves to opposite sides, at the zero of the interpolated displacement.
    m = surface_mesh(surfaces.practical(), 30, 30)
    lines = I.polylines(I.parabolic_lines(m))
    K = m.point_data["K"]
    assert K.min() < 0 < K.max() and len(lines) >= 1
    d = I.focal_surface(m, 2.0, "gaussian").point_data["displacement"]
    T = I._triangles(m)
    edges = np.unique(np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1), axis=0)
    A, B = m.points[edges[:, 0]], m.points[edges[:, 1]]
    for p in np.concatenate(lines):
        s = np.clip(np.einsum("ij,ij->i", p - A, B - A) / np.einsum("ij,ij->i", B - A, B - A), 0, 1)
        dist = np.linalg.norm(A + s[:, None] * (B - A) - p, axis=1)
        on = dist < 1e-9
        assert np.any(on)
        e, t = edges[on], s[on]
        da, db = d[e[:, 0]], d[e[:, 1]]
        assert np.any((da * db <= 0) & (np.abs((1 - t) * da + t * db) <= 1e-12 * np.abs(d).max()))


# -- errors ------------------------------------------------------------------------------------


def test_errors(sphere_mesh):
    with pytest.raises(ValueError, match=r"unknown focal function 'curvy'; expected one of 'gaussian'"):
        I.focal_surface(sphere_mesh, 1.0, "curvy")
    with pytest.raises(TypeError, match="function must be a name or a callable"):
        I.focal_surface(sphere_mesh, 1.0, 3)
    with pytest.raises(ValueError, match=r"needs curvature point data K, H, k1, k2, N; missing K, H, k1, k2, N"):
        I.focal_surface(pyvista.Sphere(), 1.0)
    with pytest.raises(TypeError, match="expected a lab.Surface, a lab.BezierPatches, a lab.Model or a pyvista.PolyData"):
        I.focal_sheets(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="resolution applies to surfaces and patches only"):
        I.parabolic_lines(sphere_mesh, resolution=10)
    with pytest.raises(ValueError, match="tol must be a positive number"):
        I.focal_sheets(sphere_mesh, tol=-1)
    with pytest.raises(ValueError, match="tol must be >= 0; got nan"):
        I.parabolic_lines(sphere_mesh, tol=np.nan)
    with pytest.raises(TypeError, match="scale must be a real number; got str 'big'"):
        I.focal_surface(sphere_mesh, "big")
    with pytest.raises(ValueError, match="resolution must be an integer >= 2"):
        I.focal_surface(surfaces.plane(), 1.0, resolution=1)
