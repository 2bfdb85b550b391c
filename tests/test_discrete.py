"""Discrete curvature on triangle meshes (lab.geometry.discrete): closed forms on small meshes, Gauss–Bonnet, the
mixed area against libigl's, and convergence to the exact K and H on the lab's surfaces."""

import numpy as np
import pytest

from lab.geometry import discrete as D
from lab.mesh import mesh_arrays, triangle_mesh
from lab.model import surfaces


def octahedron():
    points = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float)
    faces = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return points, faces


def test_octahedron_in_closed_form():
    points, faces = octahedron()
    np.testing.assert_allclose(D.corner_angles(points, faces), np.pi / 3, rtol=1e-15)
    np.testing.assert_allclose(D.angle_deficit(points, faces), 2 * np.pi / 3, rtol=1e-14)
    # eight equilateral triangles of side √2, area √3/2 each; every vertex gets a third of its four triangles
    np.testing.assert_allclose(D.mixed_areas(points, faces), 4 * (np.sqrt(3) / 2) / 3, rtol=1e-14)
    assert not D.boundary_vertices(faces, 6).any()
    # the mean curvature normal points inwards (H < 0 with outward normals, the lab's sign)
    assert np.all(D.mean_curvature(points, faces) < 0)
    np.testing.assert_allclose(np.linalg.norm(D.vertex_normals(points, faces), axis=1), 1, rtol=1e-15)


def test_flat_grid_boundary_and_obtuse_rule():
    x = np.arange(3.0)
    X, Y = np.meshgrid(x, x, indexing="ij")
    points = np.stack([X, Y, 0 * X], -1).reshape(-1, 3)
    faces = np.array([[0, 3, 4], [0, 4, 1], [1, 4, 5], [1, 5, 2], [3, 6, 7], [3, 7, 4], [4, 7, 8], [4, 8, 5]])
    deficit = D.angle_deficit(points, faces)
    assert D.boundary_vertices(faces, 9).tolist() == [True] * 4 + [False] + [True] * 4
    # flat: 0 inside and along the edges, a right angle's turning π/2 at the four corners
    np.testing.assert_allclose(deficit, [np.pi / 2, 0, np.pi / 2, 0, 0, 0, np.pi / 2, 0, np.pi / 2], atol=1e-15)
    np.testing.assert_allclose(D.mixed_areas(points, faces).sum(), 4.0, rtol=1e-15)
    # an obtuse triangle: half its area at the obtuse corner, a quarter at the others
    tri = np.array([[0.0, 0, 0], [4, 0, 0], [2, 1, 0]])
    np.testing.assert_allclose(D.mixed_areas(tri, np.array([[0, 1, 2]])), [0.5, 0.5, 1.0], rtol=1e-15)  # area 2


def test_gauss_bonnet_on_closed_meshes():
    for surface, chi in ((surfaces.torus(), 0), (surfaces.ellipsoid(), 2)):
        points, faces = mesh_arrays(triangle_mesh(surface, 17, diagonals="random"))
        assert abs(D.angle_deficit(points, faces).sum() - 2 * np.pi * chi) < 1e-11


def test_mixed_area_is_libigls_voronoi_mass():
    igl = pytest.importorskip("igl")
    points, faces = mesh_arrays(triangle_mesh(surfaces.saddle(), 9, diagonals="random"))
    mass = igl.massmatrix(points, faces, igl.MASSMATRIX_TYPE_VORONOI).diagonal()
    np.testing.assert_allclose(D.mixed_areas(points, faces), mass, rtol=1e-12)


def test_converges_to_the_exact_torus_with_order_two():
    errors = []
    for n in (33, 65):
        mesh = triangle_mesh(surfaces.torus(), n)
        points, faces = mesh_arrays(mesh)
        errors.append((np.abs(D.gaussian_curvature(points, faces) - mesh["K"]).max(),
                       np.abs(D.mean_curvature(points, faces) - mesh["H"]).max()))
    (K1, H1), (K2, H2) = errors
    assert K2 < 0.003 and H2 < 0.002  # K from -1 to 1/3, H from 0 to 2/3
    assert 3.5 < K1 / K2 < 4.5 and 3.5 < H1 / H2 < 4.5  # half the mesh size, a quarter of the error


def test_bad_input_is_named():
    points, faces = octahedron()
    with pytest.raises(TypeError, match=r"faces must be an \(f, 3\) array of integer vertex indices; got float64"):
        D.angle_deficit(points, faces.astype(float))
    with pytest.raises(ValueError, match=r"faces must index the 6 points \(0 … 5\); got indices from 0 to 6"):
        D.mixed_areas(points, np.vstack([faces, [[0, 1, 6]]]))
    with pytest.raises(ValueError, match=r"points must be an \(n, 3\) array of vertex coordinates; got shape \(6, 2\)"):
        D.gaussian_curvature(points[:, :2], faces)
    with pytest.raises(ValueError, match=r"normals must have the shape of points \(6, 3\); got \(6, 2\)"):
        D.mean_curvature(points, faces, normals=np.ones((6, 2)))
