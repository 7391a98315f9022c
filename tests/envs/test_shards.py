"""A sharded step (slices of the batch on several threads) gives exactly an unsharded step."""

import pytest
import torch

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.shards import ShardedStepper
from gvgai_pcg.games import get_game
from gvgai_pcg.levels import human_levels


@pytest.mark.parametrize("game", ["zelda", "solarfox", "frogs", "boulderdash"])
def test_sharded_steps_equal_unsharded_steps_across_resets(game):
    envs = [GVGAIEnv(game, num_envs=7, levels="human", seed=3, shards=shards) for shards in (1, 3)]
    assert [len(env._runner.sharded.slices(7)) for env in envs] == [1, 3]
    tds = [env.reset() for env in envs]
    generator = torch.Generator().manual_seed(0)
    for _ in range(60):
        action = torch.randint(0, envs[0].game.num_actions, (7,), generator=generator)
        outs = []
        for i, env in enumerate(envs):
            tds[i].set("action", action.clone())
            stepped, tds[i] = env.step_and_maybe_reset(tds[i])
            outs.append(stepped)
        assert (outs[0] == outs[1]).all()
        assert (envs[0].state == envs[1].state).all()


def test_shards_cover_the_batch_in_order_one_env_at_least_each():
    stepper = ShardedStepper(3)
    assert [(s.start, s.stop) for s in stepper.slices(10)] == [(0, 3), (3, 6), (6, 10)]
    assert [(s.start, s.stop) for s in stepper.slices(2)] == [(0, 1), (1, 2)]
    assert [(s.start, s.stop) for s in stepper.slices(1)] == [(0, 1)]


def test_the_callers_torch_threads_are_restored():
    threads = torch.get_num_threads()
    env = GVGAIEnv("zelda", num_envs=4, shards=2)
    td = env.reset()
    td.set("action", torch.zeros(4, dtype=torch.int64))
    env.step(td)
    assert torch.get_num_threads() == threads


def test_an_env_steps_whole_unless_asked_for_shards():
    assert len(GVGAIEnv("zelda", num_envs=4096)._runner.sharded.slices(4096)) == 1


def test_shards_must_be_positive():
    with pytest.raises(ValueError, match="at least 1"):
        ShardedStepper(0)


def assert_no_shared_memory(state) -> None:
    owners: dict[int, object] = {}
    for key, value in state.items(True, True):
        if value.numel():
            assert owners.setdefault(value.untyped_storage().data_ptr(), key) == key


@pytest.mark.parametrize("game", ["zelda", "solarfox", "frogs", "boulderdash"])
def test_no_two_state_entries_share_memory(game):
    """A shard writes its replaced entries back into the full state (after a step, and the fresh
    states after a reset tick), so no entry may alias another: not as compiled, nor after a reset."""
    levels = list(human_levels(game))
    assert_no_shared_memory(get_game(game).compile(levels, torch.arange(5), torch.device("cpu")))
    env = GVGAIEnv(game, num_envs=5, levels="human")
    env.reset()
    assert_no_shared_memory(env.state)
