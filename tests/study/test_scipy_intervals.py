"""The t, Welch and Wilson intervals against scipy and against the numbers the hand-written
formulas gave before they moved onto scipy, so that no published figure moves."""

import pytest
from scipy import stats

from gvgai_pcg.evaluation import ued
from gvgai_pcg.report import table
from gvgai_pcg.study.verdicts import intervals

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
    """scipy's on a whole count; a fractional count (the weighted tail's), which binomtest refuses,
    keeps the written-out formula."""
    ci = stats.binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    assert close(ued.wilson_interval(k / n, n), (ci.low, ci.high))
    z, f = stats.norm.ppf(0.975), k / n  # the formula it replaced, to 1e-9
    centre = (f + z * z / (2 * n)) / (1 + z * z / n)
    half = z * (f * (1 - f) / n + z * z / (4 * n * n)) ** 0.5 / (1 + z * z / n)
    assert ued.wilson_interval(k / n, n) == pytest.approx(
        (max(0, centre - half), min(1, centre + half)), abs=1e-9
    )


def _by_hand(a, b):
    """The formulas as they were written out before scipy: mean (difference), Welch-Satterthwaite
    df, t quantile from scipy (it always was), two-sided p."""
    import math

    def mean_var(v):
        m = sum(v) / len(v)
        return m, sum((x - m) ** 2 for x in v) / (len(v) - 1)

    (ma, va), (mb, vb) = mean_var(a), (mean_var(b) if b else (0.0, 0.0))
    qa, qb = va / len(a), (vb / len(b) if b else 0.0)
    df = (qa + qb) ** 2 / (qa**2 / (len(a) - 1) + (qb**2 / (len(b) - 1) if b else 0.0))
    se, value = math.sqrt(qa + qb), ma - mb
    half = stats.t.ppf(0.975, df) * se
    return value - half, value + half, 2 * stats.t.sf(abs(value) / se, df)


def test_the_published_curricula_cells_keep_their_numbers_to_1e9():
    """Every per-seed cell of ``results/curricula`` and every difference with PPCG: scipy's
    intervals and p values are the written-out formulas' to 1e-9, so no published figure moves."""
    from pathlib import Path

    from gvgai_pcg.evaluation.checkpoints import find_runs
    from gvgai_pcg.evaluation.protocol import Protocol
    from gvgai_pcg.study import BUDGETS
    from gvgai_pcg.study.verdicts.comparison import collect_runs

    published = Path(__file__).resolve().parents[2] / "results" / "curricula"
    if not (published / "runs").is_dir():
        pytest.skip("no published curricula runs")
    budget = BUDGETS["curricula"]
    games = collect_runs(find_runs([published / "runs"]), Protocol(**budget.protocol), budget.ued)
    checked = 0
    for curricula in games.values():
        for runs in curricula.values():
            for metric, values in runs.values.items():
                base = curricula["PPCG"].values.get(metric)
                for b in [None] + ([base] if base and runs.label != "PPCG" else []):
                    if len(values) < 2 or max(values) == min(values) or (b and max(b) == min(b)):
                        continue
                    got = intervals.estimate(values, b, 0.0)
                    assert (got.low, got.high, got.p) == pytest.approx(_by_hand(values, b), abs=1e-9, rel=0)
                    checked += 1
                if len(values) > 1 and max(values) != min(values):
                    assert ued.t_interval(values) == pytest.approx(_by_hand(values, None)[:2], abs=1e-9)
                    assert table.t_interval(values) == pytest.approx(_by_hand(values, None)[:2], abs=1e-9)
    assert checked > 50
