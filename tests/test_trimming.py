"""Trimmed surfaces: trimming loops, their validation and triangulation, meshes (lab.trimming, lab.trimmed_mesh)."""

import warnings

import numpy as np
import pytest
from scipy.interpolate import BSpline

import lab
from lab import surfaces
from lab import trimming as T


def triangle_areas(uv, triangles):
    """Signed areas of triangles in the parameter plane."""
    X = uv[triangles]
    d1, d2 = X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]
    return 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def covering_triangles(uv, triangles, point, eps=1e-12):
    """Indices of the triangles that contain ``point`` (closed, within ``eps`` in barycentric coordinates)."""
    X = uv[triangles]
    a, b, c = X[:, 0], X[:, 1], X[:, 2]

    def cross(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0])

    area = cross(a, b, c)
    l0, l1, l2 = cross(point, b, c) / area, cross(a, point, c) / area, cross(a, b, point) / area
    return np.flatnonzero((l0 >= -eps) & (l1 >= -eps) & (l2 >= -eps))


def polygon_area_of_circle(r, n):
    """Area of the regular n-gon inscribed in a circle of radius r: (n/2) r² sin(2π/n)."""
    return 0.5 * n * r**2 * np.sin(2 * np.pi / n)


# -- area of a trimmed disc -------------------------------------------------------------


@pytest.mark.parametrize("n", [64, 256, 1024])
def test_disc_trimmed_from_a_plane_has_the_polygon_area_and_converges_to_pi_r2(n):
    size, r = 2.0, 0.4  # plane(size) maps [0, 1]^2 onto [0, size]^2: the disc has radius size * r in 3-D
    s = T.trimmed(surfaces.plane(size), T.circle((0.5, 0.5), r, n=n))
    uv, tri = s.triangulate(n_u=24, n_v=24)
    area_uv = triangle_areas(uv, tri)
    assert area_uv.min() > 0  # every triangle counter-clockwise, none degenerate
    polygon = polygon_area_of_circle(r, n)
    # the triangulation covers exactly the polygon bounded by the sampled loop (up to rounding)
    np.testing.assert_allclose(area_uv.sum(), polygon, rtol=1e-12)
    np.testing.assert_allclose(s.area_uv, polygon, rtol=1e-12)
    mesh = s.to_mesh(n_u=24, n_v=24)
    np.testing.assert_allclose(mesh.area, size**2 * polygon, rtol=1e-12)
    # the inscribed n-gon misses pi r^2 (1 - sin(x)/x) with x = 2 pi / n, i.e. about pi r^2 x^2 / 6
    exact = np.pi * (size * r) ** 2
    x = 2 * np.pi / n
    assert 0 < exact - mesh.area <= exact * x**2 / 6 * (1 + 1e-3)


def test_disc_from_an_exact_nurbs_circle_is_within_the_sampling_tolerance():
    r, tol = 0.4, 1e-6
    s = T.trimmed(surfaces.plane(), T.circle_curve((0.5, 0.5), r), tol=tol)
    # sampled points lie on the circle; the polygon is inscribed, so it lacks at most perimeter * tol
    np.testing.assert_allclose(np.linalg.norm(s.outer - 0.5, axis=1), r, rtol=1e-14)
    mesh = s.to_mesh()
    np.testing.assert_allclose(mesh.area, T.signed_area(s.outer), rtol=1e-12)
    assert 0 < np.pi * r**2 - mesh.area <= 2 * np.pi * r * tol


# -- holes --------------------------------------------------------------------------------


def test_a_hole_is_a_hole():
    hole = T.circle((0.4, 0.6), 0.15, n=40, clockwise=True)
    s = T.trimmed(surfaces.plane(), holes=[hole])  # outer=None: the whole domain
    uv, tri = s.triangulate(n_u=20, n_v=20)
    centre = np.array([0.4, 0.6])
    assert covering_triangles(uv, tri, centre).size == 0
    assert covering_triangles(uv, tri, np.array([0.8, 0.2])).size >= 1
    assert not s.contains(*centre) and s.contains(0.8, 0.2)
    np.testing.assert_allclose(triangle_areas(uv, tri).sum(), 1.0 - abs(T.signed_area(hole)), rtol=1e-12)
    # every point of the hole is a vertex
    k = len(hole)
    for p in hole:
        assert np.min(np.linalg.norm(uv - p, axis=1)) == 0.0
    # every edge of the hole polyline is made of boundary edges of the mesh: the boundary edges lying on
    # the hole add up to its perimeter and, oriented by their triangles, run clockwise like the hole
    edges = T.boundary_edges(tri)
    on_hole = np.all(T.distance_to_loop(uv[edges.ravel()], hole).reshape(-1, 2) <= 1e-14, axis=1)
    perimeter = np.sum(np.linalg.norm(hole - np.roll(hole, -1, axis=0), axis=1))
    lengths = np.linalg.norm(uv[edges[:, 1]] - uv[edges[:, 0]], axis=1)
    np.testing.assert_allclose(lengths[on_hole].sum(), perimeter, rtol=1e-12)
    a, b = uv[edges[on_hole, 0]], uv[edges[on_hole, 1]]
    hole_signed = 0.5 * np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1])
    np.testing.assert_allclose(hole_signed, T.signed_area(hole), rtol=1e-12)
    assert on_hole.sum() >= k
    # and the 3-D mesh has the same boundary: outer square + hole
    mesh = s.to_mesh(n_u=20, n_v=20)
    feature = mesh.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                         non_manifold_edges=False)
    assert feature.n_cells == len(edges)


def test_holes_from_b_splines_and_polylines_together():
    s = T.trimmed(surfaces.plane(), T.circle_curve((0.5, 0.5), 0.45),
                  holes=[T.circle_curve((0.35, 0.5), 0.1, clockwise=True),
                         T.rectangle((0.6, 0.4), (0.75, 0.6), clockwise=True)])
    uv, tri = s.triangulate()
    for centre in ([0.35, 0.5], [0.675, 0.5]):
        assert covering_triangles(uv, tri, np.array(centre)).size == 0
    np.testing.assert_allclose(triangle_areas(uv, tri).sum(), s.area_uv, rtol=1e-12)
    assert np.all(s.contains(uv[:, 0], uv[:, 1]))  # vertices on the loops count as inside


def test_iso_parameter_nodes_are_vertices():
    """Choi & Lee, §2.2: nodes of the iso-parameter grid inside the region, and the loops' crossings with the lines."""
    s = T.trimmed(surfaces.practical(), T.circle((3.5, 3.5), 3.0, n=16))
    n = 15
    uv, _tri = s.triangulate(n_u=n, n_v=n, min_angle=None)
    grid = np.linspace(0, 7, n)
    h = grid[1] - grid[0]
    U, V = np.meshgrid(grid, grid, indexing="ij")
    G = np.column_stack([U.ravel(), V.ravel()])
    interior = T.point_in_loop(G, s.outer) & (T.distance_to_loop(G, s.outer) >= 0.5 * h)
    vertex_set = {tuple(p) for p in uv}
    assert interior.sum() > 50
    assert all(tuple(p) in vertex_set for p in G[interior])
    # boundary nodes include crossings, exactly on the iso-lines u = const
    on_loop = uv[T.distance_to_loop(uv, s.outer) <= 1e-12]
    on_u_line = np.isin(on_loop[:, 0], grid) & ~np.isin(on_loop[:, 1], grid)
    assert on_u_line.sum() >= 10


# -- curvature and the mesh -------------------------------------------------------------------


def practical_with_holes():
    P = np.array([[0.3, 0.3], [3.5, 0.2], [6.7, 0.3], [6.8, 3.5], [6.7, 6.7], [3.5, 5.0], [0.3, 6.7], [0.2, 3.5],
                  [0.3, 0.3]])
    knots = np.array([0, 0, 0, 0, 1, 2, 3, 4, 5, 6, 6, 6, 6]) / 6
    outer = T.BSplineLoop(P, knots, 3)
    holes = [T.circle_curve((4.5, 3.0), 1.0, clockwise=True), T.rectangle((1.5, 2), (2.5, 4), clockwise=True)]
    return T.trimmed(surfaces.practical(), outer, holes)


def test_curvature_on_the_trimmed_mesh_equals_the_base_surface():
    s = practical_with_holes()
    mesh = s.to_mesh(n_u=24, n_v=24)
    uv = np.asarray(mesh.point_data["uv"])
    base = s.surface
    c = base.curvature(uv[:, 0], uv[:, 1])
    for name in ("K", "H", "k1", "k2"):
        np.testing.assert_allclose(mesh.point_data[name], getattr(c, name), rtol=1e-12, atol=1e-12, err_msg=name)
    assert not np.any(mesh.point_data["degenerate"])
    np.testing.assert_allclose(mesh.points, base.evaluate(uv[:, 0], uv[:, 1]), atol=1e-12)
    np.testing.assert_allclose(mesh.point_data["N"], base.normal(uv[:, 0], uv[:, 1]), atol=1e-12)
    # the trimmed surface's own curvature is the base surface's inside the region
    ct = s.curvature(uv[:, 0], uv[:, 1])
    np.testing.assert_array_equal(ct.K, c.K)
    # faces are oriented like N (b_u x b_v), so tools using the mesh orientation agree with the normals
    tri = mesh.faces.reshape(-1, 4)[:, 1:]
    X = mesh.points[tri]
    face_normal = np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0])
    assert np.all(np.einsum("ij,ij->i", face_normal, mesh.point_data["N"][tri].mean(axis=1)) > 0)


def test_trimmed_practical_surface_holes_and_colours():
    s = practical_with_holes()
    mesh = s.to_mesh(n_u=24, n_v=24, curvature_mode=lab.CurvatureMode.GAUSSIAN, color_map=lab.ColorMap.LINEAR)
    assert mesh.point_data["RGB"].shape == (mesh.n_points, 3)
    np.testing.assert_array_equal(mesh.point_data["values"], mesh.point_data["K"])
    uv = np.asarray(mesh.point_data["uv"])
    tri = mesh.faces.reshape(-1, 4)[:, 1:]
    for centre in ([4.5, 3.0], [2.0, 3.0]):  # centres of the holes
        assert covering_triangles(uv, tri, np.array(centre)).size == 0
    assert covering_triangles(uv, tri, np.array([5.0, 5.0])).size >= 1
    np.testing.assert_allclose(triangle_areas(uv, tri).sum(), s.area_uv, rtol=1e-12)
    # three boundary loops: the outer one and two holes
    edges = mesh.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                       non_manifold_edges=False)
    assert edges.connectivity().point_data["RegionId"].max() == 2


def test_curvature_outside_the_region():
    s = practical_with_holes()
    with pytest.raises(ValueError, match=r"curvature: 1 of 2 \(u, v\) points lie outside the trimmed region, "
                                         r"e\.g\. \(4\.5, 3\)"):
        s.curvature([5.0, 4.5], [5.0, 3.0])
    c = s.curvature([5.0, 4.5], [5.0, 3.0], outside="nan")
    assert np.isfinite(c.K[0]) and np.isnan(c.K[1]) and not c.degenerate[1]
    np.testing.assert_array_equal(c.K[0], s.surface.curvature(5.0, 5.0).K)
    with pytest.raises(ValueError, match="lie outside the trimmed region"):
        s.evaluate(2.0, 3.0)


def test_a_seam_of_a_closed_base_surface_is_welded():
    s = T.trimmed(surfaces.cylinder(1.0, 2.0))  # the whole domain: u = 0 and u = 1 meet
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = s.to_mesh(n_u=17, n_v=5)
    edges = mesh.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                       non_manifold_edges=False)
    # only the two rims are boundary: both circles, no seam
    np.testing.assert_allclose(np.sort(np.unique(np.round(edges.points[:, 2], 12))), [0.0, 2.0])
    np.testing.assert_allclose(mesh.point_data["H"], -0.5, rtol=1e-12)


# -- B-spline trimming curves -----------------------------------------------------------------


@pytest.mark.parametrize("clamped", [True, False], ids=["clamped", "unclamped"])
def test_b_spline_loop_matches_scipy(clamped, rng):
    p = 3
    if clamped:
        knots = np.array([0, 0, 0, 0, 0.2, 0.5, 0.6, 1, 1, 1, 1])
        P = rng.uniform(0.2, 0.8, size=(7, 2))
        P[-1] = P[0]
    else:  # a periodic cubic: the last p control points repeat the first ones
        knots = np.arange(-3, 8, dtype=float)
        P = rng.uniform(0.2, 0.8, size=(7, 2))
        P[-3:] = P[:3]
    c = T.BSplineLoop(P, knots, p)
    lo, hi = c.domain
    t = np.linspace(lo, hi, 41)
    np.testing.assert_allclose(c.evaluate(t), BSpline(knots, P, p)(t), atol=1e-14)
    np.testing.assert_allclose(c.reversed().evaluate(lo + hi - t), c.evaluate(t), atol=1e-14)


def test_b_spline_sampling_keeps_within_the_chordal_tolerance():
    c = T.BSplineLoop([[0.2, 0.2], [0.8, 0.1], [0.9, 0.9], [0.5, 0.4], [0.1, 0.9], [0.2, 0.2]],
                      [0, 0, 0, 0, 0.3, 0.7, 1, 1, 1, 1], 3)
    for tol in (1e-2, 1e-4):
        P = c.sample(tol=tol)
        dense = c.evaluate(np.linspace(0, 1, 20001))
        assert T.distance_to_loop(dense, P).max() <= tol
        assert all(np.min(np.linalg.norm(P - c.evaluate(b), axis=1)) < 1e-15 for b in c.breakpoints()[:-1])
    assert len(c.sample(tol=1e-4)) > len(c.sample(tol=1e-2))
    P = c.sample(n=49)  # 49 evenly spaced points plus the two interior breakpoints
    assert len(P) == 51


def test_explicitly_and_implicitly_closed_polylines_agree():
    loop = T.circle((0.5, 0.5), 0.3, n=12)
    a = T.trimmed(surfaces.plane(), loop)
    b = T.trimmed(surfaces.plane(), np.vstack([loop, loop[:1]]))
    np.testing.assert_array_equal(a.outer, b.outer)


# -- validation -----------------------------------------------------------------------------------

SQUARE = np.array([[0.1, 0.1], [0.9, 0.1], [0.9, 0.9], [0.1, 0.9]])


@pytest.mark.parametrize(
    "outer, holes, match",
    [
        (SQUARE[::-1], [], (r"outer loop runs clockwise \(signed area -0\.64\); the outer loop must run "
                            r"counter-clockwise: reverse it \(loop\[::-1\]")),
        (SQUARE, [T.circle((0.5, 0.5), 0.1)], (r"hole 0 runs counter-clockwise \(signed area 0\.0\d+\); holes must "
                                                r"run clockwise: reverse it")),
        ([[0.1, 0.1], [0.9, 0.9], [0.9, 0.1], [0.1, 0.9]], [],
         (r"outer loop intersects itself: segments 0 and 2 meet near \(0\.5, 0\.5\); a trimming loop must be a "
          r"simple closed curve")),
        ([[0.1, 0.1], [0.9, 0.1], [0.5, 0.1], [0.5, 0.9]], [], r"outer loop intersects itself: segments 0 and 1"),
        (SQUARE, [T.circle((0.5, 0.5), 0.1, clockwise=True), T.circle((1.2, 0.5), 0.1, clockwise=True)],
         (r"hole 1: points must lie in the surface's domain \[0, 1\] x \[0, 1\]; \d+ of 64 do not, e.g. point 0 = "
          r"\(1\.3, 0\.5\)")),
        ([[0.1, 0.1], [1.5, 0.5], [0.1, 0.9]], [],
         (r"outer loop: points must lie in the surface's domain \[0, 1\] x \[0, 1\]; 1 of 3 do not, e.g. point 1 = "
          r"\(1\.5, 0\.5\)")),
        ([[0.1, 0.1], [0.9, 0.1], [0.1, 0.1]], [], r"outer loop must have at least 3 distinct points; got 2"),
        ([[0.1, 0.1, 0.0], [0.9, 0.1, 0.0], [0.1, 0.9, 0.0]], [],
         r"outer loop must be a \(k, 2\) array of \(u, v\) points or a BSplineLoop; got shape \(3, 3\)"),
        (T.circle((0.3, 0.3), 0.2), [T.circle((0.75, 0.75), 0.1, clockwise=True)],
         r"hole 0 lies outside the outer loop"),
        (SQUARE, [T.circle((0.85, 0.5), 0.1, clockwise=True)],
         r"hole 0 meets the outer loop: its segment \d+ meets segment 1 of the outer loop near \(0\.9, 0\.\d+\)"),
        (SQUARE, [T.rectangle((0.1, 0.3), (0.4, 0.6), clockwise=True)], r"hole 0 meets the outer loop"),
        (SQUARE, [T.circle((0.4, 0.5), 0.1, clockwise=True), T.circle((0.55, 0.5), 0.1, clockwise=True)],
         r"holes 0 and 1 intersect: segment \d+ of hole 0 meets segment \d+ of hole 1 near"),
        (SQUARE, [T.circle((0.5, 0.5), 0.3, clockwise=True), T.circle((0.5, 0.5), 0.1, clockwise=True)],
         r"hole 1 lies inside hole 0; holes must not nest \(islands are not supported\)"),
    ],
    ids=["outer-clockwise", "hole-counter-clockwise", "self-intersecting", "turns-back", "hole-outside-domain",
         "outer-outside-domain", "too-few-points", "wrong-shape", "hole-outside-outer", "hole-crosses-outer",
         "hole-touches-outer", "holes-intersect", "holes-nest"],
)
def test_invalid_loops_are_rejected_with_clear_messages(outer, holes, match):
    with pytest.raises(ValueError, match=match):
        T.trimmed(surfaces.plane(), outer, holes)


def test_b_spline_loop_errors():
    with pytest.raises(ValueError, match=r"a B-spline trimming loop must be closed; it starts at \(0\.1, 0\.1\) "
                                         r"and ends at \(0\.9, 0\.9\)"):
        T.BSplineLoop([[0.1, 0.1], [0.9, 0.1], [0.9, 0.9]], [0, 0, 0, 1, 1, 1], 2)
    with pytest.raises(ValueError, match=r"control points of the trimming curve must have shape \(n, 2\)"):
        T.BSplineLoop([[0.1, 0.1, 0], [0.9, 0.1, 0], [0.1, 0.1, 0]], [0, 0, 0, 1, 1, 1], 2)
    with pytest.raises(ValueError, match=r"knot vector of the trimming curve must have 6 knots"):
        T.BSplineLoop([[0.1, 0.1], [0.9, 0.1], [0.1, 0.1]], [0, 0, 1, 1], 2)
    # a figure eight: the message names the segments of the sampled polyline
    eight = T.BSplineLoop([[0.5, 0.5], [0.9, 0.9], [0.9, 0.1], [0.1, 0.9], [0.1, 0.1], [0.5, 0.5]],
                          [0, 0, 0, 0.25, 0.5, 0.75, 1, 1, 1], 2)
    with pytest.raises(ValueError, match=r"outer loop intersects itself: segments \d+ and \d+ of the sampled "
                                         r"polyline meet near \(0\.5, 0\.5\)"):
        T.trimmed(surfaces.plane(), eight)


def test_triangulation_option_errors():
    s = T.trimmed(surfaces.plane(), SQUARE)
    with pytest.raises(ValueError, match=r"min_angle must be in \(0, 33\] degrees or None; got 40"):
        s.triangulate(min_angle=40)
    with pytest.raises(ValueError, match=r"max_area must be positive; got 0"):
        s.triangulate(max_area=0)
    with pytest.raises(ValueError, match=r"n_u must be an integer >= 2; got 1"):
        s.triangulate(n_u=1)
    with pytest.raises(TypeError, match=r"holes must be a list of loops"):
        T.trimmed(surfaces.plane(), SQUARE, holes=T.circle((0.5, 0.5), 0.1, clockwise=True))
    with pytest.raises(ValueError, match=r"unknown outside 'zero'; expected one of 'raise', 'nan'"):
        s.curvature(0.5, 0.5, outside="zero")


def test_max_area_refines():
    s = T.trimmed(surfaces.plane(), T.circle((0.5, 0.5), 0.4, n=64))
    uv, tri = s.triangulate(n_u=8, n_v=8, max_area=1e-3)
    areas = triangle_areas(uv, tri)
    assert areas.max() <= 1e-3 * (1 + 1e-12)
    np.testing.assert_allclose(areas.sum(), s.area_uv, rtol=1e-12)


def test_triangulation_areas_and_angles():
    s = T.trimmed(surfaces.plane(), T.circle((0.5, 0.5), 0.4, n=64), holes=[T.rectangle((0.4, 0.4), (0.6, 0.6), clockwise=True)])
    t = s.triangulate(n_u=9, n_v=9, min_angle=25.0)
    np.testing.assert_allclose(t.areas, triangle_areas(t.uv, t.triangles), rtol=1e-12)
    assert np.all(t.areas > 0)  # counter-clockwise
    np.testing.assert_allclose(t.areas.sum(), s.area_uv, rtol=1e-12)
    np.testing.assert_allclose(t.angles.sum(axis=1), 180.0, atol=1e-9)
    assert t.angles.min() >= 25.0 - 1e-9  # Triangle's quality guarantee (no input angle is smaller here)
    right = T.Triangulation(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.array([[0, 1, 2]]))
    np.testing.assert_allclose(right.angles, [[90.0, 45.0, 45.0]], atol=1e-12)
    assert right.areas[0] == 0.5


@pytest.mark.parametrize("seed", range(6))
def test_loop_intersections_finds_every_crossing_pair(seed):
    """The sweep over the segments' boxes (lab.trimming.loops._box_pairs, which replaced a k-d tree of midpoints:
    one long segment made that pair every segment with every other) finds exactly the pairs a test of all pairs
    finds, on random polylines that cross themselves often, with one segment across the whole box."""
    from lab.interrogation.trimming import loops as L

    rng = np.random.default_rng(seed)
    P = rng.uniform(0, 1, size=(60, 2))
    P[7], P[8] = (0.0, 0.5), (1.0, 0.52)  # a long, nearly horizontal segment
    pairs, _ = T.loop_intersections(P, 1.0)
    k = len(P)
    A0, A1 = L._segments(P)
    i, j = np.triu_indices(k, 1)
    far = ~((j - i == 1) | ((i == 0) & (j == k - 1)))
    hit, _ = L._intersect(A0[i[far]], A1[i[far]], A0[j[far]], A1[j[far]], L._eps(1.0))
    reference = {(a, b) for a, b in zip(i[far][hit], j[far][hit])}
    folds = {tuple(p) for p in pairs if p[1] - p[0] == 1 or (p[0] == 0 and p[1] == k - 1)}
    assert {tuple(p) for p in pairs} - folds == reference and len(reference) > 20
    np.testing.assert_array_equal(pairs, pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))])
