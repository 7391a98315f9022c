"""Generator throughput, measured the way training uses it: one level per call, on one core."""

from __future__ import annotations

import time

from gvgai_pcg.games.registry import get_generator


def levels_per_second(
    game: str, difficulty: float = 1.0, count: int = 2000, repeats: int = 3, warmup: int = 20
) -> float:
    """Levels per second of ``game``'s generator at ``difficulty`` on seeds 0..count-1.

    After ``warmup`` levels, the seeds are timed in ``repeats`` rounds and the fastest round
    counts: on a shared machine the slower rounds measure the neighbours, not the generator.
    """
    generate = get_generator(game)
    for seed in range(warmup):
        generate(difficulty, seed)
    per_round = max(1, count // repeats)
    best = float("inf")
    for round_index in range(repeats):
        seeds = range(round_index * per_round, (round_index + 1) * per_round)
        begin = time.perf_counter()
        for seed in seeds:
            generate(difficulty, seed)
        best = min(best, time.perf_counter() - begin)
    return per_round / best
