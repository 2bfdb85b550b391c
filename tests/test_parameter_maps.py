"""Parameter maps (lab.geometry.parameter_maps) and lab.ReparametrizedSurface: a CAD file's angle against the
parameter of the exact NURBS form of its circle (OpenCASCADE's Convert_TgtThetaOver2 arcs), checked against
the closed forms of the circle and the cylinder; no OpenCASCADE needed."""

import numpy as np
import pytest

import lab
from lab.geometry.parameter_maps import ParameterMap, circle_spans


def nurbs_arc(a, b, r=1.0, height=1.0):
    """The arc a..b of radius r as OpenCASCADE's TgtThetaOver2 conversion builds it (equal spans of at most
    150 degrees, knots at the angles of the span ends, weights 1, cos h, 1), extruded along z: degree (2, 1)."""
    n, h = circle_spans(b - a)
    angles = a + 2 * h * np.arange(n + 1)
    P, w = [], []
    for k in range(n):
        m = angles[k] + h
        P += [(np.cos(angles[k]), np.sin(angles[k])), (np.cos(m) / np.cos(h), np.sin(m) / np.cos(h))]
        w += [1.0, np.cos(h)]
    P.append((np.cos(b), np.sin(b)))
    w.append(1.0)
    P = r * np.array(P)
    net = np.stack([np.column_stack([P, np.zeros(len(P))]), np.column_stack([P, np.full(len(P), height)])], axis=1)
    knots = np.concatenate([[a] * 3, np.repeat(angles[1:-1], 2), [b] * 3])
    return lab.BSplineSurface(net, knots, [0, 0, 1, 1], 2, 1, weights=np.repeat(np.array(w)[:, None], 2, axis=1))


def arc_map(surface):
    (a, b), _ = surface.domain
    return ParameterMap.circle(a, circle_spans(b - a)[1], knots=surface.knots_u, degree=2)


@pytest.mark.parametrize(("a", "b"), [(0.3, 4.0), (-1.0, 1.2), (0.0, 2 * np.pi)])
def test_the_circle_map_gives_the_nurbs_parameter_of_an_angle(a, b):
    """At s = map(theta) OpenCASCADE's rational quadratic arcs pass through (cos theta, sin theta), to rounding;
    the map equals the angle at every knot, its derivatives are those of differences, and it inverts."""
    s_nurbs = nurbs_arc(a, b)
    m = arc_map(s_nurbs)
    theta = np.linspace(a, b, 397)
    s, ds, dds = m(theta)
    np.testing.assert_allclose(s_nurbs.evaluate(s, 0.0)[:, :2], np.column_stack([np.cos(theta), np.sin(theta)]),
                               rtol=0, atol=2e-15)
    knots = np.unique(s_nurbs.knots_u)
    np.testing.assert_allclose(m(knots)[0], knots, rtol=0, atol=1e-14)
    np.testing.assert_allclose(m.inverse(s), theta, rtol=0, atol=1e-14)
    e = 1e-5
    inner = theta[1:-1]
    far = np.abs((inner - a) / (2 * m.half) - np.round((inner - a) / (2 * m.half))) > 1e-3  # s'' jumps at knots
    np.testing.assert_allclose(ds[1:-1][far], ((m(inner + e)[0] - m(inner - e)[0]) / (2 * e))[far], rtol=1e-9)
    np.testing.assert_allclose(dds[1:-1][far], ((m(inner + e)[1] - m(inner - e)[1]) / (2 * e))[far], rtol=1e-6,
                               atol=1e-9)


def test_a_cylinder_in_its_angle_has_the_closed_form_derivatives_and_curvature():
    """x(theta, z) = (r cos theta, r sin theta, z): the chain rule over the NURBS gives x_theta, x_thetatheta, the
    normal, H = -1/(2r) (x_theta x x_z points outward) and K = 0 to rounding, also exactly at the knots, where
    the NURBS's second derivatives jump and the map takes the evaluator's span; grids give the same."""
    r, (a, b) = 2.5, (0.3, 5.5)
    base = nurbs_arc(a, b, r=r, height=3.0)
    s = lab.ReparametrizedSurface(base, arc_map(base), ParameterMap.identity(), ((a, b), (0.0, 1.0)))
    knots = np.unique(base.knots_u)
    theta = np.concatenate([np.linspace(a, b, 101), knots])
    z = np.full_like(theta, 0.4)
    d = s.derivatives(theta, z)
    c, st = np.cos(theta), np.sin(theta)
    zero = np.zeros_like(theta)
    np.testing.assert_allclose(d.b, np.column_stack([r * c, r * st, 3.0 * z]), rtol=0, atol=1e-14)
    np.testing.assert_allclose(d.bu, np.column_stack([-r * st, r * c, zero]), rtol=0, atol=1e-13)
    np.testing.assert_allclose(d.buu, np.column_stack([-r * c, -r * st, zero]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(d.bv, np.column_stack([zero, zero, zero + 3.0]), rtol=0, atol=1e-14)
    np.testing.assert_allclose(d.buv, 0.0, rtol=0, atol=1e-13)
    np.testing.assert_allclose(d.bvv, 0.0, rtol=0, atol=1e-13)
    curv = s.curvature(theta, z)
    np.testing.assert_allclose(curv.H, -1 / (2 * r), rtol=1e-12)
    np.testing.assert_allclose(curv.K, 0.0, atol=1e-13)
    np.testing.assert_allclose(s.normal(theta, z), np.column_stack([c, st, zero]), rtol=0, atol=1e-13)
    grid = s.curvature_grid(knots, np.array([0.2, 0.7]))
    np.testing.assert_allclose(grid.H, -1 / (2 * r), rtol=1e-12)
    # the base surface's curvature at the mapped parameters is the same (reparametrising keeps K, H)
    base_curv = base.curvature(arc_map(base)(theta)[0], z)
    np.testing.assert_allclose(curv.H, base_curv.H, rtol=1e-12)


def test_the_hyperbola_and_affine_maps():
    """A hyperbola branch (cosh t, sinh t) as OpenCASCADE converts it (one span, middle weight cosh h) and a
    Bézier curve cut to [a, b] (affine onto [0, 1])."""
    lo, hi = -1.0, 1.5
    h = (hi - lo) / 2
    P = np.array([[np.cosh(lo), np.sinh(lo)],
                  [(np.sinh(hi) - np.sinh(lo)) / np.sinh(hi - lo), (np.cosh(hi) - np.cosh(lo)) / np.sinh(hi - lo)],
                  [np.cosh(hi), np.sinh(hi)]])
    net = np.stack([np.column_stack([P, np.zeros(3)]), np.column_stack([P, np.ones(3)])], axis=1)
    w = np.repeat(np.array([1.0, np.cosh(h), 1.0])[:, None], 2, axis=1)
    branch = lab.BSplineSurface(net, [lo] * 3 + [hi] * 3, [0, 0, 1, 1], 2, 1, weights=w)
    m = ParameterMap.hyperbola(lo, hi)
    t = np.linspace(lo, hi, 51)
    np.testing.assert_allclose(branch.evaluate(m(t)[0], 0.0)[:, :2], np.column_stack([np.cosh(t), np.sinh(t)]),
                               rtol=0, atol=1e-14)
    np.testing.assert_allclose(m.inverse(m(t)[0]), t, rtol=0, atol=1e-14)
    e = 1e-6
    np.testing.assert_allclose(m(t)[1], (m(t + e)[0] - m(t - e)[0]) / (2 * e), rtol=1e-8)
    np.testing.assert_allclose(m(t)[2], (m(t + e)[1] - m(t - e)[1]) / (2 * e), rtol=1e-5, atol=1e-8)
    affine = ParameterMap.affine(-0.2 / 0.7, 1 / 0.7)  # [0.2, 0.9] onto [0, 1]
    np.testing.assert_allclose(affine(np.array([0.2, 0.9]))[0], [0.0, 1.0], atol=1e-15)
    np.testing.assert_allclose(affine.inverse(np.array([0.0, 1.0])), [0.2, 0.9], atol=1e-15)


def test_bad_maps_and_surfaces_are_refused():
    with pytest.raises(ValueError, match="a circle's spans must open less than 180 degrees; got half opening 2"):
        ParameterMap.circle(0.0, 2.0)
    with pytest.raises(ValueError, match="an affine parameter map must increase; got scale -1"):
        ParameterMap.affine(0.0, -1.0)
    with pytest.raises(ValueError, match="a hyperbola's span must have lo < hi; got \\[1, 0\\]"):
        ParameterMap.hyperbola(1.0, 0.0)
    with pytest.raises(ValueError, match="needs the NURBS's knots"):
        ParameterMap.circle(0.0, 1.0, period=2 * np.pi)
    with pytest.raises(TypeError, match="base must be a lab.Surface; got str"):
        lab.ReparametrizedSurface("surface", ParameterMap.identity(), ParameterMap.identity(), ((0, 1), (0, 1)))
    with pytest.raises(TypeError, match="map_u and map_v must be callables"):
        lab.ReparametrizedSurface(lab.surfaces.practical(), None, ParameterMap.identity(), ((0, 1), (0, 1)))
