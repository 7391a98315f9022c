"""Generated samples shared by the distribution tests, generated once per test session."""

from __future__ import annotations

import functools

from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels.level import Level

SEEDS = range(200)
DIFFICULTIES = (0.0, 0.5, 1.0)
GAMES = ("zelda", "solarfox", "frogs", "boulderdash")


@functools.cache
def sample(game: str, difficulty: float) -> tuple[Level, ...]:
    """Levels of ``game`` at ``difficulty`` for seeds 0..199."""
    return tuple(generate_level(game, difficulty, seed) for seed in SEEDS)
