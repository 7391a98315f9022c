"""Next episodes prepared ahead: the same trajectories as resetting each env on its own turn,
with the reset ticks of many resets run in one batch."""

import pytest
import torch

from gvgai_pcg.envs import GVGAIEnv, gvgai_env
from gvgai_pcg.envs.level_sources import GeneratedLevels
from gvgai_pcg.levels import human_levels


def rollout(env: GVGAIEnv, steps: int, seed: int = 0) -> list[dict]:
    """Every step's output of ``env`` under random actions, with partial resets as a collector does."""
    generator = torch.Generator().manual_seed(seed)
    td = env.reset()
    outputs = []
    for _ in range(steps):
        action = torch.randint(0, env.game.num_actions, (env.num_envs,), generator=generator)
        stepped, td = env.step_and_maybe_reset(td.set("action", action))
        outputs.append(
            {
                "next": stepped.get("next").exclude("action").clone(),
                "root": td.exclude("action").clone(),  # after the partial resets
                "levels": env.current_levels,
            }
        )
    return outputs


def count_prepared(env: GVGAIEnv, observed: list[bool] | None = None) -> list[int]:
    """Record the batch size of every call that prepares episodes (compiles and reset-ticks), and
    into ``observed`` whether it rendered them (a reset's own envs) or not (prepared ahead)."""
    sizes = []
    prepare = env._prepare

    def counted(index, observe):
        sizes.append(len(index))
        if observed is not None:
            observed.append(observe)
        return prepare(index, observe)

    env._prepare = counted
    return sizes


@pytest.mark.parametrize("game", ["frogs", "zelda"])
def test_prepared_episodes_give_the_same_trajectories(game):
    ahead = GVGAIEnv(game, num_envs=24, levels="human", seed=5, max_steps=60)
    plain = GVGAIEnv(game, num_envs=24, levels="human", seed=5, max_steps=60)
    plain._ready = None  # every reset compiles and ticks its own envs
    assert ahead._ready is not None
    ahead_sizes, plain_sizes = count_prepared(ahead), count_prepared(plain)
    for got, want in zip(rollout(ahead, 150), rollout(plain, 150), strict=True):
        assert (got["next"] == want["next"]).all() and (got["root"] == want["root"]).all()
        assert got["levels"] == want["levels"]
    assert len(plain_sizes) > 10  # many steps ended episodes...
    assert len(ahead_sizes) < len(plain_sizes) / 1.5  # ...whose reset ticks ran in fewer batches
    assert sum(ahead_sizes) <= sum(plain_sizes) + 2 * 24  # at most the episodes prepared but not reached


def test_large_resets_tick_their_own_envs_and_both_kinds_mix(monkeypatch):
    monkeypatch.setattr(gvgai_env, "PREPARED_RESETS_MAX", 2)  # resets of 3+ envs tick their own
    mixed = GVGAIEnv("frogs", num_envs=16, levels="human", seed=7, max_steps=40)
    plain = GVGAIEnv("frogs", num_envs=16, levels="human", seed=7, max_steps=40)
    plain._ready = None
    observed = []
    sizes = count_prepared(mixed, observed)
    for got, want in zip(rollout(mixed, 120), rollout(plain, 120), strict=True):
        assert (got["root"] == want["root"]).all() and got["levels"] == want["levels"]
    own = [size for size, rendered in zip(sizes[1:], observed[1:], strict=True) if rendered]
    assert own and min(own) > 2  # the resets of 3+ envs ticked their own envs...
    assert not all(observed[1:])  # ...and smaller ones took episodes prepared ahead


def test_a_new_seed_drops_the_prepared_episodes():
    env = GVGAIEnv("frogs", num_envs=8, levels="human", seed=1, max_steps=30)
    rollout(env, 40)  # prepares episodes under seed 1
    env.set_seed(2)
    fresh = GVGAIEnv("frogs", num_envs=8, levels="human", seed=2, max_steps=30)
    for got, want in zip(rollout(env, 40), rollout(fresh, 40), strict=True):
        assert (got["root"] == want["root"]).all()


def test_sources_that_read_the_difficulty_are_not_prepared_ahead():
    assert GVGAIEnv("zelda", num_envs=2, levels=GeneratedLevels("zelda"))._ready is None
    assert GVGAIEnv("zelda", num_envs=2, levels=list(human_levels("zelda")[:2]))._ready is not None
