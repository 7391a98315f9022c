"""Intervals over seeds and Holm's correction: what a verdict on a few seeds can honestly say.

A comparison tests a per-seed statistic (one condition's, or the difference of two conditions'
means) against a bound. Its interval is the two-sided 95 % t interval over seeds (Student's t for
one condition, Welch's for a difference); its p value is the two-sided t test of "the statistic
equals the bound". Holm's step-down procedure over every comparison of a family keeps the chance
of any wrong call at 5 %. Cells given as point estimates (the study's: the paper prints no
per-seed values) are compared as they are, with no interval.

Level sampling: a generated test set is one draw of levels from the generator, the same
levels for every model, so the seeds' spread cannot show how the score would move with another
draw. Where per-level results exist, a statistic's level-sampling variance is added to its seeds'
(``levels``: per test set, the statistic's per-level contribution, e.g. one condition's per-level
mean over seeds, or the difference of two conditions' on the same levels). The design is crossed
(every seed plays every level), not nested, so the level term is the spread of the per-level means
over the levels, s^2 / L, once for all seeds: resampling levels within each seed would divide it by
the seeds again and hide most of it. For a mean this is what a bootstrap over levels estimates, in
closed form (no Monte Carlo error). The interval is then a t interval with Welch-Satterthwaite
degrees of freedom over both sources (written out here: scipy's Welch test takes two samples, not
a sum of several variance terms), or the interval over seeds alone where that is wider (with
3-5 seeds the estimated df can grow enough to narrow it), with the larger of the two p values; it
is conservative by the seed-by-level noise counted in both terms
(``tests/study/test_level_intervals.py`` measures its coverage on a simulated hierarchy).

The random agent's row has its own interval (``random_estimate``): a fixed policy, so its
episodes are independent draws and the interval is the t interval over episodes (each generated
level played once, so that includes the levels' spread).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from scipy import stats

LEVEL = 0.95  # two-sided interval level, and family-wise 1 - alpha for Holm
ALPHA = 1 - LEVEL
NO_SPREAD = 1e-12  # a standard error this small (relative) is rounding, not spread
SEEDS_AND_LEVELS_INTERVAL = (
    "two-sided 95 % t interval over seeds and levels (the seeds' variance, Welch's for a difference, plus "
    "the generated test sets' level-sampling variance, the same levels for every model; "
    "Welch-Satterthwaite degrees of freedom; never narrower than the interval over seeds alone)"
)


@dataclass(frozen=True)
class Estimate:
    """A statistic's value, its interval and the p value of "it equals ``bound``"."""

    value: float
    low: float
    high: float
    p: float  # two-sided; 1 where there is no interval (one seed)
    seeds: int  # the fewest seeds behind it (0: a point estimate)

    @property
    def has_interval(self) -> bool:
        return math.isfinite(self.low) and math.isfinite(self.high)


def _mean_var(values: Sequence[float]) -> tuple[float, float]:
    mean = sum(values) / len(values)
    var = sum((v - mean) ** 2 for v in values) / (len(values) - 1) if len(values) > 1 else math.nan
    return mean, var


def _from_t(value: float, se: float, df: float, bound: float, seeds: int) -> Estimate:
    if not math.isfinite(se) or not math.isfinite(df) or df <= 0:
        return Estimate(value, -math.inf, math.inf, 1.0, seeds)
    # Every seed gave the same value (to rounding: equal per-seed means of floats can differ in
    # the last bits, which would give a t statistic of 1e16 and a p of 1e-33): no spread at all.
    if se <= NO_SPREAD * max(1.0, abs(value)):
        return Estimate(value, value, value, 1.0 if value == bound else 0.0, seeds)
    low, high = stats.t.interval(1 - ALPHA, df, loc=value, scale=se)
    p = float(2 * stats.t.sf(abs(value - bound) / se, df))
    return Estimate(value, float(low), float(high), p, seeds)


def _scipy_test(
    a: Sequence[float], b: Sequence[float] | None, value: float, bound: float, seeds: int, se: float
) -> Estimate:
    """The interval over seeds alone: scipy's one-sample t test (one condition) or Welch's test (a
    difference, ``a`` shifted by ``bound`` since scipy tests a zero difference); ``se`` only spots
    the no-spread case, where scipy's statistic is undefined (``_from_t`` decides it)."""
    if se <= NO_SPREAD * max(1.0, abs(value)):
        return _from_t(value, se, 1.0, bound, seeds)
    if b is None:
        test = stats.ttest_1samp(a, bound)
        shift = 0.0
    else:
        test = stats.ttest_ind([x - bound for x in a], b, equal_var=False)
        shift = bound
    interval = test.confidence_interval(LEVEL)
    return Estimate(
        value, float(interval.low) + shift, float(interval.high) + shift, float(test.pvalue), seeds
    )


def level_terms(levels: Sequence[Sequence[float]]) -> list[tuple[float, int]]:
    """Each test set's level-sampling variance of the mean of its per-level values, s^2 / L, with
    its degrees of freedom L - 1 (a set of one level adds nothing)."""
    terms = []
    for values in levels:
        if len(values) > 1:
            terms.append((_mean_var(values)[1] / len(values), len(values) - 1))
    return terms


def _satterthwaite(terms: Sequence[tuple[float, int]]) -> tuple[float, float]:
    """The standard error of a sum of independent variance terms and its Welch-Satterthwaite df."""
    total = sum(q for q, _ in terms)
    denominator = sum(q**2 / df for q, df in terms if q)
    df = total**2 / denominator if denominator else 1.0  # no spread anywhere: a degenerate interval
    return math.sqrt(total), df


def estimate(
    a: Sequence[float],
    b: Sequence[float] | None,
    bound: float,
    point: bool = False,
    levels: Sequence[Sequence[float]] = (),
) -> Estimate:
    """``mean(a)`` (or ``mean(a) - mean(b)``) with its t interval over seeds and the p value
    against ``bound``; ``point``: the values are point estimates, compared as they are;
    ``levels``: per generated test set, the statistic's per-level values, whose level-sampling
    variance widens the interval (module docstring)."""
    mean_a, var_a = _mean_var(a)
    if point:
        value = mean_a - (_mean_var(b)[0] if b else 0.0)
        return Estimate(value, value, value, math.nan, 0)
    seeds = len(a) if b is None else min(len(a), len(b))
    value = mean_a - (0.0 if b is None else _mean_var(b)[0])
    if seeds < 2:
        return _from_t(value, math.nan, math.nan, bound, seeds)
    terms = [(var_a / len(a), len(a) - 1)]
    if b is not None:
        terms.append((_mean_var(b)[1] / len(b), len(b) - 1))
    over_seeds = _scipy_test(a, b, value, bound, seeds, _satterthwaite(terms)[0])
    sampled = level_terms(levels)
    if not sampled:
        return over_seeds
    # Never narrower than the interval over seeds alone: Satterthwaite's df, estimated from a few
    # seeds, would otherwise grow with a small level term and shrink the interval below it.
    both = _from_t(value, *_satterthwaite(terms + sampled), bound, seeds)
    wider = both if both.high - both.low >= over_seeds.high - over_seeds.low else over_seeds
    return Estimate(value, wider.low, wider.high, max(both.p, over_seeds.p), seeds)


MOST_SEEDS = 30  # the projection below stops here: more seeds than any budget of this package trains
LEVEL_FACTORS = (2, 3, 5, 10, 20, 50, 100)  # larger test sets tried, as multiples of the ones seen
POWER = 0.8  # the chance a projected number of seeds decides a comparison, if the spreads seen held


def power(value: float, bound: float, se: float, df: float, alpha: float) -> float:
    """The chance that ``estimate``'s test decides a statistic whose true value is ``value``, with
    standard error ``se`` and ``df`` degrees of freedom, on the side of ``value`` at two-sided
    ``alpha``: the one-sided t test at ``alpha / 2`` in that direction, whose statistic is
    noncentral t with noncentrality ``|value - bound| / se`` (the chance of deciding it the other
    way, below 1e-3 wherever this is near ``POWER``, is left out)."""
    if not math.isfinite(se) or not math.isfinite(df) or df <= 0:
        return 0.0
    if se <= NO_SPREAD * max(1.0, abs(value)):  # no spread: decided without a test (``_from_t``)
        return 0.0 if value == bound else 1.0
    critical = float(stats.t.ppf(1 - alpha / 2, df))
    return float(stats.nct.sf(critical, df, abs(value - bound) / se))


def seeds_to_decide(
    a: Sequence[float],
    b: Sequence[float] | None,
    bound: float,
    alpha: float,
    levels: Sequence[Sequence[float]] = (),
    most: int = MOST_SEEDS,
) -> tuple[int | None, str]:
    """How many seeds per condition ``estimate`` would need to decide "the statistic equals
    ``bound``" at two-sided ``alpha`` with ``POWER`` (80 %), if the observed mean and per-seed
    variance were the truth: ``(seeds, "")``, or ``(None, why not)``. Only reaching ``alpha``
    at the observed mean would be a coin toss (about 50 % power): a new set of seeds would land
    on either side of it. The seeds' variance shrinks with more seeds; the test sets'
    level-sampling variance does not (the same levels for every seed), so where it alone keeps
    the comparison from ``POWER``, no number of seeds decides it: then ``why`` says how many
    levels per test set (with how many seeds) would, if the per-level spread held. With a level
    term ``estimate`` takes the larger of two p values, so the power is the smaller of the two
    tests' (an upper bound on deciding both, which share their numerator)."""
    if len(a) < 2 or (b is not None and len(b) < 2):
        return None, "one seed: no spread to project from"
    mean_a, var_a = _mean_var(a)
    mean_b, var_b = _mean_var(b) if b is not None else (0.0, 0.0)
    value = mean_a - mean_b
    if value == bound:
        return None, "the estimate sits on the bound"
    first = min(len(a), len(b) if b is not None else len(a))

    def power_of(terms: list[tuple[float, int]]) -> float:
        return power(value, bound, *_satterthwaite(terms), alpha)

    def seeds_for(sampled: list[tuple[float, int]]) -> int | None:
        for seeds in range(first, most + 1):
            terms = [(var_a / seeds, seeds - 1)] + ([(var_b / seeds, seeds - 1)] if b is not None else [])
            chance = power_of(terms)
            if sampled:
                chance = min(chance, power_of(terms + sampled))
            if chance >= POWER:
                return seeds
        return None

    sampled = level_terms(levels)
    if not sampled or power_of(sampled) >= POWER:
        seeds = seeds_for(sampled)
        if seeds is None:
            return None, f"more than {most} seeds would be needed for {POWER * 100:.0f} % power"
        return seeds, ""
    sizes = [len(values) for values in levels if len(values) > 1]
    for factor in LEVEL_FACTORS:  # a set k times larger: s^2 / (k L), with k L - 1 df
        seeds = seeds_for([(q / factor, factor * (df + 1) - 1) for q, df in sampled])
        if seeds is not None:
            return None, (
                "the test sets' level sampling alone leaves it undecided: about "
                f"{factor * max(sizes):,} levels per test set (now {max(sizes):,}) and {seeds} seeds "
                f"per condition would decide it at {POWER * 100:.0f} % power, if the spreads seen held"
            )
    return None, (
        f"the test sets' level sampling alone leaves it undecided, and neither {LEVEL_FACTORS[-1]} times "
        f"the levels nor {most} seeds would decide it at {POWER * 100:.0f} % power"
    )


def agents_estimate(wins: Sequence[tuple[int, int]], bound: float) -> Estimate:
    """Whether every agent's win rate is on one side of ``bound``, from each agent's (episodes won,
    played): a fixed policy's episodes are independent draws, so each agent has its exact two-sided
    binomial test. "Some agent is above" is decided by the smallest p of the agents above,
    Bonferroni over the agents; "every agent is below" by the largest p of all (each must be
    decided: an intersection-union test). The value is the most-winning agent's rate, with its
    95 % Clopper-Pearson interval (``seeds``: the agents)."""
    tests = [stats.binomtest(k, n, bound) for k, n in wins]
    rates = [k / n for k, n in wins]
    top = max(range(len(wins)), key=rates.__getitem__)
    above = [test.pvalue for test, rate in zip(tests, rates, strict=True) if rate > bound]
    p = min(1.0, len(wins) * min(above)) if above else max(test.pvalue for test in tests)
    interval = tests[top].proportion_ci(LEVEL)
    return Estimate(rates[top], interval.low, interval.high, p, len(wins))


def random_estimate(scores: Sequence[float], bound: float = 0.0) -> Estimate:
    """The random agent's mean score on a test set with its t interval over episodes (a fixed
    policy: its episodes are independent draws; ``seeds`` counts the episodes)."""
    return estimate(scores, None, bound)


def holm(p_values: Sequence[float], alpha: float = ALPHA) -> tuple[list[float], list[bool]]:
    """Holm's adjusted p values and which hypotheses it rejects at family-wise ``alpha``."""
    m = len(p_values)
    order = sorted(range(m), key=lambda i: p_values[i])
    adjusted, running = [1.0] * m, 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p_values[i]))
        adjusted[i] = running
    return adjusted, [p <= alpha for p in adjusted]
