"""``Game.reset_tick`` leaves a fresh state exactly as ``tick`` with NIL does (RULES.md §1.8).

Frogs replaces its reset tick with the few things tick 0 does; these tests hold it to the full
tick on the human levels, generated levels of every difficulty and levels built to provoke the
rules it skips, with enough seeds that every spawner both fires and does not. A game that says its
reset tick is seed-free (``Game.seed_free_reset_tick``: an env then keeps its levels started) is
held to leaving the same state whatever the episode seed.
"""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.games import get_game, get_game_spec, registered_games, study_games
from gvgai_pcg.generators import get_generator
from gvgai_pcg.levels import Level, human_levels

CPU = torch.device("cpu")
SEEDS_PER_LEVEL = 16

# Frogs levels aimed at the rules Frogs' reset tick leaves out: a frog starting on a log in the
# water ('B'), next to trucks, under a spawner and beside a wall, and a level without a goal.
FROGS_EDGE_LEVELS = [
    ("wwwwwwwww", "3=00B00=1", "++++++++g", "x_-l+++++", "wwwwwwwww"),
    ("ww2wwwwww", "0000000=4", "++++A++++", "-x_lAl_x-", "wwwwwwwww"),
    ("wwwwwwwww", "1000=0003", "+++++++++", "++++A++++", "wwwwwwwww"),
]


def _levels(game: str) -> list[Level]:
    # a GVGAI corpus game (GVGAI_VGDL_DIR) has no generator: its human levels alone
    generate = get_generator(game) if get_game_spec(game).generator is not None else None
    generated = [generate(d, seed) for d in (0.0, 0.5, 1.0) for seed in range(4)] if generate else []
    edge = [Level(game, rows) for rows in FROGS_EDGE_LEVELS] if game == "frogs" else []
    return [*human_levels(game), *generated, *edge]


def _assert_states_equal(expected, actual) -> None:
    assert set(expected.keys(True, True)) == set(actual.keys(True, True))
    for key in expected.keys(True, True):
        assert torch.equal(expected.get(key), actual.get(key)), key


@pytest.mark.parametrize("game_name", registered_games())
def test_the_reset_tick_equals_a_tick_with_nil(game_name):
    game = get_game(game_name)
    levels = [level for level in _levels(game_name) for _ in range(SEEDS_PER_LEVEL)]
    seeds = torch.arange(len(levels), dtype=torch.int64) * 7919 + 1
    fresh = game.compile(levels, seeds, CPU)
    expected, actual = fresh.clone(), fresh.clone()
    game.tick(expected, torch.zeros(len(levels), dtype=torch.int64))
    game.reset_tick(actual)
    _assert_states_equal(expected, actual)
    assert (actual.get("tick") == 0).all()


def test_frogs_reset_ticks_cover_spawning_and_not_spawning():
    """The comparison above means something for Frogs only if tick 0 spawns in some envs and not
    in others, and if the no-goal level is won at once."""
    game = get_game("frogs")
    levels = [level for level in _levels("frogs") for _ in range(SEEDS_PER_LEVEL)]
    state = game.compile(levels, torch.arange(len(levels), dtype=torch.int64) * 7919 + 1, CPU)
    level_logs = state.get(("logs", "alive")).sum(-1)
    game.reset_tick(state)
    spawned = state.get(("logs", "alive")).sum(-1) - level_logs
    assert (spawned > 0).any() and (spawned == 0).any()
    no_goal = torch.tensor([level.count("g") == 0 for level in levels])
    assert no_goal.any()
    assert torch.equal(state.get("won"), no_goal)


def _states_after_reset_tick(game_name: str, seed_base: int):
    game = get_game(game_name)
    levels = _levels(game_name)
    seeds = torch.arange(len(levels), dtype=torch.int64) * 7919 + seed_base
    state = game.compile(levels, seeds, CPU)
    game.reset_tick(state)
    return state.exclude("seed")


@pytest.mark.parametrize("game_name", registered_games())
def test_a_seed_free_reset_tick_leaves_the_same_state_whatever_the_seed(game_name):
    """The same states after tick 0 for three seeds per level where the game says so; where it does
    not (Solarfox's shots and Frogs' logs may spawn at tick 0), the comparison tells them apart."""
    states = [_states_after_reset_tick(game_name, base) for base in (1, 2**40 + 3, 2**61 + 5)]
    same = all((state == states[0]).all() for state in states[1:])
    if game_name in study_games():
        assert same == get_game(game_name).seed_free_reset_tick
    else:  # a game that does not say so (a GVGAI corpus game) only pays its reset tick at each reset
        assert same or not get_game(game_name).seed_free_reset_tick
