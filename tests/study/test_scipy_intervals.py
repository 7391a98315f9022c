"""The t, Welch and Wilson intervals against scipy and against the numbers the hand-written
formulas gave before they moved onto scipy, so that no published figure moves."""

import pytest
from scipy import stats

from gvgai_pcg.evaluation import ued
from gvgai_pcg.report import table
from gvgai_pcg.study import intervals

A = [0.1, 0.5, 0.35, 0.8]
B = [1.0, 2.5, 3.25]
# What the hand-written t formulas gave on A and B.
T_A = (-0.028119737316552762, 0.9031197373165527)
T_B = (-0.5959372751975693, 5.095937275197569)


def close(got, want) -> bool:
    return got == pytest.approx(want, abs=1e-12, rel=0)


def test_t_intervals_keep_the_old_numbers():
    assert close(ued.t_interval(A), T_A) and close(ued.t_interval(B), T_B)
    assert close(table.t_interval(A), T_A) and close(table.t_interval(B), T_B)
    assert ued.t_interval([2.0]) == (2.0, 2.0) and ued.t_interval([1.0, 1.0]) == (1.0, 1.0)
    assert table.t_interval([2.0]) is None and table.t_interval([1.0, 1.0]) == (1.0, 1.0)


def test_weighted_intervals_keep_the_old_numbers():
    assert close(ued.weighted_interval(A, [1, 1, 1, 1], False), T_A)
    assert close(
        ued.weighted_interval(A, [1, 1, 0.5, 0.5], False), (-0.13823382528444106, 0.9215671586177743)
    )
    assert close(ued.weighted_interval(A, [1, 1, 0.5, 0.5], True), (0.0989927752669979, 0.7904835726314982))
    assert ued.weighted_interval([0.5, 0.5], [1, 1], False) == (0.5, 0.5)


def test_estimates_keep_the_old_numbers():
    one = intervals.estimate(A, None, 0.0)
    assert close((one.low, one.high, one.p), (*T_A, 0.058118948832070805))
    two = intervals.estimate(A, B, 0.0)
    assert close((two.low, two.high, two.p), (-4.490561632184032, 0.8655616321840318, 0.10500909606660913))
    with_levels = intervals.estimate(A, B, 0.0, levels=[[0.1, 0.3, 0.2], [1.0, 0.0]])
    assert close((with_levels.low, with_levels.high, with_levels.p), (two.low, two.high, 0.11523796859929986))


def test_two_seed_sets_are_welchs_test():
    """Without level terms ``estimate`` of a difference is scipy's Welch test, interval and p."""
    welch = stats.ttest_ind(A, B, equal_var=False)
    two = intervals.estimate(A, B, 0.0)
    assert close((two.low, two.high, two.p), (*welch.confidence_interval(0.95), welch.pvalue))


@pytest.mark.parametrize(("k", "n"), [(0, 10), (3, 10), (5, 5), (1, 2), (17, 40)])
def test_wilson_is_scipys_on_whole_counts(k, n):
    """Kept hand-written: the weighted tail takes it at fractional counts, which binomtest refuses."""
    ci = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    assert close(ued.wilson_interval(k / n, n), (ci.low, ci.high))
