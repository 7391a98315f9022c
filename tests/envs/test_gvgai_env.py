"""GVGAIEnv: the torchrl contract, Gym reset/step semantics, partial resets and reproducibility."""

import pytest
import torch
from tensordict import TensorDict
from torchrl.envs import check_env_specs

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.games import registered_games
from gvgai_pcg.games.render import sprite_images
from gvgai_pcg.levels import Level, human_level

CLOSED_ROOM = Level("zelda", ("wwwww", "wA.gw", "wwwww"))  # no monster, no key: never ends


@pytest.mark.parametrize("game", registered_games())
@pytest.mark.parametrize("obs", ["tiles", "pixels"])
def test_specs_hold_for_every_game(game, obs):
    # eager: the specs are the env's, whatever ticks it (compiled steps are held equal to eager
    # ones in tests/engine/test_compiled.py), and compiling eight envs cost a minute of the suite
    env = GVGAIEnv(game, num_envs=3, obs=obs, max_steps=50, compile_tick=False)
    check_env_specs(env)
    td = env.reset()
    assert td.get(obs).shape[0] == 3 and td.get(obs).dtype == torch.uint8
    assert env.state.get("tick").tolist() == [0, 0, 0]  # reset runs tick 0 with NIL


@pytest.mark.parametrize("obs", ["tiles", "pixels"])
def test_step_outputs_are_as_torchrl_would_complete_them(obs):
    """The env skips TorchRL's completion of its step outputs (CompleteStepHook): they must need
    none, for every game's done entries and reward. Eager: the outputs are the env's whatever ticks
    it, and compiling every game's tick here cost over a minute of the suite."""
    from torchrl.envs import EnvBase

    for game in registered_games():
        env = GVGAIEnv(game, num_envs=3, obs=obs, max_steps=2, compile_tick=False)
        td = env.reset()
        for _ in range(3):  # through a truncation
            out = env._step(td.set("action", torch.randint(0, env.game.num_actions, (3,))))
            completed = EnvBase._step_proc_data(env, out.clone())
            assert set(completed.keys()) == set(out.keys()) and (completed == out).all()
            assert all(completed.get(key).shape == out.get(key).shape for key in out.keys())
            td = env.reset(out.set("_reset", out.get("done")))


@pytest.mark.parametrize("obs", ["tiles", "pixels"])
def test_observation_specs_hold_what_is_observed(obs):
    """Tiles are 0/1 and pixels any uint8, both under a uint8 Unbounded spec (neither Bounded nor
    Binary: see gvgai_pcg.envs.specs)."""
    env = GVGAIEnv("frogs", num_envs=8, obs=obs, seed=1)
    spec = env.observation_spec[obs]
    rollout = env.rollout(30, break_when_any_done=False)
    assert spec.is_in(rollout.get(obs)[:, -1]) and spec.is_in(rollout.get(("next", obs))[:, -1])
    if obs == "tiles":
        assert set(rollout.get(obs).unique().tolist()) == {0, 1}
        assert not spec.is_in(rollout.get(obs)[:, -1].to(torch.int16))
    else:
        assert spec.is_in(torch.full(spec.shape, 255, dtype=torch.uint8))
        assert not spec.is_in(torch.zeros(spec.shape, dtype=torch.int16))


def test_reward_is_the_score_delta_and_a_win_terminates():
    env = GVGAIEnv("zelda", levels=Level("zelda", ("wwwwww", "w+A.gw", "wwwwww")))
    env.reset()
    rewards, done = [], []
    for action in ["LEFT", "LEFT", "RIGHT", "RIGHT", "RIGHT"]:
        td = env.step(TensorDict({"action": torch.tensor([env.game.actions.index(action)])}, batch_size=[1]))
        rewards.append(td.get(("next", "reward")).item())
        done.append(td.get(("next", "done")).item())
    assert rewards == [0.0, 1.0, 0.0, 0.0, 1.0]
    assert done == [False, False, False, False, True]
    assert td.get(("next", "won")).item() and td.get(("next", "terminated")).item()
    assert not td.get(("next", "truncated")).item() and td.get(("next", "score")).item() == 2.0


def test_step_limit_truncates_exactly_at_max_steps():
    env = GVGAIEnv("zelda", levels=CLOSED_ROOM, max_steps=2000)
    td = env.reset()
    nil = torch.zeros(1, dtype=torch.int64)
    for step in range(1, 2001):
        td = env.step(td.set("action", nil)).get("next")
        assert td.get("truncated").item() == (step == 2000)
    assert td.get("done").item() and not td.get("terminated").item()


def test_partial_reset_only_touches_masked_envs():
    env = GVGAIEnv("zelda", num_envs=4, levels="human", seed=3)
    td = env.reset()
    for _ in range(12):
        td = env.step(td.set("action", torch.tensor([2, 3, 4, 5]))).get("next")
    before = [env.game.snapshot(env.state, i) for i in range(4)]
    mask = torch.tensor([[True], [False], [True], [False]])
    env.reset(TensorDict({"_reset": mask}, batch_size=[4]))
    after = [env.game.snapshot(env.state, i) for i in range(4)]
    assert after[1] == before[1] and after[3] == before[3]
    assert after[0]["tick"] == 0 and after[2]["tick"] == 0 and before[0]["tick"] == 12


def test_batched_env_equals_single_envs_across_resets():
    batched = GVGAIEnv("zelda", num_envs=4, levels="human", seed=11, max_steps=40)
    singles = [GVGAIEnv("zelda", levels="human", seed=[int(s)], max_steps=40) for s in batched.env_seeds]
    actions = torch.randint(0, 6, (120, 4), generator=torch.Generator().manual_seed(0))
    td = batched.reset()
    tds = [env.reset() for env in singles]
    for t in range(120):
        _, td = batched.step_and_maybe_reset(td.set("action", actions[t]))
        for i, env in enumerate(singles):
            _, tds[i] = env.step_and_maybe_reset(tds[i].set("action", actions[t, i : i + 1]))
            assert torch.equal(td.get("tiles")[i], tds[i].get("tiles")[0])
            assert batched.current_levels[i] == env.current_levels[0]


def test_env_seed_decides_the_trajectory():
    def trace(seed):
        env = GVGAIEnv("zelda", levels=human_level("zelda", 0), seed=seed)
        td = env.reset()
        frames = []
        for _ in range(30):
            td = env.step(td.set("action", torch.zeros(1, dtype=torch.int64))).get("next")
            frames.append(td.get("tiles").clone())
        return torch.stack(frames)

    assert torch.equal(trace(1), trace(1))
    assert not torch.equal(trace(1), trace(2))


def test_pixels_use_the_tile_art():
    env = GVGAIEnv("zelda", levels=human_level("zelda", 0), obs="pixels")
    frame = env.reset().get("pixels")[0]
    assert frame.shape == (3, 90, 130)
    wall = sprite_images(env.game.art["wall"])[0, :3, 0, 0]
    assert torch.equal(frame[:, 0, 0], wall)  # the top-left cell is a wall
    assert env.render(0).shape == (90, 130, 3)
    assert env.render(0, mode="ansi").splitlines()[1].startswith("wA")


def test_bad_arguments_are_refused_with_the_choices():
    with pytest.raises(ValueError, match="registered games are: .*zelda"):
        GVGAIEnv("pacman")
    with pytest.raises(ValueError, match="valid kinds are: tiles, pixels"):
        GVGAIEnv("zelda", obs="rgb")
    with pytest.raises(ValueError, match="env plays 'zelda'"):
        GVGAIEnv("zelda", levels=human_level("frogs", 0))


@pytest.mark.parametrize(("game", "obs"), [("solarfox", "tiles"), ("zelda", "pixels")])
def test_a_reset_of_one_env_ticked_compiled_equals_an_eager_reset(game, obs):
    """Partial resets tick through the compiled tick, a single env twice over; an eager env
    starts the same episodes."""
    from gvgai_pcg.envs.level_sources import GeneratedLevels

    compiled, eager = (
        GVGAIEnv(game, 4, GeneratedLevels(game), obs=obs, seed=3, difficulty=0.7, compile_tick=compile_tick)
        for compile_tick in (True, False)
    )
    assert compiled.step_plan.compiled_resets
    assert not eager.step_plan.compiled
    for mask in (
        [True] * 4,
        [False, False, True, False],
        [True, False, False, True],
        [False, True, False, False],
    ):
        reset = TensorDict({"_reset": torch.tensor(mask).unsqueeze(-1)}, batch_size=[4])
        outs = [env.reset(reset.clone() if not all(mask) else None) for env in (compiled, eager)]
        assert torch.equal(outs[0].get(obs), outs[1].get(obs))
        for i in range(4):
            assert compiled.game.snapshot(compiled.state, i) == eager.game.snapshot(eager.state, i)
        action = torch.tensor([1, 2, 3, 4]) % compiled.game.num_actions
        stepped = [
            env.step(out.set("action", action)) for env, out in zip((compiled, eager), outs, strict=True)
        ]
        assert torch.equal(stepped[0].get(("next", obs)), stepped[1].get(("next", obs)))


def test_a_game_with_a_reset_tick_of_its_own_keeps_it():
    assert GVGAIEnv("zelda", 4).step_plan.compiled_resets
    assert not GVGAIEnv("frogs", 4).step_plan.compiled_resets  # Frogs' reset tick is a third of its tick
    assert not GVGAIEnv("zelda", 1).step_plan.compiled_resets  # a single env never compiles
