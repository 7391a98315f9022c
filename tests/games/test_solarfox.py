"""Solarfox scenarios at exact ticks (RULES.md §5.3-5.9), max scores, and batched equals single.

Levels are tiny and inline. Shot spawns are random: the tests that need one monkeypatch
``rng.uniform`` (the module's only random draw) to fire at chosen ticks.
"""

import pytest
import torch

from gvgai_pcg.games import get_game, rng
from gvgai_pcg.games.solarfox.rules import SHOTS_PER_ENEMY
from gvgai_pcg.levels import Level, human_level

GAME = get_game("solarfox")
NIL, LEFT, RIGHT, DOWN, UP = range(5)
CPU = torch.device("cpu")


def level(*rows: str) -> Level:
    return Level("solarfox", rows)


def play(lvl: Level, actions: list[int], seed: int = 0, place: tuple[int, int] | None = None) -> list[dict]:
    """Snapshots after tick 0 (NIL) and after each action; ``place`` puts the ship at pixel (x, y)
    before tick 0."""
    state = GAME.compile([lvl], torch.tensor([seed]), CPU)
    if place is not None:
        state.set(("avatar", "x"), torch.tensor([place[0]]))
        state.set(("avatar", "y"), torch.tensor([place[1]]))
    snaps = []
    for action in [NIL, *actions]:
        GAME.tick(state, torch.tensor([action]))
        snaps.append(GAME.snapshot(state, 0))
    return snaps


def sprites(snap: dict, name: str) -> list[list[int]]:
    return [[x, y] for kind, x, y in snap["sprites"] if kind == name]


def ship(snap: dict) -> tuple[int, int] | None:
    return None if snap["avatar"] is None else (snap["avatar"]["x"], snap["avatar"]["y"])


def hover(ticks: int) -> list[int]:
    """UP, DOWN, … : the ship stays in its column, at y - 1 after odd ticks and y after even ones."""
    return [UP if t % 2 == 0 else DOWN for t in range(ticks)]


@pytest.fixture
def fire_at(monkeypatch):
    """Make every enemy on enemyground fire exactly in the given ticks."""

    def install(ticks: set[int]) -> None:
        def uniform(seed, tick, slot, stream):
            shape = torch.broadcast_shapes(tick.unsqueeze(-1).shape, torch.as_tensor(slot).shape)
            fire = torch.tensor([t in ticks for t in tick.tolist()]).unsqueeze(-1)
            return torch.where(fire, 0.0, 1.0).expand(shape).to(torch.float64)

        monkeypatch.setattr(rng, "uniform", uniform)

    return install


# --- §5.9 -------------------------------------------------------------------------------------


def test_level0_blibs_at_ticks_1_and_11_then_right_wall_at_31():
    snaps = play(human_level("solarfox", 0), [NIL] * 31)
    scores = [s["score"] for s in snaps]
    assert scores[0] == 0 and scores[1] == 1 and scores[10] == 1 and scores[11] == 2
    assert ship(snaps[1]) == (51, 50) and ship(snaps[11]) == (61, 50) and ship(snaps[30]) == (80, 50)
    assert snaps[30]["status"] == "running"
    assert snaps[31]["avatar"] is None and snaps[31]["score"] == 2 - 10 and snaps[31]["status"] == "lose"


def test_misaligned_ship_collects_four_blibs_at_once():
    lvl = level("wwwwwwww", "w++++++w", "w++bb++w", "w++bb++w", "w+A++++w", "w++++++w", "wwwwwwww")
    snaps = play(lvl, [], place=(35, 25))  # overlaps cells (3..4) x (2..3); no move in the reset tick
    assert ship(snaps[0]) == (35, 25) and snaps[0]["score"] == 4 and snaps[0]["status"] == "win"


def test_misaligned_ship_dies_on_two_walls():
    lvl = level("wwwwww", "wb+++w", "w+A++w", "w++++w", "wwwwww")
    snaps = play(lvl, [DOWN] * 5 + [RIGHT] * 25)
    assert ship(snaps[5]) == (20, 25)
    assert ship(snaps[25]) == (40, 25) and snaps[25]["score"] == 0
    assert snaps[26]["avatar"] is None and snaps[26]["score"] == -20 and snaps[26]["status"] == "lose"


def test_death_rules_stack_across_types_enemy_and_two_enemyground_tiles():
    lvl = level("w2..w", "w+A+w", "w++bw", "wwwww")
    snaps = play(
        lvl, [UP], place=(15, 10)
    )  # tick 1: (15, 9) overlaps cell 1 (top + ground) and cell 2 (ground)
    assert sprites(snaps[1], "top") == [[10, 0]]
    assert snaps[1]["avatar"] is None and snaps[1]["score"] == -30 and snaps[1]["status"] == "lose"


def test_dying_ship_still_collects_and_lose_is_checked_before_win():
    lvl = level("wwwwwwww", "w+++++ww", "w+A+++bw", "wwwwwwww")
    snaps = play(lvl, [UP] * 5 + [RIGHT] + [NIL] * 30)
    # y = 15 from tick 5: the ship reaches column 6 (wall above, blib below) at x = 51, tick 36.
    assert ship(snaps[35]) == (50, 15) and snaps[35]["score"] == 0
    last = snaps[36]
    assert last["avatar"] is None and last["sprites"] == []
    assert last["score"] == 1 - 10 and last["status"] == "lose"


def test_ship_does_not_move_at_reset_then_one_pixel_with_instant_reversal():
    lvl = level("wwwwwwww", "w++++++w", "w++A+++w", "w+++++bw", "wwwwwwww")
    snaps = play(lvl, [NIL, LEFT, RIGHT, UP, DOWN])
    assert [ship(s) for s in snaps] == [(30, 20), (31, 20), (30, 20), (31, 20), (31, 19), (31, 20)]
    assert [s["avatar"]["orientation"] for s in snaps] == ["RIGHT", "RIGHT", "LEFT", "RIGHT", "UP", "DOWN"]


# --- §5.6 powerblib sequence ----------------------------------------------------------------------


def test_powerblib_staying_on_it_gives_blib_at_t3_and_collects_it_at_t4():
    lvl = level("wwwwwwwwwww", "w+++++++++w", "w+A+p+++++w", "w+++++++++w", "wwwwwwwwwww")
    state = GAME.compile([lvl], torch.tensor([0]), CPU)
    snaps, res = [], []
    for _ in range(16):
        GAME.tick(state, torch.tensor([NIL]))
        snaps.append(GAME.snapshot(state, 0))
        res.append(state.get("res")[0, 2, 4].item())
    t = 11  # first overlap: x = 31 touches the powerblib at x = 40
    assert ship(snaps[t]) == (31, 20) and sprites(snaps[t - 1], "powerblibturning") == []
    for k in range(3):
        assert sprites(snaps[t + k], "powerblib") == [[40, 20]]
        assert sprites(snaps[t + k], "powerblibturning") == [[40, 20]]
        assert res[t + k] == k and snaps[t + k]["score"] == 0
    assert res[t + 3] == 3 and snaps[t + 3]["score"] == 1
    assert sprites(snaps[t + 3], "powerblib") == [] and sprites(snaps[t + 3], "blib") == [[40, 20]]
    assert sprites(snaps[t + 3], "powerblibturning") == []  # rule 7 killed it, rule 9 skipped (P is dead)
    assert snaps[t + 4]["score"] == 2 and snaps[t + 4]["status"] == "win"


def test_powerblib_one_touch_still_yields_blib_and_turning_flickers_ten_frames():
    lvl = level("wwwwwwwwwww", "w+++++++++w", "w+A+p+++++w", "w+++++++++w", "w+b+++++++w", "wwwwwwwwwww")
    snaps = play(lvl, [NIL] * 11 + [LEFT] * 20)
    t = 11
    assert ship(snaps[t]) == (31, 20) and ship(snaps[t + 1]) == (30, 20)
    visible = [k for k, s in enumerate(snaps) if sprites(s, "powerblibturning")]
    assert visible == list(range(t, t + 10))  # present in 11 event phases, shown in 10 frames
    assert [s["score"] for s in snaps[t : t + 4]] == [0, 0, 0, 1]
    assert sprites(snaps[t + 3], "blib") == [[40, 20], [20, 40]] and sprites(snaps[t + 3], "powerblib") == []


def test_each_powerblib_is_worth_exactly_two():
    lvl = level("wwwwwwwwwww", "w+++++++++w", "w+A+pp+++bw", "w+++++++++w", "wwwwwwwwwww")
    snaps = play(lvl, [NIL] * 30)
    # Touches: p1 at x = 31 (tick 11), p2 at x = 41 (tick 21); each: +1 at t+3 (P eaten), +1 at t+4.
    scores = [s["score"] for s in snaps]
    assert scores[13] == 0 and scores[14] == 1 and scores[15] == 2
    assert scores[23] == 2 and scores[24] == 3 and scores[25] == 4
    assert GAME.max_score(lvl) == 5


# --- §5.7 enemies and shots -----------------------------------------------------------------------


def test_enemy_columns_follow_the_54_tick_period():
    snaps = play(human_level("solarfox", 0), [NIL] * 120)
    top = [sprites(s, "top")[0][0] // 10 for s in snaps]
    btm = [sprites(s, "btm")[0][0] // 10 for s in snaps]
    expected_top = []
    col, step = 1, 1
    for t in range(121):
        if t >= 2 and t % 3 == 2:
            col += step
        expected_top.append(col)
        if col in (0, 9) and t % 3 == 1:  # after 3 ticks (3 flips) in a wall column: one reversal
            step = -step
    assert top == expected_top
    assert top[2] == 2 and top[23] == 9 and top[26] == 8 and top[50] == 0 and top[53] == 1
    assert top[:54] == top[54:108]
    assert btm[0] == 8 and btm[2] == 7 and btm[23] == 0 and btm[26] == 1 and btm[50] == 9
    assert sprites(snaps[0], "top") == [[10, 0]] and sprites(snaps[0], "btm") == [[80, 100]]


def test_no_shots_from_wall_columns(fire_at):
    fire_at({23, 24, 25, 26})  # both enemies are in a wall column in 23-25, on enemyground at 26
    snaps = play(human_level("solarfox", 0), [NIL] * 26)
    assert all(not sprites(s, "upshot") and not sprites(s, "downshot") for s in snaps[:26])
    assert sprites(snaps[26], "downshot") == [[80, 0]] and sprites(snaps[26], "upshot") == [[10, 100]]


def test_shot_waits_one_tick_then_flies_one_pixel_through_everything(fire_at):
    fire_at({1})
    lvl = level("ww2..ww", "w+++++w", "w+++++w", "w+++++w", "w++A++w", "w++++bw", "wwwwwww")
    snaps = play(lvl, hover(60))
    assert sprites(snaps[0], "downshot") == [] and sprites(snaps[1], "downshot") == [[20, 0]]
    assert sprites(snaps[2], "downshot") == [[20, 0]] and sprites(snaps[3], "downshot") == [[20, 1]]
    assert sprites(snaps[20], "downshot") == [[20, 18]]
    assert snaps[20]["status"] == "running"
    # The shot moves down 1 px per tick at x = 20; the ship hovers at x = 30, cells apart: no hit.
    assert sprites(snaps[60], "downshot") == [[20, 58]] and snaps[60]["status"] == "running"


def test_shot_kills_the_ship_minus_ten(fire_at):
    fire_at({1})
    lvl = level("ww2..ww", "w+++++w", "w+++++w", "w+++++w", "w+A+++w", "w++++bw", "wwwwwww")
    snaps = play(lvl, hover(50))
    # Ship at x = 20, y = 39 after odd ticks and 40 after even ones; the shot at y = t - 2.
    assert snaps[31]["status"] == "running" and sprites(snaps[31], "downshot") == [[20, 29]]
    assert snaps[32]["avatar"] == {"type": "avatar", "x": 20, "y": 40, "orientation": "DOWN", "resources": {}}
    assert snaps[33]["avatar"] is None and snaps[33]["score"] == -10 and snaps[33]["status"] == "lose"


def test_shot_is_dropped_once_off_screen_and_beyond_the_ship(fire_at):
    """Departure from GVGAI (docs/fidelity.md): GVGAI keeps shots forever."""
    fire_at({1})
    lvl = level("ww2..ww", "w+++++w", "w+++++w", "w+++++w", "w+++A+w", "w++++bw", "wwwwwww")
    snaps = play(lvl, hover(80))
    assert snaps[71]["status"] == "running"
    assert sprites(snaps[71], "downshot") == [[20, 69]]  # y + 10 > 70: still (partly) on the 70-px screen
    assert sprites(snaps[72], "downshot") == []  # y = 70: off screen and beyond the ship, dropped


def test_each_enemy_keeps_at_most_sixteen_shots(fire_at):
    """Departure from GVGAI (docs/fidelity.md): a spawn that finds its enemy's slots full fails."""
    fire_at(set(range(0, 22)))
    snaps = play(human_level("solarfox", 0), hover(22))
    assert len(sprites(snaps[14], "downshot")) == 15
    assert len(sprites(snaps[21], "downshot")) == SHOTS_PER_ENEMY == 16
    assert len(sprites(snaps[21], "upshot")) == 16


# --- scores and batching ----------------------------------------------------------------------------


def test_max_score_of_human_levels_from_the_rules():
    assert [GAME.max_score(human_level("solarfox", i)) for i in range(5)] == [32, 29, 34, 70, 62]


def test_batched_equals_single():
    ticks, count = 90, 6
    levels = [human_level("solarfox", i % 5) for i in range(count)]
    seeds = torch.tensor([11, 22, 33, 44, 55, 66])
    actions = torch.randint(0, 5, (ticks, count), generator=torch.Generator().manual_seed(3))
    actions[:, 3] = torch.tensor(hover(ticks))  # a survivor: its enemies keep firing at it
    batched = GAME.compile(levels, seeds, CPU)
    singles = [GAME.compile([lvl], seeds[i : i + 1], CPU) for i, lvl in enumerate(levels)]
    shots = 0
    for t in range(ticks):
        GAME.tick(batched, actions[t])
        for i, single in enumerate(singles):
            GAME.tick(single, actions[t, i : i + 1])
            assert GAME.snapshot(batched, i) == GAME.snapshot(single, 0)
            for key in single.keys(include_nested=True, leaves_only=True):
                assert torch.equal(batched.get(key)[i], single.get(key)[0]), (t, i, key)
        shots += int(batched.get(("enemies", "shots", "alive")).sum())
    assert shots > 0  # the random shot spawns were exercised


def test_kept_pickups_and_shown_turnings_match_the_grids():
    """The tick keeps the count of blibs and powerblibs left and the grid of shown turnings itself,
    touching only cells near the ship; both must match the grids every tick, on powerblib levels
    and on an open one (no side walls) that the ships leave and come back to."""
    open_level = level(
        "w2.......w",
        *["+p+pb+pp++", "++p++p+b++", "+pp+p+A+p+", "+b+pp+p+b+", "++p+b+pp++"],
        *["+p+pp+pb++", "++b++p+p++", "+pp+p+b+p+", "++p++p+b++"],
        "w.......1w",
    )
    levels = [human_level("solarfox", 3), human_level("solarfox", 4), open_level] * 8
    count, ticks = len(levels), 150
    state = GAME.compile(levels, torch.arange(count), CPU)
    gen = torch.Generator().manual_seed(5)
    action, eaten, away = torch.zeros(count, dtype=torch.int64), 0, 0
    for t in range(ticks):
        turn = torch.rand(count, generator=gen) < 0.15
        action = torch.where(turn, torch.randint(0, 5, (count,), generator=gen), action) if t else action
        GAME.tick(state, action)
        grids = state.get("blib") | state.get("powerblib")
        assert torch.equal(state.get("pickups"), grids.flatten(1).sum(-1, dtype=torch.int32)), t
        shown = state.get("turning_born") >= (state.get("tick") - 9).view(-1, 1, 1)
        assert torch.equal(state.get("turning"), shown), t
        eaten = max(eaten, int((state.get("res") >= 2).sum()))
        x = state.get(("avatar", "x"))
        away += int(((x < 0) | (x > 90)).sum())
    assert eaten > 0 and away > 0  # powerblibs were paired, and ships flew off the grid
