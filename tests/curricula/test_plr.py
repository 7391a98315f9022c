"""PLR⊥ (``regimen=plr``): the replay distribution, the buffer, the scores from the signals, the
robust mask, and training and resuming through the real trainer. The known sampler bugs of the
reference libraries are tested against: the rank temperature is a power, an empty buffer draws
new levels, an unfinished episode writes no score, the lowest score is evicted."""

from __future__ import annotations

import math

import pytest
import torch
from tensordict import TensorDict

from gvgai_pcg.cli import main
from gvgai_pcg.config import ConfigError, compose_config
from gvgai_pcg.curricula.level_buffer import LevelBuffer, rank_weights, staleness_weights
from gvgai_pcg.curricula.plr import PrioritizedLevels, ReplaySettings
from gvgai_pcg.generators import generate_level
from gvgai_pcg.rl.environment import EnvFactory, curriculum_run, training_source

SMALL = ["game=zelda", "env.num_envs=4", "env.max_steps=6", "log.every_episodes=4", "log.curve=false"]


@pytest.fixture
def eager(monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")


def filled(capacity: int, scores: list[float], clock: int = 0) -> LevelBuffer:
    buffer = LevelBuffer(capacity)
    for i, score in enumerate(scores):
        assert buffer.insert(100 + i, 0.1 * i, score, 0.0) == i
    buffer.clock[0] = clock
    return buffer


def signals(rows: list[dict]) -> TensorDict:
    """Hand-made ``LevelSignals`` rows (``env``, ``seed``, ``d``, ``steps``, ``finished``,
    ``adv``: mean positive advantage, ``value``: mean V, ``ret``: return)."""
    return TensorDict(
        {
            "env": torch.tensor([r["env"] for r in rows]),
            "level_seed": torch.tensor([r["seed"] for r in rows]),
            "level_difficulty": torch.tensor([r["d"] for r in rows], dtype=torch.float64),
            "steps": torch.tensor([r["steps"] for r in rows]),
            "finished": torch.tensor([r["finished"] for r in rows]),
            "won": torch.zeros(len(rows), dtype=torch.bool),
            "return": torch.tensor([r.get("ret", 0.0) for r in rows]),
            "length": torch.tensor([r["steps"] for r in rows]),
            "advantage_positive": torch.tensor([r.get("adv", 0.0) for r in rows]),
            "state_value": torch.tensor([r.get("value", 0.0) for r in rows]),
        },
        batch_size=[len(rows)],
    )


# --- the replay distribution ---
def test_the_rank_temperature_is_a_power_not_a_division():
    weights = rank_weights(torch.tensor([1.0, 3.0, 2.0]), temperature=0.5)
    expected = torch.tensor([1 / 9, 1.0, 1 / 4], dtype=torch.float64)
    assert torch.allclose(weights, expected / expected.sum())
    # a division would cancel in the normalisation: every temperature would give 1/rank
    assert not torch.allclose(
        rank_weights(torch.tensor([1.0, 3.0, 2.0]), 0.3), rank_weights(torch.tensor([1.0, 3.0, 2.0]), 1.0)
    )


def test_staleness_is_the_levels_handed_out_since_each_was_last():
    buffer = filled(4, [0.0, 0.0, 0.0], clock=10)
    buffer.last_sampled[:3] = torch.tensor([10, 6, 2])
    only_staleness = buffer.replay_probabilities(temperature=0.3, staleness_coef=1.0)
    assert torch.allclose(only_staleness, torch.tensor([0.0, 4 / 12, 8 / 12, 0.0], dtype=torch.float64))
    assert buffer.tick() == 11
    index = buffer.pick(only_staleness, uniform=0.99)
    assert index == 2 and int(buffer.last_sampled[2]) == 11  # sampled now: staleness 0
    assert float(buffer.replay_probabilities(0.3, 1.0)[2]) == 0.0
    assert torch.equal(staleness_weights(torch.zeros(3)), torch.full((3,), 1 / 3, dtype=torch.float64))


def test_the_mixture_weights_score_and_staleness_and_leaves_empty_slots_out():
    buffer = filled(5, [0.5, 0.1, 0.9], clock=3)
    probabilities = buffer.replay_probabilities(temperature=1.0, staleness_coef=0.3)
    by_rank = torch.tensor([1 / 2, 1 / 3, 1.0], dtype=torch.float64)
    by_staleness = torch.full((3,), 1 / 3, dtype=torch.float64)  # all inserted at clock 0
    expected = 0.7 * by_rank / by_rank.sum() + 0.3 * by_staleness
    assert torch.allclose(probabilities[:3], expected) and probabilities[3:].eq(0).all()
    assert probabilities.sum().item() == pytest.approx(1.0)


def test_an_empty_buffer_has_no_replay_distribution():
    with pytest.raises(ValueError, match="the level buffer is empty"):
        LevelBuffer(3).replay_probabilities(0.3, 0.3)


# --- the buffer ---
def test_a_full_buffer_evicts_its_lowest_score_and_refuses_a_lower_one():
    buffer = filled(3, [0.5, 0.1, 0.9])
    assert buffer.insert(7, 0.5, 0.05, 0.0) == -1  # below the lowest: not kept
    assert buffer.insert(8, 0.5, 0.2, 0.0) == 1  # replaces 0.1, the lowest
    assert buffer.seed.tolist() == [100, 8, 102] and buffer.score.tolist() == pytest.approx([0.5, 0.2, 0.9])
    assert buffer.find(
        torch.tensor([8, 101, 102]), torch.tensor([0.5, 0.1, 0.2], dtype=torch.float64)
    ).tolist() == [1, -1, 2]


# --- the source: handing out levels ---
def source_of(buffer: LevelBuffer, **settings) -> PrioritizedLevels:
    return PrioritizedLevels("zelda", buffer, ReplaySettings(**{"rho": 0.0, **settings}))


def test_the_first_levels_are_new_even_when_replay_is_certain():
    source = source_of(LevelBuffer(4), replay_prob=1.0)
    seeds = torch.tensor([3, 2**40 + 5], dtype=torch.int64)
    levels = source.next_levels(torch.arange(2), seeds, torch.zeros(2, dtype=torch.float64))
    drawn = source.level_difficulties(torch.arange(2), seeds, torch.zeros(2, dtype=torch.float64))
    for level, d, seed in zip(levels, drawn.tolist(), seeds.tolist(), strict=True):
        assert level == generate_level("zelda", d, seed % 2**31) and level.seed == seed % 2**31
    assert int(source.buffer.clock[0]) == 2  # two levels handed out


def test_new_levels_are_drawn_in_the_configured_difficulty_range():
    source = source_of(LevelBuffer(4), replay_prob=0.0, min_difficulty=0.2, max_difficulty=0.4)
    seeds = torch.arange(6, dtype=torch.int64)
    source.next_levels(torch.arange(6), seeds, torch.zeros(6, dtype=torch.float64))
    drawn = source.level_difficulties(torch.arange(6), seeds, torch.zeros(6, dtype=torch.float64))
    assert ((drawn >= 0.2) & (drawn <= 0.4)).all() and len(set(drawn.tolist())) == 6


def test_replays_hand_out_buffer_levels_and_wait_for_rho():
    buffer = LevelBuffer(4)
    buffer.insert(11, 0.25, 1.0, 0.0)
    waiting = source_of(buffer, replay_prob=1.0, rho=0.5)  # 1 of 4: not yet
    assert waiting.next_levels(torch.arange(1), torch.tensor([9]), torch.zeros(1))[0].seed == 9
    source = source_of(buffer, replay_prob=1.0, rho=0.25)
    levels = source.next_levels(torch.arange(3), torch.tensor([1, 2, 3]), torch.zeros(3))
    assert all(level == generate_level("zelda", 0.25, 11) for level in levels)
    assert (
        source.level_difficulties(torch.arange(3), torch.tensor([1, 2, 3]), torch.zeros(3)).tolist()
        == [0.25] * 3
    )
    assert int(buffer.last_sampled[0]) == int(buffer.clock[0]) == 4


# --- the source: scores from the signals ---
def test_an_unfinished_episode_writes_no_score_and_carries_its_partial_sums():
    source = source_of(LevelBuffer(4))
    source.observe(signals([dict(env=0, seed=5, d=0.5, steps=4, finished=False, adv=1.0)]))
    assert source.buffer.size == 0  # nothing yet: no -inf, no NaN, no partial entry
    source.observe(signals([dict(env=0, seed=5, d=0.5, steps=2, finished=True, adv=4.0, ret=1.0)]))
    assert source.buffer.size == 1
    assert float(source.buffer.score[0]) == pytest.approx((4 * 1.0 + 2 * 4.0) / 6)  # over the whole episode
    assert bool(torch.isfinite(source.buffer.score).all())


def test_a_maxmc_replay_without_a_complete_episode_never_scores_minus_infinity():
    buffer = filled(4, [0.5])  # level 100 at d 0.0, its best return 0.0
    source = source_of(buffer, score="maxmc")
    # a replay that runs past the batch: no complete episode, so no score (dcd's bug: -inf from
    # the max over no returns), and the level keeps its own
    source.observe(signals([dict(env=0, seed=100, d=0.0, steps=5, finished=False, value=0.25, ret=3.0)]))
    assert float(buffer.score[0]) == 0.5 and float(buffer.max_return[0]) == 0.0
    source.observe(signals([dict(env=0, seed=100, d=0.0, steps=3, finished=True, value=0.25, ret=2.0)]))
    assert float(buffer.score[0]) == pytest.approx(2.0 - 0.25) and bool(torch.isfinite(buffer.score).all())


def test_a_replayed_level_gets_its_latest_score_and_a_new_one_follows_the_old_on_one_env():
    buffer = filled(4, [0.5])
    source = source_of(buffer, score="maxmc")
    batch = [
        dict(env=0, seed=100, d=0.0, steps=3, finished=True, value=0.5, ret=2.0),  # a replay
        dict(env=0, seed=7, d=0.3, steps=2, finished=True, value=1.0, ret=1.5),  # then a new level
        dict(env=1, seed=8, d=0.3, steps=1, finished=True, value=float("nan"), ret=1.0),  # NaN: kept out
    ]
    source.observe(signals(batch))
    assert float(buffer.score[0]) == pytest.approx(2.0 - 0.5) and float(buffer.max_return[0]) == 2.0
    assert buffer.find(torch.tensor([7, 8]), torch.tensor([0.3, 0.3], dtype=torch.float64)).tolist() == [
        1,
        -1,
    ]
    assert float(buffer.score[1]) == pytest.approx(1.5 - 1.0)
    source.observe(signals([dict(env=0, seed=100, d=0.0, steps=2, finished=True, value=0.5, ret=1.0)]))
    assert float(buffer.score[0]) == pytest.approx(2.0 - 0.5)  # MaxMC keeps the highest return


def test_robust_trains_on_the_steps_of_replayed_levels_only():
    buffer = filled(4, [0.5, 0.2])
    seeds = torch.tensor([[100, 100, 9], [101, 55, 55]]).unsqueeze(-1)
    ds = torch.tensor([[0.0, 0.0, 0.7], [0.1, 0.1, 0.1]], dtype=torch.float64).unsqueeze(-1)
    rollout = TensorDict({"next": {"level_seed": seeds, "level_difficulty": ds}}, batch_size=[2, 3])
    assert source_of(buffer).trains_on(rollout).tolist() == [[True, True, False], [True, False, False]]
    assert source_of(buffer, robust=False).trains_on(rollout) is None


def test_observe_names_the_signal_it_lacks():
    rows = signals([dict(env=0, seed=5, d=0.5, steps=1, finished=True)]).exclude("advantage_positive")
    with pytest.raises(ValueError, match="needs the learner's per-step 'advantage_positive'"):
        source_of(LevelBuffer(2)).observe(rows)


# --- the regimen ---
def test_regimen_plr_composes_with_dcds_defaults_and_checks_its_range():
    cfg = compose_config(["game=zelda", "regimen=plr"])
    assert cfg.run_name == "zelda-plr-tiles-compact-seed0"
    section = cfg.regimen
    assert (section.buffer_size, section.temperature, section.staleness_coef, section.replay_prob) == (
        4000,
        0.3,
        0.3,
        0.5,
    )
    assert section.score == "pvl" and section.robust is True
    state = curriculum_run(section, "zelda").state
    assert isinstance(state, LevelBuffer) and state.capacity == 4000 and math.isnan(state.difficulty)
    assert isinstance(training_source("zelda", section, state), PrioritizedLevels)
    with pytest.raises(ConfigError, match="regimen.min_difficulty=0.8: expected at most"):
        compose_config(
            ["game=zelda", "regimen=plr", "regimen.min_difficulty=0.8", "regimen.max_difficulty=0.2"]
        )
    with pytest.raises(ConfigError, match="regimen.score='regret'"):
        compose_config(["game=zelda", "regimen=plr", "regimen.score=regret"])


@pytest.mark.parametrize("regimen", ["plr", "accel"])
def test_robust_replay_without_replays_is_refused_before_training(regimen, tmp_path, capsys):
    # robust trains on replayed levels only: with replay_prob=0 it could never take a step
    argv = [f"regimen={regimen}", "regimen.replay_prob=0", "total_frames=40", f"out_dir={tmp_path}"]
    with pytest.raises(
        ConfigError, match=r"^regimen.replay_prob=0: expected more than 0 with regimen.robust=true"
    ):
        compose_config(argv)
    assert main(["train", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "regimen.robust=false" in err
    assert not any(tmp_path.iterdir())
    compose_config([*argv, "regimen.robust=false"])  # plain PLR trains on new levels too


def test_the_env_reports_the_levels_it_replays(eager):
    cfg = compose_config(
        ["game=zelda", "regimen=plr", "regimen.buffer_size=2", "regimen.rho=0.5", "regimen.replay_prob=1.0"]
    )
    run = curriculum_run(cfg.regimen, "zelda")
    run.state.insert(42, 0.6, 1.0, 0.0)
    env = EnvFactory("zelda", cfg.regimen, 2, "tiles", 4, "cpu", seed=3, run=run)()
    out = env.reset()
    assert out["level_seed"].flatten().tolist() == [42, 42]
    assert out["level_difficulty"].flatten().tolist() == [0.6, 0.6]
    assert env.current_levels[0] == generate_level("zelda", 0.6, 42)
    env.close()


def test_it_trains_through_the_command_line_and_resumes_its_buffer(eager, tmp_path):
    from gvgai_pcg.commands.train import run_raw

    run = [*SMALL, "regimen=plr", "regimen.buffer_size=64", "regimen.rho=0.05", f"out_dir={tmp_path}"]
    assert run_raw([*run, "total_frames=200"]) == 0
    checkpoint = tmp_path / "zelda-plr-tiles-compact-seed0" / "checkpoints" / "last.pt"
    first = torch.load(checkpoint, weights_only=False)["curriculum"]
    kept = set(first["seed"][first["valid"]].tolist())
    assert kept and bool(torch.isfinite(first["score"]).all())
    assert run_raw([*run, "total_frames=400"]) == 0
    second = torch.load(checkpoint, weights_only=False)["curriculum"]
    assert kept <= set(second["seed"][second["valid"]].tolist())  # the resumed run started from it
    assert int(second["clock"][0]) > int(first["clock"][0])
