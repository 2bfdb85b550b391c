"""Colour maps of the practical (section 4), Dill's table and our own designs (lab.colormaps)."""

import numpy as np
import pytest

import lab.i18n
from lab import colormaps as cm


def test_h_anchor_points_and_pieces():
    np.testing.assert_array_equal(cm.h([0.0, 0.25, 0.5, 0.75, 1.0]), [[0, 0, 1], [0, 1, 1], [0, 1, 0], [1, 1, 0], [1, 0, 0]])
    x = np.array([0.1, 0.3, 0.6, 0.9])
    expected = [[0, 0.4, 1], [0, 1, 2 - 1.2], [4 * 0.6 - 2, 1, 0], [1, 4 - 3.6, 0]]
    np.testing.assert_allclose(cm.h(x), expected, atol=1e-15)
    assert cm.h(np.zeros((2, 3))).shape == (2, 3, 3)


def test_h_is_continuous():
    x = np.linspace(0, 1, 100001)
    assert np.max(np.abs(np.diff(cm.h(x), axis=0))) <= 4 * 1e-5 + 1e-12


def test_f1_cuts():
    np.testing.assert_array_equal(cm.f1([-2, 0, 0.3, 1, 5]), [0, 0, 0.3, 1, 1])


def test_f2_linear_and_all_equal():
    np.testing.assert_allclose(cm.f2([2.0, 4.0, 3.0]), [0, 1, 0.5])
    np.testing.assert_array_equal(cm.f2([1.5, 1.5, 1.5]), [0.5, 0.5, 0.5])
    # rounding noise on a sphere is not stretched over the whole ramp
    np.testing.assert_array_equal(cm.f2([0.25, 0.25 + 1e-13, 0.25 - 1e-13]), [0.5, 0.5, 0.5])
    np.testing.assert_array_equal(cm.f2([1e-17, -1e-17], atol=1e-9), [0.5, 0.5])
    np.testing.assert_allclose(cm.f2([0, 10], vmin=0, vmax=20), [0, 0.5])
    with pytest.raises(ValueError, match="f2 needs vmin <= vmax; got vmin=2, vmax=1"):
        cm.f2([1.0], vmin=2, vmax=1)


def test_f3_with_tolerance():
    np.testing.assert_array_equal(cm.f3([-1, -1e-12, 0, 1e-12, 2]), [0, 0.5, 0.5, 0.5, 1])
    np.testing.assert_array_equal(cm.f3([-1e-12, 1e-12], tol=0), [0, 1])
    with pytest.raises(ValueError, match="tol must be >= 0"):
        cm.f3([1.0], tol=-1)


def test_dill_five_bands_of_figure_6():
    values = [-0.06, -0.04, -0.02, 0.0, 0.02, -0.5, 0.5]
    names = ["blue", "turquoise", "green", "yellow", "red", "blue", "red"]
    lookup = {"blue": [0, 0, 1], "turquoise": [0, 1, 1], "green": [0, 1, 0], "yellow": [1, 1, 0], "red": [1, 0, 0]}
    np.testing.assert_array_equal(cm.dill(values), [lookup[n] for n in names])
    np.testing.assert_array_equal(cm.dill([0.5, 1.0, 1.5], vmin=0, vmax=2), [lookup["turquoise"], lookup["green"], lookup["yellow"]])
    with pytest.raises(ValueError, match="dill needs vmin < vmax"):
        cm.dill([0.0], vmin=1, vmax=1)
    # the names: Dill's table (Dill 1981, figure 6) read off band by band, and scaled by a = 12.5
    assert list(cm.dill_names(values)) == names
    assert list(cm.dill_names([-0.009, 0.009, 0.011, -0.011])) == ["yellow", "yellow", "red", "green"]
    a = 12.5
    assert list(cm.dill_names([-1.0, -0.5, -0.2, 0.0, 0.2], -0.07 * a, 0.03 * a)) == [
        "blue", "turquoise", "green", "yellow", "red"]
    assert cm.dill_names(np.zeros((2, 3))).shape == (2, 3)
    # in German the same bands by their German names (notebook 09 prints them), the English above unchanged
    with lab.i18n.using("de"):
        assert list(cm.dill_names(values)) == ["blau", "türkis", "grün", "gelb", "rot", "blau", "rot"]
    assert list(cm.dill_names(values)) == names


def test_own_designs():
    x = np.array([-2.0, -1.0, 0.0, 0.5, 1.0])
    s = cm.symmetric(x)
    assert s[2] == 0.5 and s[0] == 0.0 and s[-1] == 0.75  # zero is always green
    rng = np.random.default_rng(0)
    data = np.r_[rng.normal(size=1000), 1e6]  # one outlier
    p = cm.percentile(data)
    assert np.ptp(p[:-1]) > 0.9  # the outlier does not squeeze the rest
    assert cm.f2(data)[:-1].max() < 1e-4  # ... while the practical's f2 does
    g = cm.signed_log(np.array([-100.0, -1.0, 0.0, 1.0, 100.0]), scale=1.0)
    np.testing.assert_allclose(g, [0, 0.5 - 0.5 * np.log(2) / np.log(101), 0.5, 0.5 + 0.5 * np.log(2) / np.log(101), 1])
    for name in cm.COLOR_MAPS:
        rgb = cm.apply(name, x)
        assert rgb.shape == (5, 3) and rgb.min() >= 0 and rgb.max() <= 1


def test_bad_input_messages():
    with pytest.raises(ValueError, match=r"h expects values in \[0, 1\]; got values in \[-0.5, 1\]"):
        cm.h([-0.5, 1.0])
    with pytest.raises(ValueError, match=r"h expects values in \[0, 1\]; got 1.5"):
        cm.h(1.5)
    with pytest.raises(ValueError, match="values contain NaN"):
        cm.f1([np.nan])
    with pytest.raises(ValueError, match="unknown colour map 'rainbow'; expected one of 'linear', 'cut'"):
        cm.apply("rainbow", [1.0])
    with pytest.raises(ValueError, match="percentiles must satisfy"):
        cm.percentile([1.0, 2.0], 90, 10)


@pytest.mark.parametrize("name", sorted(cm.COLOR_MAPS))
def test_colours_in_chunks_equal_colours_at_once(name, rng):
    # colors_for finds the map's range once and colours chunk by chunk: the same colours as one chunk
    x = rng.normal(size=(999, 2, 2)) * 3
    x[5, 1, 1] = np.nan
    whole = cm.colors_for(x, name, chunk=10**6)
    parts = cm.colors_for(x, name, chunk=7)
    np.testing.assert_array_equal(parts, whole)
    np.testing.assert_array_equal(whole[5, 1, 1], [0.5, 0.5, 0.5])  # NaN: grey
    direct = cm.apply(name, x[np.isfinite(x)])
    np.testing.assert_allclose(whole[np.isfinite(x)], direct, atol=1e-15)  # and what the map gives on its own


def test_one_number_gives_what_an_array_of_it_gives():
    """The scalar paths of h and f2 (a student's loop calls them once per corner) equal the array paths bit for bit,
    and refuse NaN and inf with the array path's messages."""
    for x in np.linspace(-0.3, 1.3, 1601):
        one, array = cm.f2(x, 0.0, 1.0), cm.f2(np.array([x]), 0.0, 1.0)[0]
        assert one == array and isinstance(one, np.float64)
        assert np.array_equal(cm.h(float(one)), cm.h(np.array([one]))[0])
    assert np.array_equal(cm.h(np.int64(1)), [1.0, 0.0, 0.0]) and cm.f2(3.0, 1.0, 1.0) == 0.5
    for bad in (float("nan"), np.float64("inf")):
        with pytest.raises(ValueError, match="NaN|finite"):
            cm.h(bad)
        with pytest.raises(ValueError, match="NaN|finite"):
            cm.f2(bad, 0.0, 1.0)


def test_signed_log_at_extreme_scales_stays_finite_and_exact():
    """A scale far above every value gives the linear map it tends to (log1p(M/s) would underflow to 0 and divide by
    it); a scale far below gives log(a) - log(s) where a/s overflows; no warning either way (the fuzzer found both)."""
    import warnings

    x = np.array([-1.0, 0.0, 2.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_allclose(cm.signed_log(x, scale=1e308), 0.5 + 0.5 * x / 2.0, rtol=0, atol=1e-15)
        huge = cm.signed_log(np.array([-1.7e308, 0.0, 1.7e308, 1e-300]), scale=1e-300)
    assert np.all(np.isfinite(huge)) and list(huge[:3]) == [0.0, 0.5, 1.0]
    # 1e-300 against M = 1.7e308 at s = 1e-300: log(2) / (log(1.7e308) - log(1e-300)) by the closed form
    expected = 0.5 + 0.5 * np.log1p(1.0) / (np.log(1.7e308) - np.log(1e-300))
    assert huge[3] == pytest.approx(expected, rel=1e-12)
    np.testing.assert_allclose(cm.signed_log(x, scale=0.5), 0.5 + 0.5 * np.sign(x) * np.log1p(np.abs(x) / 0.5)
                               / np.log1p(2.0 / 0.5), rtol=1e-15)


def test_an_integer_beyond_the_float_range_is_named():
    """f2's scalar shortcut handed 10**400 on to the array path's message instead of an OverflowError (fuzzer)."""
    with pytest.raises(ValueError, match=r"vmax must be a finite number; got an integer of about"):
        cm.f2(np.array([-1.0, 0.0, 2.0]), 0.0, 10**400)
