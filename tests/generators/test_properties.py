"""Hypothesis: for any d in [0, 1] and seed, every generator returns a valid, full-size,
reproducible level that keeps its playability guarantees."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from gvgai_pcg.generators import generate_level
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
    assert level.seed == seed and level.name == f"{game}_d{d:g}_s{seed}"
