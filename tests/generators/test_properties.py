"""Hypothesis: for any d in [0, 1] and seed, every generator returns a valid, full-size,
reproducible level that keeps its playability guarantees."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from gvgai_pcg.games.solarfox.generator import _draw
from gvgai_pcg.generators import generate_level
from gvgai_pcg.generators._common import UniformStream, difficulty_tag
from gvgai_pcg.generators.validation import playability_problems
from gvgai_pcg.levels.level import Level

games = st.sampled_from(["zelda", "solarfox", "frogs", "boulderdash"])
difficulties = st.floats(min_value=0.0, max_value=1.0, allow_nan=False)
seeds = st.integers(min_value=0, max_value=2**63)


@settings(max_examples=300, deadline=None)
@given(game=games, d=difficulties, seed=seeds)
def test_valid_full_size_reproducible(game, d, seed):
    level = generate_level(game, d, seed)
    parsed = Level.parse(str(level), game)
    assert (parsed.width, parsed.height) == (level.format.width, level.format.height)
    assert playability_problems(level) == []
    assert generate_level(game, d, seed).rows == level.rows
    assert level.seed == seed and level.name == f"{game}_d{difficulty_tag(d)}_s{seed}"


# Seeds whose first draw at d = 0 puts the player on the only pills (found by a sweep of 300,000).
SOLARFOX_PILLLESS_FIRST_DRAWS = (55458, 220947, 259800, 272348)


def test_a_solarfox_draw_without_pills_is_redrawn():
    """A level without pills is won at its first tick (docs/fidelity.md); other seeds keep their
    first draw, so every other level is the original algorithm's."""
    for seed in SOLARFOX_PILLLESS_FIRST_DRAWS:
        first = _draw(0.0, UniformStream(np.random.default_rng(seed)))
        assert not any("b" in row or "p" in row for row in first)
        level = generate_level("solarfox", 0.0, seed)
        assert level.count("b") + level.count("p") > 0 and playability_problems(level) == []
        assert generate_level("solarfox", 0.0, seed).rows == level.rows
    for seed in range(200):
        first = _draw(0.0, UniformStream(np.random.default_rng(seed)))
        assert list(generate_level("solarfox", 0.0, seed).rows) == first
