"""Shortest geodesics between two points (lab.geodesic_between): polyhedral start, exact shooting, caches."""

import numpy as np
import pytest
from lab.geodesics import geodesic, geodesic_between

from lab import surfaces
from lab.interrogation.geodesics.polyhedral import PolyhedralMesh, polyhedral_mesh
from lab.interrogation.geodesics.problem import GEODESIC, _geodesic_rhs, _problem

#: Lengths found by the previous implementation (36-path fan guesses, Gauss-Newton, solve_ivp per patch), which
#: did not use the polyhedral path: an independent route to the same geodesics.  It ran on the practical's
#: surface with u along x; the surface now runs u along y as the course program does (issue 11), so the
#: parameters of the same points are swapped, and a geodesic's length does not depend on the parametrisation.
PREVIOUS = [
    (surfaces.practical, (1.0, 1.0), (2.0, 6.0), 6.478681175016995),
    (surfaces.practical, (0.5, 0.5), (6.5, 6.5), 11.928690845642647),
    (surfaces.practical, (0.5, 3.5), (6.5, 3.5), 8.989255866854778),
    (surfaces.isodistance_geodesics_example, (0.8, 0.6), (0.2, 0.3), 19.700056350798985),
    (surfaces.isodistance_sections_example, (0.5, 0.1), (0.5, 0.9), 6.5078302175443685),
]


@pytest.mark.parametrize("factory, a, b, length", PREVIOUS, ids=[f"{f.__name__}-{a}" for f, a, _, _ in PREVIOUS])
def test_agrees_with_the_previous_implementation(factory, a, b, length):
    s = factory()
    p = geodesic_between(s, a, b)
    assert p.length == pytest.approx(length, abs=1e-8)
    np.testing.assert_allclose(p.points[-1], s.evaluate(*b), atol=1e-9 * max(1.0, np.linalg.norm(p.points[-1] - p.points[0])))
    np.testing.assert_allclose(p.uv[0], a, atol=1e-14)
    # it is a geodesic: integrating eq. 11 from A at its angle for its length with solve_ivp ends at B too
    q = geodesic(s, a, p.angle, p.length)
    np.testing.assert_allclose(q.points[-1], s.evaluate(*b), atol=1e-8)


def test_shorter_than_every_other_geodesic_found_and_close_to_the_mesh_path():
    s = surfaces.practical()
    a, b = (0.5, 0.5), (6.5, 6.5)
    p = geodesic_between(s, a, b)
    mesh = polyhedral_mesh(s)
    poly = mesh.path(mesh.nearest_vertex(s.evaluate(*a)), mesh.nearest_vertex(s.evaluate(*b)))
    mesh_length = np.linalg.norm(np.diff(poly, axis=0), axis=1).sum()
    # the mesh path joins the nearest vertices (up to 0.07 from A and B) on a mesh with edges of about 0.1:
    # it is within one per cent of the exact length
    assert abs(mesh_length - p.length) < 0.01 * p.length
    # the fallback guesses alone (no polyhedral start) find this geodesic or a longer one, never a shorter one
    from lab.interrogation.geodesics import shortest

    d = s.derivatives(np.array([a[0]]), np.array([a[1]]))
    xa, xb = s.evaluate(*a), s.evaluate(*b)
    shooter = shortest._Shooter(s, _problem(s, GEODESIC), d, a, xb, 1e-9 * np.linalg.norm(xb - xa), 1e-10, 1e-12)
    found = shooter.solve(shortest._fallback_guesses(shooter, d, xa, xb, float(np.linalg.norm(xb - xa)), 4))
    if found is not None:
        _alpha, _state, end, _ = found
        assert end >= p.length - 1e-8


def test_periodic_surface_and_mesh_cache():
    t = surfaces.torus()
    mesh = polyhedral_mesh(t)
    assert polyhedral_mesh(t) is mesh  # built once per surface
    assert _problem(t, GEODESIC) is _problem(t, GEODESIC)
    assert polyhedral_mesh(surfaces.torus()) is not mesh  # another surface, another mesh
    # closed: welded by index, every edge is shared by two triangles
    edges = np.sort(np.concatenate([mesh.faces[:, [0, 1]], mesh.faces[:, [1, 2]], mesh.faces[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.all(counts == 2)
    assert 4000 < len(mesh.vertices) < 6000
    a, b = (0.05, 0.0), (0.95, 0.5)  # across both seams
    p = geodesic_between(t, a, b)
    np.testing.assert_allclose(p.points[-1], t.evaluate(*b), atol=1e-9 * p.length)
    # not longer than the mesh's exact polyhedral distance between the nearest vertices by more than the mesh error
    poly = mesh.path(mesh.nearest_vertex(t.evaluate(*a)), mesh.nearest_vertex(t.evaluate(*b)))
    assert p.length <= np.linalg.norm(np.diff(poly, axis=0), axis=1).sum() * 1.01 + 0.2


def test_sphere_poles_collapse_in_the_mesh():
    mesh = PolyhedralMesh(surfaces.sphere(1.0), n_vertices=800)
    top = np.flatnonzero(np.isclose(mesh.vertices[:, 2], 1.0, atol=1e-12))
    bottom = np.flatnonzero(np.isclose(mesh.vertices[:, 2], -1.0, atol=1e-12))
    assert len(top) == len(bottom) == 1  # each pole one vertex
    assert not np.any((mesh.faces[:, 0] == mesh.faces[:, 1]) | (mesh.faces[:, 1] == mesh.faces[:, 2]))


def test_fast_right_hand_side_equals_the_general_one(rng):
    for s in (surfaces.practical(), surfaces.torus(), surfaces.isodistance_geodesics_example()):
        problem = _problem(s, GEODESIC)
        (u0, u1), (v0, v1) = s.domain
        uv = np.column_stack([rng.uniform(u0, u1, 7), rng.uniform(v0, v1, 7)])
        y = np.column_stack([uv, rng.normal(size=(7, 2))])
        cell = problem.locate(uv, y[:, 2:])
        fast = problem.rhs(y, cell)
        general = _geodesic_rhs(problem.derivatives(uv, cell), y)
        np.testing.assert_allclose(fast, general, rtol=1e-12, atol=1e-12 * np.abs(general).max())
