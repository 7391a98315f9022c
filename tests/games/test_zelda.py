"""Zelda rules (RULES.md §4.7) as scripted scenarios on small inline levels."""

import pytest
import torch

from gvgai_pcg.games.geometry import DOWN, LEFT, RIGHT, UP
from gvgai_pcg.levels import human_level
from tests.games.zelda_helpers import ACTION, ZELDA, play, script_directions, sprite_at


def alternate_right_left(tick, slot):
    """RIGHT on draws at even ticks, LEFT on draws at odd ticks."""
    return torch.where(tick % 2 == 0, RIGHT, LEFT) + 0 * slot


@pytest.mark.parametrize(
    ("char", "kind", "draws", "moves"),
    [
        ("1", "monsterQuick", [6, 13, 20], [6, 8, 10, 12, 14, 16, 18, 20, 22, 24]),
        ("2", "monsterNormal", [8, 17], [8, 12, 16, 20, 24]),
        ("3", "monsterSlow", [12, 25], [12, 20]),
    ],
)
def test_monster_schedule(monkeypatch, char, kind, draws, moves):
    script_directions(monkeypatch, alternate_right_left)
    rows = [
        "wwwwwwwwwwwwwwwwwwwwwwwww",
        "w" + "." * 11 + char + "." * 11 + "w",
        "wA....................g.w",
        "w" * 25,
    ]
    snaps = play(rows, ["NIL"] * 25)
    columns = [sprite_at(s, kind)[0][0] for s in snaps]
    moved = [t for t in range(1, 26) if columns[t] != columns[t - 1]]
    assert moved == moves
    # Between two draws the direction is held; it flips at every draw of the alternating script.
    direction_at = {t: columns[t] - columns[t - 1] for t in moved}
    for t in moved:
        last_draw = max(d for d in draws if d <= t)
        assert direction_at[t] == (1 if last_draw % 2 == 0 else -1)
    assert all(c == columns[0] for c in columns[: moves[0]])  # still until its first move


def test_blocked_moves_still_consume_the_cooldown(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.full_like(tick + slot, UP))
    rows = ["wwwww", "w.2.w", "wA.gw", "wwwww"]  # the monster faces the wall above it
    snaps = play(rows, ["NIL"] * 20)
    assert all(sprite_at(s, "monsterNormal") == [(2, 1)] for s in snaps)
    script_directions(monkeypatch, lambda tick, slot: torch.where(tick < 10, UP, DOWN) + 0 * slot)
    snaps = play(["wwwww", "w.2.w", "w...w", "wA.gw", "wwwww"], ["NIL"] * 20)
    cells = [sprite_at(s, "monsterNormal")[0] for s in snaps]
    # Drawn UP at 8 (into the wall: undone), DOWN at 17 (moves at 20, not earlier).
    assert cells[16] == (2, 1) and cells[19] == (2, 1) and cells[20] == (2, 2)


def test_everything_stays_cell_aligned_under_random_play():
    levels = [human_level("zelda", i % 5) for i in range(20)]
    state = ZELDA.compile(levels, torch.arange(20), torch.device("cpu"))
    generator = torch.Generator().manual_seed(0)
    for _ in range(300):
        ZELDA.tick(state, torch.randint(0, 6, (20,), generator=generator))
        for key in (("avatar", "x"), ("avatar", "y"), ("monsters", "x"), ("monsters", "y")):
            assert (state.get(key) % 10 == 0).all()


def test_swapping_cells_passes_through(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.full_like(tick + slot, LEFT))
    snaps = play(["wwwwwww", "wA1...w", "w....gw", "wwwwwww"], ["NIL"] * 5 + ["RIGHT"])
    assert snaps[6]["avatar"]["x"] == 20 and sprite_at(snaps[6], "monsterQuick") == [(1, 1)]
    assert snaps[6]["score"] == 0 and snaps[6]["status"] == "running"


def test_monster_walking_into_the_avatar_kills_it(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.full_like(tick + slot, LEFT))
    snaps = play(["wwwwwww", "wA1...w", "w....gw", "wwwwwww"], ["NIL"] * 6)
    assert snaps[5]["status"] == "running"
    assert snaps[6]["avatar"] is None and snaps[6]["score"] == -1 and snaps[6]["status"] == "lose"


def test_two_monsters_in_one_cell_first_in_order_goes_back(monkeypatch):
    # slot 0 = the quick monster (quick before normal), slot 1 = the normal one.
    script_directions(monkeypatch, lambda tick, slot: torch.where(slot == 0, RIGHT, LEFT) + 0 * tick)
    snaps = play(["wwwwwww", "w1..2.w", "wA...gw", "wwwwwww"], ["NIL"] * 12)
    assert sprite_at(snaps[6], "monsterQuick") == [(2, 1)]
    assert sprite_at(snaps[8], "monsterQuick") == [(2, 1)]  # both entered column 3: quick went back
    assert sprite_at(snaps[8], "monsterNormal") == [(3, 1)]
    assert sprite_at(snaps[10], "monsterQuick") == [(2, 1)]  # blocked by the standing normal monster
    assert sprite_at(snaps[12], "monsterQuick") == [(3, 1)]  # swap: they pass through each other
    assert sprite_at(snaps[12], "monsterNormal") == [(2, 1)]


def test_at_most_one_monster_reaches_the_avatar(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.where(slot == 0, RIGHT, LEFT) + 0 * tick)
    snaps = play(["wwwwwww", "w.2A2.w", "w....gw", "wwwwwww"], ["NIL"] * 8)
    assert snaps[8]["score"] == -1 and snaps[8]["status"] == "lose"
    assert sprite_at(snaps[8], "monsterNormal") == [(2, 1), (3, 1)]


def test_sword_lifetime_and_cooldown():
    snaps = play(["wwwwwww", "wA...gw", "wwwwwww"], ["USE"] * 16)
    present = [t for t, s in enumerate(snaps) if sprite_at(s, "sword")]
    assert present == [1, 2, 3, 4, 5, 6, 8, 9, 10, 11, 12, 13, 15, 16]
    assert all(sprite_at(snaps[t], "sword") == [(2, 1)] for t in present)


def test_monster_stepping_out_of_the_faced_cell_survives(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.full_like(tick + slot, DOWN))
    snaps = play(["wwwww", "wA1.w", "w...w", "w..gw", "wwwww"], ["NIL"] * 5 + ["USE"])
    assert sprite_at(snaps[6], "sword") == [(2, 1)]
    assert sprite_at(snaps[6], "monsterQuick") == [(2, 2)] and snaps[6]["score"] == 0


def test_monster_walking_into_a_dying_sword_still_dies(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.full_like(tick + slot, UP))
    # USE at tick 2: the sword is in the event phase of ticks 2..8 and drawn at 2..7.
    snaps = play(["wwwww", "wA..w", "w.2.w", "w..gw", "wwwww"], ["NIL", "USE"] + ["NIL"] * 6)
    assert sprite_at(snaps[7], "sword") == [(2, 1)]
    assert (
        snaps[8]["score"] == 2
        and sprite_at(snaps[8], "monsterNormal") == []
        and sprite_at(snaps[8], "sword") == []
    )


def test_killed_monster_still_kills_the_avatar_in_the_same_tick(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.full_like(tick + slot, UP))
    # USE at tick 2 puts the sword at (2, 1); the avatar steps onto it at tick 3; the monster
    # walks into that cell at tick 8: +2 for the kill, -1 for the touch, lose.
    snaps = play(["wwwww", "wA..w", "w.2.w", "w..gw", "wwwww"], ["NIL", "USE", "RIGHT"] + ["NIL"] * 5)
    assert snaps[3]["avatar"]["x"] == 20 and sprite_at(snaps[3], "sword") == [(2, 1)]
    assert snaps[8]["score"] == 1 and snaps[8]["status"] == "lose" and snaps[8]["avatar"] is None


def test_key_then_door_wins_and_key_faces_right():
    snaps = play(["wwwwww", "w+A.gw", "wwwwww"], ["LEFT", "LEFT", "RIGHT", "RIGHT", "RIGHT"])
    assert snaps[1]["avatar"]["orientation"] == "LEFT" and snaps[1]["avatar"]["x"] == 20
    assert snaps[2]["avatar"] == {
        "type": "withkey",
        "x": 10,
        "y": 10,
        "orientation": "RIGHT",
        "resources": {},
    }
    assert snaps[2]["score"] == 1 and sprite_at(snaps[2], "key") == []
    assert snaps[3]["avatar"]["x"] == 20  # facing RIGHT already: the first RIGHT moves
    assert snaps[5]["status"] == "win" and snaps[5]["score"] == 2


def test_door_and_monster_in_the_same_tick_is_a_win(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.full_like(tick + slot, LEFT))
    # Key at tick 2, then to column 3 by tick 4; the door (column 4) is entered at tick 8, the
    # tick in which the normal monster makes its first move, into the same cell.
    actions = ["LEFT", "LEFT", "RIGHT", "RIGHT", "NIL", "NIL", "NIL", "RIGHT"]
    snaps = play(["wwwwwww", "w+A.g2w", "wwwwwww"], actions)
    assert snaps[2]["score"] == 1 and snaps[7]["avatar"]["x"] == 30
    assert snaps[8]["status"] == "win" and snaps[8]["score"] == 1  # +1 key, +1 door, -1 monster


def test_walls_and_the_closed_door_step_the_avatar_back():
    snaps = play(["wwwww", "wAg.w", "w..+w", "wwwww"], ["RIGHT", "UP", "UP", "LEFT", "LEFT"])
    assert [(s["avatar"]["x"], s["avatar"]["y"]) for s in snaps] == [(10, 10)] * 6
    assert sprite_at(snaps[-1], "goal") == [(2, 1)] and snaps[-1]["score"] == 0


def test_a_disabled_avatar_still_scores_the_key_but_keeps_no_key(monkeypatch):
    script_directions(monkeypatch, lambda tick, slot: torch.full_like(tick + slot, LEFT))
    # At tick 6 the avatar steps onto the key while the quick monster steps onto it too.
    snaps = play(["wwwwwww", "wA+1..w", "w....gw", "wwwwwww"], ["NIL"] * 5 + ["RIGHT"])
    assert snaps[6]["score"] == 0  # -1 for the monster, +1 for the key, no transform
    assert snaps[6]["avatar"] is None and sprite_at(snaps[6], "key") == [(2, 1)]


def test_max_score_per_human_level():
    assert [ZELDA.max_score(human_level("zelda", i)) for i in range(5)] == [8, 8, 8, 10, 8]


def test_batched_equals_single():
    levels = [human_level("zelda", i % 5) for i in range(6)]
    seeds = torch.tensor([3, 17, 256, 1000, 7, 99])
    actions = torch.randint(0, 6, (150, 6), generator=torch.Generator().manual_seed(1))
    batched = ZELDA.compile(levels, seeds, torch.device("cpu"))
    singles = [ZELDA.compile([lv], seeds[i : i + 1], torch.device("cpu")) for i, lv in enumerate(levels)]
    for t in range(150):
        ZELDA.tick(batched, actions[t])
        for i, single in enumerate(singles):
            ZELDA.tick(single, actions[t, i : i + 1])
            assert ZELDA.snapshot(batched, i) == ZELDA.snapshot(single, 0)
    assert ACTION["USE"] == 1
