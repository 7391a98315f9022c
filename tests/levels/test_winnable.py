"""Levels without what their game needs to be won are named in a warning, once."""

from __future__ import annotations

import logging

import pytest

from gvgai_pcg.levels import LEVEL_FORMATS, Level, human_levels
from gvgai_pcg.levels.test_sets import TEST_DIFFICULTIES, frozen_test_set
from gvgai_pcg.levels.winnable import missing_to_win, warn_unwinnable


@pytest.mark.parametrize(
    ("game", "rows", "says"),
    [
        ("zelda", ["wwwww", "wA.gw", "wwwww"], "key (+): needs 1, has 0"),
        ("zelda", ["wwwww", "wA+.w", "wwwww"], "goal (g): needs 1, has 0"),
        ("boulderdash", ["wwwww", "wAxxw", "wwwww"], "exit (e): needs 1, has 0"),
        ("boulderdash", ["wwwwwwwwwww", "wAxxxxxxxxe", "wwwwwwwwwww"], "diamonds (x): needs 9, has 8"),
        ("frogs", ["wwwww", "wA++w", "wwwww"], "goal (g): needs 1, has 0"),
        ("solarfox", ["wwwww", "wA++w", "wwwww"], "pill (b or p): needs 1, has 0"),
    ],
)
def test_what_a_level_lacks_to_be_won(game, rows, says):
    assert says in missing_to_win(Level(game, tuple(rows)))


@pytest.mark.parametrize("game", sorted(LEVEL_FORMATS))
def test_the_shipped_levels_can_all_be_won(game):
    levels = human_levels(game) + [lv for d in TEST_DIFFICULTIES for lv in frozen_test_set(game, d)]
    assert [lv.name for lv in levels if missing_to_win(lv)] == []


def test_an_unwinnable_level_is_named_once(caplog):
    keyless = Level("zelda", ("wwwww", "wA.gw", "wwwww"), name="zelda_keyless_once")
    with caplog.at_level(logging.WARNING, logger="gvgai_pcg.levels.winnable"):
        assert warn_unwinnable([keyless, keyless, human_levels("zelda")[0]], "training") == [keyless]
        assert warn_unwinnable([keyless], "evaluation") == []
    assert [r.getMessage() for r in caplog.records] == [
        "training level zelda_keyless_once cannot be won (key (+): needs 1, has 0)"
    ]


def test_evaluating_an_unwinnable_level_warns_with_its_name(tmp_path, caplog):
    from gvgai_pcg.evaluation import RandomAgent, evaluate_levels

    path = tmp_path / "zelda_nokey.txt"
    path.write_text("wwwwww\nwA..gw\nwwwwww\n")
    with caplog.at_level(logging.WARNING, logger="gvgai_pcg.levels.winnable"):
        evaluate_levels("zelda", [Level.load(path)], RandomAgent(5), episodes=1, max_steps=5, progress=False)
    assert "evaluation level zelda_nokey cannot be won (key (+)" in caplog.text


@pytest.mark.parametrize("game", sorted(LEVEL_FORMATS))
def test_generated_levels_can_be_won(game):
    # why training checks only given levels: the generators always place what a win needs
    from gvgai_pcg.generators import generate_level

    levels = [generate_level(game, d, seed) for d in (0.0, 0.5, 1.0) for seed in range(40)]
    assert [(lv.name, missing_to_win(lv)) for lv in levels if missing_to_win(lv)] == []
