"""The generic VGDL step beside the hand-written engines: env steps/s of the same game both ways.

Each study game with a registered VGDL description (``gvgai_pcg.vgdl.registry``) is ticked by
its hand-written engine and by the generic step on that description (``VGDLGame``), eagerly and
through the engine's compiled tick (``engine_tick``: where a tick does not compile, it runs
eagerly, as the env would run it). The tick alone: a batch of the game's human levels (repeated),
uniformly random actions (the same for both engines), no env wrapper, resets or observations. The
two engines' windows alternate (hand-written, generic, hand-written ...), so both see the same
load; steps per CPU second of this process (a loaded machine moves CPU time less than wall time),
and the figure is generic / hand-written of the median windows. A game without a
description says so in one line.
"""

from __future__ import annotations

import statistics
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import torch

from gvgai_pcg.bench.peers import load_average, slowest
from gvgai_pcg.bench.targets import Section
from gvgai_pcg.bench.throughput import MIN_CALLS, WINDOWS, Rate
from gvgai_pcg.bench.timing import time_windows
from gvgai_pcg.engine.compiled import engine_tick
from gvgai_pcg.games import Game, get_game, registered_games
from gvgai_pcg.levels import human_levels
from gvgai_pcg.progress import track
from gvgai_pcg.vgdl.registry import VGDLEntry
from gvgai_pcg.vgdl.registry import registered_games as vgdl_games

BATCH_SIZES = (12, 64, 1024, 4096)
MODES = ("eager", "compiled")
WARM_UP_TICKS = 3  # before the windows: the compiled tick compiles in its first calls
ACTION_ROWS = 64  # random action rows drawn once, played in turn


@dataclass(frozen=True)
class GenericRow:
    """One game at one batch size in one mode: both engines' steps/s."""

    game: str
    batch: int
    mode: str  # "eager" or "compiled"
    hand_written: Rate
    generic: Rate

    @property
    def ratio(self) -> float:
        return self.generic.median / self.hand_written.median


def described_games(games: Sequence[str]) -> dict[str, VGDLEntry]:
    """The games of ``games`` that a registered VGDL description plays, with its entry."""
    entries = {entry.levels: entry for entry in vgdl_games().values()}
    return {game: entries[game] for game in games if game in entries}


def generic_game(entry: VGDLEntry) -> Game:
    from gvgai_pcg.vgdl.engine import VGDLGame

    return VGDLGame.from_file(entry.description, name=f"vgdl:{entry.name}", draw_order=entry.draw_order)


class Ticking:
    """Ticks a fresh batch of ``level_game``'s human levels once a call, with the next row of
    random actions, and returns ``batch``; warmed up (compiled) when made. ``state`` is the batch."""

    def __init__(self, game: Game, level_game: str, batch: int, mode: str, seed: int = 0) -> None:
        levels = (human_levels(level_game) * batch)[:batch]
        self.state = game.compile(levels, torch.arange(batch) + seed, torch.device("cpu"))
        generator = torch.Generator().manual_seed(seed)
        self.actions = torch.randint(0, game.num_actions, (ACTION_ROWS, batch), generator=generator)
        self.tick = engine_tick(game) if mode == "compiled" else game.tick
        self.batch, self.calls = batch, 0
        for _ in range(WARM_UP_TICKS):
            self()

    def __call__(self) -> int:
        self.tick(self.state, self.actions[self.calls % ACTION_ROWS])
        self.calls += 1
        return self.batch


def alternated(works: Sequence[Callable[[], int]], seconds: float, windows: int = WINDOWS) -> list[Rate]:
    """Each of ``works`` timed in ``windows`` windows of at least ``seconds / windows`` seconds,
    the works' windows alternating; a ``Rate`` (median, slowest, fastest) of units per CPU second
    of this process for each (the machine's other load moves CPU time less than wall time)."""
    rates: list[list[float]] = [[] for _ in works]
    for _ in range(windows):
        for index, work in enumerate(works):
            window = time_windows(work, seconds / windows, 1, MIN_CALLS)[0]
            rates[index].append(window.units / max(window.cpu, 1e-9))
    return [Rate(statistics.median(r), min(r), max(r)) for r in rates]


def measure_rows(
    games: Sequence[str],
    batch_sizes: Sequence[int] = BATCH_SIZES,
    modes: Sequence[str] = MODES,
    min_seconds: float = 2.0,
    progress: bool = True,
) -> list[GenericRow]:
    """Both engines of every described game of ``games`` at each batch size and mode."""
    configs = [
        (game, entry, mode, batch)
        for game, entry in described_games(games).items()
        for mode in modes
        for batch in batch_sizes
    ]
    rows = []
    for game, entry, mode, batch in track(configs, "generic VGDL step", "config", progress):
        engines = (get_game(game), generic_game(entry))
        works = [Ticking(engine, game, batch, mode) for engine in engines]
        hand_written, generic = alternated(works, min_seconds)
        rows.append(GenericRow(game, batch, mode, hand_written, generic))
    return rows


def generic_lines(rows: list[GenericRow], without: Sequence[str], load: str) -> list[str]:
    """The Markdown subsection: a row per game and batch size, eager and compiled side by side."""
    lines = [
        "",
        "### The generic VGDL step beside the hand-written engines",
        "",
        "The tick alone (no env, resets or observations), human levels repeated, random actions, "
        "on the package's own VGDL description of the game (`gvgai-pcg vgdl list`) and on the "
        "hand-written engine, eagerly and through the engine's compiled tick; the two engines' "
        "windows alternate. Steps per CPU second of this process (less moved by the machine's other load "
        "than wall time): medians of the same windows, the slowest in brackets; "
        f"generic / hand-written of the medians. Measured with {load} at the end.",
    ]
    if rows:
        lines += [
            "",
            "| game | B | eager: hand-written | eager: generic | generic / hand-written "
            "| compiled: hand-written | compiled: generic | generic / hand-written |",
            "|---|---:|---:|---:|---:|---:|---:|---:|",
        ]
    by_config = {(row.game, row.batch, row.mode): row for row in rows}
    for game, batch in dict.fromkeys((row.game, row.batch) for row in rows):
        cells = []
        for mode in MODES:
            row = by_config.get((game, batch, mode))
            cells += (
                ["-", "-", "-"]
                if row is None
                else [slowest(row.hand_written), slowest(row.generic), f"{row.ratio:.2f}x"]
            )
        lines.append(f"| {game} | {batch} | " + " | ".join(cells) + " |")
    if without:
        lines += ["", f"No description yet: {', '.join(without)}."]
    return lines


def generic_section(
    games: Sequence[str] | None = None,
    batch_sizes: Sequence[int] = BATCH_SIZES,
    min_seconds: float = 2.0,
    progress: bool = True,
    modes: Sequence[str] = MODES,
) -> Section:
    """Every study game of ``games`` (all by default): its engines' ratio where it has a
    description, "no description yet" where it has none."""
    games = tuple(games or registered_games())
    rows = measure_rows(games, batch_sizes, modes, min_seconds, progress)
    without = [game for game in games if game not in described_games(games)]
    return Section("\n".join(generic_lines(rows, without, load_average())) + "\n")


def main(argv: list[str]) -> int:
    """``python -m gvgai_pcg.bench.generic [B ...]``: this section alone, printed."""
    sizes = tuple(int(b) for b in argv) or BATCH_SIZES
    print(generic_section(None, sizes).text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
