"""The plan compiled from a description: how each type is held, which stay on whole cells,
each table's capacity, the rules in Java's order with their kinds, and the refusals."""

from __future__ import annotations

import textwrap

import pytest

from gvgai_pcg.vgdl import VGDLError, parse_vgdl
from gvgai_pcg.vgdl.plan import analyse, compile_plan

GAME = """
    SpriteSet
        floor > Immovable
        door > Door
        gem > Resource limit=3
        crate > Passive
        pad > Passive
        spark > Flicker limit=2
        slash > Flicker limit=1 singleton=True
        log > Missile orientation=LEFT speed=0.1
        rock > Missile orientation=DOWN speed=1
        splinter > Immovable
        ghost > Immovable
        nest > SpawnPoint stype=rock total=2 cooldown=5
        hive > SpawnPoint stype=ghost
        hero > ShootAvatar stype=slash
    LevelMapping
        . > floor
        c > floor crate
        p > floor pad
        l > floor log
        r > floor rock
        n > floor nest
        A > floor hero
    InteractionSet
        hero EOS > stepBack
        log EOS > killSprite
        crate hero > bounceForward
        hero log > pullWithIt
        gem hero > collectResource
        pad hero > changeResource resource=gem
        rock wall > transformTo stype=splinter repeat=2
        log door > spawn stype=ghost
        door hero > spawn stype=spark
        pad rock > spawn stype=hive
        hero wall > stepBack
    TerminationSet
        SpriteCounter stype=door win=True
        MultiSpriteCounter stype1=rock stype2=log limit=0 win=False
"""


def game_of(body: str = GAME, path: str = "g.txt"):
    return parse_vgdl("BasicGame\n" + textwrap.indent(textwrap.dedent(body).strip("\n"), "    ") + "\n", path)


def test_static_stateless_types_are_count_grids_the_avatar_and_singletons_records():
    types = analyse(game_of()).types
    held = {name: sprite.representation for name, sprite in types.items()}
    assert held["floor"] == held["door"] == held["wall"] == held["splinter"] == held["gem"] == "grid"
    assert held["hero"] == held["slash"] == "record"
    assert types["slash"].singleton and not types["hero"].singleton
    tables = {name for name, how in held.items() if how == "table"}
    assert tables == {"crate", "pad", "spark", "log", "rock", "ghost", "nest", "hive"}
    assert types["crate"].why == "moved or turned by bounceForward"
    assert types["pad"].why == "changeResource (line 31) changes what it holds"
    assert types["spark"].why == "Flicker keeps an age"
    assert types["nest"].why == "a SpawnPoint with total keeps a count"
    assert types["hive"].why == "a SpawnPoint made during play keeps its start tick"
    assert types["gem"].why == "still, stateless, on whole cells"  # collected: the hero holds the count


def test_alignment_follows_steps_creations_and_moves_to_unaligned_sprites():
    types = analyse(game_of()).types
    assert (types["log"].aligned, types["log"].step_px) == (False, 1)  # (int)(0.1 * 10) px
    assert types["ghost"].why_unaligned == "made by spawn where log is"
    assert types["ghost"].representation == "table"  # still, but off the cells
    assert types["hero"].why_unaligned == "moved 1 px by pullWithIt (line 29)"  # by the log's speed
    # a log faces LEFT and nothing turns it: its row, and the row of the hero it pulls, stay whole
    assert (types["log"].aligned_x, types["log"].aligned_y) == (False, True)
    assert (types["hero"].aligned_x, types["hero"].aligned_y) == (False, True)
    assert (types["ghost"].aligned_x, types["ghost"].aligned_y) == (False, True)
    assert types["crate"].aligned  # pushed a whole cell by the hero's speed, wherever the hero is
    assert (types["rock"].aligned, types["rock"].step_px) == (True, 10)
    assert types["splinter"].aligned and types["spark"].aligned


def test_a_push_by_a_slow_pusher_and_a_wrap_with_an_offset_leave_the_cells():
    types = analyse(
        game_of("""
        SpriteSet
            box > Passive
            car > Missile orientation=RIGHT
            bolt > Missile orientation=UP speed=0.5
            hero > MovingAvatar speed=0.5
        InteractionSet
            box hero > bounceForward
            car EOS > wrapAround offset=0.5
            bolt wall > flipDirection
    """)
    ).types
    assert types["box"].why_unaligned == "moved 5 px by bounceForward (line 8)"
    assert types["car"].why_unaligned == "wrapped 5 px from the edge (line 9)"
    assert (types["car"].aligned_x, types["car"].aligned_y) == (False, True)
    assert not types["box"].aligned_x and not types["box"].aligned_y  # the hero moves both ways
    assert not types["bolt"].aligned_x and not types["bolt"].aligned_y  # a turned missile may go any way


def test_capacities_are_formulas_over_a_level_with_bounds_where_creation_has_one():
    plan = analyse(game_of())
    formulas = {name: sprite.capacity.formula() for name, sprite in plan.types.items() if sprite.capacity}
    assert formulas["log"] == "level log"
    assert formulas["rock"] == "level rock + 2 x level nest"  # SpawnPoint total=2
    assert formulas["ghost"] == "level ghost + cells"  # a spawn with no bound: one slot a cell
    assert plan.types["hero"].capacity is None and plan.types["floor"].capacity is None
    rows = ["A.ll", "rnn.", "c..."]
    slots = plan.table_slots(rows)
    assert (slots["log"], slots["rock"], slots["ghost"], slots["crate"]) == (2, 5, 12, 1)


def test_a_transform_is_bounded_by_its_source_and_a_plan_holds_its_level_slots():
    game = game_of("""
        SpriteSet
            egg > Missile
            bird > Missile
            hero > MovingAvatar
        LevelMapping
            e > egg
            H > hero
        InteractionSet
            egg wall > transformTo stype=bird
            hero bird > transformTo stype=egg
        TerminationSet
            SpriteCounter stype=hero win=False
    """)
    # the hero's record becomes an egg once (nothing makes a hero again), each egg a bird once
    assert compile_plan(game).types["egg"].capacity.formula() == "level egg + level hero"
    assert compile_plan(game).types["bird"].capacity.formula() == "level bird + level egg + level hero"
    assert compile_plan(game).slots is None
    assert compile_plan(game, ["wHee", "eeew"]).slots == {"egg": 6, "bird": 6}


def test_a_level_that_does_not_fit_is_refused_in_one_line():
    plan = analyse(game_of())
    with pytest.raises(ValueError, match=r"^level row 2: character 'z' is not in the LevelMapping$"):
        plan.table_slots(["A..", ".z."])
    with pytest.raises(ValueError, match=r"^the level places 2 sprites of 'hero', which holds one"):
        plan.table_slots(["A.A"])


def test_rules_in_java_order_with_leaves_repeats_and_kinds():
    plan = analyse(game_of())
    assert [(rule.first, rule.second, rule.name) for rule in plan.eos] == [
        ("hero", "EOS", "stepBack"),
        ("log", "EOS", "killSprite"),
    ]
    pairs = [(rule.first, rule.second, rule.name, rule.kind) for rule in plan.pairs]
    assert pairs[4:6] == [("rock", "wall", "transformTo", "A")] * 2  # repeat=2
    assert ("gem", "hero", "collectResource", "X") in pairs
    spawn = next(rule for rule in plan.pairs if rule.name == "spawn")
    assert spawn.random and spawn.values["prob"] == 1 and spawn.values["stype"] == "ghost"
    assert spawn.effect == next(rule for rule in plan.pairs if rule.line == spawn.line).effect


def test_terminations_name_the_types_they_count():
    first, second = analyse(game_of()).terminations
    assert (first.counted, first.win, first.limit) == ((("door",),), True, 0)
    assert (second.counted, second.win) == ((("rock",), ("log",)), False)  # 'False' is a String in Java


def test_an_unimplemented_feature_is_refused_at_its_line():
    game = game_of(GAME.replace("crate > Passive", "crate > Chaser stype=hero"), "chase.txt")
    with pytest.raises(VGDLError) as refused:
        compile_plan(game)
    assert str(refused.value) == "chase.txt:6: Chaser is not implemented by the engine yet"


def test_what_a_carried_sprite_pushes_moves_along_both_axes():
    types = analyse(
        game_of("""
        SpriteSet
            box > Passive
            raft > Missile orientation=RIGHT speed=0.5
            lift > Missile orientation=UP
            hero > MovingAvatar
        InteractionSet
            raft lift > pullWithIt
            box raft > bounceForward
    """)
    ).types
    assert (types["raft"].aligned_x, types["raft"].aligned_y) == (False, True)  # lifted a whole cell
    assert not types["box"].aligned_y  # the raft's last move may be the lift's, up


def test_inspect_says_which_sprites_refuse_a_singletons_creation():
    from gvgai_pcg.vgdl.plan_text import describe_plan

    text = describe_plan(analyse(game_of()))
    assert "  slash: record (" in text
    line = next(line for line in text.splitlines() if line.startswith("  slash:"))
    assert line.endswith("; not created while a slash exists (singleton)")
    assert "singleton" not in next(line for line in text.splitlines() if line.startswith("  hero:"))
