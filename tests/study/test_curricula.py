"""The curricula comparison (issue 36): its budgets and conditions, the refusal of a curriculum not
registered yet, the answer's logic on records with known answers, and (slow) the smoke budget from
training to the page."""

from __future__ import annotations

import json

import pytest
from hydra import compose, initialize_config_dir

from gvgai_pcg.config import config_dir
from gvgai_pcg.curricula import Curriculum, get_curriculum, register_curriculum, unregister_curriculum
from gvgai_pcg.games.registry import generate_level
from gvgai_pcg.study import BUDGETS
from gvgai_pcg.study.sweeps.conditions import (
    CURRICULA_CONDITIONS,
    CURRICULA_EXTRA,
    MEDIUM_SETUP,
    condition_regimen,
    conditions_of,
    unregistered,
)
from gvgai_pcg.study.sweeps.curricula_runs import (
    REPLAY_PICTURE,
    REPLAY_STATS,
    level_count_summary,
    write_levels_picture,
    write_replay_picture,
    write_replay_stats,
)
from gvgai_pcg.study.verdicts.comparison import (
    DOES_NOT_HOLD,
    HOLDS,
    INCONCLUSIVE,
    NOT_MEASURED,
    CurriculumRuns,
    answer_sentences,
    comparison_markdown,
    judge,
    read_ued_summary,
    ued_values,
)

SUMMARY = {
    "levels": 8,
    "episodes": 16,
    "solved_rate": 0.25,
    "solved_interval": [0.1, 0.5],
    "mean_score": 1.5,
    "score_interval": [1.0, 2.0],
    "cvars": [
        {"metric": "score", "alpha": 0.01, "levels": 1, "corrected": -1.0, "naive": -2.0, "interval": [0, 0]},
        {"metric": "score", "alpha": 0.1, "levels": 1, "corrected": 0.5, "naive": 0.0, "interval": [0, 0]},
        {"metric": "solved", "alpha": 0.1, "levels": 1, "corrected": 0.0, "naive": 0.0, "interval": [0, 0]},
    ],
}


def test_the_curricula_budget_is_six_curricula_on_zelda_and_frogs_with_one_tuned_learner():
    budget = BUDGETS["curricula"]
    assert {c.split("-")[0] for c in budget.conditions} == {"zelda", "frogs"} and len(budget.conditions) == 12
    assert {c.split("-")[0] for c in conditions_of(budget, extra=True)} == {
        "zelda",
        "frogs",
        "solarfox",
        "boulderdash",
    }
    assert len(budget.seeds) >= 3 and budget.frames >= 10_000_000 and budget.comparison == "curricula"
    assert set(MEDIUM_SETUP) <= set(budget.overrides) and not any("algo=" in o for o in budget.overrides)
    assert budget.ued["levels"] >= 1000 and budget.page == "docs/results-curricula.md"
    smoke = BUDGETS["curricula-smoke"]
    assert smoke.conditions == budget.conditions and smoke.frames <= 1_000 and smoke.ued["levels"] < 20


def test_every_curricula_condition_names_its_curriculum_and_the_registered_ones_compose():
    conditions = CURRICULA_CONDITIONS + CURRICULA_EXTRA
    names = {c: c.split("-", 1)[1].replace("pcg1", "pcg") for c in conditions}
    assert {c: condition_regimen(c) for c in conditions} == names
    refused = unregistered(conditions)
    assert not {"zelda-pcg1", "frogs-ppcg", "zelda-dr"} & set(refused)  # on main from the start
    for condition in [c for c in CURRICULA_CONDITIONS if c not in refused]:
        with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
            cfg = compose("config", overrides=[f"condition={condition}"])
        assert cfg.regimen.name == names[condition] and cfg.game.name == condition.split("-")[0]


def test_a_condition_whose_curriculum_is_not_registered_is_refused_with_one_line_naming_it(tmp_path):
    dr = get_curriculum("dr")
    unregister_curriculum("dr")
    try:
        refused = unregistered(["zelda-dr", "zelda-ppcg"])
        from gvgai_pcg.study.pipeline import reproduce

        with pytest.raises(ValueError, match="zelda-dr: the curriculum 'dr' is not registered"):
            reproduce(BUDGETS["curricula-smoke"], ["zelda-dr"], tmp_path, train=False)
    finally:
        register_curriculum(dr)
    assert list(refused) == ["zelda-dr"] and "\n" not in refused["zelda-dr"]
    assert "'dr' is not registered (registered: " in refused["zelda-dr"] and "ppcg" in refused["zelda-dr"]


def runs(label: str, regimen: str, **values: list[float]) -> CurriculumRuns:
    seeds = len(next(iter(values.values())))
    return CurriculumRuns(label, regimen, [800] * seeds, {k: list(v) for k, v in values.items()})


def synthetic() -> dict[str, dict[str, CurriculumRuns]]:
    """Known answers: Zelda's DR beats PPCG on the human levels and is behind on CVaR 10 %; PCG 1
    is behind on the human levels; SFL's seeds scatter (inconclusive); Frogs wins nothing on the
    human levels with any curriculum (no spread: does not hold); Frogs' DR has no UED records."""
    return {
        "zelda": {
            "PPCG": runs(
                "PPCG", "ppcg", human=[1.0, 1.1, 0.9], cvar1=[0.0, 0.1, -0.1], cvar10=[2.0, 2.1, 1.9]
            ),
            "DR": runs("DR", "dr", human=[5.0, 5.1, 4.9], cvar1=[0.0, 0.2, -0.1], cvar10=[0.0, 0.1, -0.1]),
            "PCG 1": runs(
                "PCG 1", "pcg", human=[-1.0, -1.1, -0.9], cvar1=[0, 0.1, -0.1], cvar10=[2, 2.2, 1.8]
            ),
            "SFL": runs(
                "SFL", "sfl", human=[-3.0, 6.0, 1.0], cvar1=[-4.0, 5.0, 0.0], cvar10=[0.0, 6.0, -1.0]
            ),
        },
        "frogs": {
            "PPCG": runs(
                "PPCG", "ppcg", human=[0.0, 0.0, 0.0], cvar1=[0.0, 0.0, 0.0], cvar10=[0.2, 0.1, 0.3]
            ),
            "DR": runs("DR", "dr", human=[0.0, 0.0, 0.0]),
        },
    }


def test_the_answer_holds_does_not_hold_or_is_inconclusive_as_the_records_say():
    verdicts = {(v.game, v.label, v.metric): v for v in judge(synthetic())}
    assert verdicts["zelda", "DR", "human"].outcome == HOLDS
    assert verdicts["zelda", "DR", "cvar10"].outcome == DOES_NOT_HOLD
    assert verdicts["zelda", "DR", "cvar1"].outcome == INCONCLUSIVE
    assert verdicts["zelda", "PCG 1", "human"].outcome == DOES_NOT_HOLD
    assert {verdicts["zelda", "SFL", m].outcome for m in ("human", "cvar1", "cvar10")} == {INCONCLUSIVE}
    assert verdicts["frogs", "DR", "human"].outcome == DOES_NOT_HOLD  # 0 on every seed of both
    assert verdicts["frogs", "DR", "cvar10"].outcome == NOT_MEASURED
    assert not any(label == "PPCG" for _, label, _ in verdicts)
    dr = verdicts["zelda", "DR", "human"]
    assert dr.difference.low < 4.0 < dr.difference.high and dr.adjusted_p <= 0.05
    # Holm: each adjusted p is at least the raw one
    assert all(v.adjusted_p >= v.difference.p for v in verdicts.values() if v.difference is not None)
    # an open comparison says what would decide it; a decided one says nothing of the kind
    assert (
        verdicts["zelda", "DR", "cvar1"].decides == "more than 30 seeds would be needed for 80 % power"
    )  # +0.03, seeds spread 0.15
    assert verdicts["zelda", "PCG 1", "cvar1"].decides == "the estimate sits on the bound"  # the same seeds
    assert dr.decides == ""


def test_the_answer_is_written_as_sentences_with_its_intervals():
    text = "\n".join(answer_sentences(judge(synthetic())))
    assert "**Zelda, on the human levels (mean score over levels 0-4)**: yes: DR beats PPCG." in text
    assert "**Frogs, on the human levels (mean score over levels 0-4)**: no: none beats PPCG." in text
    assert "none shown to beat PPCG at this budget (DR, PCG 1, SFL inconclusive)" in text  # Zelda CVaR 1 %
    assert "  - DR beats PPCG: **holds** (difference +4.00, 95 % Welch t interval [+" in text
    assert "  - DR beats PPCG: **not measured** (no data on one side)." in text
    page = comparison_markdown(synthetic())
    page = page[page.index("#### Zelda") :]
    assert page.index("| PCG 1 |") < page.index("| PPCG |") < page.index("| DR |") < page.index("| SFL |")
    assert "| DR | 3 | 800 | 5.00 [4.75, 5.25] |" in page


def test_a_control_is_shown_but_not_judged_so_holms_family_is_unchanged():
    games = synthetic()
    without = {(v.game, v.label, v.metric): v.adjusted_p for v in judge(games)}
    games["zelda"]["ACCEL, no selection"] = runs(
        "ACCEL, no selection", "accel-noselect", human=[9.0, 9.1, 8.9], cvar1=[0, 0, 0], cvar10=[0, 0, 0]
    )
    verdicts = judge(games)
    assert not any(v.label == "ACCEL, no selection" for v in verdicts)
    assert {(v.game, v.label, v.metric): v.adjusted_p for v in verdicts} == without
    assert "| ACCEL, no selection | 3 | 800 | 9.00 [" in comparison_markdown(games)


def test_the_tail_protocols_win_rate_cvar_is_shown_and_judged_only_where_runs_have_it():
    tail = {**SUMMARY, "rank_episodes": 10}
    assert ued_values(tail) == {
        "solved": 0.25,
        "ued_score": 1.5,
        "cvar1": -1.0,
        "cvar10": 0.5,
        "wincvar10": 0.0,
    }
    old_page = comparison_markdown(synthetic())
    assert "win-rate" not in old_page  # the first protocol's records: the page as it was
    games = synthetic()
    games["zelda"]["PPCG"].values["wincvar1"] = [0.30, 0.32, 0.28]
    games["zelda"]["DR"].values["wincvar1"] = [0.0, 0.02, 0.01]
    verdicts = {(v.game, v.label, v.metric): v for v in judge(games)}
    assert verdicts["zelda", "DR", "wincvar1"].outcome == DOES_NOT_HOLD
    assert verdicts["frogs", "DR", "wincvar1"].outcome == NOT_MEASURED
    assert ("zelda", "DR", "wincvar10") not in verdicts  # no run has it: not asked
    page = comparison_markdown(games)
    assert "UED win-rate CVaR 1 %" in page and "UED win-rate CVaR 10 %" not in page
    assert "the worst 1 % of the UED levels by win rate" in page


def test_a_ued_summary_is_read_from_the_runs_records_of_the_budgets_protocol(tmp_path):
    assert ued_values(SUMMARY) == {"solved": 0.25, "ued_score": 1.5, "cvar1": -1.0, "cvar10": 0.5}
    (tmp_path / "eval").mkdir()
    other = {"protocol": {"levels": 1000, "seeds": 2}, "frames": 900, "summary": {**SUMMARY, "mean_score": 9}}
    (tmp_path / "eval" / "ued-aaa.json").write_text(json.dumps(other))
    assert read_ued_summary(tmp_path, {"levels": 8, "seeds": 2}) is None
    ours = {"protocol": {"levels": 8, "seeds": 2, "max_steps": 50}, "frames": 800, "summary": SUMMARY}
    (tmp_path / "eval" / "ued-bbb.json").write_text(json.dumps(ours))
    assert read_ued_summary(tmp_path, {"levels": 8, "seeds": 2})["mean_score"] == 1.5


def test_a_curriculum_replays_no_level_by_default_and_no_level_makes_no_picture(tmp_path):
    assert Curriculum().replay_levels(None, 4) == [] and get_curriculum("ppcg").replay_levels(None, 4) == []
    assert write_levels_picture([], tmp_path / "none.png") is None and not (tmp_path / "none.png").exists()


class ReplaysFromItsState(Curriculum):
    """A toy curriculum that replays the levels its state names (as (d, seed) pairs)."""

    name, summary = "toy-replay", "replays the levels of its state"

    def make_state(self, game, section):
        import torch

        return torch.nn.Module()

    def replay_levels(self, state, k):
        return [generate_level("zelda", d, seed) for d, seed in ((0.1, 3), (0.9, 4), (0.5, 5))][:k]


def write_toy_replay_run(run):
    """A run folder of the toy curriculum: its config and a last checkpoint with an empty state."""
    import torch
    import yaml

    (run / "checkpoints").mkdir()
    config = {"game": {"name": "zelda"}, "regimen": {"name": "toy-replay"}}
    (run / "config.yaml").write_text(yaml.safe_dump(config))
    torch.save({"model": {}, "config": config, "difficulty": {}}, run / "checkpoints" / "last.pt")


@pytest.mark.slow  # importing the renderer: half a minute on the loaded 2-core machine
def test_a_run_pictures_the_levels_its_curriculum_replays_from_its_last_checkpoint(tmp_path):
    write_toy_replay_run(tmp_path)
    assert write_replay_picture(tmp_path) is None  # its curriculum is not registered here
    register_curriculum(ReplaysFromItsState())
    try:
        path = write_replay_picture(tmp_path, k=2)
    finally:
        unregister_curriculum("toy-replay")
    assert path == tmp_path / REPLAY_PICTURE and path.read_bytes().startswith(b"\x89PNG")
    levels = [generate_level("zelda", d, 1) for d in (0.2, 0.8)]
    assert write_levels_picture(levels, tmp_path / "two.png", "two").stat().st_size > 1000


def test_a_level_count_summary_gives_each_counts_median_90th_percentile_and_most():
    from gvgai_pcg.levels import human_levels

    levels = human_levels("zelda")
    enemies = sorted(sum(level.count(c) for c in "123") for level in levels)
    summary = level_count_summary(levels)
    assert summary["levels"] == 5 and set(summary["counts"]) >= {"enemies", "interior_walls"}
    assert summary["counts"]["enemies"]["median"] == enemies[2]
    assert summary["counts"]["enemies"]["max"] == enemies[-1]
    assert enemies[2] <= summary["counts"]["enemies"]["p90"] <= enemies[-1]
    assert level_count_summary([]) == {"levels": 0}


def test_a_run_summarises_every_level_its_curriculum_holds_once_per_checkpoint(tmp_path):
    write_toy_replay_run(tmp_path)
    assert write_replay_stats(tmp_path) is None  # its curriculum is not registered here
    register_curriculum(ReplaysFromItsState())
    try:
        path = write_replay_stats(tmp_path)
        expected = level_count_summary(ReplaysFromItsState().replay_levels(None, 10))
        assert path == tmp_path / REPLAY_STATS and json.loads(path.read_text()) == expected
        assert expected["levels"] == 3  # all it holds, not the picture's few
        kept = {**expected, "levels": -1}
        path.write_text(json.dumps(kept))  # newer than the checkpoint, the same counts: kept
        assert json.loads(write_replay_stats(tmp_path).read_text()) == kept
        path.write_text(json.dumps({"levels": -1, "counts": {"gone": {}}}))  # counts renamed since
        assert json.loads(write_replay_stats(tmp_path).read_text()) == expected
    finally:
        unregister_curriculum("toy-replay")


def test_the_page_sets_the_held_levels_beside_the_generators_and_the_human_ones(tmp_path):
    from types import SimpleNamespace

    from gvgai_pcg.study.pages.curricula_page import REFERENCE_LEVELS, _held_levels_tables

    run = tmp_path / "zelda-accel-seed0"
    run.mkdir()
    held = {"levels": 4000, "counts": {"enemies": {"median": 32.0, "p90": 41.0, "max": 50}}}
    (run / REPLAY_STATS).write_text(json.dumps(held))
    info = SimpleNamespace(path=run, game="zelda", label="ACCEL", seed=0)
    lines = _held_levels_tables([info, SimpleNamespace(path=tmp_path, game="zelda", label="DR", seed=0)])
    table = "\n".join(lines)
    assert "| ACCEL seed 0, 4,000 held | - | 32 (41, 50) |" in table
    assert f"| generator, d = 1 ({REFERENCE_LEVELS} levels) |" in table and "| human levels |" in table
    assert "DR" not in table  # a run without the file has no row
    assert table.count("\n| ") == 4  # the header and three rows, none for DR


@pytest.mark.slow
def test_the_smoke_comparison_trains_evaluates_publishes_and_writes_the_page(tmp_path):
    from gvgai_pcg.evaluation.checkpoints import find_runs
    from gvgai_pcg.study.pages.curricula_page import END, START, write_curricula_page
    from gvgai_pcg.study.pipeline import reproduce

    budget = BUDGETS["curricula-smoke"]
    conditions = ["zelda-pcg1", "zelda-ppcg", "zelda-dr"]
    outcome = reproduce(budget, conditions, tmp_path / "out", publish_to=tmp_path / "pub", progress=False)
    published = find_runs([tmp_path / "pub" / "runs"])
    assert len(published) == 3
    report = (outcome.report / "curricula.md").read_text()
    assert "| PCG 1 | 1 | 800 |" in report and "| PPCG | 1 | 800 |" in report and "| DR | 1 | 800 |" in report
    assert "- **Zelda, on the human levels (mean score over levels 0-4)**:" in report
    assert (outcome.report / "curricula-curves-zelda.png").is_file()  # PPCG logs its d
    for run in published:  # a UED record as the protocol writes it (the page reads data only)
        made = sorted((run / "eval").glob("ued-*"))  # the protocol's own, published with the run
        assert [path.suffix for path in made] == [".csv", ".json"]
        for path in made:
            path.unlink()
        record = {"protocol": {**budget.ued, "greedy": False, "seed": 0}, "frames": 800, "summary": SUMMARY}
        (run / "eval" / "ued-0123456789.json").write_text(json.dumps(record))
    page = tmp_path / "docs" / "results-curricula.md"
    page.parent.mkdir()
    page.write_text(f"# Curricula\n\nbefore\n{START}\nold\n{END}\nafter\n")
    write_curricula_page(page, tmp_path / "pub", budget, "abc1234")
    text = page.read_text()
    assert text.startswith("# Curricula\n\nbefore\n") and text.endswith("after\n") and "\nold\n" not in text
    assert "commit `abc1234`" in text and "| zelda-dr-tiles-compact-seed0 | 800 | yes |" in text
    assert "| 0.25 (1 seed) | 1.50 (1 seed) | -1.00 (1 seed) | 0.50 (1 seed) |" in text
    assert "DR beats PPCG: **inconclusive** (difference +0.00, one seed: no interval, Holm p 1)" in text
    assert "(images/results-curricula/curricula-curves-zelda.png)" in text
    assert (page.parent / "images" / "results-curricula" / "curricula-curves-zelda.png").is_file()
    assert "No run's curriculum replays levels yet" in text


def test_the_ued_levels_are_binned_by_difficulty_over_every_evaluation_seed():
    from gvgai_pcg.study.pages.ued_by_difficulty import solved_by_bin

    rows = [
        {"difficulty": "0.0", "won_0": "1", "won_1": "0"},
        {"difficulty": "0.05", "won_0": "1", "won_1": "1"},
        {"difficulty": "0.5", "won_0": "0", "won_1": "0"},
        {"difficulty": "1", "won_0": "1", "won_1": "0"},  # d = 1 falls in the last bin
    ]
    assert solved_by_bin(rows, bins=4) == [0.75, None, 0.0, 0.5]


def test_the_page_draws_each_curriculum_s_solved_rate_by_difficulty(tmp_path):
    from gvgai_pcg.study.pages.ued_by_difficulty import write_solved_by_difficulty

    settings = {"levels": 4, "seeds": 2}
    runs = []
    for label, won in (("DR", "1"), ("PPCG", "0"), ("PPCG", "1")):
        run = tmp_path / f"{label}-{len(runs)}"
        (run / "eval").mkdir(parents=True)
        record = {"protocol": {**settings, "seed": 0}, "frames": 800, "summary": SUMMARY}
        (run / "eval" / "ued-abc.json").write_text(json.dumps(record))
        lines = ["index,difficulty,level_seed,score_0,won_0,length_0,score_1,won_1,length_1"]
        lines += [f"{i},{i / 3:.4f},{i},1,{won},5,1,{won},5" for i in range(4)]
        (run / "eval" / "ued-abc.csv").write_text("\n".join(lines) + "\n")
        runs.append(("zelda", label, run))
    runs.append(("frogs", "DR", tmp_path / "no-records"))  # no UED record: no figure
    (tmp_path / "no-records" / "eval").mkdir(parents=True)
    written = write_solved_by_difficulty(runs, settings, tmp_path / "images")
    assert [p.name for p in written] == ["ued-solved-by-d-zelda.png"]
    assert written[0].read_bytes().startswith(b"\x89PNG")
    assert write_solved_by_difficulty(runs, {"levels": 1000}, tmp_path / "images") == []  # other protocol


def _ued_file(run, name: str, protocol: dict) -> None:
    (run / "eval").mkdir(parents=True, exist_ok=True)
    record = {"protocol": protocol, "frames": 10, "summary": {"solved_rate": 0.5, "mean_score": 1.0}}
    (run / "eval" / f"ued-{name}.json").write_text(json.dumps(record))


def test_a_game_is_read_on_the_tail_protocol_where_any_run_has_it_and_never_falls_back(tmp_path):
    from gvgai_pcg.study.pages.curricula_page import _ued_settings
    from gvgai_pcg.study.verdicts.comparison import ued_record

    budget = BUDGETS["curricula"]
    tail, first = tmp_path / "tail", tmp_path / "first"
    _ued_file(tail, "tail", {**budget.ued, "max_steps": 2000})
    _ued_file(first, "first", {"levels": budget.ued["levels"], "seeds": 2, "max_steps": 2000})
    settings, name = _ued_settings(budget, [tail, first])
    assert (settings, name) == (budget.ued, "the tail protocol")
    assert ued_record(first, settings) is None  # the run without it shows none, not the first's
    settings, name = _ued_settings(budget, [first])
    assert name == "the first protocol" and ued_record(first, settings) is not None
    assert ued_record(tail, settings) is None
    assert budget.fair == "curricula-fair"
