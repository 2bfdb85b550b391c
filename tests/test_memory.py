"""Guards against work that would not fit in memory, and memory per patch of refine and visualize_curvature."""

import time

import numpy as np
import pytest

import lab
import lab.mesh
from lab import surfaces
from lab.geometry import validation as _v
from tests.measure import traced_peak


@pytest.fixture
def limit():
    """Restore the memory limit after a test that sets it."""
    previous = lab.set_memory_limit(None)
    yield
    lab.set_memory_limit(previous)


def test_refine_14_is_refused_before_any_work(limit):
    p = surfaces.practical().to_bezier_patches()
    before = p.control_points
    start = time.process_time()
    with pytest.raises(ValueError, match=r"refine\(14\) of 49 patches \(13153337344 patches\) would need about "
                                         r"[0-9.]+ TiB of memory, more than the limit of .* \(50% of the .* available\)"):
        p.refine(14)
    assert time.process_time() - start < 5  # refused up front, nothing allocated (a generous bound: no timing test)
    assert p.control_points is before and len(p) == 49  # unchanged


def test_limit_from_keyword_setting_and_environment(limit, monkeypatch):
    p = surfaces.practical().to_bezier_patches()
    for depth in (2, 4):  # the estimate covers what refine really allocates, without overstating it much
        need = p.refine_bytes(depth)
        peak, _ = traced_peak(lambda depth=depth: p.copy().refine(depth))
        assert peak <= need <= 10 * peak + 4e6
    with pytest.raises(ValueError, match=r"more than the limit of 1000 B \(given as memory_limit\)"):
        p.refine(2, memory_limit=1000)
    assert len(p.refine(2, memory_limit="1G")) == 49 * 16
    assert lab.set_memory_limit("1 MiB") is None
    assert lab.memory_limit() == (2**20, "set with lab.set_memory_limit")
    with pytest.raises(ValueError, match=r"a 2000 x 2000 parameter grid would need about 61 MiB .* 1 MiB "
                                         r"\(set with lab.set_memory_limit\)"):
        surfaces.torus().grid(2000, 2000)
    assert lab.set_memory_limit(None) == 2**20
    monkeypatch.setenv("LAB_MEMORY_LIMIT", "3G")
    assert lab.memory_limit() == (3 * 2**30, "from LAB_MEMORY_LIMIT")
    monkeypatch.delenv("LAB_MEMORY_LIMIT")
    limit_now, source = lab.memory_limit()
    available = _v.available_memory()
    assert limit_now == int(0.5 * available) or abs(limit_now - 0.5 * available) < 0.05 * available  # it moves
    assert "available" in source


@pytest.mark.parametrize("bad", ["lots", -5, 0, float("nan"), True])
def test_bad_limits_are_refused(bad, limit):
    with pytest.raises(ValueError, match="memory limit must be a"):
        lab.set_memory_limit(bad)


def test_calls_that_grow_with_the_work_are_guarded(limit):
    lab.set_memory_limit("100 KiB")
    s = surfaces.practical()
    u = np.linspace(0, 7, 5000)
    calls = [
        (lambda: s.curvature(u, u), "evaluating the surface at 5000 points"),
        (lambda: s.curvature_grid(u[:300], u[:300]), "evaluating the surface on a 300 x 300 grid"),
        (lambda: lab.mesh.surface_mesh(s, 300, 300), "a surface mesh of 300 x 300 vertices"),
        (lambda: s.to_bezier_patches().to_mesh(resolution=16), "a mesh of 49 patches at resolution 16"),
        (lambda: s.to_bezier_patches().curvature_at(u[:50, None], u[None, :50] / 7), "curvature of 49 patches"),
        (lambda: lab.geodesic_fan(s, (3.0, 3.0), 400, 1.0), "400 geodesic"),
    ]
    for call, what in calls:
        with pytest.raises(ValueError, match=what + ".* more than the limit of 100 KiB"):
            call()
    assert s.curvature(1.0, 2.0).K.shape == ()  # small work passes


@pytest.mark.parametrize("depth", [3, 4])
def test_memory_per_patch_of_refine_and_visualize(depth):
    # the bound: 1.2 KiB per patch; the collection itself holds 512 B per bicubic patch
    base = surfaces.practical().to_bezier_patches()
    peak, p = traced_peak(lambda: base.refine(depth))
    n = len(p)
    assert n == 49 * 4**depth
    assert peak / n <= 1.2 * 1024
    held = p.control_points.nbytes + p.curvature.nbytes + p.colors.nbytes
    assert held == 512 * n
    peak, _ = traced_peak(lambda: p.visualize_curvature(p.CURVATURE_GAUSSIAN, p.COLOR_MAP_LINEAR))
    assert (held + peak) / n <= 1.2 * 1024
    assert np.all(np.isfinite(p.colors))


def test_refine_in_one_pass_equals_refining_level_by_level(rng):
    s = surfaces.torus()  # rational, on a grid
    one = s.to_bezier_patches().refine(3)
    steps = s.to_bezier_patches()
    for _ in range(3):
        steps.refine(1)
    np.testing.assert_array_equal(one.control_points, steps.control_points)
    np.testing.assert_array_equal(one.weights, steps.weights)
    assert one.grid_shape == steps.grid_shape == (4 * 8, 4 * 8) and one.seams == s.seams
    loose = lab.BezierPatches(rng.normal(size=(3, 3, 4, 3)))  # no grid: the descendants follow their patch
    ref = lab.BezierPatches(loose.control_points.copy())
    loose.refine(2)
    for _ in range(2):
        ref.refine(1)
    np.testing.assert_array_equal(loose.control_points, ref.control_points)
    # every descendant reproduces its part of the parent: patch 0's first descendant is [0, 1/4]^2 of patch 0
    from lab.bezier import evaluate

    t = np.linspace(0, 1, 5)
    np.testing.assert_allclose(evaluate(loose.control_points[0], t[:, None], t[None, :]),
                               evaluate(ref.control_points[0], t[:, None], t[None, :]), atol=1e-14)
    parent = lab.BezierPatches(loose.control_points[:0].copy() if False else rng.normal(size=(1, 3, 4, 3)))
    kids = parent.copy().refine(2)
    np.testing.assert_allclose(evaluate(kids.control_points[0], t[:, None], t[None, :]),
                               evaluate(parent.control_points[0], t[:, None] / 4, t[None, :] / 4), atol=1e-13)


def test_mode_and_map_errors_name_plain_values():
    p = surfaces.practical().to_bezier_patches()
    with pytest.raises(ValueError) as err:
        p.visualize_curvature("curvy", p.COLOR_MAP_LINEAR)
    assert str(err.value) == ("unknown curvature mode 'curvy'; expected one of 'gaussian', 'mean', 'k1', 'k2', "
                              "'strain-energy'")
    with pytest.raises(ValueError, match=r"unknown colour map 'nope'; expected one of 'linear', 'cut'"):
        p.visualize_curvature(p.CURVATURE_GAUSSIAN, "nope")
    assert "CurvatureMode" not in str(err.value) and "<" not in str(err.value)
