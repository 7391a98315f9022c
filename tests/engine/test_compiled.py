"""The compiled tick computes what the eager tick computes, and the engine runs it by default.

The golden traces replay through the engine's tick as well (tests/games/golden_replay.py), so a
compiled game matches the Java engine batched, where it runs compiled.
"""

import warnings

import pytest
import torch

from gvgai_pcg.engine.compiled import (
    COMPILE_VARIABLE,
    LARGE_BATCH_PER_THREAD,
    CompiledTick,
    engine_tick,
    large_batch,
)
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.games import get_game, get_game_spec, registered_games
from gvgai_pcg.games.spec import StepFacts
from gvgai_pcg.generators import get_generator
from gvgai_pcg.levels import Level, human_levels
from tests.games.toy_game import LEVEL_TEXT, Walk

COMPILED_GAMES = [name for name in registered_games() if get_game(name).step_facts.compiles]


def assert_same_states(expected, actual, when: str = "") -> None:
    """Every leaf of ``actual`` equals ``expected``'s (``when`` says at which tick, for a failure)."""
    for key in expected.keys(True, True):
        assert torch.equal(expected.get(key), actual.get(key)), f"{key} differs{when}"


def test_the_games_that_compile():
    assert set(COMPILED_GAMES) == {"zelda", "boulderdash", "frogs", "solarfox"}


# Levels that take a tick's other whole-batch branch (``Game.host_arguments``): Boulderdash levels
# without a full wall border, whose sprites can leave the screen.
BRANCH_LEVELS = {
    "boulderdash": [("A-o", "o.x", "-cb"), ("--e", "Ao-"), ("b-o-c", "-o-o-", "c-A-b"), ("Aoooo",)],
}
BATCHES = [(name, False) for name in COMPILED_GAMES] + [
    (name, True) for name in COMPILED_GAMES if name in BRANCH_LEVELS
]


@pytest.mark.parametrize(("game_name", "other_branch"), BATCHES)
def test_compiled_tick_equals_eager_tick(game_name, other_branch):
    # a mixed batch: human levels and generated ones of every difficulty, of several sizes
    game = get_game(game_name)
    generate = get_generator(game_name)
    levels = human_levels(game_name) + [generate(d / 4, seed) for seed in range(3) for d in range(5)]
    if other_branch:
        levels += [Level(game_name, rows) for rows in BRANCH_LEVELS[game_name]]
        assert any(
            game.host_arguments(game.compile(levels, torch.arange(len(levels)), torch.device("cpu"))).values()
        )
    seeds = torch.arange(len(levels)) * 7919
    eager = game.compile(levels, seeds, torch.device("cpu"))
    compiled = game.compile(levels, seeds, torch.device("cpu"))
    tick = engine_tick(game)
    assert isinstance(tick, CompiledTick)
    generator = torch.Generator().manual_seed(0)
    for step in range(150):
        action = torch.randint(0, game.num_actions, (len(levels),), generator=generator)
        game.tick(eager, action)
        tick(compiled, action)
        assert_same_states(eager, compiled, f" at tick {step}")
    assert tick.failed is None


def test_the_env_runs_the_compiled_tick_by_default():
    env = GVGAIEnv("zelda", num_envs=4, levels="human", seed=0)
    assert env.step_plan.compiled and env._runner.compiled_tick is engine_tick(env.game)
    assert isinstance(env._runner.compiled_tick, CompiledTick)


def test_a_sharded_env_ticks_eagerly():
    env = GVGAIEnv("boulderdash", num_envs=4, levels="human", seed=0, shards=2)
    assert not env.step_plan.compiled and env._runner.compiled_tick is None


def test_compiling_can_be_turned_off(monkeypatch):
    monkeypatch.setenv(COMPILE_VARIABLE, "0")
    game = get_game("zelda")
    assert engine_tick(game) == game.tick


class WalkWithHostSync(Walk):
    """Claims to compile but reads a value on the host in its tick, which a full graph refuses."""

    step_facts = StepFacts(compiles=True)

    def tick(self, state, action):
        if bool(state.get("won").any()):
            state.get("score").add_(0)
        super().tick(state, action)


def test_a_tick_that_does_not_compile_runs_eagerly_after_a_warning():
    game = WalkWithHostSync()
    game.name = "toy"
    level = Level("toy", tuple(LEVEL_TEXT.splitlines()))
    compiled_state = game.compile([level, level], torch.tensor([1, 2]), torch.device("cpu"))
    eager_state = game.compile([level, level], torch.tensor([1, 2]), torch.device("cpu"))
    tick = CompiledTick(game)
    action = torch.tensor([2, 3])  # RIGHT, DOWN
    with pytest.warns(RuntimeWarning, match="compiling toy's tick for cpu failed"):
        tick(compiled_state, action)
    game.tick(eager_state, action)
    assert tick.failed and set(tick.failures) == {"cpu"}  # other devices would still compile
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said once
        tick(compiled_state, action)
    game.tick(eager_state, action)
    assert_same_states(eager_state, compiled_state)


def test_a_tick_and_draw_that_does_not_compile_leaves_the_state_to_the_separate_calls():
    game = WalkWithHostSync()
    game.name = "toy"
    level = Level("toy", tuple(LEVEL_TEXT.splitlines()))
    state = game.compile([level, level], torch.tensor([1, 2]), torch.device("cpu"))
    before = state.clone()
    tick = CompiledTick(game)
    with pytest.warns(RuntimeWarning, match="compiling toy's tick and tiles render for cpu failed"):
        assert tick.tick_and_draw(state, torch.tensor([2, 3]), torch.ones(2, dtype=torch.int64), 9) is None
    assert set(tick.fused_failures) == {"cpu"} and not tick.failures  # the tick alone may still compile
    assert all(torch.equal(before.get(key), state.get(key)) for key in state.keys(True, True))  # not ticked
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # said once, and not tried again
        assert tick.tick_and_draw(state, torch.tensor([2, 3]), torch.ones(2, dtype=torch.int64), 9) is None


def test_the_speedup_script_times_both_ticks():
    from gvgai_pcg.bench.compiled import measure_speedup

    result = measure_speedup("zelda", batch=3, rounds=1, steps_per_round=30)
    assert result.compiled > 0 and result.eager > 0 and result.ratio == result.compiled / result.eager


def test_a_branch_the_compiler_gets_wrong_ticks_eagerly(monkeypatch):
    game = get_game("boulderdash")
    assert game.step_facts.eager_when == ("leaving",)
    tick = CompiledTick(game)
    monkeypatch.setattr(tick, "_compiled", lambda *args, **kwargs: pytest.fail("ticked compiled"))
    levels = [Level("boulderdash", rows) for rows in BRANCH_LEVELS["boulderdash"]]
    state = game.compile(levels, torch.arange(len(levels)), torch.device("cpu"))
    tick(state, torch.zeros(len(levels), dtype=torch.int64))
    assert state.get("tick").tolist() == [0] * len(levels)


def test_a_zelda_batch_with_a_wide_monster_table_ticks_eagerly(monkeypatch):
    """Compiled, the ordered stepBack runs one round per monster slot; eagerly it stops early, and
    past ``COMPILED_MONSTER_SLOTS`` the eager tick is the faster (ACCEL's edited levels)."""
    from gvgai_pcg.games.zelda.rules import COMPILED_MONSTER_SLOTS

    game = get_game("zelda")
    assert "crowded" in game.step_facts.eager_when
    free = "." * 11
    rows = (
        ("wwwwwwwwwwwww", "wA+........gw")
        + tuple(f"w{free}w" for _ in range(4))
        + ("w" + "1" * 11 + "w",) * 2
    )
    crowded = Level("zelda", rows + ("wwwwwwwwwwwww",))
    assert crowded.count("1") > COMPILED_MONSTER_SLOTS
    seeds = torch.arange(6)
    human = game.compile(human_levels("zelda"), seeds[:5], torch.device("cpu"))
    assert game.host_arguments(human) == {"crowded": False}
    state = game.compile(human_levels("zelda") + [crowded], seeds, torch.device("cpu"))
    assert game.host_arguments(state) == {"crowded": True}
    tick = CompiledTick(game)
    monkeypatch.setattr(tick, "_compiled", lambda *args, **kwargs: pytest.fail("ticked compiled"))
    eager, before = state.clone(), state.get("tick").clone()
    action = torch.tensor([0, 1, 2, 3, 4, 0])
    tick(state, action)
    game.tick(eager, action)
    assert_same_states(eager, state)
    assert torch.equal(state.get("tick"), before + 1)


# Frogs' case compiles for 20 CPU-seconds: run with `-m slow`
@pytest.mark.parametrize(
    "game_name", [pytest.param(n, marks=pytest.mark.slow) if n == "frogs" else n for n in COMPILED_GAMES]
)
def test_a_batch_as_wide_as_an_entity_table_ticks_as_eagerly(game_name):
    """Sizes that are equal when first traced once shared a symbol (duck shaping), and inductor
    miscompiled Boulderdash's tick for 4 envs of 4 monster slots each (every human level has 4)."""
    game = get_game(game_name)
    levels = human_levels(game_name)[:4]
    seeds = torch.arange(4) * 31 + 5
    eager = game.compile(levels, seeds, torch.device("cpu"))
    compiled = game.compile(levels, seeds, torch.device("cpu"))
    tick = engine_tick(game)
    generator = torch.Generator().manual_seed(0)
    for step in range(20):
        action = torch.randint(0, game.num_actions, (4,), generator=generator)
        game.tick(eager, action)
        tick(compiled, action)
        assert_same_states(eager, compiled, f" at tick {step}")


def test_a_batch_above_the_games_compiled_limit_ticks_eagerly(monkeypatch):
    game = get_game("solarfox")
    assert game.step_facts.max_compiled_batch == 2048
    tick = CompiledTick(game)
    monkeypatch.setattr(tick, "_compiled", lambda *args, **kwargs: pytest.fail("ticked compiled"))
    levels = [human_levels("solarfox")[i % 5] for i in range(2049)]
    state = game.compile(levels, torch.arange(2049), torch.device("cpu"))
    tick(state, torch.zeros(2049, dtype=torch.int64))
    assert state.get("tick").eq(0).all()


class WalkWithHostSyncOnCuda(WalkWithHostSync):
    step_facts = StepFacts(compiles=True, compiled_devices=("cuda",))


def test_a_device_left_out_of_compiled_devices_ticks_eagerly():
    game = WalkWithHostSyncOnCuda()  # its compiled tick would fail with a warning
    game.name = "toy"
    level = Level("toy", tuple(LEVEL_TEXT.splitlines()))
    state = game.compile([level, level], torch.tensor([1, 2]), torch.device("cpu"))
    tick = CompiledTick(game)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no attempt to compile, so no warning
        tick(state, torch.tensor([2, 3]))
    assert tick.failed is None


def test_frogs_ticks_eagerly_on_cuda():
    # the compiled CUDA tick differed from the CPU's in an env of generated levels (see Frogs)
    assert get_game("frogs").step_facts.compiled_devices == ("cpu",)
    others = [name for name in COMPILED_GAMES if name != "frogs"]
    assert all(get_game(name).step_facts.compiled_devices == ("cpu", "cuda") for name in others)


@pytest.mark.parametrize("game_name", sorted(g for g in registered_games() if get_game_spec(g).generator))
def test_the_traced_render_draws_what_the_render_draws(game_name):
    from gvgai_pcg.games.render import render_tiles, render_tiles_traced

    game = get_game(game_name)
    generate = get_generator(game_name)
    levels = human_levels(game_name) + [generate(d / 4, seed) for seed in range(2) for d in range(5)]
    state = game.compile(levels, torch.arange(len(levels)) * 7919, torch.device("cpu"))
    generator = torch.Generator().manual_seed(0)
    for _ in range(40):
        game.tick(state, torch.randint(0, game.num_actions, (len(levels),), generator=generator))
        assert torch.equal(render_tiles_traced(game, state), render_tiles(game, state))


# Frogs', Solarfox's and Boulderdash's compiled env takes 30-70 CPU-seconds to build: run with `-m slow`.
DRAWING_CASES = [
    pytest.param(name, marks=pytest.mark.slow) if name in ("frogs", "solarfox", "boulderdash") else name
    for name in sorted(COMPILED_GAMES)
]


@pytest.mark.parametrize("game_name", DRAWING_CASES)
def test_an_env_drawing_compiled_observes_what_an_eager_one_does(game_name, monkeypatch):
    from gvgai_pcg.envs.level_sources import GeneratedLevels

    envs = [
        GVGAIEnv(
            game_name, 6, GeneratedLevels(game_name), seed=2, difficulty=0.5, max_steps=25, compile_tick=c
        )
        for c in (True, False)
    ]
    assert envs[0].step_plan.fused
    assert envs[0].step_plan.compiled_resets == (game_name != "frogs")  # Frogs keeps its own reset tick
    assert not envs[1].step_plan.compiled  # all eager
    resets = 0
    fused = []  # steps that ticked and drew in one compiled call
    tick_and_draw = envs[0]._runner.compiled_tick.tick_and_draw
    monkeypatch.setattr(
        envs[0]._runner.compiled_tick,
        "tick_and_draw",
        lambda *args: fused.append(tick_and_draw(*args)) or fused[-1],
    )
    tds = [env.reset() for env in envs]
    generator = torch.Generator().manual_seed(0)
    for _ in range(60):
        action = torch.randint(0, envs[0].game.num_actions, (6,), generator=generator)
        outs = []
        for i, env in enumerate(envs):
            tds[i].set("action", action)
            out, tds[i] = env.step_and_maybe_reset(tds[i])
            outs.append(out)
        resets += bool(outs[0].get(("next", "done")).any())  # a reset call
        assert torch.equal(outs[0].get(("next", "tiles")), outs[1].get(("next", "tiles")))
        assert torch.equal(tds[0].get("tiles"), tds[1].get("tiles"))
        assert_same_states(envs[0].state, envs[1].state)
    # the fused call ran for every step and every reset (compiled resets tick through it too)
    resets_fused = 1 + resets if envs[0].step_plan.compiled_resets else 0  # the first, then each reset
    assert len(fused) == 60 + resets_fused and all(tiles is not None for tiles in fused[:4])
    assert resets >= 2, resets
    assert not envs[0]._runner.compiled_tick.fused_failures


def test_a_large_batch_on_several_threads_ticks_through_a_graph_of_its_own(monkeypatch):
    # Inductor decides which loops run in parallel from the batch size of a graph's first trace;
    # a large batch gets its own graph so that one first traced small never serves it.
    threads = torch.get_num_threads()
    torch.set_num_threads(2)
    try:
        large = LARGE_BATCH_PER_THREAD * 2
        game = get_game("zelda")
        tick, facts = CompiledTick(game), game.step_facts
        assert large_batch(facts, large, "cpu", 2) and not large_batch(facts, large - 1, "cpu", 2)
        assert not large_batch(facts, large, "cuda", 2)  # CUDA keeps one graph
        assert not large_batch(get_game("boulderdash").step_facts, large * 4, "cpu", 2)  # parallel_graph
        assert not large_batch(facts, large * 8, "cpu", 1)  # one thread: no loop is parallel anyway
        levels = [human_levels("zelda")[i % 5] for i in range(large)]
        seeds = torch.arange(large) * 7919
        eager, compiled = (game.compile(levels, seeds, torch.device("cpu")) for _ in range(2))
        tick(game.compile(levels[:8], seeds[:8], torch.device("cpu")), torch.zeros(8, dtype=torch.int64))
        monkeypatch.setattr(
            tick, "_compiled", lambda *args, **kwargs: pytest.fail("ticked by the small graph")
        )
        generator = torch.Generator().manual_seed(0)
        for step in range(20):
            action = torch.randint(0, game.num_actions, (large,), generator=generator)
            game.tick(eager, action)
            tick(compiled, action)
            assert_same_states(eager, compiled, f" at tick {step}")
        assert tick.failed is None
    finally:
        torch.set_num_threads(threads)
