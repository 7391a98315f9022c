"""The editors' bounds: what each game's generator can place, derived from its own constants.
Generated levels lie inside them, and edits kept without any selection (ACCEL's children made
from children, hundreds of generations on) never leave them, yet still change the levels."""

from __future__ import annotations

import importlib
from collections import Counter

import pytest

from gvgai_pcg.games.editing import CountBound, apply_edit, out_of_bounds
from gvgai_pcg.games.zelda import editor as zelda_editor
from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels import Level

GAMES = ("zelda", "solarfox", "frogs", "boulderdash")
GENERATIONS = 600
EDITS_PER_CHILD = 5  # conf/regimen/accel.yaml's num_edits
START_DIFFICULTIES = (0.0, 0.5, 1.0)
MOVING_FROM = 0.5  # below, a Frogs level may be grass only, where only the goal can move


def editor_module(game: str):
    return importlib.import_module(f"gvgai_pcg.games.{game}.editor")


@pytest.mark.parametrize("game", GAMES)
def test_generated_levels_lie_inside_the_bounds(game):
    bounds = editor_module(game).BOUNDS
    for d in (0.0, 0.2, 0.4, 0.6, 0.8, 1.0):
        for seed in range(25):
            level = generate_level(game, d, seed=seed)
            assert out_of_bounds(level, bounds) == {}, (game, d, seed)


def test_zeldas_bounds_come_from_its_generator():
    bounds = {bound.name: bound for bound in zelda_editor.BOUNDS}
    assert (bounds["monsters"].low, bounds["monsters"].high) == (0, 3)  # floor(5.85 * 0.6) at d = 1
    assert bounds["inner walls"].high == zelda_editor.maze_inner_walls() - 9  # floor(96 * 0.1) opened
    assert zelda_editor.maze_inner_walls() == 30  # 7 x 11 inside the border, less 24 cells + 23 passages


@pytest.mark.parametrize("game", GAMES)
def test_edits_without_selection_stay_inside_the_bounds_and_keep_moving(game):
    """Every child kept and edited again, as a curriculum without any selection would."""
    module = editor_module(game)
    counted = [bound for bound in module.BOUNDS if isinstance(bound, CountBound) and bound.low < bound.high]
    for start in START_DIFFICULTIES:
        level = generate_level(game, start, seed=11)
        seen: dict[str, set[int]] = {bound.name: set() for bound in counted}
        changed = 0
        for generation in range(GENERATIONS):
            child = level
            for j in range(EDITS_PER_CHILD):
                child = module.edit(child, generation * EDITS_PER_CHILD + j)
            changed += child != level
            level = Level.parse(str(child), game)  # still a valid level of its game
            assert out_of_bounds(level, module.BOUNDS) == {}, (game, start, generation)
            for bound in counted:
                seen[bound.name].add(bound.count(level))
        if start < MOVING_FROM:
            continue
        assert changed >= GENERATIONS * 0.9, (game, start, changed)
        for name, values in seen.items():
            assert len(values) > 1, f"{game} from d={start}: {name} never changed"


def _at_the_monster_cap() -> Level:
    level = generate_level("zelda", 1.0, seed=0)
    for seed in range(400):
        if zelda_editor.BOUNDS[0].count(level) == zelda_editor.BOUNDS[0].high:
            return level
        _, level = apply_edit(level, seed, {"add": zelda_editor.add_monster}, "zelda", zelda_editor.BOUNDS)
    raise AssertionError("no Zelda level reached the monster cap")


def test_an_edit_that_would_leave_a_bound_is_not_made_and_another_kind_is_drawn():
    level = _at_the_monster_cap()
    only_add = {"add_monster": zelda_editor.add_monster}
    kind, same = apply_edit(level, 1, only_add, "zelda", zelda_editor.BOUNDS)
    assert (kind, same) == (None, level)
    kinds = Counter(
        apply_edit(level, seed, zelda_editor.KINDS, "zelda", zelda_editor.BOUNDS)[0] for seed in range(60)
    )
    assert kinds["add_monster"] == 0 and kinds["remove_monster"] > 0


def test_a_level_outside_a_bound_is_edited_but_never_further_out():
    rows = list(generate_level("zelda", 1.0, seed=0).rows)
    crowded = Level("zelda", tuple(rows))
    for seed in range(40):  # well past the cap, without bounds
        _, crowded = apply_edit(crowded, seed, {"add": zelda_editor.add_monster}, "zelda")
    monsters = zelda_editor.BOUNDS[0]
    assert monsters.count(crowded) > monsters.high
    kinds = Counter()
    for seed in range(60):
        kind, child = apply_edit(crowded, seed, zelda_editor.KINDS, "zelda", zelda_editor.BOUNDS)
        kinds[kind] += 1
        assert monsters.count(child) <= monsters.count(crowded)
    assert kinds["remove_monster"] > 0 and kinds["add_monster"] == 0


def test_a_bound_with_low_above_high_is_refused_by_name():
    with pytest.raises(ValueError, match="bound 'monsters'"):
        CountBound("monsters", "123", 4, 3)
