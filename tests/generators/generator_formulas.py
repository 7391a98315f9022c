"""GENERATORS.md §1 formulas, written out again independently of the generators, so that the
distribution tests compare the generators against the spec and not against themselves.

Each function returns Monte-Carlo draws of one parameter (many uniform draws, fixed seed)."""

from __future__ import annotations

import numpy as np

DRAWS = 200_000


def _r(n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).random((n, DRAWS))


def zelda_enemies(d: float) -> np.ndarray:
    (r,) = _r(1, 1)
    return np.floor((0.4 * d + 0.2 * r) * 0.05 * 13 * 9)


def zelda_walls_removed(d: float) -> np.ndarray:
    (r,) = _r(1, 2)
    return np.floor((0.3 * (1 - d) + 0.1 + 0.1 * r) * 12 * 8)


def solarfox_pill_target(d: float) -> np.ndarray:
    (r,) = _r(1, 3)
    return np.floor((0.8 * d + 0.1 + 0.1 * r) * 0.7 * 8 * 9)


def frogs_size(d: float) -> tuple[np.ndarray, np.ndarray]:
    """(active width W, emitted height H + 2)."""
    r1, r2 = _r(2, 4)
    width = np.maximum(np.floor(17 * d + 3 * r1) + 6, 6) + 2
    height = np.maximum(np.floor(2 * d + 3 * r2) + 4, 4) + 2
    return width, height


def frogs_first_lane(d: float) -> np.ndarray:
    """Probabilities (street, water, grass) of the first lane row (it always gets its own draw)."""
    r1, r2 = _r(2, 5)
    street, water, safe = (1 + 0.5 * r1) * d, (2 + r2) * d, np.full(DRAWS, 1 - d)
    total = street + water + safe
    return np.array([(street / total).mean(), (water / total).mean(), (safe / total).mean()])


def boulderdash_counts(d: float) -> dict[str, np.ndarray]:
    """Gem target 10 + E, boulders B (raw fraction g), enemies N."""
    rw, rh, re, rb, rg = _r(5, 6)
    width = np.floor(14 * d + 2 * rw) + 10
    height = np.floor(d + 2 * rh) + 10
    g = 0.7 * (1 - d) + 0.1 + 0.2 * rg
    return {
        "gems": 10 + np.floor(g * 0.05 * width * height),
        "boulders": np.floor((0.7 + 0.3 * rb) * d * 2 * (10 + g)),
        "enemies": np.floor((0.7 + 0.3 * re) * d * 0.05 * width * height),
    }
