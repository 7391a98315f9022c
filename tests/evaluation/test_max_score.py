"""Max scores derived from levels and rules (RULES.md §4.6, 5.8, 6.6, 7.6)."""

import pytest
import torch

from gvgai_pcg.evaluation.max_score import level_max_score, mean_max_score
from gvgai_pcg.games import get_game
from gvgai_pcg.levels import Level, human_levels


@pytest.mark.parametrize(
    ("game", "expected"),
    [
        ("zelda", [8, 8, 8, 10, 8]),
        ("solarfox", [32, 29, 34, 70, 62]),  # level 1 has 29 blibs (the paper's 32 is a copy error)
        ("frogs", [1, 1, 1, 1, 1]),
        ("boulderdash", [22, 22, 22, 22, 22]),  # 10-diamond cap + 2 butterflies with crabs
    ],
)
def test_human_levels(game, expected):
    assert [level_max_score(level) for level in human_levels(game)] == expected


def level(game, *rows):
    return Level.parse("\n".join(rows), game)


def test_zelda_two_per_monster_plus_key_and_door():
    assert level_max_score(level("zelda", "wwwwwww", "wA1.2gw", "w+...3w", "wwwwwww")) == 2 * 3 + 2


def test_solarfox_blibs_and_powerblibs():
    assert level_max_score(level("solarfox", "wwwwww", "wbbbpw", "w.Ap.w", "wwwwww")) == 3 + 2 * 2


def test_frogs_one_for_the_goal():
    assert level_max_score(level("frogs", "wwwww", "wg..w", "w..Aw", "wwwww")) == 1


@pytest.mark.parametrize(
    ("rows", "expected"),
    [
        (("wwwwwww", "wAxxx.w", "wbc.b.w", "w....ew", "wwwwwww"), 2 * (3 + 2) + 2),  # k = 2 butterflies
        (("wwwwwww", "wAxxx.w", "wb..b.w", "w....ew", "wwwwwww"), 2 * 3),  # no crab: k = 0
        (("wwwwwwwwwwwww", "wAxxxxxxxxxxw", "wbbcx......ew", "wwwwwwwwwwwww"), 2 * 10 + 2),  # cap at 10
    ],
)
def test_boulderdash_capped_diamonds_plus_butterflies_with_a_crab(rows, expected):
    assert level_max_score(level("boulderdash", *rows)) == expected


def test_boulderdash_several_butterflies_meet_one_crab_in_one_tick():
    """RULES.md §7.4 rules 15-16: the crab is killed by the first butterfly it touches, but it is
    removed only at the end of the tick, so every butterfly touching it in that tick turns into a
    diamond (+1 each). So k counts all butterflies even with a single crab."""
    game = get_game("boulderdash")
    cross = level("boulderdash", "wwwww", "wwbww", "wbcbw", "wwbww", "wwwww", "wAwew", "wwwww")
    n = 256
    state = game.compile([cross] * n, torch.arange(n), torch.device("cpu"))
    score, biggest_tick = torch.zeros(n, dtype=torch.int64), torch.zeros(n, dtype=torch.int64)
    for _ in range(30):
        game.tick(state, torch.zeros(n, dtype=torch.int64))
        biggest_tick = torch.maximum(biggest_tick, state["score"] - score)
        score = state["score"].clone()
    assert int(biggest_tick.max()) >= 2  # two or more butterflies met the one crab in one tick
    assert bool((score == biggest_tick).all())  # after that tick the crab is gone: no more points
    assert int(score.max()) <= level_max_score(cross) == 2 * 4 + 4


def test_mean_over_a_set():
    assert mean_max_score(human_levels("zelda")) == pytest.approx(42 / 5)
    with pytest.raises(ValueError):
        mean_max_score([])
