"""Boulderdash scenarios (RULES.md §7.7), max scores, batched equals single, boulder invariants.

Scenarios that need a monster to walk a given way monkeypatch ``boulderdash.draw_enemy_directions``
(the one random decision of the game); everything else is deterministic.
"""

import pytest
import torch

from gvgai_pcg.games import get_game
from gvgai_pcg.games.boulderdash import rules as boulderdash
from gvgai_pcg.games.geometry import DOWN, LEFT, RIGHT, UP
from gvgai_pcg.levels import Level, human_level

GAME = get_game("boulderdash")


def play(rows: list[str], actions: list[str], seed: int = 0) -> list[dict]:
    """Snapshots of ticks 0..len(actions): the reset tick with NIL, then one tick per action."""
    state = GAME.compile([Level("boulderdash", tuple(rows))], torch.tensor([seed]), torch.device("cpu"))
    snaps = []
    for name in ["NIL", *actions]:
        GAME.tick(state, torch.tensor([GAME.actions.index(name)]))
        snaps.append(GAME.snapshot(state, 0))
    return snaps


def sprites(snap: dict, name: str) -> list[tuple[int, int]]:
    return [(x, y) for kind, x, y in snap["sprites"] if kind == name]


def force_directions(monkeypatch, direction_of) -> list[int]:
    """Make every enemy draw ``direction_of(draw_tick, slot)``; returns the draw ticks asked for."""
    asked = []

    def draw(seed, draw_tick, slots):
        asked.append(int(draw_tick[0]))
        return torch.tensor([[direction_of(int(draw_tick[0]), int(s)) for s in slots]], dtype=torch.int64)

    monkeypatch.setattr(boulderdash, "draw_enemy_directions", draw)
    return asked


# --- boulders ---


def test_unsupported_boulder_falls_2px_per_tick_from_tick_1_and_lands_aligned_supported_one_rests():
    level = ["wwwww", "wo.ow", "w-..w", "w-A.w", "wwwwe"]
    snaps = play(level, ["NIL"] * 15)
    falling = [y for s in snaps for x, y in sprites(s, "boulder") if x == 10]
    assert falling[:12] == [10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30, 30]
    assert falling[10:] == [30] * 6  # aligned on the wall, for good
    assert all((30, 10) in sprites(s, "boulder") for s in snaps)  # the dirt under it holds it


def test_dirt_dug_this_tick_still_holds_the_boulder_and_the_pickaxe_undermines_it():
    level = ["wwwww", "w.o.w", "wA..w", "wwwwe"]
    snaps = play(level, ["USE"] + ["NIL"] * 7)
    assert (20, 20) not in sprites(snaps[1], "dirt")  # dug by the pickaxe at tick 1 ...
    assert sprites(snaps[1], "boulder") == [(20, 10)]  # ... but held by the dead dirt in that tick
    assert [sprites(s, "boulder")[0][1] for s in snaps[1:]] == [10, 12, 14, 16, 18, 20, 20, 20]
    assert snaps[-1]["avatar"]["x"] == 10 and snaps[-1]["status"] == "running"


def test_boulders_fall_through_the_exit_never_roll_and_diamonds_never_fall():
    level = ["wwwwww", "wo.x.w", "we.-ow", "w-A-ow", "wwwwww"]
    snaps = play(level, ["NIL"] * 14)
    falling = [y for s in snaps for x, y in sprites(s, "boulder") if x == 10]
    assert falling[5] == 20 and falling[10:] == [30] * 5  # through the exit's cell onto the wall
    for snap in snaps:
        assert sprites(snap, "exitdoor") == [(10, 20)]
        assert sprites(snap, "diamond") == [(30, 10)]  # an empty cell below, and it stays
        assert [y for x, y in sprites(snap, "boulder") if x == 40] == [20, 30]  # free cells beside


def test_the_avatar_cannot_push_a_boulder():
    snaps = play(["wwwww", "wAo-w", "wwwwe"], ["RIGHT", "RIGHT"])
    assert [s["avatar"]["x"] for s in snaps] == [10, 10, 10]
    assert sprites(snaps[-1], "boulder") == [(20, 10)]


def test_a_boulder_passes_through_a_monster_that_stays_and_steps_back_one_that_walks_into_it(monkeypatch):
    level = ["wwwww", "w.o.w", "w.-.w", "w.c.w", "wA-.w", "wwwwe"]
    force_directions(monkeypatch, lambda tick, slot: LEFT)  # into dirt: the crab never leaves
    snaps = play(level, ["NIL"] * 16)
    assert [sprites(s, "boulder")[0][1] for s in snaps] == [10 + 2 * t for t in range(16)] + [40]
    assert all(sprites(s, "crab") == [(20, 30)] for s in snaps)

    force_directions(monkeypatch, lambda tick, slot: UP)
    snaps = play(level, ["NIL"] * 12)
    crab_y = [sprites(s, "crab")[0][1] for s in snaps]
    assert crab_y == [30] * 10 + [20, 10, 10]  # stepped back while the boulder overlaps the cell above


# --- the avatar and boulders ---


def test_moving_sideways_under_a_boulder_bounces_back_but_collects_the_diamond_there():
    level = ["wwwwww", "w.o..w", "wAx..w", "w....w", "wwwwwe"]
    snaps = play(level, ["RIGHT"] + ["NIL"] * 6)
    first = snaps[1]
    assert (first["avatar"]["x"], first["avatar"]["y"]) == (10, 20)
    assert first["score"] == 2 and first["avatar"]["resources"] == {"diamond": 1}
    assert sprites(first, "diamond") == []
    assert sprites(first, "boulder") == [(20, 10)]  # held by the collected diamond this tick
    assert [sprites(s, "boulder")[0][1] for s in snaps[1:]] == [10, 12, 14, 16, 18, 20, 20]
    assert snaps[-1]["status"] == "running"


def test_moving_up_under_a_boulder_bounces_back_digs_and_is_then_crushed_standing_below():
    level = ["wwwww", "w.o.w", "w...w", "w.A.w", "wwwwe"]
    snaps = play(level, ["UP", "UP"] + ["NIL"] * 6)
    dig = snaps[2]
    assert (dig["avatar"]["x"], dig["avatar"]["y"]) == (20, 30)
    assert (20, 20) not in sprites(dig, "dirt")
    assert sprites(dig, "boulder") == [(20, 10)]
    assert [sprites(s, "boulder")[0][1] for s in snaps[3:8]] == [12, 14, 16, 18, 20]
    assert snaps[7]["avatar"] is not None and snaps[7]["score"] == 0
    assert snaps[8]["avatar"] is None and snaps[8]["score"] == -1 and snaps[8]["status"] == "lose"
    assert sprites(snaps[8], "boulder") == [(20, 22)]


def test_a_standing_avatar_under_an_unsupported_boulder_dies_at_tick_1():
    snaps = play(["wwwww", "w.o.w", "w.A.w", "w...w", "wwwwe"], ["NIL"])
    assert snaps[0]["avatar"] is not None
    assert snaps[1]["avatar"] is None and snaps[1]["score"] == -1 and snaps[1]["status"] == "lose"


# --- monsters ---


def test_monsters_stand_still_at_tick_0_then_move_every_tick_with_a_draw_every_other_tick(monkeypatch):
    asked = force_directions(monkeypatch, lambda tick, slot: RIGHT if tick % 4 == 1 else LEFT)
    snaps = play(["wwwwwww", "w-c---w", "wA....w", "wwwwwwe"], ["NIL"] * 6)
    assert [sprites(s, "crab")[0][0] for s in snaps] == [20, 30, 40, 30, 20, 30, 40]
    assert asked[1:] == [1, 1, 3, 3, 5, 5]  # drawn at odd ticks, kept for the next (tick 0's is unused)


def test_monsters_stay_in_their_pocket_of_dirt_and_diamonds():
    level = Level("boulderdash", ("wwwwwww", "w.....w", "w.c-x.w", "w.....w", "wA...ew", "wwwwwww"))
    batch = 16
    state = GAME.compile([level] * batch, torch.arange(batch), torch.device("cpu"))
    for _ in range(100):
        GAME.tick(state, torch.zeros(batch, dtype=torch.int64))
        x, y = state.get(("enemies", "x")), state.get(("enemies", "y"))
        assert ((x == 20) | (x == 30)).all() and (y == 20).all()
    assert state.get(("enemies", "x")).unique().tolist() == [20, 30]  # they did move
    assert GAME.snapshot(state, 0)["sprites"].count(["diamond", 40, 20]) == 1


def test_monsters_stand_on_the_exit_and_crabs_overlap_crabs(monkeypatch):
    force_directions(monkeypatch, lambda tick, slot: RIGHT)
    snaps = play(["wwwwwww", "wcce--w", "wA....w", "wwwwwww"], ["NIL"] * 3)
    assert sprites(snaps[1], "crab") == [(20, 10), (30, 10)]
    assert sprites(snaps[2], "crab") == [(30, 10), (40, 10)]  # on the exit, which stays
    assert sprites(snaps[2], "exitdoor") == [(30, 10)]
    force_directions(monkeypatch, lambda tick, slot: RIGHT if slot == 0 else DOWN)
    snaps = play(["wwwwwww", "w.cc..w", "wA.w..w", "wwwwwwe"], ["NIL"] * 2)
    assert sprites(snaps[1], "crab") == [(30, 10), (30, 10)]  # the second is walled in below
    assert sprites(snaps[2], "crab") == [(30, 10), (30, 10)]  # both blocked, still together


def test_a_crab_meeting_a_butterfly_leaves_a_diamond_where_the_butterfly_was(monkeypatch):
    force_directions(monkeypatch, lambda tick, slot: LEFT)  # butterfly into dirt, crab onto it
    snaps = play(["wwwwww", "w.bc.w", "wA...w", "wwwwwe"], ["NIL"])
    assert snaps[1]["score"] == 1
    assert sprites(snaps[1], "crab") == [] and sprites(snaps[1], "butterfly") == []
    assert sprites(snaps[1], "diamond") == [(20, 10)]


def test_walking_into_a_monster_or_a_monster_walking_in_kills(monkeypatch):
    force_directions(monkeypatch, lambda tick, slot: LEFT)
    snaps = play(["wwwwww", "w-A-bw", "wwwwwe"], ["NIL", "NIL"])
    assert snaps[2]["avatar"] is None and snaps[2]["score"] == -1 and snaps[2]["status"] == "lose"


# --- the pickaxe and the exit ---


def test_the_pickaxe_digs_the_faced_cell_without_moving_and_lives_two_frames():
    snaps = play(["wwwwww", "wA...w", "wwwwwe"], ["USE"] * 5)
    assert [s["avatar"]["x"] for s in snaps] == [10] * 6
    assert sprites(snaps[1], "dirt") == [(30, 10), (40, 10)]
    assert [sprites(s, "sword") for s in snaps] == [[], [(20, 10)], [(20, 10)], [], [(20, 10)], [(20, 10)]]


def test_the_exit_is_walkable_below_nine_diamonds_and_opens_with_nine():
    snaps = play(["wwwwwwwwwwwww", "wAxxxxxxxxe-w", "wwwwwwwwwwwww"], ["RIGHT"] * 10)
    assert snaps[9]["avatar"]["x"] == 100 and snaps[9]["status"] == "running"
    assert sprites(snaps[10], "exitdoor") == [(100, 10)] and snaps[10]["score"] == 16
    snaps = play(["wwwwwwwwwwwww", "wAxxxxxxxxxew", "wwwwwwwwwwwww"], ["RIGHT"] * 10)
    assert snaps[10]["status"] == "win" and snaps[10]["score"] == 18 and sprites(snaps[10], "exitdoor") == []


def test_opening_the_exit_while_dying_loses(monkeypatch):
    force_directions(monkeypatch, lambda tick, slot: UP)  # the crab steps onto the exit and stays
    level = ["wwwwwwwwwwwww", "wAxxxxxxxxxew", "wwwwwwwwwwwcw", "wwwwwwwwwwwww"]
    snaps = play(level, ["RIGHT"] * 10)
    assert sprites(snaps[1], "crab") == [(110, 10)]
    assert snaps[9]["avatar"]["resources"] == {"diamond": 9}
    last = snaps[10]
    assert last["avatar"] is None and sprites(last, "exitdoor") == []
    assert last["status"] == "lose" and last["score"] == 9 * 2 - 1


# --- off the screen (no border wall: RULES.md §1.1, §7.7) ---
#
# boulderdash.txt has no EOS rule, and nothing in the rules depends on where the screen ends: a
# level surrounded by more background plays exactly the same, moved by the margin. So the same
# scenario is played on the open level (its sprites leave the screen, where the engine tests them
# by rectangles) and with a margin of background around it (they stay on the screen, where it
# reads grid cells): every snapshot must agree. The avatar's side is also checked against the
# Java engine (golden traces boulderdash_offgrid_*); the monsters' cannot be, as they move at
# random there, so these scenarios script their directions.

MARGIN = 4


def surrounded(rows: list[str], margin: int = MARGIN) -> list[str]:
    """``rows`` with ``margin`` cells of background on every side."""
    width = len(rows[0]) + 2 * margin
    return (
        ["-" * width] * margin + ["-" * margin + row + "-" * margin for row in rows] + ["-" * width] * margin
    )


def moved_back(snap: dict, margin: int = MARGIN) -> dict:
    """A snapshot of the surrounded level in the open level's coordinates."""
    d = 10 * margin
    avatar = snap["avatar"] and {**snap["avatar"], "x": snap["avatar"]["x"] - d, "y": snap["avatar"]["y"] - d}
    sprites = sorted(([k, x - d, y - d] for k, x, y in snap["sprites"]), key=lambda s: (s[0], s[2], s[1]))
    return {**snap, "avatar": avatar, "sprites": sprites}


def play_open_and_surrounded(rows: list[str], actions: list[str], seed: int = 0) -> list[dict]:
    """Snapshots of the open level, checked tick by tick against the surrounded one."""
    snaps = play(rows, actions, seed)
    for tick, (open_snap, inner) in enumerate(zip(snaps, play(surrounded(rows), actions, seed), strict=True)):
        assert open_snap == moved_back(inner), f"tick {tick}"
    return snaps


def test_a_crab_following_a_boulder_out_of_the_screen_is_stepped_back_by_it(monkeypatch):
    """Rule 5 (moving × boulder) for a monster off the screen: the crab, held by the wall on its
    right until tick 5, then walks down after the boulder that falls out of the level, and is
    stepped back whenever its step would overlap it, so it keeps one cell behind it."""
    force_directions(monkeypatch, lambda tick, slot: RIGHT if tick < 5 else DOWN)
    snaps = play_open_and_surrounded(["cw-A", "o---"], ["NIL"] * 16)
    assert [sprites(s, "boulder") for s in snaps] == [[(0, 10 + 2 * t)] for t in range(17)]
    assert [sprites(s, "crab")[0][1] for s in snaps] == [0] * 5 + [10] * 5 + [20] * 5 + [30] * 2


def test_a_butterfly_turned_into_a_diamond_off_the_screen_stops_a_boulder_and_a_crab(monkeypatch):
    """Rules 16, 11 and 14 off the screen: the butterfly (slot 0) and a crab (slot 1) walk out of the
    bottom and meet at (20, 30): +1, a diamond there. The other crab (slot 2) walking into it is
    stepped back (rule 14), and the boulder falling out of the level lands on it (rule 11)."""
    plan = {1: (DOWN, DOWN, DOWN), 3: (RIGHT, LEFT, LEFT), 5: (UP, UP, LEFT)}
    force_directions(monkeypatch, lambda tick, slot: plan.get(tick, (UP, UP, RIGHT))[slot])
    snaps = play_open_and_surrounded(["Awo-ww", "wb-c-c"], ["NIL"] * 14)
    assert snaps[2]["score"] == 0 and snaps[3]["score"] == 1
    assert all(sprites(s, "diamond") == [(20, 30)] for s in snaps[3:])
    assert sprites(snaps[3], "butterfly") == [] and sprites(snaps[3], "crab") == [(40, 30)]
    assert [sprites(s, "crab")[0][0] for s in snaps[4:10]] == [30, 30, 30, 40, 50, 60]  # back at 5, 6
    assert [sprites(s, "boulder")[0][1] for s in snaps[9:]] == [18, 20, 20, 20, 20, 20]


def test_the_avatar_collects_a_diamond_off_the_screen(monkeypatch):
    """Rule 3 off the screen: the diamond a butterfly left below the screen at tick 3 is collected
    (+2) when the avatar walks onto it at tick 6, and is gone."""
    plan = {1: (DOWN, DOWN), 3: (RIGHT, LEFT)}
    force_directions(monkeypatch, lambda tick, slot: plan.get(tick, (UP, UP))[slot])
    snaps = play_open_and_surrounded(
        ["A--", "b-c"], ["DOWN", "DOWN", "DOWN", "DOWN", "RIGHT", "RIGHT", "NIL"]
    )
    assert sprites(snaps[5], "diamond") == [(10, 30)] and snaps[5]["score"] == 1
    assert (snaps[6]["avatar"]["x"], snaps[6]["avatar"]["y"]) == (10, 30)
    assert snaps[6]["score"] == 3 and snaps[6]["avatar"]["resources"] == {"diamond": 1}
    assert sprites(snaps[6], "diamond") == sprites(snaps[7], "diamond") == []


def test_only_a_level_without_a_full_wall_border_lets_sprites_leave_its_screen():
    """The tick does its off-screen work only in a batch holding such a level (``open``): walls
    stop everything that moves, so a full wall border keeps every sprite on the screen. An exit
    on the border is walkable, so it opens the border. Every human level is closed."""
    closed, gap, exit_corner = ("wwww", "wA-w", "wwww"), ("wwww", "wA--", "wwww"), ("wwwe", "wA-w", "wwww")
    levels = [human_level("boulderdash", i) for i in range(5)]
    levels += [Level("boulderdash", rows) for rows in (closed, gap, exit_corner)]
    state = GAME.compile(levels, torch.arange(8), torch.device("cpu"))
    assert state.get("open").tolist() == [False] * 6 + [True, True]


@pytest.mark.parametrize(
    "rows",
    [("A-o", "o.x", "-cb"), ("--e", "Ao-"), ("oe", "--", "A-"), ("b-o-c", "-o-o-", "c-A-b"), ("Aoooo",)],
)
def test_an_open_level_plays_as_with_a_margin_around_it(rows):
    """Random actions and monsters, four seeds at once: the avatar, the monsters and the boulders
    leave the screen on every side and meet out there, as they would on a larger screen."""
    seeds, ticks = torch.arange(4), 120
    actions = torch.randint(0, 6, (ticks, 4), generator=torch.Generator().manual_seed(len(rows[0])))
    actions[0] = 0
    states = [
        GAME.compile([Level("boulderdash", r)] * 4, seeds, torch.device("cpu"))
        for r in (rows, surrounded(rows))
    ]
    for tick in range(ticks):
        for state in states:
            GAME.tick(state, actions[tick])
        for env in range(4):
            assert GAME.snapshot(states[0], env) == moved_back(GAME.snapshot(states[1], env)), (
                f"{env}, {tick}"
            )


# --- scores ---


@pytest.mark.parametrize("index", range(5))
def test_max_score_of_every_human_level_is_22(index):
    assert GAME.max_score(human_level("boulderdash", index)) == 22


def test_the_studys_max_scores_ignore_the_ten_diamond_cap():
    study = [48, 52, 58, 48, 44]
    for index, paper in enumerate(study):
        level = human_level("boulderdash", index)
        assert paper == 2 * level.count("x") + 2  # every diamond +2, plus 2 butterflies
        assert GAME.max_score(level) < paper
    snaps = play(["wwwwwwwwwwwwwww", "wAxxxxxxxxxxxxw", "wwwwwwwwwwwwwwe"], ["RIGHT"] * 12)
    assert snaps[-1]["score"] == 20 and snaps[-1]["avatar"]["resources"] == {"diamond": 10}
    assert sprites(snaps[-1], "diamond") == [(120, 10), (130, 10)]  # walked over, neither taken nor scored


# --- batching and long runs ---


def test_batched_equals_single():
    levels = [human_level("boulderdash", i % 5) for i in range(6)]
    seeds = torch.tensor([11, 22, 33, 44, 55, 66])
    ticks = 60
    actions = torch.randint(0, 6, (ticks, len(levels)), generator=torch.Generator().manual_seed(3))
    batched = GAME.compile(levels, seeds, torch.device("cpu"))
    singles = [GAME.compile([level], seeds[i : i + 1], torch.device("cpu")) for i, level in enumerate(levels)]
    for t in range(ticks):
        action = actions[t] if t else torch.zeros(len(levels), dtype=torch.int64)
        GAME.tick(batched, action)
        for i, single in enumerate(singles):
            GAME.tick(single, action[i : i + 1])
            assert GAME.snapshot(batched, i) == GAME.snapshot(single, 0), f"env {i}, tick {t}"


def test_boulders_persist_and_end_every_tick_aligned_falling_or_stacked():
    """2,000 random ticks on the human levels. A boulder is cell-aligned or fell 2 px this tick, except
    in one corner case of rule 12 (list order, RULES.md §7.7, confirmed by the Java traces): when
    three touching boulders fall together and the bottom one lands, the middle one is stepped back
    by rule 12 after the top one already fell, so the top one rests 2 px inside the middle one; it
    then misaligns and is held until the one below it moves away."""
    levels = [human_level("boulderdash", i % 5) for i in range(10)]
    state = GAME.compile(levels, torch.arange(10), torch.device("cpu"))
    counts = [level.count("o") for level in levels]
    generator = torch.Generator().manual_seed(0)
    GAME.tick(state, torch.zeros(10, dtype=torch.int64))
    boulders = state.get("boulders")
    below, has_below = boulders.get("below").long(), boulders.get("has_below")
    for _ in range(2000):
        last = boulders.get("y").clone()
        GAME.tick(state, torch.randint(0, 6, (10,), generator=generator))
        y, alive = boulders.get("y"), boulders.get("alive")
        assert alive.sum(-1).tolist() == counts
        stacked = has_below & (torch.gather(last, 1, below) - last == 8) & (y == last)
        assert ((y % 10 == 0) | (y == last + 2) | stacked | ~alive).all()


def test_rule_12_in_list_order_leaves_the_top_of_a_three_stack_2px_low():
    """RULES.md §7.7, as the Java engine does it (golden traces ``boulderdash_stack3_resting``,
    ``boulderdash_three_stack_fall``): in rule 12 the top boulder is checked against the middle
    one's moved position (no overlap, it stays moved), then the middle one is stepped back onto the
    bottom one, so the top one ends 2 px inside it."""
    level = ["wwwww", "w.o.w", "w.o.w", "w.o.w", "wA..w", "w.-.w", "wwwwe"]
    snaps = play(level, ["NIL", "NIL", "RIGHT"] + ["NIL"] * 12)
    column = [[y for _, y in sprites(s, "boulder")] for s in snaps]
    assert column[0] == [10, 20, 30]
    assert column[1:4] == [[12, 20, 30]] * 3  # resting on dirt, the top one sagged at tick 1
    assert (20, 40) not in sprites(snaps[3], "dirt")  # dug at tick 3, holding the stack one more tick
    assert column[4] == [12, 22, 32]  # held once more by the middle one it overlaps
    assert column[5:14] == [[y, y + 10, y + 20] for y in range(14, 31, 2)]  # falling together
    assert column[14:] == [[32, 40, 50]] * 2  # the bottom one landed at tick 13
