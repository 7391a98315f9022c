"""What an inconclusive verdict says would decide it: the seeds a comparison needs, at 80 % power, at
the means and spreads seen, or why no number of seeds would."""

from __future__ import annotations

import numpy as np
import pytest

from gvgai_pcg.study.verdicts.claim_rules import Claim, Comparison
from gvgai_pcg.study.verdicts.intervals import estimate, power, seeds_to_decide
from gvgai_pcg.study.verdicts.judging import judge


def _seeds_like(mean: float, sd: float, n: int) -> tuple[float, ...]:
    """``n`` values with exactly this mean and sample standard deviation."""
    centred = [i - (n - 1) / 2 for i in range(n)]
    scale = (sum(c * c for c in centred) / (n - 1)) ** 0.5
    return tuple(mean + sd * c / scale for c in centred)


def test_the_projection_is_the_textbook_sample_size_at_80_percent_power():
    # Cohen's d = 0.5 at two-sided alpha 0.05 and 80 % power: 34 for a one-sample t test, 64 per
    # group for two independent samples (Cohen 1988, Table 2.4.1; G*Power gives the same). The
    # spread seen is the truth here, so three seeds with sd 1 stand for any number.
    a = _seeds_like(0.5, 1.0, 3)
    assert seeds_to_decide(a, None, 0.0, alpha=0.05, most=100) == (34, "")
    assert seeds_to_decide(a, _seeds_like(0.0, 1.0, 3), 0.0, alpha=0.05, most=100) == (64, "")


def test_the_projected_seeds_decide_the_comparison_four_times_in_five():
    a = _seeds_like(0.4, 0.1, 3)  # three seeds leave "above 0.25" open at alpha 0.01
    assert estimate(a, None, 0.25).p > 0.01
    seeds, why = seeds_to_decide(a, None, 0.25, alpha=0.01)
    assert why == "" and seeds is not None and seeds > 3
    # new seeds drawn from the mean and spread seen: that many decide it at least 80 % of the time,
    # one fewer less often, as the noncentral t says (binomial error over 4,000 draws: about 0.007)
    rng = np.random.default_rng(0)

    def decided(n: int) -> float:
        draws = rng.normal(0.4, 0.1, size=(4000, n))
        return float(np.mean([estimate(row.tolist(), None, 0.25).p <= 0.01 for row in draws]))

    for n in (seeds - 1, seeds):
        assert decided(n) == pytest.approx(power(0.4, 0.25, 0.1 / n**0.5, n - 1, 0.01), abs=0.025)
    assert power(0.4, 0.25, 0.1 / seeds**0.5, seeds - 1, 0.01) >= 0.8
    assert power(0.4, 0.25, 0.1 / (seeds - 1) ** 0.5, seeds - 2, 0.01) < 0.8
    assert seeds_to_decide(a, None, 0.25, alpha=0.01, most=seeds - 1) == (
        None,
        f"more than {seeds - 1} seeds would be needed for 80 % power",
    )


def test_reaching_alpha_at_the_mean_seen_is_not_enough_seeds():
    # the seeds at which the mean seen would just reach alpha decide it only about half the time
    a = _seeds_like(0.4, 0.1, 3)
    at_alpha = next(n for n in range(3, 100) if estimate(_seeds_like(0.4, 0.1, n), None, 0.25).p <= 0.01)
    seeds, _ = seeds_to_decide(a, None, 0.25, alpha=0.01)
    assert seeds > at_alpha


def test_more_seeds_cannot_beat_the_level_sampling_of_a_fixed_test_set():
    a, b = (0.52, 0.50, 0.51), (0.49, 0.50, 0.48)  # a tiny, steady difference of 0.02
    levels = [[0.3, -0.3] * 10]  # per-level differences that swing widely over 20 levels
    seeds, why = seeds_to_decide(a, b, 0.0, alpha=0.05, levels=levels)
    assert seeds is None and "level sampling alone" in why
    assert seeds_to_decide(a, b, 0.0, alpha=0.05)[0] is not None  # without the level term, seeds do


def test_where_levels_keep_it_open_the_projection_names_the_levels_and_seeds_that_would_decide_it():
    import re

    from gvgai_pcg.study.verdicts.intervals import POWER, _satterthwaite, level_terms, power

    a, b = (0.52, 0.50, 0.51), (0.49, 0.50, 0.48)
    levels = [[0.1, -0.1] * 10]
    _, why = seeds_to_decide(a, b, 0.0, alpha=0.05, levels=levels)
    found = re.search(r"about ([\d,]+) levels per test set \(now 20\) and (\d+) seeds .* at 80 % power", why)
    assert found, why
    size, seeds = int(found[1].replace(",", "")), int(found[2])

    def chance(levels_per_set: int) -> float:
        seeds_terms = [(0.01**2 / seeds, seeds - 1)] * 2  # both sides' sd, 0.01
        sampled = level_terms([[0.1, -0.1] * (levels_per_set // 2)])
        return power(0.02, 0.0, *_satterthwaite(seeds_terms + sampled), 0.05)

    assert chance(size) >= POWER > chance(size // 2)  # that many levels decide it, half as many do not


def test_one_seed_or_an_estimate_on_the_bound_gives_no_projection():
    assert seeds_to_decide((0.4,), None, 0.25, 0.05) == (None, "one seed: no spread to project from")
    assert seeds_to_decide((0.2, 0.3), None, 0.25, 0.05) == (None, "the estimate sits on the bound")


def test_an_inconclusive_claim_says_how_many_seeds_would_decide_it():

    comparison = Comparison("PPCG on pcg1", (0.30, 0.50, 0.40), None, 0.25, above=True)
    claim = Claim("frogs", "PPCG wins a large share.", ("PPCG",), [comparison])
    [verdict] = judge([claim])
    assert verdict.verdict == "inconclusive"
    seeds, _ = seeds_to_decide(comparison.a, None, 0.25, alpha=0.05)
    assert verdict.evidence.endswith(
        f"Undecided at this budget: about {seeds} seeds per condition would decide it at 80 % power, if "
        "the means and spreads seen held."
    )


def test_an_open_curriculum_comparison_says_how_many_seeds_each_would_decide_it():
    import re

    from gvgai_pcg.study.verdicts.comparison import CurriculumRuns, answer_sentences
    from gvgai_pcg.study.verdicts.comparison import judge as judge_curricula

    games = {
        "zelda": {
            "PPCG": CurriculumRuns("PPCG", "ppcg", [800] * 3, {"human": [1.0, 1.2, 0.8]}),
            "DR": CurriculumRuns("DR", "dr", [800] * 3, {"human": [1.3, 1.9, 1.0]}),
        }
    }
    [verdict] = [v for v in judge_curricula(games) if v.metric == "human"]
    assert verdict.outcome == "inconclusive"
    seeds = int(
        re.fullmatch(
            r"about (\d+) seeds each would decide it at 80 % power, if the means and spreads seen held",
            verdict.decides,
        ).group(1)
    )
    assert seeds == seeds_to_decide([1.3, 1.9, 1.0], [1.0, 1.2, 0.8], 0.0, alpha=0.05)[0] and seeds > 3
    assert f"Holm p {verdict.adjusted_p:.3g}; {verdict.decides})." in "\n".join(answer_sentences([verdict]))


def test_a_difference_too_small_for_any_projected_set_says_so():
    a, b = (0.5002, 0.5, 0.5001), (0.5, 0.5001, 0.4999)  # a difference of 0.0001
    levels = [[0.3, -0.3] * 50]
    seeds, why = seeds_to_decide(a, b, 0.0, alpha=0.05, levels=levels)
    assert seeds is None and "neither 100 times the levels nor 30 seeds would decide it at 80 % power" in why
