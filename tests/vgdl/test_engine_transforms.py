"""The generic step's transformTo into a table (``vgdl/engine/transform_table.py``) with Java's
singleton guard, an avatar made into a still (grid) type or renewed as its own type (``effects``),
and the pixel-perfect stepBack (``pixel_perfect.py``), on small levels worked out by hand from
Java's TransformTo, Game.addSprite and Effect.calculatePixelPerfect."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl import VGDLError
from gvgai_pcg.vgdl.engine import VGDLGame

NIL, LEFT, RIGHT = 0, 1, 2

RACE = """BasicGame
    SpriteSet
        floor > Immovable
        goal > Door
        camel > Missile orientation=RIGHT speed=0.5
            camelA >
            camelB >
        winner > Immovable {singleton}
            winA >
            winB >
        avatar > MovingAvatar
    InteractionSet
{rules}
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > floor
        g > floor goal
        a > floor camelA
        b > floor camelB
        A > floor avatar
"""


def play(vgdl: VGDLGame, rows: tuple[str, ...], actions: list[int]) -> list:
    state = vgdl.compile([Level("mine", rows)], torch.zeros(1, dtype=torch.int64), "cpu")
    history = []
    for action in actions:
        vgdl.tick(state, torch.tensor([action]))
        history.append(state.clone())
    return history


def sprites(vgdl: VGDLGame, state, names: list[str]) -> list:
    return sorted(vgdl.sprites(state[0], names))


def race(rules: str, singleton: str = "", path: str = "race.txt") -> VGDLGame:
    return VGDLGame.from_text(RACE.format(rules=rules, singleton=singleton), path)


def test_a_camel_at_the_goal_becomes_a_winner_in_a_table_where_it_is():
    vgdl = race("        camel goal > transformTo stype=winA scoreChange=-1")
    assert vgdl.layout.places["winA"].representation == "table"  # made off the cells
    history = play(vgdl, ("a.g", "A.."), [NIL] * 4)
    # 5 px a move from its second update: 0, 5, 10, then 15 overlaps the goal at 20
    assert sprites(vgdl, history[2], ["camelA", "winA"]) == [["camelA", 10, 0]]
    assert sprites(vgdl, history[3], ["camelA", "winA"]) == [["winA", 15, 0]]
    table = history[3].get(vgdl.layout.places["winA"].key)
    made = table.get("alive")[0]
    assert table.get("lastx")[0][made].tolist() == [10]  # the camel's last position
    assert history[3].get("score").item() == -1


def test_a_singleton_winner_is_made_by_the_first_camel_in_the_rules_order_and_refuses_the_next():
    """Both camels reach the goal in tick 3. The rule takes camelA before camelB (``iSubTypes``
    order), though camelB is first in list order: camelA becomes the winner; camelB's transform
    finds a winner (Java makes nothing and kills nothing), scores anyway and runs on."""
    vgdl = race("        camel goal > transformTo stype=winA scoreChange=1", "singleton=True", "one.txt")
    history = play(vgdl, ("b.g", "a.g", "A.."), [NIL] * 5)
    assert sprites(vgdl, history[3], ["camelA", "camelB", "winA"]) == [["camelB", 15, 0], ["winA", 15, 10]]
    assert history[3].get("score").item() == 2
    assert sprites(vgdl, history[4], ["camelB"]) == [["camelB", 20, 0]]  # refused again: +1
    assert history[4].get("score").item() == 3


def test_a_singleton_made_by_an_earlier_rule_refuses_a_later_rules_transform():
    rules = (
        "        camelB goal > transformTo stype=winB scoreChange=1\n"
        "        camelA goal > transformTo stype=winA scoreChange=2"
    )
    vgdl = race(rules, "singleton=True", "two.txt")
    history = play(vgdl, ("a.g", "b.g", "A.."), [NIL] * 4)
    assert sprites(vgdl, history[3], ["camelA", "camelB", "winA", "winB"]) == [
        ["camelA", 15, 0],
        ["winB", 15, 10],
    ]
    assert history[3].get("score").item() == 3


PRIZE = """BasicGame
    SpriteSet
        floor > Immovable
        goal > Immovable
        prize > Immovable
        avatar > MovingAvatar
    InteractionSet
        avatar goal > transformTo stype=prize scoreChange=1
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > floor
        g > floor goal
        G > floor goal goal
        A > floor avatar
"""


def test_an_avatar_made_into_a_still_type_is_disabled_and_scores_for_every_second_it_meets():
    vgdl = VGDLGame.from_text(PRIZE, "prize.txt")
    assert vgdl.layout.places["prize"].representation == "grid"
    for rows, score in ((("Ag.",), 1), (("AG.",), 2)):  # one goal, then two in the cell
        history = play(vgdl, rows, [NIL, RIGHT])
        assert history[0].get("score").item() == 0
        assert history[1].get("prize")[0, 0].tolist() == [0, 1, 0]  # one prize however many goals
        assert not history[1].get(("avatar", "alive")).item() and history[1].get("lost").item()
        assert history[1].get("score").item() == score


BETS = """BasicGame
    SpriteSet
        arena > Immovable
        pit > Immovable
        avatar > MovingAvatar
            bet >
            normal >
    InteractionSet
        avatar arena > transformTo stype=normal scoreChange=1
        avatar pit > transformTo stype=bet scoreChange=10
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > arena
        p > pit
        A > normal arena
"""


def test_an_avatar_made_into_its_own_type_is_renewed_in_place_once_a_rule():
    """On the arena ``normal`` becomes a new ``normal`` (+1) every tick; on the pit it becomes
    ``bet`` (+10); back on the arena ``bet`` becomes ``normal`` (+1), and that new ``normal``,
    made by the rule, is no first of it (no second +1)."""
    vgdl = VGDLGame.from_text(BETS, "bets.txt")
    history = play(vgdl, ("A.p",), [NIL, RIGHT, RIGHT, LEFT])
    assert [state.get("score").item() for state in history] == [1, 2, 12, 13]
    alive = [[n for n in ("bet", "normal") if state.get((n, "alive")).item()] for state in history]
    assert alive == [["normal"], ["normal"], ["bet"], ["normal"]]
    assert history[3].get(("normal", "x")).item() == 10
    assert history[3].get(("normal", "lastx")).item() == 20  # the bet's last position


WALLED = """BasicGame
    SpriteSet
        floor > Immovable
        barrier > Immovable
        camel > Missile orientation={orientation} speed=0.7
        avatar > MovingAvatar
    InteractionSet
        camel barrier > stepBack {perfect}
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > floor
        b > floor barrier
        c > floor camel
        A > floor avatar
"""


def test_a_pixel_perfect_step_back_puts_a_camel_flush_against_the_barrier():
    """7 px a move: 0, 7, 14, then 21 overlaps the barrier at 30; a plain stepBack goes back to
    14, a pixel-perfect one stops flush at 20 and stays there."""
    for orientation, rows, perfect, seen in (
        ("RIGHT", ("c..b", "A..."), "", [0, 7, 14, 14, 14]),
        ("RIGHT", ("c..b", "A..."), "pixelPerfect=True", [0, 7, 14, 20, 20]),
        ("LEFT", ("b..c", "A..."), "pixelPerfect=True", [30, 23, 16, 10, 10]),
    ):
        text = WALLED.format(orientation=orientation, perfect=perfect)
        vgdl = VGDLGame.from_text(text, f"walled{orientation}{bool(perfect)}.txt")
        history = play(vgdl, rows, [NIL] * 5)
        assert [sprites(vgdl, state, ["camel"])[0][1] for state in history] == seen


PAINT = """BasicGame
    SpriteSet
        ground > Immovable
        paint > Immovable
        mark > Flicker limit=2
        marking > Resource limit=2
        avatar > MovingAvatar
    InteractionSet
        mark avatar > killSprite
        ground avatar > spawn stype=mark scoreChange=5
        mark ground > changeResource resource=marking value=1
        mark ground > spawnIfHasMore resource=marking limit=2 stype=paint
        ground mark > killIfOtherHasMore resource=marking limit=2 scoreChange=1
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > ground
        G > ground ground
        A > avatar ground
"""


def test_a_still_type_spawns_once_per_sprite_and_is_killed_by_a_table_sprite_that_has_more():
    """Tick 0: the ground under the avatar spawns a mark (+5), which takes 1 marking. Tick 1, one
    cell right onto two grounds: each spawns a mark (+10), each of which takes a marking per ground
    (2, the limit); the first mark, left behind, takes its second: each application of
    spawnIfHasMore makes a paint (1 + 2 x 2), and every ground under a mark with 2 is killed (+3)."""
    vgdl = VGDLGame.from_text(PAINT, "paint.txt")
    assert vgdl.layout.places["ground"].representation == "grid"
    assert vgdl.layout.places["mark"].representation == "table"
    history = play(vgdl, ("AG..",), [NIL, RIGHT])  # 4 cells: 4 slots for marks
    assert history[0].get("score").item() == 5
    assert sprites(vgdl, history[0], ["mark"]) == [["mark", 0, 0]]
    assert history[1].get("score").item() == 18
    assert sprites(vgdl, history[1], ["mark"]) == [["mark", 0, 0], ["mark", 10, 0], ["mark", 10, 0]]
    assert history[1].get("paint")[0].tolist() == [[1, 4, 0, 0]]
    assert history[1].get("ground")[0].tolist() == [[0, 0, 1, 1]]


SICK = """BasicGame
    SpriteSet
        floor > Immovable
        sick > Immovable
        hosts >
            fast > Missile orientation=LEFT speed=0.5
                host1 >
            slow > Missile orientation=RIGHT speed=0.1
                host2 >
        avatar > MovingAvatar
    InteractionSet
        hosts sick > transformTo stype=sick scoreChange=1
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > floor
        s > floor sick
        f > floor host1
        l > floor host2
        A > floor avatar
"""


def test_what_a_transform_makes_is_no_second_of_the_same_rule():
    """Tick 3: host1 (5 px a move left from 20) reaches 5 and becomes a sick sprite there; host2
    (1 px right from 10), at 13, overlaps that new sprite but not the old one at 0: Java's rule
    took its seconds before it applied, so host2 becomes sick only in tick 4, at 14."""
    vgdl = VGDLGame.from_text(SICK, "sick.txt")
    assert vgdl.layout.places["host1"].key != vgdl.layout.places["host2"].key  # two sides
    history = play(vgdl, ("slf", "A.."), [NIL] * 5)
    names = ["sick", "host1", "host2"]
    assert sprites(vgdl, history[3], names) == [["host2", 13, 0], ["sick", 0, 0], ["sick", 5, 0]]
    assert history[3].get("score").item() == 1
    assert sprites(vgdl, history[4], names) == [["sick", 0, 0], ["sick", 5, 0], ["sick", 14, 0]]


DOORS = """BasicGame
    SpriteSet
        floor > Immovable
        door > SpawnPoint stype=walker total=2 cooldown=3 portal=True
        walker > RandomNPC speed=0
        avatar > MovingAvatar
    InteractionSet
        avatar walker > killSprite
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > floor
        d > floor door
        A > floor avatar
"""


def test_a_spawn_point_with_a_total_is_killed_once_it_made_that_many():
    vgdl = VGDLGame.from_text(DOORS, "doors.txt")
    assert vgdl.layout.places["door"].representation == "table"  # it keeps a count
    history = play(vgdl, ("A.d", "d.."), [NIL] * 5)
    counts = [(len(sprites(vgdl, s, ["door"])), len(sprites(vgdl, s, ["walker"]))) for s in history]
    # ticks 0 and 3 (tick % cooldown == 0) each door makes a walker; at 3 it has made 2: killed
    assert counts == [(2, 2), (2, 2), (2, 2), (0, 4), (0, 4)]
    assert sprites(vgdl, history[4], ["walker"]) == [["walker", 0, 10]] * 2 + [["walker", 20, 0]] * 2


ZEN = """BasicGame
    SpriteSet
        ground > Immovable
        walked > Immovable
        mark > Flicker limit=1
        avatar > MovingAvatar
    InteractionSet
        avatar walked > stepBack
        ground avatar > transformTo stype=walked scoreChange=1
        walked avatar > spawn stype=mark
    TerminationSet
        MultiSpriteCounter stype1=mark stype2=ground limit=0 win=True
    LevelMapping
        . > ground
        G > ground ground
        A > avatar
"""


def test_a_still_type_transforms_into_another_in_its_own_cells():
    """Tick 1 onto two grounds: both become walked (+2), each of which spawns a mark; tick 2 onto
    the last ground (+1); tick 3 left onto walked: stepped back."""
    vgdl = VGDLGame.from_text(ZEN, "zen.txt")
    assert vgdl.layout.places["walked"].representation == "grid"
    history = play(vgdl, ("AG.",), [NIL, RIGHT, RIGHT, LEFT])
    assert [state.get("score").item() for state in history] == [0, 2, 3, 3]
    assert [state.get("ground")[0].tolist() for state in history[:3]] == [
        [[0, 2, 1]],
        [[0, 0, 1]],
        [[0, 0, 0]],
    ]
    assert history[2].get("walked")[0].tolist() == [[0, 2, 1]]
    assert sprites(vgdl, history[1], ["mark"]) == [["mark", 10, 0]] * 2
    assert history[3].get(("avatar", "x")).item() == 20
    assert not history[3].get("won").item()  # the marks under the avatar keep it from winning


def refusal(text: str) -> str:
    with pytest.raises(VGDLError) as caught:
        VGDLGame.from_text(text, "mine.txt")
    message = str(caught.value)
    assert "\n" not in message
    return message


def test_what_these_kernels_do_not_cover_is_refused_in_one_line():
    # a later rule that kills a still first applies once whether it meets the renewed sprite alone
    # or also the killed one Java keeps as a second (labyrinthdual's exit); one that spawns would not
    killed_once = BETS.replace(
        "        avatar pit > transformTo stype=bet scoreChange=10",
        "        avatar pit > transformTo stype=bet scoreChange=10\n        pit normal > killSprite",
    )
    assert "pit" in VGDLGame.from_text(killed_once, "mine.txt").layout.plan.types
    renewed_second = killed_once.replace("pit normal > killSprite", "pit normal > spawn stype=arena")
    assert refusal(renewed_second) == (
        "mine.txt:9: transformTo of normal into itself, with normal a second of a rule, is not implemented"
    )
    drawn = DOORS.replace("cooldown=3 portal=True", "cooldown=3 prob=0.5")
    assert refusal(drawn) == (
        "mine.txt:4: door: a SpawnPoint held as a table is implemented for level spawners with prob 1"
    )
    kept = PAINT.replace("mark > Flicker limit=2", "mark > Missile orientation=LEFT")
    assert refusal(kept).startswith(
        "mine.txt:10: spawn from a still (grid) type is implemented for spawn with"
    )
