"""Hints that name every mistake (issue 20): students' visualize_curvature with one mistake each (tests/students.py),
through lab.check; the report gives one diagnosis, the first failing case's, and groups the cases that share it."""

import numpy as np
import pytest

from lab import check
from lab.teaching.tasks import mutants, references
from tests.students import MISTAKES, student_class

#: What the report's headline must say for each mistake (the first failing case's hint).
HEADLINES = {
    "bu_bv_without_m_n": ["b_u has the factor 1 = 1 instead of m = 3", "b_v has the factor 1 = 1 instead of n = 3",
                          "81 times the right ones"],
    "buv_(m-1)n": ["b_uv has the factor (m − 1)n = 6 instead of mn = 9"],  # the non-square cases tell which
    "buv_without_mn": ["b_uv has the factor 1 = 1 instead of mn = 9"],
    "buu_m_bvv_n": ["the second derivatives need m(m-1) and n(n-1), not m and n"],
    "bu_1_buu_m": ["b_u has the factor 1 = 1 instead of m = 3", "b_uu has the factor m = 3 instead of m(m − 1) = 6"],
    "bv_m_bvv_1": ["b_v has the factor m instead of n (on this patch both are 3)",
                   "b_vv has the factor 1 = 1 instead of n(n − 1) = 6"],
    "second_derivatives_without_factors": ["b_uu has the factor 1 = 1", "b_uv has the factor 1 = 1",
                                           "b_vv has the factor 1 = 1"],
    "no_factors": ["the derivative nets need the degree factors"],
    "normal_over_norm_squared": ["you divided the cross product by |b_u × b_v|²"],
    "unnormalised_normal": ["you used the cross product without dividing by its length"],
    "hard_coded_factors_3_3": ["your degree factors are those of degree (3, 3), but this patch has degree (2, 3)"],
    "hard_coded_degree_4_4": ["an IndexError also on a square patch (one 3×3 patch", "take the degrees m and n from patch.degree"],
    "swapped_degrees_in_loops": ["m and n are swapped", "IndexError on a patch of degree (2, 3); the square cases pass"],
    "swapped_degree_factors": ["m and n are swapped"],
    "transposed_loops": ["your derivative nets are transposed", "IndexError on the non-square patches"],
    "sqrt_at_umbilics": ["use √(max(H² − K, 0))"],
    "f2_divides_by_zero": ["f2 must not divide by zero"],
    "f3_equals_zero": ["f3 must compare with a tolerance, not with == 0"],
    "f3_absolute_tolerance": ["your f3 tolerance is absolute and too large for this model"],
    "corner_order": ["c01 = the value at u = 0, v = 1"],
}


def test_every_mistake_has_its_headline():
    assert sorted(HEADLINES) == sorted(MISTAKES)


def test_the_students_right_solution_passes():
    rep = check.visualize_curvature(student_class(), seed=7)
    assert rep.passed, str(rep)


@pytest.mark.parametrize("mistake", sorted(MISTAKES))
def test_each_mistake_is_named_in_the_headline_once(mistake):
    rep = check.visualize_curvature(student_class(mistake), seed=7)
    assert not rep.passed, str(rep)
    text = str(rep)
    headline = text.splitlines()[1]
    for fragment in HEADLINES[mistake]:
        assert fragment in headline, text
    failing = [c for c in rep.cases if c.status not in ("passed", "not run")]
    assert failing[0].hint in rep.message and rep.message in headline, "the headline is the first failing case's hint"
    assert "compare your formulas" not in text, text
    # grouped: no hint is printed more than once
    for c in failing:
        if len(c.hint) > 40:
            assert text.count(c.hint) <= 1, text


def test_swapped_degrees_are_named_only_when_the_square_cases_pass():
    """A real student's hard-coded degree (4, 4) and transposed loops raise IndexErrors on non-square patches too:
    neither is called "m and n are swapped"."""
    for mistake in ("hard_coded_degree_4_4", "transposed_loops"):
        rep = check.visualize_curvature(student_class(mistake), seed=3)
        assert "m and n are swapped" not in str(rep), str(rep)
    rep = check.visualize_curvature(student_class("swapped_degrees_in_loops"), seed=3)
    assert rep.cases[0].passed and "m and n are swapped" in rep.message


def test_a_wrong_mixed_factor_shows_on_the_twisted_case_alone():
    """The twisted case has b_uu = b_vv = 0 and b_uv ≠ 0 at every corner: K = −f²/(EG − F²) there."""
    rng = np.random.default_rng(0)
    P = references.rand_net(rng, 2, 3, "twisted")
    d = references.variant_corner_derivatives(P)
    assert np.all(d["buu"] == 0) and np.all(d["bvv"] == 0) and np.all(np.linalg.norm(d["buv"], axis=-1) > 0)
    rep = check.visualize_curvature(student_class("buv_(m-1)n"), seed=7)
    twisted = next(c for c in rep.cases if c.name.startswith("a twisted"))
    assert not twisted.passed and "b_uv has the factor (m − 1)n = 3 instead of mn = 6" in twisted.hint


@pytest.mark.parametrize("m, n", [(3, 3), (2, 3), (4, 2)])
def test_every_combination_of_degree_factors_is_found(m, n):
    """Any combination of wrong factors of the five nets (a sample of 40 of them), on the net of a random patch."""
    rng = np.random.default_rng(m * 10 + n)
    nets = np.array([references.rand_net(rng, m, n) for _k in range(2)])
    choices = mutants.factor_choices(m, n)
    right = [choices[net][0][1] for net in references.NET_NAMES]
    for _k in range(40):
        factors = tuple(int(rng.choice([v for _label, v in choices[net] if v != 0]))
                        for net in references.NET_NAMES)
        if list(factors) == right:
            continue
        mutant = mutants.Mutant("factors", factors, ("x",) * 5)
        got = mutants.mutant_values(nets, [mutant])["H"][0]
        found = mutants.explain(nets, "H", got)
        assert found, factors
        assert all(mutants.fits(mu, t, nets, "H", got) for mu, t in found)  # each reproduces the values
        wrong = sum(f != r for f, r in zip(factors, right))
        assert min(mu.mistakes + t for mu, t in found) <= wrong  # never a more complicated story than the truth


def test_leaving_out_every_degree_factor_earns_only_the_twisted_case():
    """With b_uu = b_vv = 0, dropping every degree factor is the reparametrisation u -> m u, v -> n v: K and H
    come out right on the twisted patch, which therefore does not make the flat cases count (an instructor's
    review: 4 of 18 cases, 2.22 points, for an implementation that is wrong on every other curved patch)."""
    rep = check.visualize_curvature(student_class("no_factors"), graded=True, seed=7)
    passed = [c.name for c in rep.cases if c.passed]
    assert [name[:10] for name in passed] == ["a twisted "], str(rep)
    assert rep.score == pytest.approx(1 / 18), str(rep)
    flat = [c for c in rep.cases if c.name.startswith(("tilted flat", "plane z = 0"))]
    assert len(flat) == 3 and all("a curved case that decides the formulas" in c.hint for c in flat), str(rep)
    assert "the derivative nets need the degree factors" in str(rep).splitlines()[1]
