"""The check of notebook 13's task (lab.teaching.tasks.meshes): the Gaussian curvature per vertex by the angle deficit."""

import numpy as np
import pytest

from lab import check
from lab.geometry import discrete
from lab.teaching.tasks import meshes


def deficit_curvature(points, faces, *, mistake=None):
    """A student's solution with arccos (not atan2) and np.add.at, optionally with one classic mistake."""
    P = points[faces]
    theta = np.zeros(faces.shape)
    for k in range(3):
        a, b = P[:, (k + 1) % 3] - P[:, k], P[:, (k + 2) % 3] - P[:, k]
        cos = np.sum(a * b, axis=1) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1)
        theta[:, k] = np.arccos(np.clip(cos, -1, 1))
    if mistake == "degrees":
        theta = np.degrees(theta)
    full = 360.0 if mistake == "degrees" else 2 * np.pi
    total = np.zeros(len(points))
    np.add.at(total, faces.ravel(), theta.ravel())
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    boundary = np.zeros(len(points), dtype=bool)
    boundary[unique[count == 1].ravel()] = True
    deficit = np.where(boundary & (mistake != "two_pi"), full / 2, full) - total
    area = np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1) / 2
    if mistake == "barycentric":
        share = np.repeat(area[:, None] / 3, 3, axis=1)
    else:
        share = np.zeros(faces.shape)
        for k in range(3):
            i, j = (k + 1) % 3, (k + 2) % 3
            cot = lambda c: 1 / np.tan(theta[:, c])
            share[:, k] = (np.sum((P[:, i] - P[:, k]) ** 2, 1) * cot(j) + np.sum((P[:, j] - P[:, k]) ** 2, 1) * cot(i)) / 8
        obtuse = theta > np.pi / 2
        if mistake != "voronoi":
            share = np.where(obtuse.any(axis=1, keepdims=True), np.where(obtuse, 0.5, 0.25) * area[:, None], share)
    A = np.zeros(len(points))
    np.add.at(A, faces.ravel(), share.ravel())
    return (deficit if mistake == "no_area" else deficit / A), A


def test_reference_solution_passes_public_and_graded():
    public, graded = check.deficit_curvature(deficit_curvature), check.deficit_curvature(deficit_curvature, graded=True)
    assert public.passed and graded.passed, str(public) + str(graded)
    assert len(graded.cases) > len(public.cases) >= 6


def test_reference_is_the_library_and_forty_digit_arithmetic(rng):
    import mpmath

    for spec in meshes._cases(rng, True):
        points, faces = spec.args
        K, A = meshes.reference(points, faces)
        np.testing.assert_allclose(K, discrete.gaussian_curvature(points, faces), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(A, discrete.mixed_areas(points, faces), rtol=1e-12)
    points, faces = meshes._bumpy(rng, 5)
    with mpmath.workdps(40):
        total = [mpmath.mpf(0)] * len(points)
        for f in faces:
            for k in range(3):
                p, q, r = (mpmath.matrix([mpmath.mpf(float(c)) for c in points[f[(k + s) % 3]]]) for s in range(3))
                a, b = q - p, r - p
                cos = sum(a[i] * b[i] for i in range(3)) / mpmath.sqrt(sum(x * x for x in a) * sum(x * x for x in b))
                total[f[k]] += mpmath.acos(cos)
        boundary = discrete.boundary_vertices(faces, len(points))
        exact = np.array([float((mpmath.pi if b else 2 * mpmath.pi) - t) for t, b in zip(total, boundary)])
    np.testing.assert_allclose(meshes.reference(points, faces, area="none")[0], exact, rtol=0, atol=1e-14)


@pytest.mark.parametrize("mistake, hint", [
    ("two_pi", "its deficit is π − Σθ, not 2π − Σθ"),
    ("degrees", "the angles are in degrees"),
    ("no_area", "you returned the deficit itself"),
    ("barycentric", "the barycentric area"),
    ("voronoi", "the mixed area gives half the triangle's area to the obtuse corner"),
])
def test_each_mistake_gets_its_hint(mistake, hint):
    report = check.deficit_curvature(lambda p, f: deficit_curvature(p, f, mistake=mistake))
    assert not report.passed and hint in str(report), str(report)


def test_two_mistakes_are_both_named():
    def both(points, faces):
        K, _A = meshes.reference(points, faces, boundary="2pi", area="barycentric")
        return K, meshes.reference(points, faces)[1]

    report = check.deficit_curvature(both)
    assert "2 mistakes: (1) at a boundary vertex" in str(report) and "(2) you divided by a third" in str(report)


def test_shapes_stub_area_and_delegation():
    report = check.deficit_curvature(lambda p, f: deficit_curvature(p, f)[0])
    assert not report.passed and "return two arrays, (K, A)" in str(report)
    report = check.deficit_curvature(lambda p, f: np.array(deficit_curvature(p, f)))  # a (2, n) array is (K, A)
    assert report.passed, str(report)
    report = check.deficit_curvature(lambda p, f: (deficit_curvature(p, f)[0], meshes.reference(p, f, area="ring")[1]))
    assert not report.passed and "the whole area of the adjacent triangles" in str(report)

    def stub(points, faces):
        raise NotImplementedError("return K and A")

    assert check.deficit_curvature(stub).status == "not implemented"
    report = check.deficit_curvature(lambda p, f: (discrete.gaussian_curvature(p, f), discrete.mixed_areas(p, f)))
    assert report.status == "delegated" and "discrete." in report.message
    # the faces arrive as integers: indexing needs no cast
    seen = []
    check.deficit_curvature(lambda p, f: seen.append(f.dtype.kind) or deficit_curvature(p, f))
    assert set(seen) == {"i"}
