"""The generic step's bounceForward (``vgdl/engine/push.py``), undoAll (``undo.py``) and killBoth
(``kill_both.py``) kernels on small Sokoban-like levels worked out by hand from Java's
BounceForward, UndoAll and KillBoth (``Game.eventHandling``'s pair order)."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl import VGDLError
from gvgai_pcg.vgdl.engine import VGDLGame

TEXT = """BasicGame
    SpriteSet
        floor > Immovable
        hole > Immovable
        pit > Immovable
        water > Immovable
        box > Passive
        crate > Passive
        shot > Missile orientation=DOWN
        avatar > MovingAvatar
        wall > Immovable
    InteractionSet
        avatar wall > stepBack
        box avatar > bounceForward
        crate avatar > bounceForward
        box wall box > undoAll
        crate wall > stepBack
        box hole > killSprite scoreChange=1
        box pit > killBoth scoreChange=3
        water crate > killBoth scoreChange=2
        shot EOS > killSprite
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > floor
        w > floor wall
        A > floor avatar
        1 > floor box
        c > floor crate
        0 > floor hole
        p > floor pit
        ~ > floor water
        s > floor shot
"""
ACTIONS = {"NIL": 0, "LEFT": 1, "RIGHT": 2, "DOWN": 3, "UP": 4}


def game(text: str = TEXT, path: str = "pushes.txt") -> VGDLGame:
    return VGDLGame.from_text(text, path)


def play(rows: list[tuple[str, ...]], actions: list[list[str]], vgdl: VGDLGame | None = None) -> list[dict]:
    """Each env's snapshots after each tick (the reset tick first, with NIL); ``actions[t][env]``."""
    vgdl = vgdl or game()
    levels = [Level("mine", level) for level in rows]
    state = vgdl.compile(levels, torch.arange(len(levels)), "cpu")
    history = []
    for step in [["NIL"] * len(levels), *actions]:
        vgdl.tick(state, torch.tensor([ACTIONS[name] for name in step]))
        history.append([vgdl.snapshot(state, env) for env in range(len(levels))])
    return history


def where(record: dict, name: str) -> list[tuple[int, int]]:
    return [(x, y) for kind, x, y in record["sprites"] if kind == name]


def avatar_at(record: dict) -> tuple[int, int]:
    return record["avatar"]["x"], record["avatar"]["y"]


def test_the_avatar_pushes_a_box_one_cell_along_its_own_move():
    history = play([("A1..",)], [["RIGHT"], ["RIGHT"]])
    assert [where(tick[0], "box") for tick in history] == [[(10, 0)], [(20, 0)], [(30, 0)]]
    assert [avatar_at(tick[0]) for tick in history] == [(0, 0), (10, 0), (20, 0)]


def test_a_box_pushed_into_a_wall_or_a_box_undoes_every_move_of_the_tick_in_that_env_only():
    # env 0: into a wall; env 1: into a box; env 2: a free push
    levels = [("A1w.",), ("A11.",), ("A1..",)]
    history = play(levels, [["RIGHT"] * 3])
    last = history[-1]
    assert [avatar_at(record) for record in last] == [(0, 0), (0, 0), (10, 0)]
    assert where(last[0], "box") == [(10, 0)]
    assert where(last[1], "box") == [(10, 0), (20, 0)]
    assert where(last[2], "box") == [(20, 0)]


def test_undo_all_puts_back_sprites_of_every_type_the_missile_too():
    # the shot falls a cell a tick from its second update; the push into the wall undoes its fall too
    levels = [("A1w", "s..", "...", "..."), ("A1.", "s..", "...", "...")]
    history = play(levels, [["RIGHT", "RIGHT"]])
    undone, free = history[-1]
    assert where(history[0][0], "shot") == where(undone, "shot") == [(0, 10)]
    assert where(free, "shot") == [(0, 20)]


def test_a_stepped_back_push_returns_to_where_the_box_began_this_tick_not_the_last():
    # crate wall > stepBack: the crate's start of tick is saved at its update (Java's preMovement)
    history = play([("Ac.w",)], [["RIGHT"], ["RIGHT"]])
    assert [where(tick[0], "crate") for tick in history] == [[(10, 0)], [(20, 0)], [(20, 0)]]
    assert avatar_at(history[-1][0]) == (20, 0)  # the avatar stays on the crate: nothing stops it


def test_a_box_pushed_into_a_hole_is_killed_and_scores():
    history = play([("A10",)], [["RIGHT"], ["RIGHT"]])
    assert where(history[1][0], "box") == [] and history[1][0]["score"] == 1
    assert avatar_at(history[1][0]) == (10, 0)


def test_kill_both_kills_the_box_and_the_pit_once_and_a_grid_first_the_crate():
    history = play([("A1p.",), ("Ac~.",)], [["RIGHT", "RIGHT"]])
    pit_env, water_env = history[-1]
    assert where(pit_env, "box") == [] and where(pit_env, "pit") == [] and pit_env["score"] == 3
    assert where(water_env, "crate") == [] and where(water_env, "water") == [] and water_env["score"] == 2


def test_a_push_the_avatar_did_not_make_moves_nothing():
    # the avatar stepped back from the wall before the push rule: its lastDirection is zero
    text = TEXT.replace(
        "        avatar wall > stepBack\n", "        avatar wall > stepBack\n        avatar box > stepBack\n"
    )
    history = play([("A1..",)], [["RIGHT"]], game(text, "blocked.txt"))
    assert where(history[-1][0], "box") == [(10, 0)] and avatar_at(history[-1][0]) == (0, 0)


@pytest.mark.parametrize(
    ("line", "refusal"),
    [
        ("box box > bounceForward", "@F:bounceForward"),  # a chain push
        ("box avatar > undoAll scoreChange=1", "undoAll with a scoreChange"),
        ("avatar pit > killBoth", "no avatar first"),
        ("box shot > bounceForward", "pushed by records"),
    ],
)
def test_what_the_kernels_do_not_implement_is_refused_in_one_line(line, refusal):
    text = TEXT.replace("        shot EOS > killSprite\n", f"        shot EOS > killSprite\n        {line}\n")
    with pytest.raises(VGDLError, match=refusal) as error:
        game(text, "refused.txt")
    assert "\n" not in str(error.value) and "refused.txt:" in str(error.value)


@pytest.mark.slow  # about 40 s of compiling
def test_the_compiled_tick_plays_what_the_eager_one_plays():
    from gvgai_pcg.engine.compiled import engine_tick

    vgdl = game()
    levels = [
        Level("a", ("wwwwww", "wA1..w", "w.1p.w", "w~c0.w", "wwwwww")),
        Level("b", ("wwwwww", "w.11Aw", "wc~..w", "w.s.pw", "wwwwww")),
    ]
    actions = torch.randint(5, (60, 2), generator=torch.Generator().manual_seed(1))
    actions[0] = 0
    played = []
    for tick in (vgdl.tick, engine_tick(vgdl)):
        state = vgdl.compile(levels, torch.arange(2), "cpu")
        records = []
        for action in actions:
            tick(state, action)
            records.append([vgdl.snapshot(state, env) for env in range(2)])
        played.append(records)
    eager, compiled = played
    assert compiled == eager
    moved = {str(where(tick[0], "box")) for tick in eager} | {str(where(tick[1], "box")) for tick in eager}
    assert len(moved) > 2  # the random walk pushed boxes


def test_undo_all_leaves_a_sprite_made_by_a_transform_in_an_earlier_tick_where_it_is():
    # a half-cell shot falls onto the wall and becomes a stone (off the cells: a table) with the
    # shot's last position; the stone's next update saves where it is (Java's preMovement), so an
    # undo in a later tick leaves it be
    text = TEXT.replace("        wall > Immovable\n", "        wall > Immovable\n        stone > Immovable\n")
    text = text.replace(
        "        shot > Missile orientation=DOWN\n", "        shot > Missile orientation=DOWN speed=0.5\n"
    )
    text = text.replace("        shot EOS > killSprite\n", "        shot wall > transformTo stype=stone\n")
    vgdl = game(text, "stones.txt")
    assert vgdl.layout.places["stone"].representation == "table"
    history = play([("A1.w", "s...", "w...")], [["NIL"], ["NIL"], ["RIGHT"], ["RIGHT"]], vgdl)
    made = next(tick for tick, records in enumerate(history) if where(records[0], "stone"))
    stone = where(history[made][0], "stone")
    assert made < 3 and stone != [(0, 10)]
    assert where(history[3][0], "box") == [(20, 0)]
    assert where(history[4][0], "box") == [(20, 0)] and avatar_at(history[4][0]) == (10, 0)  # undone
    assert where(history[4][0], "stone") == stone
