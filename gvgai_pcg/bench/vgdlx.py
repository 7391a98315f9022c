"""VGDLx beside ours: a generic VGDL interpreter in JAX, on GVGAI's own game descriptions.

VGDLx (github.com/shepardxia/VGDLax, ``vgdl_jax``) parses a VGDL game description and a level
into entity arrays and compiles one step; it follows py-vgdl's semantics, not GVGAI's in every
detail (its ``tests/MECHANICS_DIFF.md``). It is not on PyPI, so it is an optional peer: measured
when ``vgdl_jax`` and JAX import (``pip install git+https://github.com/shepardxia/VGDLax`` into
the env that has the ``peers`` extra), else the bench says so in one line.

The game descriptions are GVGAI's ``examples/gridphysics/<game>.txt`` (GPL-3.0-or-later, not
shipped here): read from ``$GVGAI_PCG_VGDL_GAMES/<game>.txt`` when that variable names a folder
(a GVGAI checkout's ``examples/gridphysics``), else downloaded once, at a pinned commit, into the
cache (``$GVGAI_PCG_CACHE``, default ``~/.cache/gvgai-pcg``) under ``vgdl/``. The level is our
human level 0 (a byte copy of GVGAI's ``<game>_lvl0.txt``), as VGDLx's own throughput script
plays level 0.

Measured as the target asks: ``jax.jit(jax.vmap(env.step))``, uniformly random actions drawn inside
the jitted call, the observation returned (so XLA cannot drop its rendering) and the count of
finished envs read back every step, as ours reads its ``done`` count; no auto-reset (a finished
env keeps stepping). Ours is the env table's measure (tiles, human levels, resets at their
natural rate) at the better of one and two torch threads, right before the peer. Nothing here
imports JAX until a measurement runs.
"""

from __future__ import annotations

import importlib.util
import os
import time
import urllib.request
from dataclasses import dataclass
from pathlib import Path

import torch

from gvgai_pcg.bench.peers import MAX_CALLS, Timed, measure_ours, slowest, timed_rate, version_of
from gvgai_pcg.bench.targets import VGDLX_AT, Check, Section, ratio
from gvgai_pcg.evaluation.evaluator import default_cache_dir
from gvgai_pcg.levels import human_levels
from gvgai_pcg.progress import track

GAMES = ("zelda", "frogs", "boulderdash")  # ours that VGDLx plays (it has no Solarfox)
BATCH_SIZES = (64, 4096)
GAMES_VARIABLE = "GVGAI_PCG_VGDL_GAMES"
GVGAI_COMMIT = "e58ff6597319155218759cc178931e05b81b524c"  # GAIGResearch/GVGAI master, 2021-07-12
GVGAI_URL = f"https://raw.githubusercontent.com/GAIGResearch/GVGAI/{GVGAI_COMMIT}/examples/gridphysics"
INSTALL = "pip install git+https://github.com/shepardxia/VGDLax (with the peers extra's jax[cpu])"
NOT_INSTALLED = f"VGDLx not installed: {INSTALL}"
NO_DESCRIPTIONS = (
    f"VGDLx not measured: GVGAI's game descriptions could not be read or downloaded; set "
    f"{GAMES_VARIABLE} to a GVGAI checkout's examples/gridphysics"
)
THREADS = (1, 2)  # ours at the better of these torch thread counts


@dataclass(frozen=True)
class VgdlxRow:
    game: str
    batch: int
    ours: Timed  # at its better thread count
    threads: int  # that thread count
    vgdlx: Timed


def vgdlx_installed() -> bool:
    return all(importlib.util.find_spec(name) is not None for name in ("jax", "vgdl_jax"))


def game_description(game: str) -> str:
    """GVGAI's VGDL description of ``game``: from ``$GVGAI_PCG_VGDL_GAMES``, else the cache,
    downloading it there first."""
    folder = os.environ.get(GAMES_VARIABLE)
    if folder:
        path = Path(folder) / f"{game}.txt"
        if not path.is_file():
            raise FileNotFoundError(
                f"{path}: no such file; {GAMES_VARIABLE} must name a folder with GVGAI's "
                f"{', '.join(f'{g}.txt' for g in GAMES)} (GVGAI's examples/gridphysics)"
            )
        return path.read_text()
    path = default_cache_dir() / "vgdl" / GVGAI_COMMIT[:12] / f"{game}.txt"
    if not path.is_file():
        with urllib.request.urlopen(f"{GVGAI_URL}/{game}.txt", timeout=30) as reply:
            text = reply.read().decode()
        path.parent.mkdir(parents=True, exist_ok=True)
        path.with_suffix(".part").write_text(text)
        path.with_suffix(".part").replace(path)
    return path.read_text()


def level_text(game: str) -> str:
    return "\n".join(human_levels(game)[0].rows) + "\n"


def measure_vgdlx(game: str, batch: int, min_seconds: float = 2.0, seed: int = 0) -> Timed:
    """VGDLx's ``game`` on level 0, ``jax.jit(jax.vmap(env.step))``, random actions, no resets."""
    import jax
    from vgdl_jax.env import VGDLJaxEnv

    begin = time.perf_counter()
    env = VGDLJaxEnv.from_text(game_description(game), level_text(game))
    reset = jax.jit(jax.vmap(env.reset))
    vstep = jax.vmap(env.step)

    @jax.jit
    def step(state, key):
        key, draw = jax.random.split(key)
        action = jax.random.randint(draw, (batch,), 0, env.n_actions)
        obs, state, _, done, _ = vstep(state, action)
        return state, key, obs, done.sum()

    key, start = jax.random.split(jax.random.key(seed))
    _, state = reset(jax.random.split(start, batch))
    for _ in range(3):  # the first call traces and compiles
        state, key, _, finished = step(state, key)
    int(finished)
    setup = time.perf_counter() - begin
    finished_steps = 0

    def one() -> int:
        nonlocal state, key, finished_steps
        state, key, _, finished = step(state, key)
        finished_steps += int(finished)  # waits for the step
        return batch

    rate, cores = timed_rate(one, min_seconds, MAX_CALLS)
    return Timed(rate, setup, cores, finished_steps)


def measure_ours_best(game: str, batch: int, min_seconds: float = 2.0) -> tuple[Timed, int]:
    """Ours (``peers.measure_ours``) at each of ``THREADS`` torch threads: the faster one."""
    threads = torch.get_num_threads()
    timed = {}
    for count in sorted({min(n, os.cpu_count() or 1) for n in THREADS}):
        torch.set_num_threads(count)
        try:
            timed[count] = measure_ours(batch, min_seconds, game)
        finally:
            torch.set_num_threads(threads)
    best = max(timed, key=lambda count: timed[count].rate.median)
    return timed[best], best


def measure_rows(
    games: tuple[str, ...] = GAMES,
    batch_sizes: tuple[int, ...] = BATCH_SIZES,
    min_seconds: float = 2.0,
    progress: bool = True,
) -> list[VgdlxRow]:
    configs = [(game, batch) for game in games for batch in batch_sizes]
    rows = []
    for game, batch in track(configs, "VGDLx", "config", progress):
        ours, threads = measure_ours_best(game, batch, min_seconds)
        rows.append(VgdlxRow(game, batch, ours, threads, measure_vgdlx(game, batch, min_seconds)))
    return rows


def vgdlx_lines(rows: list[VgdlxRow]) -> list[str]:
    """The Markdown "VGDLx" subsection: a row per game and batch size, ours / VGDLx."""
    lines = [
        "",
        "### VGDLx: the same CPU, the same run",
        "",
        f"VGDLx {version_of('vgdl-jax')} (jax {version_of('jax')}, CPU) on GVGAI's own "
        "game descriptions and our human level 0: `jax.jit(jax.vmap(env.step))`, random actions drawn "
        "inside the jitted call, the observation returned, its count of finished envs read back every "
        "step, no auto-reset. Ours: tiles, human levels, resets, measured right before it at 1 and 2 "
        "torch threads, the faster shown. Compile: parsing, tracing, XLA compilation and the first "
        "calls. Medians of the same windows, the slowest in brackets.",
        "",
        "| game | B | ours: steps/s | ours: threads | VGDLx | ours / VGDLx | cores: ours, VGDLx "
        "| compile (s) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        share = ratio(row.ours.rate.median, row.vgdlx.rate.median)
        lines.append(
            f"| {row.game} | {row.batch} | {slowest(row.ours.rate)} | {row.threads} "
            f"| {slowest(row.vgdlx.rate)} | {'-' if share is None else f'{share:.2f}x'} "
            f"| {row.ours.cores:.1f}, {row.vgdlx.cores:.1f} | {row.vgdlx.setup_s:.1f} |"
        )
    return lines


def vgdlx_checks(rows: list[VgdlxRow] | None, games: tuple[str, ...] = GAMES) -> list[Check]:
    """Every game against VGDLx at each batch size the issue sets a ratio for; unmeasured ones
    (VGDLx not installed, a batch size left out) say so."""
    measured = {(row.game, row.batch): row for row in rows or []}
    checks = []
    for game in games:
        for batch, goal in VGDLX_AT.items():
            row = measured.get((game, batch))
            share = ratio(row.ours.rate.median, row.vgdlx.rate.median) if row else None
            checks.append(Check(f"{game} tiles at B = {batch:,} / VGDLx", goal, share))
    return checks


def vgdlx_section(
    games: tuple[str, ...], batch_sizes: tuple[int, ...], min_seconds: float = 2.0, progress: bool = True
) -> Section:
    """VGDLx beside each of ``games`` it plays, at the target batch sizes (``VGDLX_AT``) among ``batch_sizes``
    (all of ``batch_sizes`` when none is); one line instead when VGDLx is not installed."""
    games = tuple(game for game in GAMES if game in games)
    if not games:
        return Section()
    if not vgdlx_installed():
        return Section(f"\n### VGDLx\n\n{NOT_INSTALLED}\n", vgdlx_checks(None, games))
    try:
        for game in games:
            game_description(game)
    except OSError as error:  # no such folder or file, no network
        return Section(f"\n### VGDLx\n\n{NO_DESCRIPTIONS} ({error})\n", vgdlx_checks(None, games))
    sizes = tuple(batch for batch in batch_sizes if batch in BATCH_SIZES) or batch_sizes
    rows = measure_rows(games, sizes, min_seconds, progress)
    return Section("\n".join(vgdlx_lines(rows)) + "\n", vgdlx_checks(rows, games))
