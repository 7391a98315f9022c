"""One torch thread against two, in one env per batch: ``python -m gvgai_pcg.bench.threads [GAME] [B ...]``.

Steps one ``GVGAIEnv`` (tiles, human levels, random actions, resets included) and alternates the
thread count between windows, so both see the same machine load (what ``threads_for_batch`` is
measured by). Defaults: Zelda at B = 64, 1,024 and 4,096. The env's plan is chosen on two threads,
so at large batches both counts run the large-batch graph.
"""

from __future__ import annotations

import os
import statistics
import sys

import torch

from gvgai_pcg.bench.timing import time_windows
from gvgai_pcg.envs import GVGAIEnv

WINDOWS = 4
WINDOW_S = 2.5


def measure_threads(
    game: str,
    batch: int,
    windows: int = WINDOWS,
    window_s: float = WINDOW_S,
    counts: tuple[int, ...] = (1, 2),
) -> dict[int, list[float]]:
    """Env steps/s of ``game`` at ``batch`` envs in each window, per torch thread count."""
    before = torch.get_num_threads()
    try:
        torch.set_num_threads(max(counts))
        env = GVGAIEnv(game, num_envs=batch, levels="human", obs="tiles", seed=0)
        generator = torch.Generator().manual_seed(0)
        td = env.reset()

        def run(calls: int) -> int:
            nonlocal td
            for _ in range(calls):
                td.set("action", torch.randint(0, env.game.num_actions, (batch,), generator=generator))
                _, td = env.step_and_maybe_reset(td)
            return batch * calls

        rates: dict[int, list[float]] = {count: [] for count in counts}
        for count in counts:  # compiles, once per thread count
            torch.set_num_threads(count)
            run(5)
        for _ in range(windows):
            for count in counts:
                torch.set_num_threads(count)
                run(2)
                rates[count].append(time_windows(lambda: run(1), window_s, min_calls=5)[0].rate)
        return rates
    finally:
        torch.set_num_threads(before)


def main(argv: list[str]) -> int:
    game = argv[0] if argv else "zelda"
    batches = [int(b) for b in argv[1:]] or [64, 1024, 4096]
    print(f"{game}: env steps/s (tiles, human levels), median (slowest-fastest) of {WINDOWS} windows")
    for batch in batches:
        rates = measure_threads(game, batch)
        one, two = (statistics.median(rates[count]) for count in (1, 2))
        load = ", ".join(f"{value:.1f}" for value in os.getloadavg())
        print(
            f"B = {batch:>5}: 1 thread {one:>10,.0f} ({min(rates[1]):,.0f}-{max(rates[1]):,.0f})  "
            f"2 threads {two:>10,.0f} ({min(rates[2]):,.0f}-{max(rates[2]):,.0f})  2/1 {two / one:.2f}  "
            f"(load {load})",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
