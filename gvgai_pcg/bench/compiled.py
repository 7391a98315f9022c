"""What compiling a game's tick buys: env steps/s with the compiled and the eager tick.

``python -m gvgai_pcg.bench.compiled [GAME] [B ...]`` steps one ``GVGAIEnv`` (tiles, human levels,
random actions, resets included) and swaps its tick between rounds, so both ticks see the same
machine load; a ratio from one run is what counts on a shared machine. Defaults: Zelda at
B = 1, 12, 64, 1024 and 4096.

``python -m gvgai_pcg.bench.compiled --split [GAME] [B ...]`` splits an env step's CPU time
instead (``step_split``, torch's profiler): the compiled call, and of it Dynamo's guard
evaluation (its cache lookup), against the whole step (TorchRL's plumbing and resets included).
"""

from __future__ import annotations

import statistics
import sys
from dataclasses import dataclass

import torch

from gvgai_pcg.bench.timing import Stopwatch, time_windows
from gvgai_pcg.engine.step_plan import eager_plan
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.stepping import PlanRunner

ROUNDS = 3
STEPS_PER_ROUND = 40_000  # env steps per round and tick (at least 20 batch steps)


@dataclass(frozen=True)
class Speedup:
    game: str
    batch: int
    compiled: float  # env steps/s, median of the rounds
    eager: float
    first_steps_s: float  # the first five steps, compiling included

    @property
    def ratio(self) -> float:
        return self.compiled / self.eager


def measure_speedup(
    game: str, batch: int, rounds: int = ROUNDS, steps_per_round: int = STEPS_PER_ROUND
) -> Speedup:
    """Env steps/s of ``game`` at ``batch`` envs with its compiled tick and with its eager one."""
    env = GVGAIEnv(game, num_envs=batch, levels="human", obs="tiles", seed=0)
    # The plan is the env's own, chosen once; swapped here between rounds (same state, same load).
    eager = PlanRunner(env.game, eager_plan("benchmark"), "tiles", batch, env.max_steps, 1, env.buffers)
    ticks = {"compiled": env._runner, "eager": eager}
    generator = torch.Generator().manual_seed(0)
    td = env.reset()

    def run(steps: int) -> int:
        nonlocal td
        for _ in range(steps):
            td.set("action", torch.randint(0, env.game.num_actions, (batch,), generator=generator))
            _, td = env.step_and_maybe_reset(td)
        return batch * steps

    with Stopwatch() as first:
        run(5)
    calls = max(20, steps_per_round // batch)
    rates: dict[str, list[float]] = {name: [] for name in ticks}
    for _ in range(rounds):
        for name, runner in ticks.items():
            env._runner = runner
            run(3)
            rates[name].append(time_windows(lambda: run(1), 0.0, min_calls=calls)[0].rate)
    compiled, eager = (statistics.median(rates[name]) for name in ticks)
    return Speedup(game, batch, compiled, eager, first.wall)


@dataclass(frozen=True)
class StepSplit:
    """CPU microseconds per env step (``step_split``)."""

    step: float  # the env's step_and_maybe_reset, whole
    compiled_call: float  # the compiled call(s): guards and the compiled region
    guards: float  # Dynamo's cache lookup: evaluating the guards over the state's leaves


def step_split(game: str, batch: int, steps: int = 200) -> StepSplit:
    """Where an env step of ``game`` at ``batch`` envs spends its CPU time (its own plan, random
    actions, resets included), from torch's profiler over ``steps`` steps after a warm-up."""
    env = GVGAIEnv(game, num_envs=batch, levels="human", obs="tiles", seed=0)
    generator = torch.Generator().manual_seed(0)
    td = env.reset()

    def run(count: int) -> None:
        nonlocal td
        for _ in range(count):
            td.set("action", torch.randint(0, env.game.num_actions, (batch,), generator=generator))
            _, td = env.step_and_maybe_reset(td)

    run(20)
    with Stopwatch() as whole:
        run(steps)
    with torch.profiler.profile(activities=[torch.profiler.ProfilerActivity.CPU]) as profile:
        run(steps)
    totals = {event.key: event.cpu_time_total for event in profile.key_averages()}
    guards = sum(t for key, t in totals.items() if key.startswith("TorchDynamo Cache Lookup"))
    region = sum(t for key, t in totals.items() if key.startswith("Torch-Compiled Region"))
    return StepSplit(whole.cpu / steps * 1e6, (guards + region) / steps, guards / steps)


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--split":
        game = argv[1] if len(argv) > 1 else "zelda"
        torch.set_num_threads(1)
        print(f"{game}: CPU us per env step (tiles, human levels, random actions, one thread)")
        for batch in [int(b) for b in argv[2:]] or [12, 64]:
            s = step_split(game, batch)
            print(
                f"B = {batch:>5}: step {s.step:7.0f}  compiled call {s.compiled_call:7.0f} "
                f"({s.compiled_call / s.step:.0%})  its guards {s.guards:5.0f} "
                f"({s.guards / max(s.compiled_call, 1e-9):.0%} of the call)",
                flush=True,
            )
        return 0
    game = argv[0] if argv else "zelda"
    batches = [int(b) for b in argv[1:]] or [1, 12, 64, 1024, 4096]
    torch.set_num_threads(1)
    print(f"{game}: env steps/s (tiles, human levels, random actions), compiled / eager tick")
    for batch in batches:
        s = measure_speedup(game, batch)
        print(
            f"B = {batch:>5}: compiled {s.compiled:>10,.0f}  eager {s.eager:>10,.0f}  "
            f"speed-up {s.ratio:.2f}  (first five steps {s.first_steps_s:.1f} s)",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
