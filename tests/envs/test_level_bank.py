"""The bank of compiled recurring levels: the same states as compiling, each level compiled once."""

import pytest
import torch

from gvgai_pcg.curricula import get_curriculum
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.level_bank import CompiledLevelBank
from gvgai_pcg.games import get_game
from gvgai_pcg.games.base import pad_level
from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels import human_levels


def bank(game: str, capacity: int = 8) -> CompiledLevelBank:
    levels = human_levels(game)
    height, width = max(lv.height for lv in levels), max(lv.width for lv in levels)
    return CompiledLevelBank(get_game(game), height, width, torch.device("cpu"), capacity)


def test_banked_states_equal_compiled_states():
    store = bank("frogs")  # level 4 is padded to the others' size
    levels = [human_levels("frogs")[i] for i in (4, 0, 4, 2, 1, 3)]
    seeds = torch.arange(6) * 7
    got = store.initial_states(levels, seeds)
    game = get_game("frogs")
    padded = [pad_level(lv, 11, 28) for lv in levels]
    want = game.compile(padded, seeds, torch.device("cpu"))
    for state in (got, want):
        game.tick(state, torch.zeros(6, dtype=torch.int64))
    for index in range(6):
        assert game.snapshot(got, index) == game.snapshot(want, index)


def test_each_level_is_compiled_once(monkeypatch):
    store = bank("zelda")
    calls = []
    game = store.game
    compile_level = game.compile
    monkeypatch.setattr(game, "compile", lambda *a: calls.append(1) or compile_level(*a))
    levels = human_levels("zelda")
    for _ in range(3):
        store.initial_states([levels[0], levels[1], levels[0]], torch.zeros(3, dtype=torch.int64))
    assert len(calls) == 2


def test_the_least_recently_used_level_goes_first():
    store = bank("zelda", capacity=2)
    a, b, c = human_levels("zelda")[:3]
    zero = torch.zeros(1, dtype=torch.int64)
    store.initial_states([a], zero)
    store.initial_states([b], zero)
    store.initial_states([a], zero)
    store.initial_states([c], zero)  # evicts b, used longest ago
    assert set(store._rows) == {a, c}
    assert len(store) == 2


def test_a_reset_that_needs_more_levels_than_the_capacity_keeps_them_all():
    store = bank("zelda", capacity=2)
    levels = human_levels("zelda")
    states = store.initial_states(levels, torch.arange(5))
    assert states.batch_size[0] == 5 and len(store) == 5


def test_small_partial_resets_of_recurring_levels_compile_nothing(monkeypatch):
    from tensordict import TensorDict

    from gvgai_pcg.envs import GVGAIEnv

    # eager: "compile" here is the level's (its parse into a state), and banked levels start with
    # their reset tick, which a compiled tick would compile anew for each batch of new levels
    env = GVGAIEnv("zelda", num_envs=10, levels="human", seed=0, compile_tick=False)
    env.reset()
    calls = []
    compile_level = env.game.compile
    monkeypatch.setattr(env.game, "compile", lambda *a: calls.append(1) or compile_level(*a))
    for rows in ([0, 1], [2, 3, 4], [5]):
        mask = torch.zeros(10, dtype=torch.bool)
        mask[rows] = True
        env.reset(TensorDict({"_reset": mask}, batch_size=[10]))
    assert calls == []


def test_generated_levels_do_not_go_through_the_bank():
    from tensordict import TensorDict

    from gvgai_pcg.envs import GVGAIEnv
    from gvgai_pcg.envs.level_sources import GeneratedLevels

    env = GVGAIEnv("frogs", num_envs=6, levels=GeneratedLevels("frogs"), seed=0)
    env.reset()
    for rows in ([0], [2, 3], [5]):  # small partial resets, each of levels never seen before
        mask = torch.zeros(6, dtype=torch.bool)
        mask[rows] = True
        env.reset(TensorDict({"_reset": mask}, batch_size=[6]))
    assert len(env._bank) == 0  # a level comes back once in 2**31 episodes: banking it only churns


def test_adding_a_level_to_a_full_bank_does_not_rebuild_it(monkeypatch):
    import gvgai_pcg.envs.level_bank as level_bank

    store = bank("zelda", capacity=3)
    a, b, c, d = human_levels("zelda")[:4]
    zero = torch.zeros(1, dtype=torch.int64)
    for level in (a, b, c):
        store.initial_states([level], zero)
    joined = []
    concatenate = level_bank.concatenate_states
    monkeypatch.setattr(
        level_bank, "concatenate_states", lambda states: joined.append(len(states)) or concatenate(states)
    )
    got = store.initial_states([d, b], torch.tensor([5, 6]))  # d comes in, a (used longest ago) goes
    assert joined == [2]  # the kept rows and the one new level, not every level again
    assert set(store._rows) == {b, c, d}
    game = store.game
    padded = [pad_level(lv, store.height, store.width) for lv in (d, b)]
    want = game.compile(padded, torch.tensor([5, 6]), torch.device("cpu"))
    for state in (got, want):
        game.tick(state, torch.zeros(2, dtype=torch.int64))
    assert [game.snapshot(got, i) for i in range(2)] == [game.snapshot(want, i) for i in range(2)]


def plr_source(game: str):
    """A PLR⊥ source over a full buffer of 12 generated levels, replaying them only."""
    section = {"name": "plr", "buffer_size": 12, "replay_prob": 1.0, "temperature": 1.0}
    run = get_curriculum("plr").start(game, section)
    for i in range(12):
        run.state.insert(7 + i, (i % 4) / 4, float(i), 0.0)
    return run.source()


@pytest.mark.parametrize(("levels", "obs"), [("human", "tiles"), ("plr", "tiles"), ("plr", "pixels")])
def test_levels_banked_started_give_the_episodes_their_reset_tick_gives(levels, obs, monkeypatch):
    if obs == "pixels":  # observations too large to keep: a reset draws them
        monkeypatch.setattr("gvgai_pcg.envs.level_bank.OBSERVATIONS_MAX_BYTES", 0)

    def rollout(banked_started: bool) -> list:
        source = plr_source("zelda") if levels == "plr" else levels
        env = GVGAIEnv("zelda", 5, levels=source, obs=obs, max_steps=40, seed=4, compile_tick=False)
        if not banked_started:  # every reset compiles its levels and runs its own reset tick
            env.level_source.levels_recur = False
        generator = torch.Generator().manual_seed(1)
        td, out = env.reset(), []
        for step in range(60):
            td.set("action", torch.randint(0, env.game.num_actions, (5,), generator=generator))
            stepped, td = env.step_and_maybe_reset(td)
            done = torch.zeros_like(td.get("done"))
            done[step % 5] = step % 4 == 0  # one env's episode cut short now and then: one-env resets
            td = env.maybe_reset(td.set("done", done))
            out += [stepped.clone(), td.clone()]
        assert (env._bank._observations is None) == (obs == "pixels" or not banked_started)
        return out

    started, ticked = rollout(True), rollout(False)
    for a, b in zip(started, ticked, strict=True):
        assert (a == b).all()


def test_a_source_of_replays_has_its_levels_kept_once_they_come_back():
    source = plr_source("zelda")
    assert source.replayed_levels == 12
    env = GVGAIEnv("zelda", 2, levels=source, seed=1, compile_tick=False)
    store = env._bank
    assert store.capacity == 64 + 12
    a, b = (generate_level("zelda", 0.5, seed) for seed in (1, 2))
    one = torch.zeros(1, dtype=torch.int64)
    assert not store.fresh_states([a], one, True)[1]  # met once: compiled, not kept
    assert a not in store
    states, started, observed = store.fresh_states([a], one, True)  # it came back: kept, started
    assert started and a in store and observed.shape[0] == 1
    assert not store.fresh_states([b], one, True)[1] and b not in store
