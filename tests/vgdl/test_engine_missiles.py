"""The generic step's Missile kernel (``vgdl/engine/missiles.py``) and EOS rules
(``vgdl/engine/eos.py``), on a small description whose every move is worked out by hand from
RULES.md §1-3: a Missile does not move at its first update (tick 0 for level sprites), then moves
``(int)(speed * 10)`` px a tick along its orientation; at the edge of its env's own screen a
stepBack undoes the tick's move, a killSprite removes it (scoring), a wrapAround puts it on the
other side by its orientation."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.engine.compiled import CompiledTick, engine_tick
from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl.engine import VGDLGame

TEXT = """BasicGame
    SpriteSet
        floor > Immovable
        car > Missile orientation=RIGHT speed=0.2
        slow > Missile orientation=LEFT speed=0.1
        rock > Missile orientation=UP
        avatar > MovingAvatar
    InteractionSet
        avatar EOS > stepBack
        slow EOS > killSprite scoreChange=2
        car EOS > wrapAround
        rock EOS > wrapAround
        avatar car > killSprite
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        c > car floor
        s > slow floor
        r > rock floor
        A > avatar floor
        . > floor
"""
LEVEL = Level("mine", ("c....", "..s..", "A..r."))  # 50 x 30 px
WIDE = Level("mine", ("c.......", "..s.....", "......r.", "A......."))  # 80 x 40 px


def game() -> VGDLGame:
    return VGDLGame.from_text(TEXT, "missiles.txt")


def positions(state, key: str, env: int = 0) -> list[tuple[int, int]]:
    table = state.get(key)
    alive = table.get("alive")[env]
    return [(table.get("x")[env, k].item(), table.get("y")[env, k].item()) for k in alive.nonzero().flatten()]


def run(levels: list[Level], actions: list[int], compiled: bool = False):
    vgdl = game()
    state = vgdl.compile(levels, torch.arange(len(levels)), "cpu")
    tick = engine_tick(vgdl) if compiled else vgdl.tick
    history = []
    for action in actions:
        tick(state, torch.full((len(levels),), action))
        history.append(state.clone())
    return vgdl, history


# compiled, a description of its own costs 20 CPU-seconds of compiling; Frogs' compiled play covers it
@pytest.mark.parametrize(
    "compiled", [False, pytest.param(True, marks=pytest.mark.slow)], ids=["eager", "compiled"]
)
def test_missiles_move_after_their_first_update_and_obey_their_eos_rules(compiled):
    nil = 0
    vgdl, history = run([LEVEL, WIDE], [nil] * 24, compiled)
    if compiled:
        tick = engine_tick(vgdl)
        assert isinstance(tick, CompiledTick) and tick.failed is None
    # tick 0: the first update, nothing moves
    assert positions(history[0], "car") == [(0, 0)] and positions(history[0], "slow") == [(20, 10)]
    assert positions(history[0], "rock") == [(30, 20)]
    # car 2 px right a tick; slow 1 px left; rock 10 px up
    assert positions(history[1], "car") == [(2, 0)] and positions(history[1], "slow") == [(19, 10)]
    assert positions(history[2], "rock") == [(30, 0)]
    # rock leaves the top at tick 3 (y = -10) and wraps to its screen's last row (y = 30 - 10)
    assert positions(history[3], "rock") == [(30, 20)]
    assert positions(history[3], "rock", env=1) == [(60, 30)]  # its own screen: 40 px high
    # car: x = 40 at tick 20, 42 at tick 21 is over the right edge of 50 px: wrapped to 0
    assert positions(history[20], "car") == [(40, 0)] and positions(history[21], "car") == [(0, 0)]
    assert positions(history[21], "car", env=1) == [(42, 0)]  # 80 px wide: still on its screen
    # slow: x = -1 at tick 21, killed there (+2) and removed at cleanup
    assert positions(history[20], "slow") == [(0, 10)] and positions(history[21], "slow") == []
    assert history[20].get("score").tolist() == [0, 0] and history[21].get("score").tolist() == [2, 2]


def test_a_moving_avatar_steps_back_from_the_edge():
    left, up, right = 1, 4, 2
    vgdl, history = run([Level("mine", ("....", "....", "A..."))], [0, left, up, up, up, right])
    avatar = [(s.get(("avatar", "x")).item(), s.get(("avatar", "y")).item()) for s in history]
    assert vgdl.actions == ("NIL", "LEFT", "RIGHT", "DOWN", "UP")
    assert avatar == [(0, 20), (0, 20), (0, 10), (0, 0), (0, 0), (10, 0)]
    assert history[-1].get(("avatar", "lastmove")).item() == 0  # it moved this tick


def test_a_wrapping_missile_with_a_cooldown_is_refused():
    """Java's wrapAround resets lastmove, which the EOS kernel does not hold."""
    from gvgai_pcg.vgdl import VGDLError

    with pytest.raises(
        VGDLError, match=r"missiles.txt:11: EOS wrapAround of car \(cooldown above 1\) is not implemented"
    ):
        VGDLGame.from_text(TEXT.replace("speed=0.2", "speed=0.2 cooldown=3"), "missiles.txt")
