"""The generic VGDL step against the hand-written engines on one torch thread, eagerly or
compiled: generic / hand-written env steps per CPU second for each study game and batch size (a
measurement, not part of the package).

Each line is one (game, B): the bench's own ``Ticking`` of both engines (human levels repeated,
the same random actions), their windows alternating (``bench.generic.alternated``), medians of 5
windows; the machine's other load moves both engines alike, so read the ratio, and compare ratios
of the same run. ``--compiled`` ticks both through the engine's compiled tick (tens of
CPU-seconds of compiling a game and size).

Usage: python docs/experiments/generic_ratios.py [GAME ...] [B ...] [--secs S] [--compiled]
       (default: the four study games at 64 and 1024 envs, 3 s a measurement, eager)
"""

from __future__ import annotations

import sys

import torch

from gvgai_pcg.bench.generic import Ticking, alternated, described_games, generic_game
from gvgai_pcg.games import get_game


def main(args: list[str]) -> None:
    torch.set_num_threads(1)
    seconds, mode = 3.0, "compiled" if "--compiled" in args else "eager"
    args = [arg for arg in args if arg != "--compiled"]
    if "--secs" in args:
        at = args.index("--secs")
        seconds = float(args[at + 1])
        del args[at : at + 2]
    games = [arg for arg in args if not arg.isdigit()] or ["zelda", "frogs", "boulderdash", "solarfox"]
    sizes = [int(arg) for arg in args if arg.isdigit()] or [64, 1024]
    entries = described_games(games)
    for game in games:
        for batch in sizes:
            engines = (get_game(game), generic_game(entries[game]))
            works = [Ticking(engine, game, batch, mode) for engine in engines]
            hand, generic = alternated(works, seconds, windows=5)
            print(
                f"{game:12s} B={batch:5d} {mode}: hand-written {hand.median:10,.0f}  generic "
                f"{generic.median:10,.0f}  ratio {generic.median / hand.median:.2f}",
                flush=True,
            )


if __name__ == "__main__":
    main(sys.argv[1:])
