"""A level behaves the same whatever it is batched with (gvgai_pcg/games/base.py).

Every game compiles levels of different sizes into the largest grid. A smaller level is padded
outside its screen: no walls appear there, its screen edge stays its own (Frogs' EOS stepBack and
truck wrap, Solarfox's shot bookkeeping), and its sprites that leave the screen (levels without a
border let them) never touch another env's cells. Each level here has no border at all, so its
sprites walk, fly, fall and drive off it, and is played beside a full human level (on both sides)
and alone: every snapshot must be the same.
"""

import pytest
import torch

from gvgai_pcg.games import get_game
from gvgai_pcg.levels import Level, human_level

CPU = torch.device("cpu")
OPEN_LEVELS = {
    "zelda": ("A.2", "+.g", "1.."),
    "solarfox": ("2...", "+Ab+", "+p++", "...1"),
    "frogs": ("g+++", "0=03", "+A++", "-.l.", "x._."),
    "boulderdash": ("A-o", "o.x", "-cb"),
}


def snapshots(game_name: str, levels: list[Level], seeds: torch.Tensor, actions: torch.Tensor) -> list:
    """``[tick][env]`` snapshots of ``levels`` played together, ``actions`` ``[T, B]``."""
    game = get_game(game_name)
    state = game.compile(levels, seeds, CPU)
    out = []
    for action in actions:
        game.tick(state, action)
        out.append([game.snapshot(state, i) for i in range(len(levels))])
    return out


@pytest.mark.parametrize("game_name", sorted(OPEN_LEVELS))
def test_an_open_level_beside_a_larger_one_plays_as_alone(game_name):
    game = get_game(game_name)
    small, big = Level(game_name, OPEN_LEVELS[game_name]), human_level(game_name, 0)
    ticks = 80
    actions = torch.randint(0, game.num_actions, (ticks, 3), generator=torch.Generator().manual_seed(5))
    actions[0] = 0  # the reset tick
    seeds = torch.tensor([7, 8, 9])
    batched = snapshots(game_name, [small, big, small], seeds, actions)
    alone = [snapshots(game_name, [small], seeds[i : i + 1], actions[:, i : i + 1]) for i in (0, 2)]
    for tick in range(ticks):
        assert batched[tick][0] == alone[0][tick][0], f"env 0, tick {tick}"
        assert batched[tick][2] == alone[1][tick][0], f"env 2, tick {tick}"


def test_the_open_levels_reach_their_edges():
    """The test above is only worth something if the levels' edges matter: sprites leave the screen
    in Zelda, Solarfox and Boulderdash, and in Frogs (where nothing ever leaves it: the frog is
    stepped back, trucks wrap) the trucks wrap at the level's own right and left edges."""
    left, truck_xs = set(), set()
    for game_name, rows in OPEN_LEVELS.items():
        game = get_game(game_name)
        ticks = 80
        actions = torch.randint(0, game.num_actions, (ticks, 1), generator=torch.Generator().manual_seed(5))
        actions[0] = 0
        height, width = 10 * len(rows), 10 * len(rows[0])
        for snap in (
            s[0] for s in snapshots(game_name, [Level(game_name, rows)], torch.tensor([7]), actions)
        ):
            placed = [snap["avatar"]] if snap["avatar"] else []
            for x, y in [(a["x"], a["y"]) for a in placed] + [(x, y) for _, x, y in snap["sprites"]]:
                if x < 0 or y < 0 or x + 10 > width or y + 10 > height:
                    left.add(game_name)
            truck_xs |= {x for name, x, _ in snap["sprites"] if game_name == "frogs" and "truck" in name}
    assert left == {"zelda", "solarfox", "boulderdash"}
    assert min(truck_xs) == 0 and max(truck_xs) == 30


def test_a_boulderdash_avatar_off_its_screen_never_touches_the_other_envs_cells():
    """Env 0's avatar walks right off its 2x2 screen, through the cells where env 1, a larger level,
    has dirt, a diamond, walls and a boulder: nothing stops it, nothing is dug or collected in
    either env, and env 1 is as if it were alone."""
    small = Level("boulderdash", ("--", "A-"))
    big = Level("boulderdash", ("wwwwwwwww", "w...x.o.w", "wA......w", "wwwwwwwwe"))
    actions = torch.tensor([[0, 0]] + [[3, 0]] * 8)  # RIGHT (it faces right: a step a tick), NIL
    batched = snapshots("boulderdash", [small, big], torch.tensor([0, 1]), actions)
    assert [s[0]["avatar"]["x"] for s in batched] == [10 * t for t in range(9)]
    assert all(s[0]["avatar"]["y"] == 10 and s[0]["score"] == 0 for s in batched)
    alone = snapshots("boulderdash", [big], torch.tensor([1]), actions[:, 1:])
    assert [s[1] for s in batched] == [s[0] for s in alone]
