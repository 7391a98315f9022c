"""What an inconclusive verdict says would decide it: the seeds a comparison needs at the means and
spreads seen, or why no number of seeds would."""

from __future__ import annotations

from gvgai_pcg.study.claims import Comparison, judge
from gvgai_pcg.study.intervals import estimate, seeds_to_decide


def _seeds_like(mean: float, sd: float, n: int) -> tuple[float, ...]:
    """``n`` values with exactly this mean and sample standard deviation."""
    centred = [i - (n - 1) / 2 for i in range(n)]
    scale = (sum(c * c for c in centred) / (n - 1)) ** 0.5
    return tuple(mean + sd * c / scale for c in centred)


def test_the_projected_seeds_decide_the_comparison_when_the_spread_stays_the_same():
    a = _seeds_like(0.4, 0.1, 3)  # three seeds leave "above 0.25" open at alpha 0.01
    assert estimate(a, None, 0.25).p > 0.01
    seeds, why = seeds_to_decide(a, None, 0.25, alpha=0.01)
    assert why == "" and seeds is not None and seeds > 3
    assert estimate(_seeds_like(0.4, 0.1, seeds), None, 0.25).p <= 0.01  # that many seeds decide it
    assert estimate(_seeds_like(0.4, 0.1, seeds - 1), None, 0.25).p > 0.01  # one fewer does not
    assert seeds_to_decide(a, None, 0.25, alpha=0.01, most=seeds - 1) == (
        None,
        f"more than {seeds - 1} seeds would be needed",
    )


def test_more_seeds_cannot_beat_the_level_sampling_of_a_fixed_test_set():
    a, b = (0.52, 0.50, 0.51), (0.49, 0.50, 0.48)  # a tiny, steady difference of 0.02
    levels = [[0.3, -0.3] * 10]  # per-level differences that swing widely over 20 levels
    seeds, why = seeds_to_decide(a, b, 0.0, alpha=0.05, levels=levels)
    assert seeds is None and "level sampling alone" in why
    assert seeds_to_decide(a, b, 0.0, alpha=0.05)[0] is not None  # without the level term, seeds do


def test_where_levels_keep_it_open_the_projection_names_the_levels_and_seeds_that_would_decide_it():
    import re

    a, b = (0.52, 0.50, 0.51), (0.49, 0.50, 0.48)
    levels = [[0.3, -0.3] * 10]
    _, why = seeds_to_decide(a, b, 0.0, alpha=0.05, levels=levels)
    found = re.search(r"about ([\d,]+) levels per test set \(now 20\) and (\d+) seeds", why)
    assert found, why
    size, seeds = int(found[1].replace(",", "")), int(found[2])
    a_more, b_more = _seeds_like(0.51, 0.01, seeds), _seeds_like(0.49, 0.01, seeds)
    assert estimate(a_more, b_more, 0.0, levels=[[0.3, -0.3] * (size // 2)]).p <= 0.05  # that many decide it
    assert estimate(a_more, b_more, 0.0, levels=[[0.3, -0.3] * (size // 4)]).p > 0.05  # half as many do not


def test_one_seed_or_an_estimate_on_the_bound_gives_no_projection():
    assert seeds_to_decide((0.4,), None, 0.25, 0.05) == (None, "one seed: no spread to project from")
    assert seeds_to_decide((0.2, 0.3), None, 0.25, 0.05) == (None, "the estimate sits on the bound")


def test_an_inconclusive_claim_says_how_many_seeds_would_decide_it():
    from gvgai_pcg.study.claims import Claim

    comparison = Comparison("PPCG on pcg1", (0.30, 0.50, 0.40), None, 0.25, above=True)
    claim = Claim("frogs", "PPCG wins a large share.", ("PPCG",), [comparison])
    [verdict] = judge([claim])
    assert verdict.verdict == "inconclusive"
    seeds, _ = seeds_to_decide(comparison.a, None, 0.25, alpha=0.05)
    assert verdict.evidence.endswith(
        f"Undecided at this budget: about {seeds} seeds per condition would decide it, if the means and "
        "spreads seen held."
    )


def test_an_open_curriculum_comparison_says_how_many_seeds_each_would_decide_it():
    import re

    from gvgai_pcg.study.comparison import CurriculumRuns, answer_sentences
    from gvgai_pcg.study.comparison import judge as judge_curricula

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
            r"about (\d+) seeds each would decide it, if the means and spreads seen held", verdict.decides
        ).group(1)
    )
    assert seeds == seeds_to_decide([1.3, 1.9, 1.0], [1.0, 1.2, 0.8], 0.0, alpha=0.05)[0] and seeds > 3
    assert f"Holm p {verdict.adjusted_p:.3g}; {verdict.decides})." in "\n".join(answer_sentences([verdict]))


def test_a_difference_too_small_for_any_projected_set_says_so():
    a, b = (0.5002, 0.5, 0.5001), (0.5, 0.5001, 0.4999)  # a difference of 0.0001
    levels = [[0.3, -0.3] * 50]
    seeds, why = seeds_to_decide(a, b, 0.0, alpha=0.05, levels=levels)
    assert seeds is None and "neither 100 times the levels nor 30 seeds would decide it" in why
