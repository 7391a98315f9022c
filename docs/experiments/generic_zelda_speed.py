"""How fast is the generic VGDL step on Zelda, against the hand-written Zelda? (a measurement, not
part of the package.)

Ticks B envs of Zelda's five human levels (repeated) with random actions, on one torch thread,
with each engine: the hand-written ``get_game("zelda")`` and the generic step on the package's own
description (``gvgai_pcg/vgdl/descriptions/zelda.txt``), each eager and through the engine's compiled
tick. Prints env steps per CPU second of this process (the tick alone: no env wrapper, resets or
observations), the median of 5 windows of 50 ticks, each from a fresh batch after 10 warm-up
ticks: CPU time, since the machine may be busy with other runs.

Usage: python docs/experiments/generic_zelda_speed.py [ENVS ...]   (default 64 1024)
"""

from __future__ import annotations

import statistics
import sys
import time

import torch

from gvgai_pcg.engine.compiled import engine_tick
from gvgai_pcg.games import get_game
from gvgai_pcg.levels import human_levels
from gvgai_pcg.vgdl.engine import VGDLGame
from gvgai_pcg.vgdl.registry import registered_game

WINDOWS, TICKS, WARM_UP = 5, 50, 10


def steps_per_second(game, tick, envs: int) -> float:
    levels = (human_levels("zelda") * envs)[:envs]
    generator = torch.Generator().manual_seed(0)
    rates = []
    for window in range(WINDOWS):
        state = game.compile(levels, torch.arange(envs) + 1000 * window, "cpu")
        actions = torch.randint(0, game.num_actions, (WARM_UP + TICKS, envs), generator=generator)
        for action in actions[:WARM_UP]:
            tick(state, action)
        start = time.process_time()
        for action in actions[WARM_UP:]:
            tick(state, action)
        rates.append(TICKS * envs / (time.process_time() - start))
    return statistics.median(rates)


def main(sizes: list[int]) -> None:
    torch.set_num_threads(1)
    generic = VGDLGame.from_file(registered_game("zelda").description)
    games = {"hand-written": get_game("zelda"), "generic": generic}
    print(f"{'envs':>6} {'engine':>13} {'eager':>10} {'compiled':>10}  (env steps per CPU second)")
    for envs in sizes:
        for name, game in games.items():
            eager = steps_per_second(game, game.tick, envs)
            compiled = steps_per_second(game, engine_tick(game), envs)
            print(f"{envs:>6} {name:>13} {eager:>10,.0f} {compiled:>10,.0f}", flush=True)


if __name__ == "__main__":
    main([int(arg) for arg in sys.argv[1:]] or [64, 1024])
