"""Intervals over seeds and Holm's correction: what a verdict on a few seeds can honestly say.

A comparison tests a per-seed statistic (one condition's, or the difference of two conditions'
means) against a bound. Its interval is the two-sided 95 % t interval over seeds (Student's t for
one condition, Welch's for a difference); its p value is the two-sided t test of "the statistic
equals the bound". Holm's step-down procedure over every comparison of a family keeps the chance
of any wrong call at 5 %. Cells given as point estimates (the study's: the paper prints no
per-seed values) are compared as they are, with no interval.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from scipy import stats

LEVEL = 0.95  # two-sided interval level, and family-wise 1 - alpha for Holm
ALPHA = 1 - LEVEL


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
    if se == 0.0:  # every seed gave the same value: the data show no spread at all
        return Estimate(value, value, value, 1.0 if value == bound else 0.0, seeds)
    half = float(stats.t.ppf(1 - ALPHA / 2, df)) * se
    p = float(2 * stats.t.sf(abs(value - bound) / se, df))
    return Estimate(value, value - half, value + half, p, seeds)


def estimate(a: Sequence[float], b: Sequence[float] | None, bound: float, point: bool = False) -> Estimate:
    """``mean(a)`` (or ``mean(a) - mean(b)``) with its t interval over seeds and the p value
    against ``bound``; ``point``: the values are point estimates, compared as they are."""
    mean_a, var_a = _mean_var(a)
    if point:
        value = mean_a - (_mean_var(b)[0] if b else 0.0)
        return Estimate(value, value, value, math.nan, 0)
    if b is None:
        se = math.sqrt(var_a / len(a)) if len(a) > 1 else math.nan
        return _from_t(mean_a, se, len(a) - 1, bound, len(a))
    mean_b, var_b = _mean_var(b)
    seeds = min(len(a), len(b))
    if seeds < 2:
        return _from_t(mean_a - mean_b, math.nan, math.nan, bound, seeds)
    qa, qb = var_a / len(a), var_b / len(b)
    se = math.sqrt(qa + qb)
    denominator = (qa**2 / (len(a) - 1) if qa else 0.0) + (qb**2 / (len(b) - 1) if qb else 0.0)
    df = (qa + qb) ** 2 / denominator if denominator else math.inf  # Welch-Satterthwaite
    if se == 0.0:
        df = 1.0  # no spread on either side: any df gives the same (degenerate) interval
    return _from_t(mean_a - mean_b, se, df, bound, seeds)


def holm(p_values: Sequence[float], alpha: float = ALPHA) -> tuple[list[float], list[bool]]:
    """Holm's adjusted p values and which hypotheses it rejects at family-wise ``alpha``."""
    m = len(p_values)
    order = sorted(range(m), key=lambda i: p_values[i])
    adjusted, running = [1.0] * m, 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p_values[i]))
        adjusted[i] = running
    return adjusted, [p <= alpha for p in adjusted]
