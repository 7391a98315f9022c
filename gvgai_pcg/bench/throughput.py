"""Throughput benchmarks: env steps/s per game, batch size and observation kind, generator
levels/s, and resets/s with a generating level source.

Warm-up (first reset and the first steps, where allocators and caches settle) is timed apart
from the steady state. Resets happen at their natural rate: finished envs are reset through the
``"_reset"`` mask as a collector would. The steady state is timed in consecutive windows and the
median window is reported with the slowest and fastest: on a shared machine a burst of load from
elsewhere spoils a window or two, which drags a mean over the whole run down but not the median
(the windows are :mod:`gvgai_pcg.bench.timing`'s, shared by every measurement of the bench).
Numbers go into ``docs/benchmarks.md`` between markers, one section per device kind, so a GPU run
does not erase the CPU figures.
"""

from __future__ import annotations

import os
import platform
import re
import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import torch
from tensordict import TensorDict

from gvgai_pcg.bench.targets import Check, Section, env_checks
from gvgai_pcg.bench.timing import Stopwatch, time_windows
from gvgai_pcg.engine.compiled import engine_tick
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.level_sources import GeneratedLevels
from gvgai_pcg.envs.shards import ShardedStepper
from gvgai_pcg.games import get_game, get_game_spec, registered_games
from gvgai_pcg.games.render import render_tiles
from gvgai_pcg.generators import registered_generators
from gvgai_pcg.generators.speed import levels_per_second
from gvgai_pcg.levels import human_levels
from gvgai_pcg.progress import track

BATCH_SIZES = (12, 64, 1024, 4096)  # 12: the study's envs; 64: training's default
ENGINE_BATCH = 4096
OBSERVATIONS = ("tiles", "pixels")
LEVEL_SETS = {"human": "human levels", "generated": "a new generated level every episode at d = 0"}
WINDOWS = 5  # timed windows per measurement; the median is reported
MIN_CALLS = 3  # calls of the step in every window, however long they take


@dataclass(frozen=True)
class Rate:
    """Steps/s over timed windows: the median window, and the slowest and fastest."""

    median: float
    low: float
    high: float

    def __str__(self) -> str:
        return f"{self.median:,.0f}"


def windowed_rate(
    step: Callable[[], int], seconds: float, windows: int = WINDOWS, max_steps: int | None = None
) -> Rate:
    """Time ``windows`` consecutive windows of at least ``seconds / windows`` seconds (and at least
    ``MIN_CALLS`` calls) of ``step``, which returns how many env steps it made; ``max_steps`` caps
    the calls."""
    per_window = max(MIN_CALLS, max_steps // windows) if max_steps else None
    rates = [w.rate for w in time_windows(step, seconds, windows, MIN_CALLS, per_window)]
    return Rate(statistics.median(rates), min(rates), max(rates))


@dataclass
class StepResult:
    game: str
    obs: str
    batch: int
    warmup_s: float
    rate: Rate
    resets: int
    peak_bytes: int | None = None  # the most GPU memory allocated while measuring (CUDA only)

    @property
    def steps_per_s(self) -> float:
        return self.rate.median


def measure_env(
    game: str,
    batch: int,
    obs: str,
    device: str = "cpu",
    min_seconds: float = 2.0,
    max_steps: int = 300,
    levels: str = "human",
) -> StepResult:
    """Steady-state env steps/s (one step = one env tick) with uniformly random actions, on the
    human levels or (``levels="generated"``) a new generated level every episode at d = 0, as PPCG
    starts: there every reset compiles a level no env has played."""
    cuda = torch.device(device).type == "cuda"
    if cuda:
        torch.cuda.empty_cache()
        torch.cuda.reset_peak_memory_stats()
    with Stopwatch(sync=cuda) as warmup:
        env = GVGAIEnv(
            game, num_envs=batch, levels=level_source(game, levels), obs=obs, device=device, seed=0
        )
        generator = torch.Generator(device=device).manual_seed(0)
        td = env.reset()
        for _ in range(3):
            td.set(
                "action", torch.randint(0, env.game.num_actions, (batch,), generator=generator, device=device)
            )
            _, td = env.step_and_maybe_reset(td)
    resets = 0

    def step() -> int:
        nonlocal td, resets
        td.set("action", torch.randint(0, env.game.num_actions, (batch,), generator=generator, device=device))
        stepped, td = env.step_and_maybe_reset(td)
        resets += int(stepped.get(("next", "done")).sum())  # also waits for a GPU
        return batch

    rate = windowed_rate(step, min_seconds, max_steps=max_steps)
    peak = torch.cuda.max_memory_allocated() if cuda else None
    return StepResult(game, obs, batch, warmup.wall, rate, resets, peak)


def level_source(game: str, levels: str) -> object:
    """What ``GVGAIEnv(levels=...)`` takes for a benchmark's ``levels`` (see ``LEVEL_SETS``)."""
    if levels not in LEVEL_SETS:
        raise ValueError(f"unknown level set {levels!r}; valid ones are: {', '.join(LEVEL_SETS)}")
    if levels == "generated":
        return GeneratedLevels(game)
    return levels


def measure_engine(game: str, batch: int = 4096, shards: int = 1, min_seconds: float = 2.0) -> Rate:
    """Steps/s of the engine alone: its tick (compiled where the engine compiles it) then
    ``render_tiles``, no resets (human levels 0-4 in turn, random actions), sliced into ``shards``
    as ``GVGAIEnv`` does on the CPU."""
    engine = get_game(game)
    tick = engine_tick(engine)
    levels = [human_levels(game)[i % 5] for i in range(batch)]  # of mixed sizes in Frogs
    state = engine.compile(levels, torch.arange(batch), torch.device("cpu"))
    stepper = ShardedStepper(shards)
    generator = torch.Generator().manual_seed(0)

    def step(part: TensorDict, action: torch.Tensor) -> torch.Tensor:
        tick(part, action)
        return render_tiles(engine, part)

    actions = [torch.randint(0, engine.num_actions, (batch,), generator=generator) for _ in range(64)]
    for action in actions[:3]:
        stepper(step, state, action)
    calls = 0

    def step_all() -> int:
        nonlocal calls
        stepper(step, state, actions[calls % len(actions)])
        calls += 1
        return batch

    return windowed_rate(step_all, min_seconds)


def measure_generating_resets(game: str, batch: int = 64, rounds: int = 5) -> float:
    """Full resets/s of a GVGAIEnv whose source generates a new level each episode (d = 1)."""
    env = GVGAIEnv(game, num_envs=batch, levels=GeneratedLevels(game), difficulty=1.0)
    env.reset()

    def reset() -> int:
        env.reset()
        return batch

    return time_windows(reset, 0.0, min_calls=rounds)[0].rate


def machine_description(device: str) -> str:
    cpu = platform.processor() or platform.machine()
    try:
        text = Path("/proc/cpuinfo").read_text()
        match = re.search(r"model name\s*:\s*(.+)", text)
        cpu = match.group(1).strip() if match else cpu
    except OSError:
        pass
    parts = [f"CPU: {cpu}, {os.cpu_count()} logical cores, torch threads {torch.get_num_threads()}"]
    if torch.device(device).type == "cuda":
        parts.append(f"GPU: {torch.cuda.get_device_name(0)}")
    parts.append(f"torch {torch.__version__}, Python {platform.python_version()}")
    return "; ".join(parts)


def run_benchmarks(
    device: str = "cpu",
    games: list[str] | None = None,
    batch_sizes: tuple[int, ...] = BATCH_SIZES,
    observations: tuple[str, ...] = OBSERVATIONS,
    min_seconds: float = 2.0,
    progress: bool = True,
    levels: str = "human",
) -> Section:
    """Run every benchmark: the Markdown section for ``device``, with the speed targets checked on
    the env table (every game's tiles at B = 64 on the CPU, human levels)."""
    games = games or registered_games()
    configs = [(g, o, b) for g in games for o in observations for b in batch_sizes]
    results = []
    for game, obs, batch in track(configs, "env throughput", "config", progress):
        results.append(measure_env(game, batch, obs, device, min_seconds, levels=levels))
    lines = [
        f"Measured {time.strftime('%Y-%m-%d')} with `make bench`. {machine_description(device)}.",
        "",
        f"### Env steps/s (random actions, {LEVEL_SETS[levels]}, resets at their natural rate)",
        "",
        f"Steps/s is the median of {WINDOWS} timed windows; the slowest and fastest window follow it.",
        "",
        "| game | obs | B | steps/s | slowest - fastest window | warm-up (s) | resets |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for r in results:
        lines.append(
            f"| {r.game} | {r.obs} | {r.batch} | {r.rate} | {_spread(r.rate)} "
            f"| {r.warmup_s:.2f} | {r.resets} |"
        )
    if torch.device(device).type == "cuda":
        lines += _memory_lines(results, torch.cuda.get_device_properties(0).total_memory)
    if torch.device(device).type == "cpu":
        engine = _engine_rates(games, min_seconds, progress)
        lines += _target_lines(results, engine)
        lines += _engine_lines(engine)
        lines += _generator_lines(games)
    return Section("\n".join(lines) + "\n", _env_checks(results, device, levels))


def _env_checks(results: list[StepResult], device: str, levels: str) -> list[Check]:
    """The env table's targets: on the CPU and the human levels only, as their figures were."""
    if torch.device(device).type != "cpu" or levels != "human":
        return []
    return env_checks({r.game: r.steps_per_s for r in results if r.obs == "tiles" and r.batch == 64})


def _memory_lines(results: list[StepResult], total_bytes: int) -> list[str]:
    """Peak GPU memory per env at each game's largest batch, and the batch that would fill the
    card at that rate (an extrapolation, not a measurement)."""
    lines = [
        "",
        "### GPU memory (peak allocated while stepping, at the largest batch measured)",
        "",
        f"The card has {total_bytes / 2**30:,.0f} GiB. 'Fills the card at' divides it by the bytes per env.",
        "",
        "| game | obs | B | peak (MiB) | bytes per env | fills the card at B of about |",
        "|---|---|---:|---:|---:|---:|",
    ]
    largest: dict[tuple[str, str], StepResult] = {}
    for r in results:
        if r.peak_bytes is not None and r.batch >= largest.get((r.game, r.obs), r).batch:
            largest[(r.game, r.obs)] = r
    for (game, obs), r in largest.items():
        per_env = r.peak_bytes / r.batch
        lines.append(
            f"| {game} | {obs} | {r.batch:,} | {r.peak_bytes / 2**20:,.0f} | {per_env:,.0f} "
            f"| {total_bytes / per_env:,.0f} |"
        )
    return lines


def _spread(rate: Rate) -> str:
    return f"{rate.low:,.0f} - {rate.high:,.0f}"


def _engine_rates(games: list[str], min_seconds: float, progress: bool) -> dict[str, tuple[Rate, ...]]:
    """Engine steps/s per game: intra-op threads (GVGAIEnv's default), one thread, one shard per thread."""
    threads = torch.get_num_threads()
    rates = {}
    for game in track(games, "engine throughput", "game", progress):
        intra = measure_engine(game, ENGINE_BATCH, 1, min_seconds)
        torch.set_num_threads(1)
        try:
            single = measure_engine(game, ENGINE_BATCH, 1, min_seconds)
            sharded = measure_engine(game, ENGINE_BATCH, threads, min_seconds)
        finally:
            torch.set_num_threads(threads)
        rates[game] = (intra, single, sharded)
    return rates


def _engine_lines(rates: dict[str, tuple[Rate, ...]]) -> list[str]:
    threads = torch.get_num_threads()
    lines = [
        "",
        f"### Engine alone: tick + tiles at B = {ENGINE_BATCH:,} (no resets)",
        "",
        f"| game | {threads} torch threads (GVGAIEnv's default) | 1 thread | {threads} shards x 1 thread |",
        "|---|---:|---:|---:|",
    ]
    for game, (intra, single, sharded) in rates.items():
        lines.append(f"| {game} | {intra} ({_spread(intra)}) | {single} | {sharded} |")
    return lines


def _target_lines(results: list[StepResult], engine: dict[str, tuple[Rate, ...]]) -> list[str]:
    env = {r.game: r.rate for r in results if r.obs == "tiles" and r.batch == ENGINE_BATCH}
    lines = [
        "",
        f"### Against the targets: tiles steps/s at B = {ENGINE_BATCH:,}",
        "",
        f"Medians of {WINDOWS} windows, the slowest window in brackets.",
        "",
        "| game | target | engine alone | met | env, random play with resets | met |",
        "|---|---:|---:|:-:|---:|:-:|",
    ]
    for game in engine:
        target = get_game_spec(game).bench_target
        if target is None or game not in env:
            continue
        rate = engine[game][0]
        lines.append(
            f"| {game} | {target:,} | {rate} ({rate.low:,.0f}) | {_met(rate.median, target)} "
            f"| {env[game]} ({env[game].low:,.0f}) | {_met(env[game].median, target)} |"
        )
    return lines


def _met(rate: float, target: float) -> str:
    return "yes" if rate >= target else "no"


def _generator_lines(games: list[str]) -> list[str]:
    lines = [
        "",
        "### Level generation (one core, d = 1)",
        "",
        "| game | levels/s | GVGAIEnv resets/s with a generating source (B = 64) |",
        "|---|---:|---:|",
    ]
    for game in games:
        if game in registered_generators():
            rate = levels_per_second(game, 1.0, count=600)
            lines.append(f"| {game} | {rate:,.0f} | {measure_generating_resets(game):,.0f} |")
    return lines


def write_section(path: Path, device_kind: str, body: str) -> None:
    """Replace (or append) the section between this device kind's markers in ``path``."""
    start, end = f"<!-- bench:{device_kind}:start -->", f"<!-- bench:{device_kind}:end -->"
    text = path.read_text() if path.exists() else "# Benchmarks\n"
    block = f"{start}\n{body}{end}"
    if start in text and end in text:
        text = text[: text.index(start)] + block + text[text.index(end) + len(end) :]
    else:
        text = text.rstrip("\n") + f"\n\n## {device_kind.upper()}\n\n{block}\n"
    path.write_text(text)
