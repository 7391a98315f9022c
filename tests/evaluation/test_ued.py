"""The UED protocol: its levels, the alpha-CVaR and its bias correction, the records and the CLI."""

import csv
import json

import pytest

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.ued import (
    UED_SEED_BASE,
    UEDLevelResult,
    UEDProtocol,
    alpha_cvar,
    cvar_count,
    evaluate_random_ued,
    evaluate_run_ued,
    rows_from_csv,
    rows_to_csv,
    summarise,
    ued_difficulties,
    ued_levels,
    wilson_interval,
    worst_levels,
)
from gvgai_pcg.levels.seeds import TEST_SEED_BASE, TRAINING_SEED_SPACE
from gvgai_pcg.levels.test_sets import TEST_DIFFICULTIES, frozen_seeds

TINY = UEDProtocol(levels=6, seeds=2, max_steps=12)


def test_levels_are_spread_over_d_and_always_the_same():
    assert ued_difficulties(5) == [0.0, 0.25, 0.5, 0.75, 1.0]
    first, again = ued_levels("zelda", 5), ued_levels("zelda", 5)
    assert first == again and [level.seed for level in first] == [UED_SEED_BASE + i for i in range(5)]
    assert len(set(first)) > 1  # different levels, not one level five times


def test_level_seeds_are_disjoint_from_training_and_the_frozen_test_sets():
    frozen = {s for game in ("zelda", "frogs") for d in TEST_DIFFICULTIES for s in frozen_seeds(game, d)}
    assert UED_SEED_BASE >= TRAINING_SEED_SPACE and UED_SEED_BASE > max(frozen)
    assert UED_SEED_BASE >= TEST_SEED_BASE + 2**24  # above the whole frozen block


def test_cvar_of_a_known_distribution():
    # ten levels scoring 0..9 under both seeds: the worst 20 % are 0 and 1
    values = [float(v) for v in range(10)]
    result = alpha_cvar(values, values, 0.2)
    assert (result.levels, result.corrected, result.naive) == (2, 0.5, 0.5)
    assert alpha_cvar(values, values, 1.0).corrected == pytest.approx(4.5)
    assert cvar_count(0.01, 1000) == 10 and cvar_count(0.1, 1000) == 100 and cvar_count(0.01, 5) == 1


def test_the_bias_correction_scores_the_chosen_levels_with_the_other_seed():
    # seed 0 happened to be unlucky on levels 3 and 7; seed 1 sees them as ordinary
    ranking = [5.0, 6.0, 7.0, -4.0, 5.0, 6.0, 7.0, -6.0, 5.0, 6.0]
    scoring = [5.0, 6.0, 7.0, 6.0, 5.0, 6.0, 7.0, 5.0, 5.0, 6.0]
    result = alpha_cvar(ranking, scoring, 0.2)
    assert worst_levels(ranking, 0.2) == [7, 3]
    assert result.naive == pytest.approx(-5.0)  # the optimistic selection, scored by itself
    assert result.corrected == pytest.approx(5.5)  # the same levels, scored independently
    assert result.interval[0] <= result.corrected <= result.interval[1]


def test_ties_are_broken_by_a_fixed_random_order_not_by_index():
    ranking = [0.0] * 100  # every level unsolved: the worst 10 % is any ten of them
    chosen = worst_levels(ranking, 0.1, seed=0)
    assert chosen == worst_levels(ranking, 0.1, seed=0) and len(chosen) == 10
    assert chosen != list(range(10)) and chosen != worst_levels(ranking, 0.1, seed=1)


def test_summary_rates_and_intervals():
    rows = [
        UEDLevelResult(i, i / 3, UED_SEED_BASE + i, [float(i), float(i)], [i >= 2, i >= 1], [5, 5])
        for i in range(4)
    ]
    summary = summarise(rows, (0.25,))
    assert summary.solved_rate == pytest.approx((0 + 0.5 + 1 + 1) / 4) and summary.episodes == 8
    assert summary.mean_score == pytest.approx(1.5)
    assert summary.solved_interval[0] < summary.solved_rate < summary.solved_interval[1]
    solved = next(c for c in summary.cvars if c.metric == "solved")
    # the worst 25 % is one of the two levels seed 0 did not solve; seed 1 solved one of them
    assert (solved.levels, solved.naive) == (1, 0.0) and solved.corrected in (0.0, 1.0)
    low, high = wilson_interval(0.0, 10)
    assert low == 0.0 and 0.2 < high < 0.35  # Wilson is not degenerate at 0


def test_csv_round_trip():
    rows = [UEDLevelResult(0, 0.0, UED_SEED_BASE, [1.0, -1.0], [True, False], [7, 2000])]
    assert rows_from_csv(rows_to_csv(rows)) == rows


@pytest.mark.parametrize(
    "settings, culprit",
    [
        ({"levels": 0}, "levels must be in 1.."),
        ({"seeds": 1}, "seeds must be at least 2"),
        ({"max_steps": 0}, "max_steps"),
    ],
)
def test_bad_settings_are_refused(settings, culprit):
    with pytest.raises(ValueError, match=culprit):
        UEDProtocol(**settings)


@pytest.mark.parametrize("alpha", [0.0, -0.1, 1.5, True])
def test_alpha_outside_the_unit_interval_is_refused(alpha):
    with pytest.raises(ValueError, match=r"alpha must be in \(0, 1\]"):
        alpha_cvar([1.0, 2.0], [1.0, 2.0], alpha)


def test_protocol_on_a_tiny_run_writes_its_csv_and_reuses_it(tiny_run, monkeypatch):
    summary, table = evaluate_run_ued(run_info(tiny_run), TINY, progress=False)
    assert table == tiny_run / "eval" / f"ued-{TINY.key}.csv" and table.is_file()
    with open(table) as handle:
        rows = list(csv.DictReader(handle))
    assert (
        len(rows) == TINY.levels
        and float(rows[0]["difficulty"]) == 0.0
        and float(rows[-1]["difficulty"]) == 1.0
    )
    assert {"score_0", "won_0", "length_0", "score_1", "won_1", "length_1"} <= set(rows[0])
    assert all(1 <= int(row["length_1"]) <= TINY.max_steps for row in rows)
    record = json.loads(table.with_suffix(".json").read_text())
    assert record["frames"] == 1000 and record["summary"]["levels"] == TINY.levels
    assert summary.episodes == TINY.levels * TINY.seeds and len(summary.cvars) == 4

    import gvgai_pcg.evaluation.ued as ued

    monkeypatch.setattr(ued, "play_ued", lambda *a, **k: pytest.fail("played again"))
    again, _ = evaluate_run_ued(run_info(tiny_run), TINY, progress=False)
    assert again == summary


def test_publishing_a_run_publishes_its_ued_records(tiny_run, tmp_path):
    from gvgai_pcg.study.sweeps.publish import publish

    _, table = evaluate_run_ued(run_info(tiny_run), TINY, progress=False)
    dest = publish(tmp_path / "out", tmp_path / "published", runs=[tiny_run])
    copied = dest / "runs" / tiny_run.name / "eval"
    assert (copied / table.name).read_text() == table.read_text()
    assert (copied / table.with_suffix(".json").name).is_file()


def test_the_random_agent_is_cached_per_game_and_settings(tmp_path, monkeypatch):
    first, table = evaluate_random_ued("zelda", TINY, cache_dir=tmp_path, progress=False)
    assert table == tmp_path / "random" / f"ued-zelda-{TINY.key}.csv" and first.levels == TINY.levels
    rows = rows_from_csv(table.read_text())
    assert [r.level_seed for r in rows] == [UED_SEED_BASE + i for i in range(TINY.levels)]
    import gvgai_pcg.evaluation.ued as ued

    monkeypatch.setattr(ued, "play_ued", lambda *a, **k: pytest.fail("played again"))
    assert evaluate_random_ued("zelda", TINY, cache_dir=tmp_path, progress=False)[0] == first


def test_cli_ued_on_a_run(tiny_run, capsys):
    assert (
        main(["evaluate", str(tiny_run), "--ued", "--ued-levels", "4", "--max-steps", "10", "--no-progress"])
        == 0
    )
    out = capsys.readouterr().out
    assert "solved rate" in out and "CVaR" in out and "ued-" in out


@pytest.mark.parametrize(
    "options, message",
    [
        (["--ued-levels", "0"], "invalid UED protocol setting: levels must be in 1.."),
        (["--alphas", "0.01,1.5"], "alpha must be in (0, 1]"),
        (["--alphas", "x"], "--alphas 'x': expected comma-separated numbers"),
    ],
)
def test_cli_refuses_bad_settings_in_one_line(tiny_run, capsys, options, message):
    with pytest.raises(SystemExit) as exit_info:
        main(["evaluate", str(tiny_run), "--ued", *options])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


def test_publishing_a_run_publishes_its_held_out_scores_over_training(tiny_run, tmp_path):
    from gvgai_pcg.study.sweeps.publish import publish

    records = tiny_run / "eval" / "snapshots" / "protocol-abc" / "model-500.jsonl"
    records.parent.mkdir(parents=True)
    records.write_text('{"frames": 500}\n')
    dest = publish(tmp_path / "out", tmp_path / "published", runs=[tiny_run])
    copied = dest / "runs" / tiny_run.name / "eval" / "snapshots" / "protocol-abc" / "model-500.jsonl"
    assert copied.read_text() == records.read_text()
    assert not (dest / "runs" / tiny_run.name / "snapshots").exists()  # the models stay behind
