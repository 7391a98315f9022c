"""Merging a partial reset into the running state: fresh envs with fewer entity slots than the
running batch merge as if they had been padded first."""

import torch

from gvgai_pcg.engine.rows import copy_rows
from gvgai_pcg.envs.states import entity_capacities, merge_states, pad_entity_tables
from gvgai_pcg.games import get_game
from gvgai_pcg.games.base import pad_level
from gvgai_pcg.generators import generate_level


def test_merging_fresh_states_with_fewer_slots_equals_merging_padded_ones():
    game = get_game("frogs")
    fmt = game.level_format
    levels = [
        pad_level(generate_level("frogs", d, seed), fmt.height, fmt.width)
        for seed, d in enumerate((1.0, 0.9, 0.0, 0.1))
    ]
    state = game.compile(levels[:2], torch.arange(2), torch.device("cpu"))
    fresh = game.compile(levels[2:], torch.arange(2, 4), torch.device("cpu"))
    sizes = entity_capacities(state)
    assert any(entity_capacities(fresh)[key] < size for key, size in sizes.items())  # fewer slots
    expected = state.clone()
    copy_rows(expected, pad_entity_tables(fresh.clone(), sizes), torch.tensor([1, 0]))
    merged = merge_states(state.clone(), fresh, torch.tensor([1, 0]))
    assert (merged == expected).all()


def test_a_compiled_game_grows_its_tables_to_a_power_of_two():
    # a compiled tick recompiles per table width: rounding up keeps the widths few
    game = get_game("zelda")
    small = game.compile([generate_level("zelda", 0.0, 0)], torch.tensor([1]), torch.device("cpu"))
    large = game.compile([generate_level("zelda", 1.0, 1)], torch.tensor([2]), torch.device("cpu"))
    slots = entity_capacities(large)["monsters"]
    assert slots > entity_capacities(small)["monsters"] and slots & (slots - 1)  # not a power of two
    exact = merge_states(small.clone(), large, torch.tensor([0]))
    rounded = merge_states(small.clone(), large, torch.tensor([0]), round_up=True)
    assert entity_capacities(exact)["monsters"] == slots
    width = entity_capacities(rounded)["monsters"]
    assert width & (width - 1) == 0 and slots < width < 2 * slots
    assert torch.equal(rounded.get(("monsters", "x"))[:, :slots], exact.get(("monsters", "x")))
    assert not rounded.get(("monsters", "alive"))[:, slots:].any()


def test_a_compiled_games_first_state_has_tables_of_at_least_two_slots_in_powers_of_two():
    # tables of 0 and 1 slots (Frogs levels without trucks of a kind) each compiled anew: ten
    # recompiles in the first 20,000 frames of PPCG Frogs, seconds each
    from gvgai_pcg.envs import GVGAIEnv
    from gvgai_pcg.envs.level_sources import GeneratedLevels

    env = GVGAIEnv("frogs", num_envs=3, levels=GeneratedLevels("frogs"), seed=0)
    env.reset()
    fresh = env.game.compile(env._levels, torch.zeros(3, dtype=torch.int64), torch.device("cpu"))
    assert min(entity_capacities(fresh).values()) < 2
    for key, width in entity_capacities(env.state).items():
        assert width >= 2 and width & (width - 1) == 0, key
        assert width >= entity_capacities(fresh)[key]
