"""The claims' verdict rules: the study's own Table 1 passes every one, and on per-seed tables
each verdict can come out every way, with Holm's correction across the claims' comparisons."""

from __future__ import annotations

import pytest

from gvgai_pcg.study.pages.claims_page import claims_markdown
from gvgai_pcg.study.verdicts.claim_rules import (
    CLOSE,
    MARGINAL,
    claims_of,
    four_levels_marginal,
    frogs_no_human_win,
    memorises,
    pcg1_beats_ppcg_generated,
    ppcg_beats_pcg05_hard,
    ppcg_never_hardest,
)
from gvgai_pcg.study.verdicts.intervals import estimate, holm
from gvgai_pcg.study.verdicts.judging import judge, study_claims, study_verdicts
from gvgai_pcg.study.verdicts.results import GameResults, SetResult, Table, _labels_by_config, collect
from gvgai_pcg.study.verdicts.table1 import TEST_SETS

STUDY_GAINS = (0.32, 0.42, 0.28)  # Lv 0-3 over Lv 0 on lv4, pcg0.5, pcg1 in the study's Table 1


def test_the_studys_own_table_passes_every_claim():
    verdicts = study_verdicts()
    assert len(verdicts) == 16
    assert {game for game, _ in verdicts} == {"zelda", "solarfox", "frogs", "boulderdash"}
    failed = [(game, v.claim, v.verdict, v.evidence) for game, v in verdicts if v.verdict != "holds"]
    assert not failed


def test_marginal_counts_the_studys_own_gains_as_marginal():
    verdict = next(v for _, v in study_verdicts() if "marginally higher" in v.claim)
    for gain in STUDY_GAINS:
        assert f"+{gain:.2f} (claim < {MARGINAL:g})" in verdict.evidence


def table(cells: dict[str, dict[str, list[float]]], game: str = "zelda", frames: int = 5_000_000, **extra):
    """A per-seed table: ``cells`` gives each condition's per-seed values on every set."""
    full = {
        label: {s: by_set.get(s, by_set.get("*", [0.0])) for s in TEST_SETS}
        for label, by_set in cells.items()
    }
    return Table(game, full, False, {label: [frames] * 3 for label in cells}, **extra)


def verdict_of(rule, t: Table) -> str:
    return judge([rule(t)])[0].verdict


def test_memorisation_holds_fails_or_stays_open_with_the_seeds():
    own, off = [0.9, 0.92, 0.91], [0.0, 0.01, -0.01]
    assert verdict_of(memorises, table({"Lv 0": {"lv0": own, "*": off}})) == "holds"
    general = [0.8, 0.81, 0.79]
    assert verdict_of(memorises, table({"Lv 0": {"lv0": own, "*": general}})) == "does not hold"
    noisy = [0.2, 1.0, 0.6]  # the same mean, seeds far apart: no decision
    assert verdict_of(memorises, table({"Lv 0": {"lv0": noisy, "*": off}})) == "inconclusive"


def test_four_levels_marginal_is_a_gain_between_zero_and_the_bound():
    def four(gain: float) -> Table:
        return table(
            {"Lv 0-3": {"*": [0.9 + gain, 0.91 + gain, 0.89 + gain]}, "Lv 0": {"*": [0.9, 0.91, 0.89]}}
        )

    assert verdict_of(four_levels_marginal, four(0.3)) == "holds"
    assert verdict_of(four_levels_marginal, four(-0.3)) == "does not hold"  # lower, not higher
    low = table({"Lv 0-3": {"*": [0.2, 0.21, 0.19]}, "Lv 0": {"*": [0.0, 0.01, -0.01]}})
    assert verdict_of(four_levels_marginal, low) == "does not hold"  # not high on its own levels
    assert CLOSE > 0.21


def test_a_single_seed_gives_no_interval_and_no_verdict():
    one = Table(
        "boulderdash",
        {"PCG 1": {s: [0.5] for s in TEST_SETS}, "PPCG": {s: [0.1] for s in TEST_SETS}},
        False,
        {},
    )
    [verdict] = judge([pcg1_beats_ppcg_generated(one)])
    assert verdict.verdict == "inconclusive" and "no interval (one seed)" in verdict.evidence


def test_seeds_without_spread_are_decided_without_a_test_and_say_so():
    same = Table(
        "boulderdash",
        {"PCG 1": {s: [0.5, 0.5, 0.5] for s in TEST_SETS}, "PPCG": {s: [0.1, 0.1, 0.1] for s in TEST_SETS}},
        False,
        {},
    )
    [verdict] = judge([pcg1_beats_ppcg_generated(same)])
    assert verdict.verdict == "holds"
    assert "no spread in the data, so decided without a test" in verdict.evidence
    assert "Holm p" not in verdict.evidence  # a p of 0 would read as a test that was run


def test_holm_corrects_across_the_claims_comparisons():
    adjusted, rejected = holm([0.01, 0.04, 0.03, 0.005])
    assert adjusted == pytest.approx([0.03, 0.06, 0.06, 0.02]) and rejected == [True, False, False, True]
    # one comparison alone holds; the same data beside 19 undecided comparisons does not
    clear = table({"PCG 1": {"*": [0.50, 0.55, 0.52]}, "PPCG": {"*": [0.40, 0.43, 0.41]}}, "boulderdash")
    assert verdict_of(pcg1_beats_ppcg_generated, clear) == "holds"
    noise = table({"PCG 1": {"*": [0.1, 0.5, 0.3]}, "PPCG": {"*": [0.2, 0.4, 0.3]}}, "boulderdash")
    verdicts = judge([pcg1_beats_ppcg_generated(clear)] + [pcg1_beats_ppcg_generated(noise)] * 10)
    assert verdicts[0].verdict == "inconclusive" and verdicts[0].comparisons == 2


def test_the_interval_is_students_t_over_seeds():
    value = estimate([1.0, 2.0, 3.0], None, 0.0)
    assert value.value == 2.0 and value.high - value.value == pytest.approx(4.303 * 1 / 3**0.5, rel=1e-3)
    assert estimate([0.3], None, 0.0).p == 1.0  # one seed: nothing decided


def test_training_dynamics_cannot_be_tested_short_of_the_studys_frames():
    reached = {"PPCG": [0.3, 0.32, 0.29]}
    short = table({"PPCG": {"*": [0.1] * 3}}, "boulderdash", 5_000_000, reached=reached)
    claim = ppcg_never_hardest(short)
    assert claim.status == "cannot be tested at this budget" and "60,000,000" in claim.reason
    long = table({"PPCG": {"*": [0.1] * 3}}, "boulderdash", 60_000_000, reached=reached)
    assert ppcg_never_hardest(long).status == "holds"
    reached_one = table(
        {"PPCG": {"*": [0.1] * 3}}, "boulderdash", 60_000_000, reached={"PPCG": [1.0, 0.3, 0.3]}
    )
    assert ppcg_never_hardest(reached_one).status == "does not hold"


def test_ppcg_against_pcg05_applies_only_where_ppcg_reached_d1():
    cells = {"PPCG": {"*": [0.6, 0.62, 0.61]}, "PCG 0.5": {"*": [0.3, 0.31, 0.29]}}
    assert ppcg_beats_pcg05_hard(table(cells, reached={"PPCG": [0.8, 1.0, 1.0]})).status == "does not apply"
    assert verdict_of(ppcg_beats_pcg05_hard, table(cells, reached={"PPCG": [1.0] * 3})) == "holds"


def test_frogs_human_wins_are_judged_on_each_seeds_best_level():
    stray = table({"PPCG": {"lv0": [0.0, 0.0, 0.067], "*": [0.0] * 3}}, "frogs")
    assert verdict_of(frogs_no_human_win, stray) == "inconclusive"
    wins = table({"PPCG": {"lv2": [0.5, 0.6, 0.55], "*": [0.0] * 3}}, "frogs")
    assert verdict_of(frogs_no_human_win, wins) == "does not hold"


def test_every_claim_of_every_game_runs_on_a_table_with_only_some_conditions():
    claims = claims_of({"zelda": table({"PPCG": {"*": [0.5] * 3}})})
    assert {c.status for c in claims if c.status} <= {"not run"}
    assert len(claims) == 6


def result(means: list[float]) -> SetResult:
    return SetResult(seed_means=means, seed_wins=[0.0] * len(means), scores=means * 10)


def test_a_claim_on_unfinished_runs_is_pending_with_its_evidence_so_far():
    sets = {s: result([0.1, 0.0, 0.05]) for s in TEST_SETS}
    own = {**sets, "lv0": result([9.0, 9.1, 9.2])}
    own4 = {**sets, "lv4": result([9.0, 9.1, 9.2])}
    zelda = GameResults(
        "zelda",
        {"Lv 0": own, "Lv 4": own4},
        {"Lv 0": [5_000_000] * 3, "Lv 4": [1_000_000] * 3},
        random={s: 0.0 for s in TEST_SETS},
        maximum={s: 10.0 for s in TEST_SETS},
        max_difficulty={},
    )
    [(name, verdict), *_] = study_claims({"zelda": zelda}, target_frames=5_000_000)
    assert name == "zelda" and verdict.verdict == "pending (holds so far)"
    assert "Lv 4 at 1,000,000 frames" in verdict.evidence
    zelda.frames["Lv 4"] = [5_000_000] * 3
    assert study_claims({"zelda": zelda}, target_frames=5_000_000)[0][1].verdict == "holds"


def test_claims_count_the_frames_of_the_evaluated_model_not_of_a_later_checkpoint(tmp_path):
    """A run that trains on after its evaluation is judged at the frames it was evaluated at."""
    import torch

    from gvgai_pcg.evaluation.checkpoints import run_info
    from gvgai_pcg.evaluation.evaluator import evaluate_run
    from gvgai_pcg.evaluation.protocol import Protocol
    from tests.evaluation.conftest import make_run

    protocol = Protocol(test_levels=1, test_episodes=1, human_episodes=1, max_steps=5)
    run = make_run(tmp_path, "lv0", seed=0, frames=1000)
    evaluate_run(run_info(run), protocol, progress=False)
    later = torch.load(run / "model.pt", weights_only=True) | {"frames": 2000}
    (run / "checkpoints").mkdir()
    torch.save(later, run / "checkpoints" / "last.pt")  # the run trained on
    assert run_info(run).frames == 2000
    assert collect([run], None, protocol)["zelda"].frames == {"Lv 0": [1000]}


def test_a_seed_still_training_is_left_out_where_its_condition_has_finished_runs(tmp_path):
    """Seed 1 at a tenth of the budget beside a finished seed 0: the claim is judged on seed 0,
    and the list says seed 1 is still training."""
    from gvgai_pcg.evaluation.checkpoints import run_info
    from gvgai_pcg.evaluation.evaluator import evaluate_run
    from gvgai_pcg.evaluation.protocol import Protocol
    from tests.evaluation.conftest import make_run

    protocol = Protocol(test_levels=1, test_episodes=1, human_episodes=1, max_steps=5)
    runs = [make_run(tmp_path, "lv0", seed=0, frames=1000), make_run(tmp_path, "lv0", seed=1, frames=100)]
    for run in runs:
        evaluate_run(run_info(run), protocol, progress=False)
    zelda = collect(runs, None, protocol, target_frames=1000)["zelda"]
    assert zelda.frames == {"Lv 0": [1000]} and zelda.training == {"Lv 0": [100]}
    assert "Lv 0 1 run(s) at 1,000-1,000 frames (and 1 still training" in claims_markdown(
        [], {"zelda": zelda}
    )
    unfinished = collect(runs, None, protocol, target_frames=5000)["zelda"]  # none finished: both count
    assert sorted(unfinished.frames["Lv 0"]) == [100, 1000] and unfinished.training == {}


def test_runs_of_two_configs_are_not_judged_as_seeds_of_one_condition():
    from types import SimpleNamespace

    def info(seed: int, lr: float):
        return SimpleNamespace(
            game="zelda", label="PPCG", path=f"p{seed}", config={"algo": {"lr": lr}, "seed": seed}
        )

    labels = _labels_by_config([info(0, 7e-4), info(1, 7e-4), info(2, 1e-3)])
    assert labels == {
        "p0": "PPCG (algo.lr=0.0007)",
        "p1": "PPCG (algo.lr=0.0007)",
        "p2": "PPCG (algo.lr=0.001)",
    }
    split = table({"PPCG (algo.lr=0.0007)": {"*": [0.5] * 3}, "PCG 1": {"*": [0.1] * 3}}, "boulderdash")
    claim = pcg1_beats_ppcg_generated(split)
    assert (
        claim.status == "not run"
        and "runs of several configs, not pooled: PPCG (algo.lr=0.0007)" in claim.reason
    )


def test_a_condition_is_pending_until_its_runs_reach_their_own_planned_frames():
    """medium trains Zelda's PPCG 20M frames and others 10M: at 10M, PPCG is not finished."""
    sets = {s: result([0.5, 0.6, 0.55]) for s in TEST_SETS}
    frogs = GameResults(
        "frogs",
        {"PCG 1": sets, "PPCG": sets},
        {"PCG 1": [10_000_000] * 3, "PPCG": [10_000_000] * 3},
        random={s: 0.0 for s in TEST_SETS},
        maximum={s: 1.0 for s in TEST_SETS},
        max_difficulty={},
        planned={"PCG 1": [10_000_000] * 3, "PPCG": [20_000_000] * 3},
    )
    verdicts = dict((v.claim, v) for _, v in study_claims({"frogs": frogs}, target_frames=10_000_000))
    assert not verdicts["PCG 1 learns nothing (0.00 at d = 1)."].verdict.startswith("pending")
    ppcg = verdicts["PPCG wins 57 % of the d = 1 levels (a large share)."]
    assert ppcg.verdict.startswith("pending") and "PPCG at 10,000,000 frames" in ppcg.evidence


def test_frogs_human_wins_are_judged_per_agent_from_its_own_episodes():
    """One agent of four winning 6 of 30 episodes on every human level (the others none) is an agent
    that wins human levels: decided against the claim by that agent's own binomial test over its
    150 episodes, where the mean of the seeds' best levels (0.05 with one seed's spread) decides
    nothing. Agents that win none of their 150 episodes each are decided below the bound."""

    def frogs(label: str, human_wins: list[int]) -> GameResults:
        sets = {}
        for s in TEST_SETS:
            won = human_wins if s.startswith("lv") else [0] * len(human_wins)
            rates = [w / 30 for w in won]
            sets[s] = SetResult(rates, rates, [], {}, [30] * len(won))
        seeds = len(human_wins)
        return GameResults(
            "frogs",
            {label: sets},
            {label: [10_000_000] * seeds},
            {s: 0.0 for s in TEST_SETS},
            {s: 1.0 for s in TEST_SETS},
            {},
        )

    def verdict(game: GameResults):
        verdicts = [v for _, v in study_claims({"frogs": game}) if "wins a human" in v.claim]
        return verdicts[0]

    against = verdict(frogs("PPCG", [0, 0, 6, 0]))
    assert against.verdict == "does not hold"
    assert "each agent's wins: 0 of 150, 0 of 150, 30 of 150, 0 of 150" in against.evidence
    assert verdict(frogs("PCG 1", [0, 0, 0, 0])).verdict == "holds"


def test_an_undecided_comparison_whose_estimate_lies_against_the_claim_says_so():
    """Solarfox's PCG 1 minus PPCG at d = 0.5 is below 0 where the claim says above: the evidence
    says more seeds would, at the means seen, decide that the claim does not hold."""
    t = table({"PCG 1": {"pcg0.5": [0.3, 0.5, 0.4], "*": [0.6, 0.7, 0.65]}, "PPCG": {"*": [0.5, 0.6, 0.4]}})
    [v] = judge([pcg1_beats_ppcg_generated(t)])
    assert v.verdict == "inconclusive"
    assert "PCG 1 minus PPCG on pcg0.5: -0.10" in v.evidence
    assert "(claim > 0; the estimate lies against the claim; 80 % power at about" in v.evidence
    assert v.evidence.endswith(
        "Where the estimate lies against the claim (PCG 1 minus PPCG on pcg0.5), more seeds would, at the "
        "means seen, decide that it does not hold."
    )
