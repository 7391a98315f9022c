"""Peers in the benchmark: other engines measured beside our Zelda tiles in the same run.

On these shared 2-core machines the same configuration moves by a quarter between runs, so a
figure is only compared with another taken in the same minutes. ``gvgai-pcg bench`` therefore
measures, when the optional extra is installed (``pip install -e '.[peers]'``), at each batch
size our Zelda tiles env and then, right after it, the peer:

- XLand-MiniGrid's ``MiniGrid-DoorKey-8x8`` (JAX): ``jax.jit(jax.vmap(env.step))``, uniformly
  random actions drawn inside the same jitted call, and the count of finished episodes read back
  every step as our measurement reads its ``done`` count. Twice: behind xminigrid's own
  ``GymAutoResetWrapper`` (a finished env is reset inside the step, as ours are; under ``vmap``
  its ``lax.cond`` becomes a select, so every env computes a reset every step), and the bare
  step with no resets (the figure the target is set against; random play rarely ends DoorKey's
  640-step episodes). Tracing and XLA compilation (reset and step, with their first calls) are
  timed apart from the steady state.
- Griddly's GVGAI Zelda (Griddly's own port of the game, fed our five human levels in turn),
  one env through its gym wrapper with vector observations and random actions: the single-env
  engine the B = 4,096 target is set against. Griddly ships wheels for Python 3.10 and
  3.11 only, so the extra installs it only there.

VGDLx, a VGDL interpreter in JAX that plays Zelda, Frogs and Boulderdash from GVGAI's own game
descriptions, is measured beside each of those games by :mod:`gvgai_pcg.bench.vgdlx`, on these
helpers.

Both sides are timed by :func:`gvgai_pcg.bench.throughput.windowed_rate` (median of consecutive windows,
the same cap on calls). Nothing here imports JAX or Griddly until a measurement runs, so the
tables can be built (and tested) without the extra.
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version

from gvgai_pcg.bench.targets import DOORKEY_BARE_AT_64, GRIDDLY_AT_4096, Check, Section, ratio
from gvgai_pcg.bench.throughput import Rate, measure_env, windowed_rate
from gvgai_pcg.bench.timing import Stopwatch
from gvgai_pcg.levels import human_levels
from gvgai_pcg.progress import track

DOORKEY = "MiniGrid-DoorKey-8x8"
GAME, OBS = "zelda", "tiles"
NOT_INSTALLED = "peers not installed: pip install -e '.[peers]'"
MAX_CALLS = 300  # measure_env's default cap on step calls, used for the peer too


@dataclass(frozen=True)
class Timed:
    """A rate with what it cost to get there and how many CPU cores it kept busy."""

    rate: Rate
    setup_s: float  # construction and warm-up; for JAX, tracing and compiling included
    cores: float  # process CPU seconds per wall second over the timed windows
    resets: int


@dataclass(frozen=True)
class PeerRow:
    batch: int
    ours: Timed
    doorkey: Timed  # with xminigrid's auto-reset
    bare: Timed  # the bare step, no resets


def missing_peers() -> list[str]:
    """The modules of the extra that cannot be imported (Griddly apart: it is optional in it)."""
    return [name for name in ("jax", "xminigrid") if importlib.util.find_spec(name) is None]


def griddly_installed() -> bool:
    return importlib.util.find_spec("griddly") is not None


def version_of(package: str) -> str:
    try:
        return version(package)
    except PackageNotFoundError:
        return "?"


def timed_rate(step: Callable[[], int], seconds: float, max_steps: int | None) -> tuple[Rate, float]:
    with Stopwatch() as watch:
        rate = windowed_rate(step, seconds, max_steps=max_steps)
    return rate, watch.cores


def measure_ours(batch: int, min_seconds: float = 2.0, game: str = GAME) -> Timed:
    """Our tiles env as the env table measures it (``measure_env``), with its cores."""
    with Stopwatch() as watch:
        result = measure_env(game, batch, OBS, "cpu", min_seconds, max_steps=MAX_CALLS)
    return Timed(result.rate, result.warmup_s, watch.cores, result.resets)


def measure_doorkey(batch: int, min_seconds: float = 2.0, seed: int = 0, auto_reset: bool = True) -> Timed:
    """XLand-MiniGrid DoorKey-8x8, ``jax.jit(jax.vmap(env.step))``, random actions, with xminigrid's
    auto-reset or without resets."""
    import jax
    import xminigrid
    from xminigrid.types import StepType
    from xminigrid.wrappers import GymAutoResetWrapper

    begin = time.perf_counter()
    env, params = xminigrid.make(DOORKEY)
    if auto_reset:
        env = GymAutoResetWrapper(env)
    num_actions = env.num_actions(params)
    reset = jax.jit(jax.vmap(env.reset, in_axes=(None, 0)))
    vstep = jax.vmap(env.step, in_axes=(None, 0, 0))

    @jax.jit
    def step(timestep, key):
        key, draw = jax.random.split(key)
        action = jax.random.randint(draw, (batch,), 0, num_actions)
        timestep = vstep(params, timestep, action)
        return timestep, key, (timestep.step_type == StepType.LAST).sum()

    key, start = jax.random.split(jax.random.key(seed))
    timestep = reset(params, jax.random.split(start, batch))
    for _ in range(3):  # the first call traces and compiles
        timestep, key, finished = step(timestep, key)
    int(finished)
    setup = time.perf_counter() - begin
    resets = 0

    def one() -> int:
        nonlocal timestep, key, resets
        timestep, key, finished = step(timestep, key)
        resets += int(finished)  # waits for the step, as ours waits on its done count
        return batch

    rate, cores = timed_rate(one, min_seconds, MAX_CALLS)
    return Timed(rate, setup, cores, resets)


def _griddly_zelda_yaml() -> str:
    """Griddly's GVGAI Zelda with our human levels 0-4 as its levels. Its level parser reads a
    digit after a character as a player number, so its spider (map character ``3``) becomes
    ``s``, and our monsters (``1``-``3``: its port has one kind) are written as ``s``."""
    from pathlib import Path

    import griddly
    import yaml

    path = Path(griddly.__file__).parent / "resources/games/Single-Player/GVGAI/zelda.yaml"
    spec = yaml.safe_load(path.read_text())
    for obj in spec["Objects"]:
        if obj["Name"] == "spider":
            obj["MapCharacter"] = "s"
    monsters = str.maketrans("123", "sss")
    spec["Environment"]["Levels"] = [
        "\n".join(level.rows).translate(monsters) + "\n" for level in human_levels(GAME)
    ]
    return yaml.safe_dump(spec)


def measure_griddly(min_seconds: float = 2.0, seed: int = 0) -> Timed:
    """Griddly's GVGAI Zelda, one env, random actions, our human levels in turn."""
    begin = time.perf_counter()
    with contextlib.redirect_stderr(io.StringIO()), contextlib.redirect_stdout(io.StringIO()):
        import gym  # noqa: F401  (prints that it is unmaintained)
        from griddly import gd
        from griddly.GymWrapper import GymWrapper

    vector = gd.ObserverType.VECTOR
    yaml_string = _griddly_zelda_yaml()
    env = GymWrapper(yaml_string=yaml_string, player_observer_type=vector, global_observer_type=vector)
    env.action_space.seed(seed)
    env.reset(level_id=0)
    resets = 0

    def one() -> int:
        nonlocal resets
        _, _, done, _ = env.step(env.action_space.sample())
        if done:
            resets += 1
            env.reset(level_id=resets % 5)
        return 1

    for _ in range(3):
        one()
    setup = time.perf_counter() - begin
    rate, cores = timed_rate(one, min_seconds, None)  # one env: time-bounded, not capped
    env.close()
    return Timed(rate, setup, cores, resets)


def measure_peers(
    batch_sizes: tuple[int, ...], min_seconds: float = 2.0, progress: bool = True
) -> tuple[list[PeerRow], Timed | None]:
    """At each batch size ours, then DoorKey right after; then Griddly's one env if installed."""
    rows = []
    for batch in track(batch_sizes, "peers", "batch size", progress):
        ours = measure_ours(batch, min_seconds)
        doorkey = measure_doorkey(batch, min_seconds)
        rows.append(PeerRow(batch, ours, doorkey, measure_doorkey(batch, min_seconds, auto_reset=False)))
    griddly = measure_griddly(min_seconds) if griddly_installed() else None
    return rows, griddly


def load_average() -> str:
    try:
        return "load average " + ", ".join(f"{x:.1f}" for x in os.getloadavg())
    except OSError:
        return "load average unknown"


def slowest(rate: Rate) -> str:
    return f"{rate} ({rate.low:,.0f})"


def _ratio(ours: float, peer: float) -> str:
    return f"{ours / peer:.2f}x" if peer > 0 else "-"


def peer_lines(rows: list[PeerRow], griddly: Timed | None, load: str | None = None) -> list[str]:
    """The Markdown "Peers" subsection: one row per batch size, the ratio ours / peer."""
    header = [
        "",
        "### Peers: the same CPU, the same run",
        "",
        f"Ours: {GAME}, {OBS}, as in the env table, measured again right before the peer at each batch "
        f"size. XLand-MiniGrid {version_of('xminigrid')} `{DOORKEY}` (jax {version_of('jax')}, CPU): "
        "`jax.jit(jax.vmap(env.step))`, random actions drawn inside the jitted call, its count of "
        "finished episodes read back every step; behind its `GymAutoResetWrapper` (resets, like ours; "
        "under `vmap` every env computes a reset every step) and bare (no resets). Compile is tracing, "
        "XLA compilation and the first calls of reset and step, timed apart. Steps/s: medians of the "
        "same windows, the slowest in brackets; cores: CPU seconds per wall second over the windows. "
        f"Measured with {load or load_average()} at the end.",
        "",
        "| B | ours: steps/s | DoorKey, auto-reset | ours / DoorKey | DoorKey, bare step | ours / bare "
        "| cores: ours, auto-reset, bare | compile (s): auto-reset, bare |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    lines = list(header)
    for row in rows:
        ours, peer, bare = row.ours, row.doorkey, row.bare
        lines.append(
            f"| {row.batch} | {slowest(ours.rate)} | {slowest(peer.rate)} "
            f"| {_ratio(ours.rate.median, peer.rate.median)} | {slowest(bare.rate)} "
            f"| {_ratio(ours.rate.median, bare.rate.median)} "
            f"| {ours.cores:.1f}, {peer.cores:.1f}, {bare.cores:.1f} "
            f"| {peer.setup_s:.1f}, {bare.setup_s:.1f} |"
        )
    lines.append("")
    if griddly is None:
        lines.append("Griddly not installed (its wheels are for Python 3.10 and 3.11), so no Griddly row.")
        return lines
    ratios = ", ".join(f"{_ratio(r.ours.rate.median, griddly.rate.median)} at B = {r.batch}" for r in rows)
    lines.append(
        f"Griddly {version_of('griddly')} GVGAI Zelda (its own port, our human levels 0-4 in turn), one env, "
        f"vector observations, random actions: {griddly.rate} steps/s (slowest window "
        f"{griddly.rate.low:,.0f}), {griddly.cores:.1f} cores, {griddly.resets} resets. "
        f"Ours / Griddly: {ratios}."
    )
    return lines


def peer_checks(rows: list[PeerRow], griddly: Timed | None) -> list[Check]:
    """The speed targets on this table: Zelda at 64 envs against DoorKey's bare step, and at
    4,096 against Griddly's one env (not measured where the run has no such row)."""
    by_batch = {row.batch: row for row in rows}
    at_64, at_4096 = by_batch.get(64), by_batch.get(4096)
    bare = ratio(at_64.ours.rate.median, at_64.bare.rate.median) if at_64 else None
    grid = ratio(at_4096.ours.rate.median, griddly.rate.median) if at_4096 and griddly else None
    return [
        Check(f"{GAME} tiles at B = 64 / DoorKey-8x8 bare step at B = 64", DOORKEY_BARE_AT_64, bare),
        Check(f"{GAME} tiles at B = 4,096 / Griddly's one {GAME} env", GRIDDLY_AT_4096, grid),
    ]


def peers_report(batch_sizes: tuple[int, ...], min_seconds: float = 2.0, progress: bool = True) -> Section:
    """The peers subsection and its targets, or the line saying how to install the extra."""
    missing = missing_peers()
    if missing:
        return Section("\n### Peers\n\n" + NOT_INSTALLED + "\n", peer_checks([], None))
    rows, griddly = measure_peers(batch_sizes, min_seconds, progress)
    return Section("\n".join(peer_lines(rows, griddly)) + "\n", peer_checks(rows, griddly))
