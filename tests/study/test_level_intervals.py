"""Level-sampling error in the intervals: known answers, pairing on shared levels, coverage on a
simulated crossed hierarchy (seeds x levels), the random agent's own interval, and the claims'
comparisons that carry it."""

from __future__ import annotations

import math
import random

import pytest
from scipy import stats

from gvgai_pcg.study.pages.claims_page import random_markdown, statistics_note
from gvgai_pcg.study.verdicts.claim_rules import frogs_ppcg_wins_hard
from gvgai_pcg.study.verdicts.intervals import estimate, level_terms, random_estimate
from gvgai_pcg.study.verdicts.judging import judge
from gvgai_pcg.study.verdicts.results import GameResults, SetResult, Table, table_of
from gvgai_pcg.study.verdicts.table1 import TEST_SETS


def test_the_level_term_is_the_variance_of_the_mean_over_levels():
    assert level_terms([[0.0, 1.0]]) == [(0.25, 1)]  # s^2 = 0.5, over 2 levels
    assert level_terms([[3.0]]) == []  # one level: nothing sampled
    same = estimate([1.0, 2.0, 3.0], None, 0.0)
    with_flat_levels = estimate([1.0, 2.0, 3.0], None, 0.0, levels=[[0.4] * 30])
    assert (with_flat_levels.low, with_flat_levels.high) == (same.low, same.high)


def test_levels_that_vary_widen_the_interval():
    seeds = [0.50, 0.52, 0.48, 0.51]
    narrow = estimate(seeds, None, 0.45)
    wide = estimate(seeds, None, 0.45, levels=[[0.1, 0.9] * 15])
    assert wide.value == narrow.value
    assert wide.high - wide.low > 3 * (narrow.high - narrow.low)
    assert narrow.p < 0.05 < wide.p  # 0.45 is excluded by the seeds alone, not once levels count


def _crossed(rng: random.Random, seeds: int, levels: int, sd_seed: float, sd_level: float, sd_noise: float):
    """Scores x[s][l] = seed effect + level effect + noise, true mean 0, levels shared by all seeds."""
    seed_effects = [rng.gauss(0, sd_seed) for _ in range(seeds)]
    level_effects = [rng.gauss(0, sd_level) for _ in range(levels)]
    return [[a + b + rng.gauss(0, sd_noise) for b in level_effects] for a in seed_effects]


def _seed_and_level_means(x):
    seeds = [sum(row) / len(row) for row in x]
    levels = [sum(column) / len(column) for column in zip(*x, strict=True)]
    return seeds, levels


def _coverage(seeds: int, sd_level: float, trials: int = 400) -> tuple[float, float]:
    """How often the seeds-and-levels and the seeds-only intervals cover the true mean (0)."""
    rng = random.Random(35)
    with_levels = seeds_only = 0
    for _ in range(trials):
        x = _crossed(rng, seeds=seeds, levels=30, sd_seed=0.1, sd_level=sd_level, sd_noise=0.3)
        seed_means, level_means = _seed_and_level_means(x)
        both = estimate(seed_means, None, 0.0, levels=[level_means])
        alone = estimate(seed_means, None, 0.0)
        assert both.high - both.low >= alone.high - alone.low  # never narrower
        with_levels += both.low <= 0.0 <= both.high
        seeds_only += alone.low <= 0.0 <= alone.high
    return with_levels / trials, seeds_only / trials


def test_coverage_on_a_simulated_crossed_hierarchy():
    """4 seeds x 30 levels, the levels' spread larger than the seeds': the seeds-only interval
    misses the true mean far more than 5 % of the time, the seeds-and-levels one about 5 % or less;
    with no level effect at all it covers as the seeds-only one does."""
    with_levels, seeds_only = _coverage(seeds=4, sd_level=1.0)
    assert with_levels >= 0.93 and seeds_only < 0.75
    with_levels, seeds_only = _coverage(seeds=3, sd_level=0.0)
    assert with_levels >= seeds_only >= 0.88


def test_a_difference_on_the_same_levels_cancels_their_shared_effect():
    """Two conditions on the same levels: a level that is hard for both moves neither's lead, so
    the difference's level term uses the per-level differences, not each side's spread."""
    rng = random.Random(7)
    hard = [rng.gauss(0, 1.0) for _ in range(30)]
    a_levels = [h + 0.3 for h in hard]
    b_levels = list(hard)
    paired = [[a - b for a, b in zip(a_levels, b_levels, strict=True)]]
    a, b = [0.31, 0.29, 0.30], [0.0, 0.01, -0.01]
    assert estimate(a, b, 0.0, levels=paired).p == estimate(a, b, 0.0).p  # nothing left to vary
    unpaired = estimate(a, b, 0.0, levels=[a_levels, b_levels])
    assert unpaired.p > estimate(a, b, 0.0, levels=paired).p


def test_the_random_agent_has_a_t_interval_over_its_episodes():
    value = random_estimate([0.0, 1.0, 0.0, 1.0])
    half = stats.t.ppf(0.975, 3) * math.sqrt(1 / 3) / 2
    assert value.value == 0.5 and value.seeds == 4
    assert value.low == pytest.approx(0.5 - half) and value.high == pytest.approx(0.5 + half)


def _frogs_table(level_spread: float, levels: bool) -> Table:
    per_seed = [0.40, 0.41, 0.39]
    cells = {"PPCG": {s: per_seed for s in TEST_SETS}}
    column = [0.4 + level_spread * (1 if i % 2 else -1) for i in range(30)]
    table = Table("frogs", cells, False, {"PPCG": [10_000_000] * 3})
    if levels:
        table.levels = {"PPCG": {"pcg1": column}}
    return table


def test_a_claim_decided_on_seeds_alone_can_be_open_once_levels_count():
    """PPCG's share of d = 1 wins at 0.4 on every seed is above 0.25; with the levels' wins spread
    0-0.8 (a few levels won, the rest not), 30 levels cannot say so."""
    assert judge([frogs_ppcg_wins_hard(_frogs_table(0.4, levels=False))])[0].verdict == "holds"
    assert judge([frogs_ppcg_wins_hard(_frogs_table(0.0, levels=True))])[0].verdict == "holds"
    open_ = judge([frogs_ppcg_wins_hard(_frogs_table(0.4, levels=True))])[0]
    assert open_.verdict == "inconclusive"


def test_per_level_means_reach_the_table_only_with_level_sampling():
    result = SetResult([0.2, 0.4], [0.0, 0.0], [], {"a": [0.0, 0.2], "b": [0.4, 0.6]})
    game = GameResults(
        "zelda", {"PCG 1": {"pcg1": result}}, {"PCG 1": [1, 1]}, {"pcg1": 0.0}, {"pcg1": 2.0}, {}
    )
    assert game.normalised_levels("PCG 1", "pcg1") == pytest.approx([0.05, 0.25])
    assert table_of(game).levels == {}
    assert table_of(game, level_sampling=True).levels == {"PCG 1": {"pcg1": pytest.approx([0.05, 0.25])}}


def test_the_note_names_the_interval_kind_and_the_random_agent_gets_its_own():
    from gvgai_pcg.study.verdicts.intervals import SEEDS_AND_LEVELS_INTERVAL

    assert SEEDS_AND_LEVELS_INTERVAL in statistics_note([], level_sampling=True)
    assert "Not in the intervals: the level sampling" in statistics_note([])
    game = GameResults("zelda", {}, {}, {}, {}, {}, random_scores={"pcg1": [0.0, 1.0, 0.0, 1.0]})
    half = stats.t.ppf(0.975, 3) * math.sqrt(1 / 3) / 2
    assert random_markdown({"zelda": game}) == (
        "- zelda random agent (95 % t interval over episodes): "
        f"pcg1 0.50 [{0.5 - half:.2f}, {0.5 + half:.2f}] (4 episodes)"
    )


def test_the_level_term_is_what_a_bootstrap_over_levels_estimates():
    """For a mean over levels, a bootstrap over the levels (10,000 resamples) has variance
    (L - 1) / L * s^2 / L: the closed form, without its Monte Carlo error."""
    import numpy as np

    rng = np.random.default_rng(35)
    levels = rng.normal(0.0, 1.0, 30)
    resampled = levels[rng.integers(0, 30, (10_000, 30))].mean(axis=1)
    ((term, df),) = level_terms([levels.tolist()])
    assert df == 29
    assert resampled.var() == pytest.approx(term * 29 / 30, rel=0.05)
