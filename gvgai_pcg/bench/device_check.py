"""Does a device compute what the CPU computes? ``python -m gvgai_pcg.bench.device_check --device cuda``.

The golden traces hold the CPU engine to GVGAI's own, tick by tick; this check carries that to
another device by holding it to the CPU, exactly, on two levels:

- **the tick**: a mixed batch (human levels and generated ones of five difficulties) ticked on the
  device by the tick the engine runs there (compiled where the game compiles) and on the CPU by
  the eager tick, every state tensor compared after every tick;
- **the env**: a ``GVGAIEnv`` on each device with generated levels, the same seeds and actions,
  resets at their natural rate, the observation, reward and done flags compared after every step.

The random draws are counter-based (``gvgai_pcg.games.rng``), so the two devices draw the same
numbers. Exit status 1 when anything differs. Run it on a new machine before trusting its
numbers; ``--device cpu`` holds the compiled CPU tick to the eager one.
"""

from __future__ import annotations

import argparse
import sys
import time
import traceback
from dataclasses import dataclass
from functools import partial

import torch

from gvgai_pcg.engine.compiled import CompiledTick, compiled_batch, engine_tick
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.level_sources import GeneratedLevels
from gvgai_pcg.games import get_game, registered_games
from gvgai_pcg.generators import get_generator
from gvgai_pcg.levels import human_levels

CPU = torch.device("cpu")


@dataclass(frozen=True)
class Check:
    """One comparison: what was compared, how long it took, and the first difference if any."""

    game: str
    what: str
    steps: int
    seconds: float
    difference: str | None

    @property
    def passed(self) -> bool:
        return self.difference is None


def check_tick(game_name: str, device: torch.device, ticks: int = 150, copies: int = 1) -> Check:
    """The engine's tick on ``device`` against the eager CPU tick, every state tensor every tick.
    ``copies`` repeats the mixed batch (a larger batch)."""
    game = get_game(game_name)
    generate = get_generator(game_name)
    levels = human_levels(game_name) + [generate(d / 4, seed) for seed in range(3) for d in range(5)]
    levels = levels * copies
    seeds = torch.arange(len(levels)) * 7919
    reference = game.compile(levels, seeds, CPU)
    state = game.compile(levels, seeds.to(device), device)
    tick = engine_tick(game)
    compiled = isinstance(tick, CompiledTick) and compiled_batch(game.step_facts, len(levels), device)
    what = "compiled tick" if compiled else "eager tick"
    generator = torch.Generator().manual_seed(0)
    begin = time.perf_counter()
    for step in range(ticks):
        action = torch.randint(0, game.num_actions, (len(levels),), generator=generator)
        game.tick(reference, action)
        tick(state, action.to(device))
        difference = _first_difference(reference, state, f"tick {step}")
        if difference:
            return Check(game_name, what, step + 1, time.perf_counter() - begin, difference)
    if isinstance(tick, CompiledTick) and device.type in tick.failures:
        what = "eager tick (compiling failed)"
        print(f"{game_name}: compiling failed on {device}:\n{tick.failure_details[device.type][-3000:]}")
    return Check(game_name, what, ticks, time.perf_counter() - begin, None)


def check_env(
    game_name: str, device: torch.device, steps: int = 300, num_envs: int = 32, obs: str = "tiles"
) -> Check:
    """A ``GVGAIEnv`` with generated levels (d = 0.5) on ``device`` against one on the CPU that
    ticks and draws eagerly."""
    envs = [  # the reference ticks and draws eagerly
        GVGAIEnv(
            game_name,
            num_envs,
            GeneratedLevels(game_name),
            obs=obs,
            device=d,
            seed=3,
            difficulty=0.5,
            compile_tick=d != CPU,
        )
        for d in (CPU, device)
    ]
    what = f"env ({obs}), {num_envs} envs"
    tds = [env.reset() for env in envs]
    generator = torch.Generator().manual_seed(1)
    begin = time.perf_counter()
    for step in range(steps):
        action = torch.randint(0, envs[0].game.num_actions, (num_envs,), generator=generator)
        stepped = []
        for i, env in enumerate(envs):
            tds[i].set("action", action.to(env.device))
            out, tds[i] = env.step_and_maybe_reset(tds[i])
            stepped.append(out)
        for key in (("next", obs), ("next", "reward"), ("next", "done"), ("next", "terminated"), obs):
            a, b = stepped[0].get(key), stepped[1].get(key).to(CPU)
            if not torch.equal(a, b):
                where = (a != b).nonzero()[0].tolist()
                difference = f"{key} at step {step} {where}"
                return Check(game_name, what, step + 1, time.perf_counter() - begin, difference)
    return Check(game_name, what, steps, time.perf_counter() - begin, None)


def _first_difference(reference, state, when: str) -> str | None:
    for key in reference.keys(True, True):
        a, b = reference.get(key), state.get(key).to(CPU)
        if a.shape != b.shape:
            return f"{key}: shape {tuple(a.shape)} on the CPU, {tuple(b.shape)} on the device, {when}"
        if not torch.equal(a, b):
            rows = (a != b).reshape(a.shape[0], -1).any(1).nonzero().flatten().tolist() if a.dim() else []
            return f"{key} differs at {when}, envs {rows[:8]}"
    return None


def run_checks(device: torch.device, games: list[str], ticks: int, env_steps: int) -> list[Check]:
    checks = []
    for name in games:
        for check in (partial(check_tick, name, device, ticks), partial(check_env, name, device, env_steps)):
            try:
                result = check()
            except Exception as error:  # a device error is a finding, and the next check still runs
                traceback.print_exc()
                result = Check(name, "raised", 0, 0.0, f"{type(error).__name__}: {error}")
            print(_line(result), flush=True)
            checks.append(result)
    return checks


def _line(check: Check) -> str:
    verdict = "identical" if check.passed else f"DIFFERS: {check.difference}"
    return f"{check.game:12} {check.what:36} {check.steps:4} steps {check.seconds:6.1f} s  {verdict}"


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--device", default="cuda" if torch.cuda.is_available() else "cpu")
    parser.add_argument("--games", default=",".join(registered_games()))
    parser.add_argument("--ticks", type=int, default=150)
    parser.add_argument("--env-steps", type=int, default=300)
    args = parser.parse_args(argv)
    device = torch.device(args.device)
    print(f"checking {device} against the CPU (torch {torch.__version__})", flush=True)
    checks = run_checks(device, args.games.split(","), args.ticks, args.env_steps)
    return 0 if all(check.passed for check in checks) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
