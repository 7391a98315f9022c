"""Java's ``Timeout`` termination in the generic step: it holds once the game tick (0 on the reset
tick) reaches ``limit``, with ``win`` deciding the verdict, in declaration order with the others;
what it has no kernel for (``use_counter``, ``compare``, ``count_score``) is refused in one line."""

from __future__ import annotations

import pytest

from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl import VGDLError
from gvgai_pcg.vgdl.engine import VGDLGame
from gvgai_pcg.vgdl.engine.trace import play_trace

TEXT = """BasicGame
    SpriteSet
        floor > Immovable
        coin > Immovable
        avatar > MovingAvatar
    LevelMapping
        . > floor
        c > floor coin
        A > floor avatar
    InteractionSet
        coin avatar > killSprite scoreChange=1
        avatar wall > stepBack
    TerminationSet
{terminations}
"""
ROWS = ("wwwwww", "wA.c.w", "wwwwww")


def play(terminations: str, actions: list[str], path: str = "t.txt") -> list[dict]:
    game = VGDLGame.from_text(TEXT.format(terminations=terminations), path)
    return play_trace(game, Level("t", ROWS), actions)


@pytest.mark.parametrize("win, status", [("True", "win"), ("False", "lose")])
def test_timeout_ends_the_game_in_the_tick_that_reaches_its_limit(win: str, status: str):
    ticks = play(f"        Timeout limit=3 win={win}", ["NIL"] * 10)
    assert [tick["status"] for tick in ticks] == ["running"] * 3 + [status]
    assert ticks[-1]["tick"] == 3


def test_a_limit_of_zero_ends_the_game_on_the_reset_tick():
    ticks = play("        Timeout limit=0 win=True", ["NIL"])
    assert [(tick["tick"], tick["status"]) for tick in ticks] == [(0, "win")]


def test_an_earlier_termination_that_holds_in_the_same_tick_decides():
    # the coin is taken in tick 2, the tick the timeout is reached: the first declared decides
    coin, timeout = "        SpriteCounter stype=coin limit=0 win=True", "        Timeout limit=2 win=False"
    ticks = play(f"{coin}\n{timeout}", ["RIGHT"] * 3)
    assert (ticks[-1]["tick"], ticks[-1]["status"], ticks[-1]["score"]) == (2, "win", 1)
    ticks = play(f"{timeout}\n{coin}", ["RIGHT"] * 3)
    assert (ticks[-1]["tick"], ticks[-1]["status"], ticks[-1]["score"]) == (2, "lose", 1)


@pytest.mark.parametrize("extra", ["use_counter=True", "compare=True", "count_score=True"])
def test_a_timeout_parameter_without_kernel_is_refused_at_its_line(extra: str):
    with pytest.raises(VGDLError) as caught:
        play(f"        Timeout limit=5 win=True {extra}", [], path="mine.txt")
    message = str(caught.value)
    assert "\n" not in message and message.startswith("mine.txt:14: Timeout: ")
    assert extra.split("=")[0] in message
