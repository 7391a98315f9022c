"""The Gymnasium adapter: API conformance, the same steps as the TorchRL env, reset options."""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest
import torch
from gymnasium.utils.env_checker import check_env

import gvgai_pcg.envs.gym_registration  # noqa: F401  (registers the ids)
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.gym.adapter import GVGAIGymEnv
from gvgai_pcg.levels import Level, human_level

GAMES = {"Zelda": "zelda", "Solarfox": "solarfox", "Frogs": "frogs", "Boulderdash": "boulderdash"}


@pytest.mark.parametrize("obs", ["tiles", "pixels"])
@pytest.mark.parametrize("name", sorted(GAMES))
def test_check_env_passes_without_warnings(name: str, obs: str) -> None:
    env = gym.make(f"gvgai_pcg/{name}-v0", obs=obs)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped)
    assert env.unwrapped.engine.game.name == GAMES[name]


def test_info_and_spaces() -> None:
    env = gym.make("gvgai_pcg/Zelda-v0", regimen="lv", level=2)
    obs, info = env.reset(seed=3)
    assert obs.shape == (9, 9, 13) and obs.dtype == np.uint8
    assert env.action_space.n == 6
    assert set(info) == {"won", "score", "difficulty", "level_seed", "level_name"}
    assert info["level_name"] == "zelda_lvl2" and info["level_seed"] == -1


def test_single_env_steps_like_the_torchrl_env() -> None:
    gym_env = GVGAIGymEnv("frogs", regimen="human")
    torch_env = GVGAIEnv("frogs", 1, levels="human", seed=11)
    obs, _ = gym_env.reset(seed=11)
    td = torch_env.reset()
    np.testing.assert_array_equal(obs, td["tiles"][0].numpy())
    actions = np.random.default_rng(0).integers(0, gym_env.action_space.n, size=40)
    for action in actions:
        obs, reward, terminated, truncated, info = gym_env.step(int(action))
        td = torch_env.step(td.set("action", torch.tensor([int(action)])))["next"]
        np.testing.assert_array_equal(obs, td["tiles"][0].numpy())
        assert reward == float(td["reward"][0, 0]) and info["score"] == float(td["score"][0, 0])
        assert terminated == bool(td["terminated"][0, 0]) and truncated == bool(td["truncated"][0, 0])
        if terminated or truncated:
            break


def test_vector_env_same_step_equals_torchrl_step_and_maybe_reset() -> None:
    """Short episodes (max_steps=7) so that many partial resets happen inside the 30 steps."""
    n, seed = 5, 4
    vec = gym.make_vec(
        "gvgai_pcg/Zelda-v0", num_envs=n, max_steps=7, autoreset_mode=gym.vector.AutoresetMode.SAME_STEP
    )
    torch_env = GVGAIEnv("zelda", n, levels="human", max_steps=7, seed=seed)
    obs, info = vec.reset(seed=seed)
    td = torch_env.reset()
    np.testing.assert_array_equal(obs, td["tiles"].numpy())
    rng = np.random.default_rng(1)
    for _ in range(30):
        actions = rng.integers(0, 6, size=n)
        obs, reward, terminated, truncated, info = vec.step(actions)
        stepped, td = torch_env.step_and_maybe_reset(td.set("action", torch.as_tensor(actions)))
        nxt = stepped["next"]
        np.testing.assert_array_equal(reward, nxt["reward"].reshape(n).numpy())
        np.testing.assert_array_equal(terminated, nxt["terminated"].reshape(n).numpy())
        np.testing.assert_array_equal(truncated, nxt["truncated"].reshape(n).numpy())
        np.testing.assert_array_equal(obs, td["tiles"].numpy())  # after the reset, like the vector env
        done = nxt["done"].reshape(n).numpy()
        if done.any():
            np.testing.assert_array_equal(info["_final_obs"], done)
            for i in np.flatnonzero(done):
                np.testing.assert_array_equal(info["final_obs"][i], nxt["tiles"][i].numpy())


def test_vector_env_next_step_returns_the_new_episode_one_step_later() -> None:
    n = 3
    vec = gym.make_vec("gvgai_pcg/Solarfox-v0", num_envs=n, max_steps=4)
    torch_env = GVGAIEnv("solarfox", n, levels="human", max_steps=4, seed=9)
    vec.reset(seed=9)
    td = torch_env.reset()
    for _ in range(4):
        obs, reward, terminated, truncated, _ = vec.step(np.zeros(n, dtype=np.int64))
        _, td = torch_env.step_and_maybe_reset(td.set("action", torch.zeros(n, dtype=torch.int64)))
    assert truncated.all() or (terminated | truncated).all()
    obs, reward, terminated, truncated, _ = vec.step(np.zeros(n, dtype=np.int64))
    np.testing.assert_array_equal(obs, td["tiles"].numpy())  # the new episodes' first observations
    assert (reward == 0).all() and not terminated.any() and not truncated.any()


def test_reset_level_option_loads_that_level_for_one_episode(tmp_path) -> None:
    env = GVGAIGymEnv("zelda", regimen="lv", level=0)
    reference = GVGAIGymEnv("zelda", regimen="lv", level=3)
    expected, _ = reference.reset(seed=0)
    path = tmp_path / "mine.txt"
    path.write_text(str(human_level("zelda", 3)))
    for spec in ("zelda_lvl3", human_level("zelda", 3), str(path), 3):
        obs, info = env.reset(seed=0, options={"level": spec})
        np.testing.assert_array_equal(obs, expected)
        assert env.unwrapped.engine.current_levels[0] == human_level("zelda", 3)
    _, info = env.reset()
    assert info["level_name"] == "zelda_lvl0"  # back to the regimen


def test_reset_level_option_refuses_another_games_level() -> None:
    env = GVGAIGymEnv("zelda")
    with pytest.raises(ValueError, match="frogs level"):
        env.reset(options={"level": human_level("frogs", 0)})


def test_difficulty_option_generates_at_that_difficulty() -> None:
    env = GVGAIGymEnv("boulderdash", regimen="pcg", difficulty=0.2)
    _, info = env.reset(seed=1)
    assert info["difficulty"] == pytest.approx(0.2) and info["level_seed"] >= 0
    _, info = env.reset(options={"difficulty": 0.9})
    assert info["difficulty"] == pytest.approx(0.9)
    with pytest.raises(ValueError, match="plays human levels"):
        GVGAIGymEnv("zelda", regimen="lv0-3").reset(options={"difficulty": 0.5})


def test_ppcg_moves_the_difficulty_once_per_finished_episode() -> None:
    """Under the study's rule a timeout is a win, so each truncated episode raises d by alpha."""
    env = GVGAIGymEnv("zelda", regimen="ppcg", difficulty=0.3, alpha=0.1, win_rule="study", max_steps=2)
    env.reset(seed=0)
    for expected in (0.4, 0.5):
        truncated = False
        while not truncated:
            *_, truncated, _ = env.step(0)
        _, info = env.reset()
        assert info["difficulty"] == pytest.approx(expected)


def test_render_modes() -> None:
    env = GVGAIGymEnv("zelda", render_mode="rgb_array")
    env.reset(seed=0)
    assert env.render().shape == (90, 130, 3)
    text_env = GVGAIGymEnv("zelda", render_mode="ansi")
    text_env.reset(seed=0)
    assert text_env.render().count("\n") == 9
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=2, render_mode="rgb_array")
    vec.reset(seed=0)
    assert [frame.shape for frame in vec.render()] == [(90, 130, 3)] * 2


def test_unknown_regimen_lists_the_valid_ones() -> None:
    with pytest.raises(ValueError, match="valid regimens are: lv, lv0-3, human, levels, pcg, ppcg"):
        GVGAIGymEnv("zelda", regimen="random")


def test_vector_env_partial_reset_mask() -> None:
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=2, regimen="lv", level=1)
    vec.reset(seed=0)
    for _ in range(3):
        obs, *_ = vec.step(np.array([3, 3]))
    fresh, _ = vec.reset(options={"reset_mask": np.array([True, False])})
    start, _ = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=2, regimen="lv", level=1).reset(seed=0)
    avatar = 4  # zelda's "nokey" channel
    assert not np.array_equal(obs[0, avatar], start[0, avatar])  # env 0 walked away...
    np.testing.assert_array_equal(fresh[0, avatar], start[0, avatar])  # ...and is back at the start
    np.testing.assert_array_equal(fresh[1], obs[1])  # env 1 was left alone


@pytest.mark.parametrize("mode", ["NextStep", "SameStep"])
def test_vector_env_autoresets_raise_no_torchrl_warnings(mode: str) -> None:
    """A NEXT_STEP reset leaves the envs that finished in the same step done; TorchRL warns about
    done envs a partial reset was not shown, so the vector env shows them."""
    vec = gym.make_vec("gvgai_pcg/Frogs-v0", num_envs=64, autoreset_mode=gym.vector.AutoresetMode(mode))
    vec.reset(seed=0)
    rng = np.random.default_rng(0)
    finished = 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for _ in range(20):
            _, _, terminated, truncated, _ = vec.step(rng.integers(0, 5, 64))
            finished += int((terminated | truncated).sum())
    assert finished > 64  # Frogs under random play: many partial resets


@pytest.mark.parametrize("actions", [[0, 6, 0], [0, -1, 0], [0.7, 1.9, 0.0], [0, 9, 0], [0, 0]])
def test_vector_env_refuses_invalid_actions_and_goes_on(actions) -> None:
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=3)
    vec.reset(seed=0)
    with pytest.raises(ValueError, match="invalid actions"):
        vec.step(np.array(actions))
    vec.step(np.zeros(3, dtype=np.int64))  # the env is untouched


@pytest.mark.parametrize("mask", [[True], True, [1, 0], [True, False, True]])
def test_vector_env_refuses_a_malformed_reset_mask(mask) -> None:
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=2)
    vec.reset(seed=0)
    with pytest.raises(ValueError, match="reset_mask must be 2 booleans"):
        vec.reset(options={"reset_mask": np.array(mask)})


def test_single_env_refuses_a_reset_mask() -> None:
    env = GVGAIGymEnv("zelda")
    with pytest.raises(ValueError, match="valid options are: level, difficulty$"):
        env.reset(options={"reset_mask": [False]})


def test_a_reset_refused_for_a_bad_option_changes_nothing() -> None:
    env = GVGAIGymEnv("zelda", regimen="ppcg")
    with pytest.raises(ValueError, match="level"):
        env.reset(seed=3, options={"difficulty": 0.7, "level": "zelda_lvl9"})
    assert env.regimen.difficulty == 0.0
    with pytest.raises(RuntimeError, match="reset"):
        env.step(0)  # still not started
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=2, regimen="ppcg")
    vec.reset(seed=0)
    with pytest.raises(ValueError, match="reset_mask"):
        vec.reset(options={"difficulty": 0.3, "reset_mask": np.array([True])})
    assert vec.unwrapped.regimen.difficulty == 0.0


def test_a_level_set_of_your_own(tmp_path) -> None:
    (tmp_path / "one.txt").write_text("wwwwww\nwA.+gw\nwwwwww\n")
    (tmp_path / "two.txt").write_text("wwwwww\nwAg.+w\nwwwwww\n")
    env = gym.make("gvgai_pcg/Zelda-v0", regimen="levels", levels=str(tmp_path))
    names = {env.reset(seed=seed)[1]["level_name"] for seed in range(12)}
    assert names == {"one", "two"}
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=3, regimen="levels", levels=[tmp_path / "two.txt"])
    vec.reset(seed=0)
    assert {lv.name for lv in vec.unwrapped.engine.current_levels} == {"two"}
    with pytest.raises(ValueError, match="levels= gives the set of regimen='levels'"):
        GVGAIGymEnv("zelda", regimen="lv", levels=str(tmp_path))


def test_a_fixed_set_of_generated_levels() -> None:
    env = gym.make("gvgai_pcg/Frogs-v0", regimen="pcg", difficulty=0.5, num_levels=2, start_seed=5)
    seeds = {env.reset(seed=seed)[1]["level_seed"] for seed in range(12)}
    assert seeds == {5, 6}
    with pytest.raises(ValueError, match="keeps the difficulty it was made at"):
        env.reset(options={"difficulty": 0.9})
    with pytest.raises(ValueError, match="num_levels and start_seed are for regimen='pcg'"):
        GVGAIGymEnv("frogs", regimen="ppcg", num_levels=3)


@pytest.mark.parametrize("ending", ["terminated", "truncated"])
def test_a_step_after_the_episode_ended_is_refused_until_reset(ending) -> None:
    # the key is one tile left and the goal two tiles right (a turn costs a step): LEFT x2,
    # RIGHT x3 wins (terminated); two steps of NIL reach the step limit (truncated)
    level = Level("zelda", ("wwwwww", "w+A.gw", "wwwwww"))
    env = GVGAIGymEnv("zelda", regimen="lv", level=level, max_steps=2 if ending == "truncated" else 50)
    env.reset(seed=0)
    actions = ["NIL", "NIL"] if ending == "truncated" else ["LEFT", "LEFT", "RIGHT", "RIGHT", "RIGHT"]
    for action in actions:
        obs, _, terminated, truncated, _ = env.step(env.action_names.index(action))
    assert (terminated, truncated) == (ending == "terminated", ending == "truncated")
    difficulty = env.regimen.difficulty
    with pytest.raises(RuntimeError, match=f"episode has ended \\({ending}\\); call reset\\(\\)"):
        env.step(0)
    assert env.regimen.difficulty == difficulty
    env.reset()
    env.step(0)  # a new episode steps again


def test_vector_env_takes_a_difficulty_per_env_for_the_resetting_envs() -> None:
    vec = gym.make_vec("gvgai_pcg/Boulderdash-v0", num_envs=4, regimen="pcg", difficulty=0.2)
    _, info = vec.reset(seed=0, options={"difficulty": [0.1, 0.3, 0.5, 0.9]})
    np.testing.assert_allclose(info["difficulty"], [0.1, 0.3, 0.5, 0.9])
    levels = vec.unwrapped.engine.current_levels
    assert [lv.name.split("_")[1] for lv in levels] == ["d0.1", "d0.3", "d0.5", "d0.9"]  # made at each d
    _, info = vec.reset(
        options={"difficulty": np.array([0.7] * 4), "reset_mask": np.array([1, 0, 0, 0], bool)}
    )
    np.testing.assert_allclose(info["difficulty"], [0.7, 0.3, 0.5, 0.9])  # only env 0 took its entry
    _, info = vec.reset(options={"difficulty": 0.6})  # one number: every env from now on
    np.testing.assert_allclose(info["difficulty"], [0.6] * 4)


def test_vector_env_takes_a_level_per_env_for_this_episode() -> None:
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=4, regimen="lv", level=0)
    vec.reset(seed=0, options={"level": [human_level("zelda", i) for i in (1, 2, 3, 4)]})
    assert [lv.name for lv in vec.unwrapped.engine.current_levels] == [f"zelda_lvl{i}" for i in (1, 2, 3, 4)]
    vec.reset(options={"level": [None, "zelda_lvl3", 2, None], "reset_mask": np.array([1, 1, 0, 1], bool)})
    names = [lv.name for lv in vec.unwrapped.engine.current_levels]
    assert names == ["zelda_lvl0", "zelda_lvl3", "zelda_lvl3", "zelda_lvl0"]  # None: the regimen's level


@pytest.mark.parametrize(
    ("regimen", "options", "says"),
    [
        (
            "pcg",
            {"difficulty": [0.1, 0.2]},
            "one value for every env, or a list of 3 \\(one per env\\); got 2",
        ),
        (
            "pcg",
            {"difficulty": "hard"},
            "expected a number in \\[0, 1\\] for every env, or a list of 3 numbers",
        ),
        ("pcg", {"difficulty": [0.1, None, 0.2]}, "expected a number in \\[0, 1\\] for every env"),
        (
            "ppcg",
            {"difficulty": [0.1, 0.3, 0.9]},
            "'ppcg' moves one difficulty for every env, so it takes one",
        ),
        ("human", {"level": ["zelda_lvl1"] * 4}, "a list of 3 \\(one per env\\); got 4 values"),
        (
            "human",
            {"level": {"name": "zelda_lvl1"}},
            "expected a Level, a human level index, a zelda level name",
        ),
        ("human", {"level": "w" * 400}, "is neither a zelda level name"),
    ],
)
def test_vector_env_refuses_a_malformed_per_env_option_in_one_line(regimen, options, says) -> None:
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=3, regimen=regimen)
    vec.reset(seed=0)
    with pytest.raises(ValueError, match=says) as refused:
        vec.reset(options=options)
    assert "\n" not in str(refused.value) and len(str(refused.value)) < 250


def test_a_short_gymnasium_job_ticks_eagerly_and_a_long_one_compiled(monkeypatch) -> None:
    """The decision of ``gvgai-pcg train``: compiling pays back only past COMPILE_PAYS_BACK_STEPS."""
    from gvgai_pcg.engine.step_plan import COMPILE_PAYS_BACK_STEPS

    monkeypatch.delenv("GVGAI_PCG_COMPILE", raising=False)
    assert not gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=8).unwrapped.engine.step_plan.compiled
    short = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=8, total_steps=COMPILE_PAYS_BACK_STEPS - 1)
    assert not short.unwrapped.engine.step_plan.compiled
    long = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=8, total_steps=COMPILE_PAYS_BACK_STEPS)
    assert long.unwrapped.engine.step_plan.compiled  # made, not stepped: nothing is compiled here
    with pytest.raises(ValueError, match="total_steps must be a whole number >= 0"):
        gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=8, total_steps=-1)


def test_a_job_that_did_not_give_its_length_is_told_once_when_it_is_long(monkeypatch) -> None:
    monkeypatch.delenv("GVGAI_PCG_COMPILE", raising=False)
    monkeypatch.setattr("gvgai_pcg.gym.vector.COMPILE_PAYS_BACK_STEPS", 3)
    vec = gym.make_vec("gvgai_pcg/Zelda-v0", num_envs=2)
    vec.reset(seed=0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(5):
            vec.step(np.zeros(2, dtype=np.int64))
    told = [str(w.message) for w in caught if "total_steps" in str(w.message)]
    assert len(told) == 1 and "stepped 3 times with the tick eager" in told[0]
