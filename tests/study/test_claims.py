"""The claims' verdict rules on hand-made results: each verdict can come out every way."""

from __future__ import annotations

from gvgai_pcg.study.claims import (
    GameResults,
    SetResult,
    four_levels_marginal,
    frogs_ppcg_wins_hard,
    one_level_overfits,
    ppcg_best,
    ppcg_stalls,
)

SETS = ("pcg0.5", "pcg1", "lv0", "lv1", "lv2", "lv3", "lv4")


def result(means: list[float], wins: float = 0.0) -> SetResult:
    return SetResult(seed_means=means, seed_wins=[wins] * len(means), scores=means * 10)


def game(conditions: dict[str, dict[str, SetResult]], name: str = "zelda", reached=None) -> GameResults:
    return GameResults(
        name,
        conditions,
        {label: [5_000_000] for label in conditions},
        random={s: 0.0 for s in SETS},
        maximum={s: 10.0 for s in SETS},
        max_difficulty={"PPCG": reached or []},
    )


def flat(value: float, **overrides: float) -> dict[str, SetResult]:
    return {s: result([overrides.get(s, value)] * 3) for s in SETS}


def test_one_level_overfits_holds_only_near_the_max_there_and_near_random_elsewhere():
    overfit = game({"Lv 0": flat(0.5, lv0=9.5), "Lv 4": flat(1.0, lv4=9.0)})
    assert one_level_overfits(overfit).verdict == "holds"
    general = game({"Lv 0": flat(6.0, lv0=9.5), "Lv 4": flat(6.0, lv4=9.0)})
    assert one_level_overfits(general).verdict == "does not hold"
    assert one_level_overfits(game({"PPCG": flat(1.0)})).verdict == "not run"


def test_four_levels_are_marginal_unless_clearly_better_on_the_held_out_sets():
    close = game({"Lv 0": flat(1.0), "Lv 0-3": flat(1.5)})
    assert four_levels_marginal(close).verdict == "holds"
    much = game({"Lv 0": flat(1.0), "Lv 0-3": flat(6.0)})
    assert four_levels_marginal(much).verdict == "does not hold"
    noisy = {"Lv 0": flat(1.0), "Lv 0-3": {s: result([0.0, 4.0, 2.0]) for s in SETS}}
    assert four_levels_marginal(game(noisy)).verdict == "inconclusive"


def test_ppcg_best_needs_to_lead_every_held_out_column():
    assert ppcg_best(game({"PPCG": flat(5.0), "PCG 1": flat(2.0), "Lv 0": flat(1.0)})).verdict == "holds"
    assert ppcg_best(game({"PPCG": flat(2.0), "PCG 1": flat(5.0)})).verdict == "does not hold"
    # a row that trained on a level is no rival there: Lv 0's 9 on lv0 does not count
    assert ppcg_best(game({"PPCG": flat(5.0), "Lv 0": flat(1.0, lv0=9.0)})).verdict == "holds"


def test_frogs_ppcg_wins_hard_levels_only_when_pcg1_wins_none():
    def frogs(ppcg_wins: float, pcg_wins: float) -> GameResults:
        return game(
            {"PPCG": {"pcg1": result([0.5], ppcg_wins)}, "PCG 1": {"pcg1": result([0.0], pcg_wins)}}, "frogs"
        )

    assert frogs_ppcg_wins_hard(frogs(0.6, 0.0)).verdict == "holds"
    assert frogs_ppcg_wins_hard(frogs(0.0, 0.0)).verdict == "does not hold"
    assert frogs_ppcg_wins_hard(frogs(0.2, 0.0)).verdict == "inconclusive"


def test_ppcg_stalls_needs_both_a_stalled_difficulty_and_pcg1_ahead():
    conditions = {"PPCG": flat(1.0), "PCG 1": flat(4.0)}
    assert ppcg_stalls(game(conditions, "solarfox", reached=[0.4, 0.5])).verdict == "holds"
    assert ppcg_stalls(game(conditions, "solarfox", reached=[1.0, 0.5])).verdict == "does not hold"
    behind = {"PPCG": flat(4.0), "PCG 1": flat(1.0)}
    assert ppcg_stalls(game(behind, "solarfox", reached=[0.4])).verdict == "does not hold"


def test_a_claim_on_unfinished_runs_is_pending_with_its_evidence_so_far():
    from gvgai_pcg.study.claims import study_claims

    zelda = game({"Lv 0": flat(0.5, lv0=9.5), "Lv 4": flat(1.0, lv4=9.0)})
    zelda.frames["Lv 4"] = [1_000_000]
    [(name, verdict), *_] = study_claims({"zelda": zelda}, target_frames=5_000_000)
    assert name == "zelda" and verdict.verdict == "pending (holds so far)"
    assert "Lv 4 at 1,000,000 frames" in verdict.evidence
    zelda.frames["Lv 4"] = [5_000_000]
    assert study_claims({"zelda": zelda}, target_frames=5_000_000)[0][1].verdict == "holds"


def test_one_level_short_of_the_max_but_random_elsewhere_is_inconclusive():
    assert one_level_overfits(game({"Lv 0": flat(0.5, lv0=6.0), "Lv 4": flat(0.5, lv4=6.0)})).verdict == (
        "inconclusive"
    )


def test_claims_count_the_frames_of_the_evaluated_model_not_of_a_later_checkpoint(tmp_path):
    """A run that trains on after its evaluation is judged at the frames it was evaluated at."""
    import torch

    from gvgai_pcg.evaluation.checkpoints import run_info
    from gvgai_pcg.evaluation.evaluator import evaluate_run
    from gvgai_pcg.evaluation.protocol import Protocol
    from gvgai_pcg.study.claims import collect
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
    from gvgai_pcg.study.claims import claims_markdown, collect
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
