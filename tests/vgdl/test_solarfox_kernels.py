"""Solarfox's kernels of the generic step on small descriptions, worked out by hand: a Missile's
first-update skip and cooldown, changeResource's limit, spawnIfHasMore, reverseDirection at each
application, a spawn into a table's free slots, and MultiSpriteCounter."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl import VGDLError
from gvgai_pcg.vgdl.engine import VGDLGame
from gvgai_pcg.vgdl.engine.layout import BORN_TICK

TEXT = """BasicGame
    SpriteSet
        floor > Immovable
        ground > Immovable
        pad > Passive
        turn > Flicker limit=8
        mark > Passive
        bug > Missile cooldown=3 orientation=RIGHT
        fly > Missile orientation=UP speed=0.15
        res > Resource value=0 limit=3
        wall > Immovable
        avatar > OngoingAvatar speed=0.15
    LevelMapping
        . > floor
        p > floor pad
        b > floor bug
        c > bug
        g > ground
        w > wall
        A > floor avatar
    InteractionSet
        avatar wall > killSprite scoreChange=-10
        pad turn > spawnIfHasMore resource=res stype=mark limit=2
        pad avatar > spawn stype=turn
        pad turn > changeResource resource=res
        bug wall > reverseDirection
        bug floor > spawn stype=fly
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
        MultiSpriteCounter stype1=pad stype2=mark limit=0 win=True
"""


def game() -> VGDLGame:
    return VGDLGame.from_text(TEXT, "kernels.txt")


def run(level: tuple[str, ...], ticks: int, action: str = "NIL"):
    g = game()
    state = g.compile([Level("kernels", level)], torch.zeros(1, dtype=torch.int64), "cpu")
    for _ in range(ticks):
        g.tick(state, torch.tensor([g.actions.index(action)]))
    return g, state


def test_a_missile_skips_its_first_update_moves_every_cooldown_and_reverses_at_each_overlap():
    g, state = run(("Acgggw",), 0)  # no floor on its way: it spawns nothing
    xs = []
    for _ in range(15):
        g.tick(state, torch.tensor([0]))
        xs.append(int(state.get("bug").get("x")[0, 0]))
    # no move at its first update (tick 0), then 10 px at ticks 2, 5, 8, 11; in the wall column at
    # ticks 11, 12, 13 it is reversed three times (once net), so tick 14 takes it back left
    assert xs == [10, 10, 20, 20, 20, 30, 30, 30, 40, 40, 40, 50, 50, 50, 40]


def test_a_spawn_fills_the_first_free_slots_and_every_spawned_missile_waits_one_update():
    g, state = run(("A....", "b...."), 3)
    fly = state.get("fly")
    # the bug on the floor spawns a fly every tick (prob 1): three flies in slots 0, 1, 2
    assert fly.get("alive")[0, :4].tolist() == [True, True, True, False]
    # made at ticks 0, 1, 2 at the bug's place; each moves 1 px up from its second update
    assert fly.get("y")[0, :3].tolist() == [9, 10, 10]


def test_spawned_missiles_keep_java_list_order_in_born_and_a_full_table_is_named():
    g, state = run(("A....", "b...."), 3)
    born = state.get("fly").get("born")[0, :3].tolist()
    # one fly a tick: each created after every earlier sprite, so born grows with creation
    assert born == sorted(born) and len(set(born)) == 3 and born[0] >= BORN_TICK
    (rule,) = [rule for rule in g.rules if rule.plan.name == "spawn" and rule.plan.values["stype"] == "fly"]
    assert rule.overflow.endswith("spawn into 'fly' found the table 'fly' full (its capacity is the plan's)")


def test_change_resource_stops_at_the_limit_and_spawn_if_has_more_fires_from_it():
    g, state = run((".pA..",), 0, "LEFT")
    counts = []
    for _ in range(6):
        g.tick(state, torch.tensor([g.actions.index("LEFT")]))
        counts.append(int(state.get("pad").get("resource_res")[0, 0]))
    assert max(counts) <= 3 and counts[:3] == [0, 0, 1]
    assert state.get("mark").sum() >= 1  # the mark came once the counter held 2


def test_multi_sprite_counter_wins_when_none_of_its_types_is_left():
    g, state = run(("A.",), 1)
    assert bool(state.get("won")[0]) and not bool(state.get("lost")[0])


def test_a_change_resource_that_subtracts_is_refused_at_its_line():
    text = TEXT.replace("changeResource resource=res", "changeResource resource=res value=-1")
    with pytest.raises(VGDLError, match=r"kernels2.txt:\d+: changeResource with a value below 1"):
        VGDLGame.from_text(text, "kernels2.txt")
