"""Curricula behind the Gymnasium API: a learning curriculum (the toy of ``tests/curricula``,
registered from outside) gets the level, return, win and length of every finished episode, and
the curricula that need a learner (PLR⊥, ACCEL: value estimates; SFL: the policy) are refused by
name, in one line."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from tensordict import TensorDict

from gvgai_pcg.curricula import register_curriculum, registry
from gvgai_pcg.curricula.signals import EpisodeOutcomes
from gvgai_pcg.gym.adapter import GVGAIGymEnv
from gvgai_pcg.gym.vector import GVGAIVectorEnv
from tests.curricula import toy_curriculum


@pytest.fixture
def toy(monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")
    register_curriculum(toy_curriculum.CURRICULUM)
    yield toy_curriculum.CURRICULUM
    registry.unregister_curriculum("toyreplay")


@pytest.mark.parametrize(
    ("regimen", "needs"),
    [("plr", "value estimates"), ("accel", "value estimates"), ("sfl", "the learner's policy")],
)
def test_a_curriculum_that_needs_a_learner_is_refused_by_name(regimen, needs):
    for make in (lambda: GVGAIGymEnv("zelda", regimen=regimen), lambda: GVGAIVectorEnv(2, "zelda", regimen)):
        with pytest.raises(ValueError) as error:
            make()
        message = str(error.value)
        assert message.startswith(f"regimen {regimen!r} needs ") and needs in message
        assert f"gvgai-pcg train regimen={regimen}" in message and "\n" not in message


def recording(env) -> list[TensorDict]:
    """The rows the env's level source is given (and still gets)."""
    rows, run = [], env.regimen.run
    observe = run.observe
    run.observe = lambda signals: rows.append(signals.clone()) or observe(signals)
    return rows


def test_the_vector_env_tells_a_learning_curriculum_each_finished_episode(toy):
    env = GVGAIVectorEnv(3, "zelda", "toyreplay", max_steps=4)
    rows = recording(env)
    env.reset(seed=1)
    returns, lengths, ended = np.zeros(3), np.zeros(3, dtype=int), []
    restarting = np.zeros(3, dtype=bool)
    for _ in range(11):  # NEXT_STEP: the step after an end restarts the env
        _, reward, terminated, truncated, info = env.step(env.action_space.sample())
        returns += np.where(restarting, 0.0, reward)
        lengths += ~restarting
        restarting = terminated | truncated
        for i in np.flatnonzero(restarting):
            ended.append(
                (i, float(returns[i]), int(lengths[i]), bool(info["won"][i]), int(info["level_seed"][i]))
            )
            returns[i], lengths[i] = 0.0, 0
    told = [
        (int(r["env"]), float(r["return"]), int(r["length"]), bool(r["won"]), int(r["level_seed"]))
        for batch in rows
        for r in batch.unbind(0)
    ]
    assert len(ended) >= 6 and sorted(told) == sorted(ended)
    assert all(
        bool(batch["finished"].all()) and torch.equal(batch["steps"], batch["length"]) for batch in rows
    )
    # the toy learnt from them: its shared counts are the finished episodes per pool level
    counts = env.regimen.source.source.state.finished
    assert int(counts.sum()) == len(ended)
    assert counts.tolist() == np.bincount([e[4] for e in ended], minlength=len(counts)).tolist()


def test_the_single_env_tells_it_too_and_a_reset_restarts_the_count(toy):
    env = GVGAIGymEnv("zelda", regimen="toyreplay", max_steps=5)
    rows = recording(env)
    env.reset(seed=2)
    env.step(0)
    env.step(0)
    env.reset()  # the episode is abandoned: it is no finished episode, and its steps are not counted
    steps = 0
    while True:
        _, _, terminated, truncated, _ = env.step(0)
        steps += 1
        if terminated or truncated:
            break
    assert len(rows) == 1 and rows[0]["length"].tolist() == [steps] and steps <= 5


def test_episode_outcomes_leave_restarting_envs_out():
    outcomes = EpisodeOutcomes(2)
    step = TensorDict(
        {
            "reward": torch.tensor([[1.0], [5.0]]),
            "done": torch.tensor([[False], [True]]),
            "won": torch.tensor([[False], [True]]),
            "level_seed": torch.tensor([[3], [4]]),
            "level_difficulty": torch.tensor([[0.5], [0.25]], dtype=torch.float64),
        },
        batch_size=[2],
    )
    assert (
        outcomes(step, torch.tensor([True, False])) is None
    )  # env 1 restarts: its done is the last episode's
    rows = outcomes(step, torch.tensor([True, True]))
    assert rows["env"].tolist() == [1] and rows["return"].tolist() == [5.0] and rows["length"].tolist() == [1]
    assert rows["won"].tolist() == [True] and rows["level_difficulty"].tolist() == [0.25]
