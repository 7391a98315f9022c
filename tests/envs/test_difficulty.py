"""DifficultyTransform: the PPCG update, clipping, win rules, sharing across processes, state."""

import multiprocessing

import pytest
import torch
from tensordict import TensorDict
from torchrl.envs import TransformedEnv, check_env_specs

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.difficulty import DifficultyTransform
from gvgai_pcg.envs.level_sources import GeneratedLevels
from gvgai_pcg.levels.seeds import TEST_SEED_BASE, TRAINING_SEED_SPACE
from tests.waiting import PATIENCE_S


def test_progressive_update_follows_wins_and_losses_in_order():
    transform = DifficultyTransform("progressive", alpha=0.01)
    assert transform.update([True, True, True, False]) == pytest.approx(0.02)
    assert transform.episodes.item() == 4


def test_clipping_happens_after_every_move():
    transform = DifficultyTransform("progressive", alpha=0.25)
    # from 0: loss (stays 0), win 0.25, loss 0, loss 0, win 0.25
    assert transform.update([False, True, False, False, True]) == pytest.approx(0.25)
    transform = DifficultyTransform("progressive", alpha=0.25, start=1.0)
    assert transform.update([True, True, False]) == pytest.approx(0.75)


def test_fixed_mode_never_moves():
    transform = DifficultyTransform("fixed", start=0.5)
    assert transform.update([True] * 10 + [False]) == 0.5


def step_outcome(won, terminated, truncated, score):
    b = len(won)
    column = lambda values, dtype: torch.tensor(values, dtype=dtype).unsqueeze(-1)  # noqa: E731
    return TensorDict(
        {
            "won": column(won, torch.bool),
            "terminated": column(terminated, torch.bool),
            "truncated": column(truncated, torch.bool),
            "done": column([a or b for a, b in zip(terminated, truncated, strict=True)], torch.bool),
            "score": column(score, torch.float32),
        },
        batch_size=[b],
    )


def test_study_rule_counts_timeouts_as_wins_and_boulderdash_by_score():
    outcome = step_outcome([False, True, False], [True, True, False], [False, False, True], [25.0, 1.0, 3.0])
    game_rule = DifficultyTransform(win_rule="game", game="zelda")
    study_zelda = DifficultyTransform(win_rule="study", game="zelda")
    study_boulderdash = DifficultyTransform(win_rule="study", game="boulderdash")
    assert game_rule.wins(outcome).tolist() == [False, True, False]
    assert study_zelda.wins(outcome).tolist() == [False, True, True]
    assert study_boulderdash.wins(outcome).tolist() == [True, False, False]


def _move_in_child(transform: DifficultyTransform) -> None:
    transform.update([True] * 5)


def test_the_difficulty_is_shared_with_worker_processes():
    transform = DifficultyTransform("progressive", alpha=0.01)
    child = multiprocessing.get_context("spawn").Process(target=_move_in_child, args=(transform,))
    child.start()
    child.join(60)
    assert child.exitcode == 0
    assert transform.difficulty == pytest.approx(0.05)


def _win_many_times(transform: DifficultyTransform, times: int) -> None:
    for _ in range(times):
        transform.update([True])


def test_workers_sharing_through_files_never_lose_a_move(tmp_path):
    """Two processes moving one difficulty at once: each move reads, changes and writes it, so
    without the shared lock file one process overwrites the other's moves."""
    transform = DifficultyTransform("progressive", alpha=1e-5)
    transform.share_through(tmp_path)
    context = multiprocessing.get_context("spawn")
    children = [context.Process(target=_win_many_times, args=(transform, 6000)) for _ in range(2)]
    for child in children:
        child.start()
    for child in children:
        child.join(PATIENCE_S)
        assert child.exitcode == 0
    assert transform.episodes.item() == 12000
    assert transform.difficulty == pytest.approx(0.12)


def test_sharing_through_files_again_starts_from_the_current_values(tmp_path):
    """A resumed run shares its restored difficulty through the files of its first session."""
    first = DifficultyTransform("progressive", alpha=0.01)
    first.share_through(tmp_path)
    first.update([True] * 30)
    resumed = DifficultyTransform("progressive", alpha=0.01)
    resumed.update([True] * 12)  # as restored from its checkpoint
    resumed.share_through(tmp_path)
    assert resumed.difficulty == pytest.approx(0.12) and resumed.episodes.item() == 12


def test_state_dict_restores_the_difficulty():
    transform = DifficultyTransform("progressive")
    transform.update([True] * 7)
    restored = DifficultyTransform("progressive")
    restored.load_state_dict(transform.state_dict())
    assert restored.difficulty == pytest.approx(0.07) and restored.episodes.item() == 7


def test_env_generates_at_the_transform_difficulty():
    env = TransformedEnv(
        GVGAIEnv("zelda", num_envs=4, levels=GeneratedLevels("zelda"), max_steps=10),
        DifficultyTransform("fixed", start=0.7),
    )
    check_env_specs(env)
    rollout = env.rollout(25, break_when_any_done=False)
    difficulty = rollout.get(("next", "difficulty"))
    assert difficulty.dtype == torch.float64 and (difficulty == 0.7).all()  # exactly the config's d
    seeds = rollout.get("level_seed")
    assert ((seeds >= 0) & (seeds < TRAINING_SEED_SPACE)).all() and TRAINING_SEED_SPACE < TEST_SEED_BASE
    assert len(set(seeds.flatten().tolist())) == 12  # 4 envs x 3 episodes of 10 steps, all distinct
    assert all(level.name.startswith("zelda_d0.7_s") for level in env.base_env.current_levels)


def test_ppcg_moves_one_difficulty_for_all_envs():
    transform = DifficultyTransform("progressive", win_rule="study", game="zelda")
    env = TransformedEnv(
        GVGAIEnv("zelda", num_envs=4, levels=GeneratedLevels("zelda"), max_steps=5), transform
    )
    env.rollout(10, break_when_any_done=False)  # every episode times out: 8 study wins
    assert transform.difficulty == pytest.approx(0.08)


def test_bad_settings_are_refused():
    with pytest.raises(ValueError, match="valid modes are: fixed, progressive"):
        DifficultyTransform("linear")
    with pytest.raises(ValueError, match="valid rules are: game, study"):
        DifficultyTransform(win_rule="paper")
    with pytest.raises(ValueError, match=r"\[0, 1\]"):
        DifficultyTransform(start=1.5)


def test_ppcg_steps_land_on_the_decimals_a_log_shows():
    """0.01 added eight times is 0.08000000000000002 in floats; the transform keeps 0.08, the value
    that the log prints and the level name records, so the level can be made again from them."""
    transform = DifficultyTransform("progressive", alpha=0.01)
    transform.update([True] * 8)
    assert transform.difficulty == 0.08
    td = transform._reset_env_preprocess(TensorDict({}, batch_size=[2]))
    levels = GeneratedLevels("zelda").next_levels(
        torch.arange(2), torch.tensor([5, 6]), td.get("difficulty").reshape(-1)
    )
    assert [level.name for level in levels] == ["zelda_d0.08_s5", "zelda_d0.08_s6"]


def test_the_study_rule_needs_the_game():
    with pytest.raises(ValueError, match="give game="):
        DifficultyTransform("progressive", win_rule="study")


def test_generated_levels_take_any_registered_generator_of_the_game(monkeypatch):
    from gvgai_pcg.games import registry
    from gvgai_pcg.generators import generate_level, register_generator

    monkeypatch.setattr(registry, "_GENERATORS", dict(registry._GENERATORS))  # forget the plugin after

    @register_generator("zelda-mirrored")
    def mirrored(difficulty: float, seed: int):
        level = generate_level("zelda", difficulty, seed)
        return type(level)(level.game, tuple(row[::-1] for row in level.rows), name=f"mirrored_s{seed}")

    source = GeneratedLevels("zelda", generator="zelda-mirrored")
    half = torch.tensor([0.5], dtype=torch.float64)
    level = source.next_levels(torch.arange(1), torch.tensor([3]), half)[0]
    assert level.rows == tuple(row[::-1] for row in generate_level("zelda", 0.5, 3).rows)
    with pytest.raises(ValueError, match="made a zelda level, not a frogs level"):
        GeneratedLevels("frogs", generator="zelda-mirrored").next_levels(
            torch.arange(1), torch.tensor([3]), half
        )
    with pytest.raises(ValueError, match="registered generators are"):
        GeneratedLevels("zelda", generator="no-such-generator")
