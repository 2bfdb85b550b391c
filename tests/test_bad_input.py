"""Issue 19, item 7: each bad input of the issue's "library and CLI" list gets a clear error naming the parameter,
what was expected and what was received, or a flag and a warning where the geometry is degenerate."""

import re
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

import lab
from lab import surfaces
from lab.geometry import colormaps as C
from lab.geometry import validation as V
from lab.geometry.curvature import DegeneratePointWarning
from lab.interrogation import meshes as I
from lab.interrogation.meshes import FocalSheetWarning

TOO_MUCH = r"would need about .* of memory, more than the limit of"


@pytest.fixture(scope="module")
def torus():
    return surfaces.torus()


@pytest.fixture(scope="module")
def small_fan(torus):
    return lab.geodesic_fan(torus, (0.1, 0.1), 8, 0.5)


def cli(*args):
    return subprocess.run([sys.executable, "-m", "lab.cli", *args], capture_output=True, text=True, timeout=300,
                          check=False)


# -- work that grows with a count is estimated before anything is allocated


@pytest.fixture
def eight_mib():
    previous = V.set_memory_limit("8M")
    yield
    V.set_memory_limit(previous)


def test_isophotes_count_is_bounded_and_estimated_first(torus, eight_mib):
    with pytest.raises(ValueError, match=r"count must be an integer from 1 to 1000; got 1000000000"):
        I.isophotes(torus, count=10**9)
    with pytest.raises(ValueError, match=r"isophotes\(count=1000\) on a mesh of \d+ cells " + TOO_MUCH):
        I.isophotes(torus, count=1000)


def test_geodesic_fan_n_angles_is_estimated_before_the_angles(torus):
    with pytest.raises(ValueError, match=r"1000000000 geodesic\(s\) of 101 samples each " + TOO_MUCH):
        lab.geodesic_fan(torus, (0.1, 0.1), 10**9, 1.0)


def test_polar_isodistance_samples_per_angle_is_estimated_first(small_fan):
    with pytest.raises(ValueError, match=r"1 polar isodistance curve\(s\) of 8 x 1000000000 samples " + TOO_MUCH):
        lab.polar_isodistance(small_fan, [0.25], samples_per_angle=10**9)


def test_reflection_lines_count_is_bounded_and_estimated_first(torus, eight_mib):
    with pytest.raises(ValueError, match=r"count must be an integer from 1 to 1000; got 1000000"):
        I.reflection_lines(torus, count=10**6)
    with pytest.raises(ValueError, match=r"reflection_lines\(count=900\) on a mesh of \d+ cells " + TOO_MUCH):
        I.reflection_lines(torus, count=900)


def test_stripe_mapping_n_stripes_is_bounded_and_estimated_first(torus, eight_mib):
    with pytest.raises(ValueError, match=r"n_stripes must be an integer from 1 to 1000; got 1000000000"):
        I.stripe_mapping(torus, n_stripes=10**9)
    with pytest.raises(ValueError, match=r"stripe_mapping\(n_stripes=500\) on a mesh of \d+ cells " + TOO_MUCH):
        I.stripe_mapping(torus, n_stripes=500)


def test_a_geodesic_on_the_closed_torus_is_bounded(torus):
    with pytest.raises(ValueError, match=r"length must be at most 100 times the surface's size \(8\.72\), i\.e\. "
                                         r"<= 872; got 1e\+07: on a closed surface .* wind round about 1\.15e\+06"):
        lab.geodesic(torus, (0.1, 0.1), 0.3, 1e7)


def test_curvature_at_a_huge_broadcast_view_is_refused_by_its_estimate(torus):
    u = np.broadcast_to(0.1, (10**5, 10**5))  # a view: no memory behind it
    with pytest.raises(ValueError, match=r"evaluating the surface on a 100000 x 100000 grid " + TOO_MUCH):
        torus.curvature(u, u)


@pytest.mark.parametrize("num, patches, need", [(600, r"8\.44e\+362", r"4\.52e\+365 B"),
                                                (10**6, r"4\.8e\+602061", r"2\.57e\+602064 B")])
def test_refine_estimate_of_astronomic_depths_is_formatted(num, patches, need):
    p = surfaces.practical().to_bezier_patches()
    with pytest.raises(ValueError, match=rf"refine\({num}\) of 49 patches \({patches} patches\) would need about "
                                         rf"{need} of memory"):
        p.refine(num)


def test_format_count_and_bytes_past_float_range():
    assert V.format_count(123) == "123" and V.format_count(10**400) == "1e+400"
    assert V.format_bytes(3 * 2**30) == "3 GiB" and V.format_bytes(7 * 10**500) == "7e+500 B"


def test_render_window_size_is_estimated_before_vtk(tmp_path):
    r = cli("render", "--surface", "torus", "--window-size", "100000x100000", "-o", str(tmp_path / "x.png"))
    assert r.returncode == 2
    assert "--window-size: a 100000 x 100000 picture (window_size) would need about 224 GiB" in r.stderr
    with pytest.raises(ValueError, match=r"a 100000 x 100000 picture \(window_size\) " + TOO_MUCH):
        lab.render.picture(surfaces.plane(), window_size=(100000, 100000))
    with pytest.raises(TypeError, match=r"window_size must be \(width, height\) in pixels; got '640x480'"):
        lab.render.picture(surfaces.plane(), window_size="640x480")


# -- degenerate geometry: flagged and warned, never a ZeroDivisionError or a silent NaN


def test_visualize_curvature_of_patches_that_are_one_point():
    p = lab.BezierPatches(np.zeros((2, 4, 4, 3)))
    with pytest.warns(DegeneratePointWarning, match="8 degenerate point"):
        p.visualize_curvature(p.CURVATURE_GAUSSIAN, p.COLOR_MAP_LINEAR)
    assert np.all(np.isnan(p.curvature)) and np.all(p.colors == 0.5)  # no curvature: the grey of non-finite values


def test_normal_and_fundamental_forms_at_a_pole_are_the_limits():
    s = surfaces.sphere(2.0)
    with pytest.warns(DegeneratePointWarning, match=r"1 degenerate point\(s\) .* the normal there is its limit"):
        N = s.normal(0.3, 0.0)  # the south pole; the outward normal there is -z
    np.testing.assert_allclose(N, [0, 0, -1], atol=1e-9)
    with pytest.warns(DegeneratePointWarning):
        ff = s.fundamental_forms(0.3, 1.0)  # the north pole
    np.testing.assert_allclose(ff.N, [0, 0, 1], atol=1e-9)
    assert ff.E == 0 and np.isfinite([ff.e, ff.f, ff.g]).all()


def test_colour_maps_refuse_inf_values_and_nan_options():
    with pytest.raises(ValueError, match=r"values must be finite for a colour map; got inf"):
        C.f2(np.array([0.0, np.inf, 1.0]))
    with pytest.raises(ValueError, match="vmin must be a finite number; got nan"):
        C.f2([0.0, 1.0], vmin=float("nan"))
    with pytest.raises(ValueError, match="vmax must be >= 0; got nan"):
        C.symmetric([0.0, 1.0], vmax=np.nan)
    with pytest.raises(ValueError, match=r"lower must be in \[0, 100\]; got nan"):
        C.percentile([0.0, 1.0], lower=np.nan)
    rgb = C.colors_for(np.array([0.0, np.inf, 1.0]), "linear")  # the documented path: non-finite is grey
    np.testing.assert_array_equal(rgb[1], [0.5, 0.5, 0.5])


def test_huge_weights_are_refused():
    P = np.random.default_rng(0).random((3, 3, 3))
    w = np.ones((3, 3))
    w[1, 1] = 1e308
    with pytest.raises(ValueError, match=r"weights must lie within a ratio of 1e\+60 .* got weights from 1 to "
                                         r"1e\+308: the rational derivatives would overflow"):
        lab.BezierSurface(P, w)


def test_parametric_surface_with_nan_derivatives_is_flagged():
    u, v = sp.symbols("u v")
    s = lab.ParametricSurface.from_sympy((u, v, sp.sqrt(u)), (u, v), ((-1, 1), (-1, 1)), name="root")
    with pytest.warns(DegeneratePointWarning, match=r"root: the derivatives are not finite at 1 of 1 point\(s\), "
                                                    r"e\.g\. \(u, v\) = \(-0\.5, 0\.5\)"):
        c = s.curvature(-0.5, 0.5)
    assert c.degenerate and np.isnan(c.K)


def test_focal_surface_with_infinite_function_values_warns(torus):
    with pytest.warns(FocalSheetWarning, match=r"(\d+) of \1 focal points are not finite"):
        m = I.focal_surface(torus, function=lambda k1, k2: np.full_like(k1, np.inf), resolution=8)
    assert not m.point_data["finite"].any()


def test_overflow_and_underflow_are_named_not_called_degenerate():
    P = np.random.default_rng(0).random((3, 3, 3))
    with pytest.raises(ValueError, match=r"control net must have coordinates of at most 1e\+60, beyond which the "
                                         r"fundamental forms overflow .* got coordinates up to 9\.97e\+199"):
        lab.BezierSurface(P * 1e200)
    with pytest.raises(ValueError, match=r"control net has an extent of only 9\.94e-201; below 1e-60 the "
                                         r"fundamental forms underflow"):
        lab.BezierSurface(P * 1e-200)


# -- numpy's own messages replaced by ours


def test_empty_arrays_in_f2_symmetric_and_percentile():
    with pytest.raises(ValueError, match=r"f2 needs at least one value to find its range; got an empty array "
                                         r"\(give vmin and vmax"):
        C.f2([])
    with pytest.raises(ValueError, match="symmetric needs at least one value"):
        C.symmetric(np.array([]))
    with pytest.raises(ValueError, match="percentile needs at least one value"):
        C.percentile([])
    assert C.f2([], vmin=0, vmax=1).shape == (0,)


def test_strings_where_numbers_belong():
    with pytest.raises(TypeError, match="R must be a real number; got str 'a'"):
        surfaces.torus("a", 1)
    with pytest.raises(TypeError, match="u must be an array of numbers; got str"):
        surfaces.plane().curvature("a", 0.5)
    with pytest.raises(TypeError, match="values must be an array of numbers; got str 'x'"):
        C.f1("x")


def test_a_degree_too_high_for_the_net():
    P = np.random.default_rng(0).random((4, 4, 3))
    k = np.array([0, 0, 0, 0, 0, 0, 1, 1, 1, 1.0])
    with pytest.raises(ValueError, match=r"degree of the knot vector in u must be below the number of control points "
                                         r"in that direction \(4, so at most 3\); got 5"):
        lab.BSplineSurface(P, k, k, 5, 3)


def test_grid_shape_junk():
    with pytest.raises(TypeError, match="grid_shape must be \\(rows, columns\\), two integers; got 'ab'"):
        lab.BezierPatches(np.zeros((4, 3, 3, 3)), grid_shape="ab")
    with pytest.raises(TypeError, match="grid_shape entry must be an integer; got float 1.5"):
        lab.BezierPatches(np.zeros((4, 3, 3, 3)), grid_shape=(1.5, 2))


def test_none_parameters():
    with pytest.raises(TypeError, match="R must be a real number; got NoneType None"):
        surfaces.torus(None, 1)
    with pytest.raises(TypeError, match="u must be an array of numbers; got NoneType None"):
        surfaces.plane().curvature(None, 0.5)
    with pytest.raises(TypeError, match="length must be a real number; got NoneType None"):
        lab.geodesic(surfaces.plane(), (0.5, 0.5), 0.0, None)


def test_complex_nets_are_refused():
    with pytest.raises(TypeError, match=r"control net must be real numbers; got complex values \(the imaginary part "
                                        r"would be dropped\)"):
        lab.BezierSurface(np.zeros((3, 3, 3)) + 1j)


def test_camera_inf(tmp_path):
    r = cli("render", "--surface", "torus", "--camera", "inf,30", "-o", str(tmp_path / "x.png"))
    assert r.returncode == 2 and "camera angles must be finite numbers of degrees; got 'inf,30'" in r.stderr
    with pytest.raises(ValueError, match="azimuth must be a finite number; got inf"):
        lab.render.picture(surfaces.plane(), camera=(np.inf, 30))


def test_grading_a_json_list(tmp_path):
    path = tmp_path / "05_visualize_curvature.ipynb"
    path.write_text("[1, 2]")
    from lab.teaching.grader.notebook import read_submission

    with pytest.raises(ValueError, match=r"not a notebook: a notebook is a JSON object with 'cells' \(nbformat 4\); "
                                         r"the file holds a JSON list"):
        read_submission(path)


def test_grading_an_empty_folder_and_bad_limits(tmp_path):
    r = cli("grade", str(tmp_path))
    assert r.returncode == 2 and f"no notebooks (.ipynb) in {tmp_path}" in r.stderr
    for option, value in (("--timeout", "-5"), ("--memory", "0")):
        r = cli("grade", str(tmp_path), option, value)
        assert r.returncode == 2 and f"argument {option}: expected a positive number; got '{value}'" in r.stderr


# -- issue 35: the last 5% (each test failed before its fix; the fuzzer, tests/test_fuzz.py, finds the kind)


def test_crash_by_allocation_a_huge_broadcast_view_is_estimated_not_copied():
    """Before: practical_height copied a (10^5, 10^5) view into 74.5 GiB (MemoryError)."""
    view = np.broadcast_to(np.float64(0.5), (10**5, 10**5))
    with pytest.raises(ValueError, match=r"practical_height at 10000000000 points " + TOO_MUCH):
        surfaces.practical_height(view, 0.5)


def test_hang_render_depth_8_is_refused_within_seconds_with_the_estimate(tmp_path):
    """Before: `render --depth 8` (3.2 million patches) worked for minutes without a word."""
    run = cli("render", "--surface", "practical", "--depth", "8", "-o", str(tmp_path / "p.vtp"))
    assert run.returncode == 2 and "Traceback" not in run.stderr
    assert re.search(r"--depth 8 would build 3211264 patches \(about \d+ s\), more than --max-patches 1000000: "
                     r"use --depth 7 or less, or raise --max-patches", run.stderr), run.stderr
    assert not (tmp_path / "p.vtp").exists()


def test_hang_a_line_of_curvature_of_absurd_length_is_refused():
    """Before: line_of_curvature(..., length=1e308) integrated until interrupted."""
    with pytest.raises(ValueError, match=r"length must be at most 100 times the surface's size"):
        lab.line_of_curvature(surfaces.ellipsoid(), (0.3, 0.4), "k1", 1e308)


def test_silent_garbage_text_where_numbers_go():
    """Before: practical_height('0.5', ...) failed in numpy; an array of text was taken as numbers."""
    with pytest.raises(TypeError, match=r"x must be an array of numbers; got str '0.5'"):
        surfaces.practical_height("0.5", 0.5)
    with pytest.raises(TypeError, match=r"u must be an array of numbers; got an array of <U3"):
        surfaces.torus().curvature(np.array(["0.5"]), 0.5)


def test_silent_garbage_set_curvature_nan_is_flagged_and_inf_refused():
    patches = lab.BezierPatches(np.random.default_rng(35).random((1, 4, 4, 3)))
    with pytest.warns(DegeneratePointWarning, match=r"set_curvature: c00 is NaN .* painted grey"):
        patches[0].set_curvature(np.nan, 0.5, 0.5, 0.5)
    with pytest.raises(ValueError, match=r"set_curvature: c11 must be a finite number; got inf"):
        patches[0].set_curvature(0.5, 0.5, 0.5, np.inf)


def test_silent_garbage_f2_near_the_float_limit_is_exact():
    """Before: 1.7e308 - (-1.7e308) overflowed: NaN colours and numpy's RuntimeWarning."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        t = C.f2(np.array([1.7e308, -1.7e308, 0.0, 0.85e308]))
    np.testing.assert_allclose(t, [1.0, 0.0, 0.5, 0.75], atol=1e-15)


def test_silent_garbage_junk_seams_are_refused():
    net = np.zeros((2, 4, 4, 3)) + np.random.default_rng(35).random((4, 4, 3))
    for junk in ("x", 3, (1, 2), ((1, 2), (3, 4))):
        with pytest.raises(TypeError, match=r"seams must be Seams\(\(periodic_u, periodic_v\)"):
            lab.BezierPatches(net, None, (1, 2), junk)
    good = lab.BezierPatches(net, None, (1, 2), ((True, False), ((False, True), (False, False))))
    assert good.seams.periodic == (True, False) and good.seams.collapsed == ((False, True), (False, False))


def test_silent_garbage_a_colour_map_without_its_measure():
    """Before: picture(surface, color_map='linear') drew a grey picture of nothing."""
    with pytest.raises(ValueError, match=r"color_map needs curvature: a colour map colours a curvature measure"):
        lab.render.picture(surfaces.plane(), color_map="linear", window_size=(64, 48))


def test_unclear_messages_become_the_labs():
    from lab.geometry.derivatives import Derivatives

    with pytest.raises(ValueError, match=r"R must be a finite number; got an integer of about 1e\+400"):
        surfaces.torus(10**400, 1.0)  # before: OverflowError: int too large to convert to float
    with pytest.raises(TypeError, match=r"derivatives\(u, v\) must return a Derivatives of six arrays .* got NoneType"):
        lab.ParametricSurface(lambda u, v: None, ((0, 1), (0, 1))).curvature(0.5, 0.5)  # before: .bu of None
    with pytest.raises(ValueError, match=r"its b has shape \(1, 2\)"):  # before: IndexError: index 2 is out of bounds
        lab.ParametricSurface(lambda u, v: Derivatives(*(np.zeros(np.shape(u) + (2,)) for _ in range(6))),
                              ((0, 1), (0, 1))).curvature(0.5, 0.5)
    with pytest.raises(ValueError, match=r"unknown colour map \['linear'\]; expected one of 'linear'"):
        C.colors_for(np.array([1.0]), ["linear"])  # before: TypeError: unhashable type: 'list'
    u, v, a = sp.symbols("u v a")
    with pytest.raises(ValueError, match=r"xyz may depend only on the parameters u and v; got the free symbol\(s\) a"):
        lab.ParametricSurface.from_sympy((u, v, a * u), (u, v), ((0, 1), (0, 1)))  # before: NameError at evaluation


def test_unclear_messages_negative_vmax_is_a_usage_error(tmp_path):
    for args in (["--color-map", "symmetric", "--vmax", "-1"], ["--vmax", "-5"]):
        run = cli("render", "--surface", "plane", "--depth", "0", *args, "-o", str(tmp_path / "p.vtp"))
        assert run.returncode == 2 and "Traceback" not in run.stderr, run.stderr
        assert "curvature-lab render: error:" in run.stderr or "curvature-lab: error:" in run.stderr


def test_unclear_messages_geodesics_on_a_zero_size_surface_and_to_a_pole():
    with pytest.raises(ValueError, match=r"is degenerate: it has zero size \(all its points coincide"):
        lab.geodesic_between(lab.BezierSurface(np.zeros((4, 4, 3))), (0.1, 0.1), (0.8, 0.7))
    with pytest.raises(ValueError, match=r"B is a degenerate point \(a pole: b_u x b_v = 0\)"):
        lab.geodesic_between(surfaces.sphere(), (0.3, 0.3), (0.5, 1.0))


# -- issue 35, the five failures the fuzzer still found at other seeds and budgets


def test_explorer_of_bezier_patches_shows_curvature_without_the_surface_tools():
    patches = surfaces.torus().to_bezier_patches()
    e = lab.CurvatureExplorer(patches, depth=0, max_depth=2, window_size=(64, 48), live=False)
    assert e.tools is None  # the probe and the combs need a surface's (u, v) domain
    assert e._base is patches


def test_release_with_a_roster_that_is_not_utf8_names_the_file(tmp_path):
    from lab.teaching.course.release import main

    roster, secret = tmp_path / "roster.csv", tmp_path / "secret"
    roster.write_bytes(b"username\n\xff\xfe")
    secret.write_text("0123456789abcdef0123456789abcdef")
    import contextlib
    import io

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main([str(tmp_path / "out"), "--per-student", str(roster), "--secret-file", str(secret)])
    assert code == 2
    assert f"{roster}: not a UTF-8 text file (byte 9 is 0xff)" in err.getvalue()


def test_normal_section_on_a_surface_that_is_nan_names_the_start_point():
    nan = lab.ParametricSurface(lambda u, v: lab.Derivatives(*(np.full(np.shape(u) + (3,), np.nan) for _ in range(6))),
                                ((0, 1), (0, 1)))
    with pytest.warns(DegeneratePointWarning), pytest.raises(
            ValueError, match=r"start point \(u, v\) = \(0.1, 0.1\) is a degenerate point .* not finite"):
        lab.normal_section(nan, (0.1, 0.1), 0.3, 1.0)


def test_stripe_mapping_of_derivatives_near_1e300_is_refused_as_degenerate():
    huge = lab.ParametricSurface(lambda u, v: lab.Derivatives(*(np.full(np.shape(u) + (3,), 1e300) for _ in range(6))),
                                 ((0, 1), (0, 1)))
    with pytest.warns(DegeneratePointWarning), pytest.raises(
            ValueError, match="nothing to draw: the surface is not finite at any of its 64 points"):
        lab.stripe_mapping(huge, resolution=8)  # refused when its mesh is made (every mesh of it, every picture)


@pytest.mark.parametrize("kw", [{"c": 5e-324}, {"c": 1e-300}, {"c": 1e300}, {"height": 1e6}])
def test_catenoid_parameters_out_of_the_accepted_range(kw):
    with pytest.raises(ValueError, match=r"(c|height) must be in \["):
        surfaces.catenoid(**kw)


def test_found_at_seed_1_a_class_for_the_explorer_and_a_huge_int_angle():
    with pytest.raises(TypeError, match="got the class BezierSurface itself"):
        lab.CurvatureExplorer(lab.BezierSurface, window_size=(64, 48), live=False)
    with pytest.raises(ValueError, match="angle must be finite .* beyond the float range"):
        lab.normal_section(surfaces.torus(), (0.1, 0.1), 10**400, 1.0)


def test_a_subnormal_size_is_refused_with_the_smallest_normal_float():
    """A positive size below 2.2e-308 (a subnormal float, whose reciprocal overflows to inf) is refused by name."""
    for make, name in ((lambda: lab.surfaces.torus(r=5e-324), "r"), (lambda: lab.surfaces.sphere(1e-310), "radius")):
        with pytest.raises(ValueError, match=rf"^{name} must be a positive number of at least 2\.23e-308 \(the smallest "
                                             r"normal float\); got .*, a subnormal number whose reciprocal is infinite"):
            make()
    with pytest.warns(DegeneratePointWarning):  # a normal but tiny tube: a circle to the floats, reported as such
        assert lab.surfaces.torus(r=1e-300).curvature(0.0, 0.0).degenerate


def test_found_at_seed_14_text_as_an_angle_and_a_subnormal_vmax():
    with pytest.raises(TypeError, match="angle must be an array of numbers; got str '1.5'"):
        lab.normal_section(surfaces.torus(), (0.1, 0.1), "1.5", 1.0)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow warning: beyond a subnormal vmax the colour saturates
        np.testing.assert_array_equal(C.signed_log(np.array([-1.0, 0.0, 2.0]), vmax=5e-324), [0.0, 0.5, 1.0])


def test_found_at_seeds_16_to_19():
    """What the fuzzer found at seeds 16–19 (the suite runs one seed), each now named or drawn right."""
    import warnings

    plane = surfaces.plane()
    with pytest.raises(TypeError, match=r"holes must be a list of loops .*; got 1.0"):
        lab.trimmed(plane, None, 1.0)  # was Python's "'float' object is not iterable"
    with pytest.raises(ValueError, match="knot vector in u must be finite numbers; got an integer beyond the float range"):
        lab.BSplineSurface(np.zeros((4, 4, 3)), [10**400] * 8, [0, 0, 0, 0, 1, 1, 1, 1], 3, 3)
    patch = surfaces.practical().to_bezier_patches()[0]
    with pytest.raises(ValueError, match=r"set_colors: c11 components must lie in \[0, 1\]"):
        patch.set_colors((0.1, 0.2, 0.3), (0.1, 0.2, 0.3), (0.1, 0.2, 0.3), [10**400, 0, 0])
    with pytest.raises(TypeError, match=r"levels must be a sequence of numbers \(the band borders\)"):
        lab.band_lines(surfaces.torus(), "gaussian", [[1.0, 2.0], [3.0]], resolution=8)
    with pytest.raises(ValueError, match="direction must be finite numbers; got an integer beyond the float range"):
        lab.reflection_lines(surfaces.torus(), resolution=8, count=3, direction=(0, 0, 10**400))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # its length overflowed before: scaled first, (1e308, 1e308, 0) is a direction
        big = lab.reflection_lines(surfaces.torus(), resolution=8, count=3, direction=(1e308, 1e308, 0))
        assert big.n_points == lab.reflection_lines(surfaces.torus(), resolution=8, count=3, direction=(1, 1, 0)).n_points
        np.testing.assert_array_equal(C.signed_log(np.array([5e-324, -5e-324, 0.0])), [1.0, 0.0, 0.5])  # 0.5 * x underflowed
    with pytest.raises(ValueError, match=r"size must be <= 1e\+60"):
        lab.probe(surfaces.torus(), 0.3, 0.4, size=1.7976931348623157e308)
    zero = lab.BezierSurface(np.zeros((4, 4, 3)))  # a picture of nothing, and PyVista's TypeError in the explorer
    for draw in (lambda: lab.render.picture(zero, "gaussian", "linear", window_size=(64, 48), resolution=1),
                 lambda: lab.CurvatureExplorer(zero, depth=0, max_depth=2, live=False)):
        with pytest.raises(ValueError, match=r"nothing to draw: all points of the surface coincide at \(0, 0, 0\)"):
            draw()


def test_found_at_seeds_20_to_23():
    """A check's timeout, a domain and a colour map's scale given out of range, and a path shorter than rounding."""
    with pytest.raises(ValueError, match=r"timeout must be a positive number of seconds, at most 86400; got 1000"):
        lab.check.h(lambda t: t, seed=1, timeout=10**400)  # was OverflowError
    with pytest.raises(ValueError, match=r"domain must be \(\(u_min, u_max\), \(v_min, v_max\)\) of finite numbers"):
        lab.ParametricSurface(lambda u, v: None, ((0, 10**400), (0, 1)))
    with pytest.raises(TypeError, match="scale must be a real number; got str '1e999'"):
        C.signed_log(np.array([]), scale="1e999")  # no values: the scale was never looked at
    with pytest.raises(ValueError, match=r"length must be at least 1e-12 times the surface's size \(8.72\)"):
        lab.line_of_curvature(surfaces.torus(), (0.3, 0.4), "k1", 1e-300)  # was the solver's RuntimeError
    assert lab.line_of_curvature(surfaces.torus(), (0.3, 0.4), "k1", 1e-10).length == pytest.approx(1e-10)


def test_found_at_seeds_24_to_26(capsys):
    """A stripe corner whose ray runs along a wall, no values with a vmax, a class where an object goes, and a file
    name the system refuses: each a result or a message, not a warning or a traceback."""
    import warnings

    from lab import cli

    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        stripes = I.stripe_mapping(surfaces.torus(), resolution=6, n_stripes=4)  # P0/P1 with P1 = 0 at a corner
        assert stripes.n_cells > 1000 and np.isfinite(np.asarray(stripes.points)).all()
        assert C.signed_log(np.zeros((3, 0)), vmax=1.7e308).shape == (3, 0)  # numpy's "mean of empty slice"
    for call in (lambda: lab.render.picture(lab.BezierSurface, "gaussian", "linear", window_size=(64, 48)),
                 lambda: lab.write(lab.BezierSurface, "x.step")):
        with pytest.raises(TypeError, match="got the class BezierSurface itself"):
            call()
    assert cli.main(["exercises", "--solutions", "x" * 300]) == 1
    assert "curvature-lab exercises: error: [Errno 36] File name too long" in capsys.readouterr().err


def test_found_at_seeds_27_to_30():
    """Huge broadcast views classified or clipped onto the domain are estimated before the copy; a surface not
    finite anywhere is refused before a blank picture is drawn."""
    from lab.geometry import curvature as Cv

    with pytest.raises(ValueError, match="classifying 10000000000 points would need about 596 GiB"):
        Cv.classify(np.broadcast_to(1.0, (10**6, 10**4)), np.array([-1e-100]))
    patches = surfaces.practical().to_bezier_patches()
    with pytest.raises(ValueError, match="clipping 10000000000 values of u onto the domain would need about 74.5 GiB"):
        patches.evaluate(np.broadcast_to(-1e-20, (10**5, 10**5)), 0.5)
    with pytest.raises(ValueError, match="curvature of 49 patches at 10000000000 points each would need"):
        patches.curvature_at(np.array(-1.1e-308), np.broadcast_to(0.5, (10**5, 10**5)))  # the scalar clipped alone
    np.testing.assert_array_equal(patches.evaluate(np.array([-1e-15, 1 + 1e-15]), 0.5),
                                  patches.evaluate(np.array([0.0, 1.0]), 0.5))  # rounding outside is still clipped
    huge = lab.ParametricSurface(lambda u, v: lab.Derivatives(*(np.full(np.shape(u) + (3,), 1e300) for _ in range(6))),
                                 ((0, 1), (0, 1)), name="huge")
    with pytest.warns(DegeneratePointWarning), pytest.raises(ValueError, match="nothing to draw: the surface is not "
                                                                               "finite at any of its"):
        lab.render.picture(huge, "gaussian", "linear", window_size=(64, 48))
