"""The practical's collection class lab.BezierPatches and its per-patch views."""

import warnings

import numpy as np
import pytest
from lab.curvature import DegeneratePointWarning

import lab
from lab import analytic, colormaps, surfaces


@pytest.fixture
def nets(rng):
    """Three random 2x3 nets with rational coordinates (non-square, so u/v mix-ups show)."""
    return np.stack([analytic.random_rational_net(rng, 2, 3) for _ in range(3)])


def test_constants_and_modes():
    B = lab.BezierPatches
    assert {B.CURVATURE_GAUSSIAN, B.CURVATURE_AVERAGE, B.CURVATURE_PRINCIPAL_MAX, B.CURVATURE_PRINCIPAL_MIN} == {
        "gaussian", "mean", "k1", "k2"}
    assert {B.COLOR_MAP_LINEAR, B.COLOR_MAP_CUT, B.COLOR_MAP_CLASSIFICATION} == {"linear", "cut", "classification"}
    assert len({B.CURVATURE_GAUSSIAN, B.CURVATURE_AVERAGE, B.CURVATURE_PRINCIPAL_MAX, B.CURVATURE_PRINCIPAL_MIN}) == 4


def test_views_share_the_arrays(nets):
    p = lab.BezierPatches(nets)
    assert len(p) == 3 and p.degree == (2, 3)
    views = list(p)
    assert [v.degree for v in views] == [(2, 3)] * 3
    np.testing.assert_array_equal(views[1].control_points, nets[1])
    views[2].set_curvature(1, 2, 3, 4)
    np.testing.assert_array_equal(p.curvature[2], [[1, 2], [3, 4]])  # c01 is (u=0, v=1)
    views[0].set_colors((1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1))
    np.testing.assert_array_equal(p.colors[0, 0, 1], (0, 1, 0))
    np.testing.assert_array_equal(views[0].colors[1, 0], (0, 0, 1))


def test_refine_counts_and_reproduces(nets):
    p = lab.BezierPatches(nets[:1])
    p.refine(2)
    assert len(p) == 16
    q = lab.BezierPatches(nets[:1]).refine(1)
    s = np.linspace(0, 1, 4)
    for k in range(4):
        a, b = divmod(k, 2)  # child k covers the a-th u-half and b-th v-half
        np.testing.assert_allclose(
            q.evaluate(s, s[::-1])[k], lab.bezier.evaluate(nets[0], (a + s) / 2, (b + s[::-1]) / 2), atol=1e-14
        )
    assert np.all(np.isnan(q.curvature))  # stale values are cleared


@pytest.mark.parametrize("mode", ["gaussian", "mean", "k1", "k2"])
def test_visualize_curvature_against_sympy_exact(nets, mode):
    p = lab.BezierPatches(nets)
    p.visualize_curvature(mode, lab.BezierPatches.COLOR_MAP_LINEAR)
    field = {"gaussian": "K", "mean": "H", "k1": "k1", "k2": "k2"}[mode]
    exact = np.zeros((3, 2, 2))
    for k in range(3):
        for (a, b), c in analytic.bezier_corner_curvature_exact(nets[k]).items():
            exact[k, a, b] = getattr(analytic.to_float(c), field)
    np.testing.assert_allclose(p.curvature, exact, rtol=1e-12, atol=1e-12)
    expected = colormaps.h((exact - exact.min()) / (exact.max() - exact.min()))
    np.testing.assert_allclose(p.colors, expected, atol=1e-9)


def test_visualize_curvature_maps(nets):
    p = lab.BezierPatches(nets)
    p.visualize_curvature("gaussian", "cut")
    np.testing.assert_allclose(p.colors, colormaps.h(np.clip(p.curvature, 0, 1)))
    p.visualize_curvature("gaussian", "classification")
    np.testing.assert_allclose(p.colors, colormaps.h(np.where(p.curvature > 0, 1.0, 0.0)))
    p.visualize_curvature("mean", "dill")
    np.testing.assert_allclose(p.colors, colormaps.dill(p.curvature))


def test_classification_ignores_rounding_noise_on_a_cylinder():
    p = surfaces.cylinder(1.0, 3.0).to_bezier_patches().refine(2)
    p.visualize_curvature("gaussian", "classification")
    assert np.max(np.abs(p.curvature)) < 1e-12  # noise, not exactly zero
    np.testing.assert_array_equal(p.colors, np.broadcast_to([0, 1, 0], p.colors.shape))  # all parabolic: green


def test_sphere_with_collapsed_edges():
    p = surfaces.sphere(2.0).to_bezier_patches().refine(1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        p.visualize_curvature("gaussian", "linear")
    assert sum(issubclass(w.category, DegeneratePointWarning) for w in caught) == 1
    np.testing.assert_allclose(p.curvature, 0.25, rtol=1e-9)
    np.testing.assert_array_equal(p.colors, np.broadcast_to([0, 1, 0], p.colors.shape))  # f2 of equal values


def test_rational_patches_against_sympy(rng):
    net = analytic.random_rational_net(rng, 2, 2)
    w = rng.integers(1, 5, size=(3, 3)) / 2
    p = lab.BezierPatches(net, w)
    p.visualize_curvature("mean", "linear")
    exact = analytic.bezier_corner_curvature_exact(net, w)
    for (a, b), c in exact.items():
        assert p.curvature[0, a, b] == pytest.approx(analytic.to_float(c).H, rel=1e-12)


def test_student_style_loop_gives_the_reference(nets):
    """A per-patch, per-corner loop written with the practical's interface agrees with the vectorised reference."""

    class Student(lab.BezierPatches):
        def visualize_curvature(self, curvature_mode, color_map):
            values = []
            for patch in self:
                P = patch.control_points
                _m, _n = patch.degree
                corners = []
                for a, b in ((0, 0), (0, 1), (1, 0), (1, 1)):
                    c = lab.BezierSurface(P).curvature(a, b)
                    corners.append(float(c.K))
                patch.set_curvature(*corners)
                values.extend(corners)
            lo, hi = min(values), max(values)
            for patch in self:
                cols = [tuple(colormaps.h((x - lo) / (hi - lo))) for x in patch.curvature.ravel()]
                patch.set_colors(*cols)

    ref = lab.BezierPatches(nets)
    ref.visualize_curvature("gaussian", "linear")
    student = Student(nets)
    student.visualize_curvature("gaussian", "linear")
    np.testing.assert_allclose(student.curvature, ref.curvature, rtol=1e-13)
    np.testing.assert_allclose(student.colors, ref.colors, atol=1e-12)


def test_errors(nets):
    p = lab.BezierPatches(nets)
    with pytest.raises(ValueError, match="unknown curvature mode 'gauss'; expected one of"):
        p.visualize_curvature("gauss", "linear")
    with pytest.raises(ValueError, match="unknown colour map 'jet'; expected one of"):
        p.visualize_curvature("gaussian", "jet")
    with pytest.raises(ValueError, match=r"control points must have shape \(\.\.\., m\+1, n\+1, 3\); got \(3, 3\)"):
        lab.BezierPatches(np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"set_colors: c10 components must lie in \[0, 1\]; got \(1.0, 2.0, 0.0\)"):
        p[0].set_colors((0, 0, 0), (0, 0, 0), (1, 2, 0), (0, 0, 0))
    with pytest.raises(ValueError, match=r"set_colors: c00 must be an \(r, g, b\) tuple of 3 numbers; got shape \(2,\)"):
        p[0].set_colors((0, 0), (0, 0, 0), (0, 0, 0), (0, 0, 0))
    with pytest.raises(TypeError, match="set_curvature: c11 must be a real number; got str 'x'"):
        p[0].set_curvature(1, 2, 3, "x")
    with pytest.raises(IndexError, match="patch index 3 out of range for 3 patches"):
        p[3]
    with pytest.raises(ValueError, match="num must be an integer >= 0; got -1"):
        p.refine(-1)
