"""The registry: names, errors that list the choices, input checks, entry-point plugins."""

from __future__ import annotations

import numpy as np
import pytest

from gvgai_pcg.games import registry
from gvgai_pcg.generators import (
    generate_level,
    get_generator,
    register_generator,
    registered_generators,
)
from gvgai_pcg.levels.level import Level


def test_the_four_games_are_registered():
    assert {"zelda", "solarfox", "frogs", "boulderdash"} <= set(registered_generators())


def test_unknown_name_lists_the_registered_ones():
    with pytest.raises(
        ValueError, match="no level generator named 'pacman'.*boulderdash, frogs, solarfox, zelda"
    ):
        get_generator("pacman")


@pytest.mark.parametrize("difficulty", [-0.1, 1.01, float("nan"), float("inf"), "0.5", None, True])
def test_bad_difficulty_is_refused(difficulty):
    with pytest.raises(ValueError, match=r"difficulty must be a number in \[0, 1\]"):
        generate_level("zelda", difficulty, 0)


@pytest.mark.parametrize("seed", [1.0, "3", None, True, -1])
def test_bad_seed_is_refused(seed):
    with pytest.raises(ValueError, match="seed must be a non-negative integer"):
        generate_level("zelda", 0.5, seed)


def test_numpy_numbers_are_accepted():
    level = generate_level("frogs", np.float32(0.5), np.int64(3))
    assert level == generate_level("frogs", 0.5, 3) and level.seed == 3 and type(level.seed) is int


def test_duplicate_registration_is_refused():
    with pytest.raises(ValueError, match="already registered"):
        register_generator("zelda")(lambda d, s: None)


class FakeEntryPoint:
    def __init__(self, name: str, value: str, target) -> None:
        self.name, self.value, self._target = name, value, target

    def load(self):
        return self._target


def test_entry_point_plugins_are_discovered(monkeypatch):
    def generate_tiny(difficulty: float, seed: int) -> Level:
        return Level("zelda", ("www", "wAw", "www"), name=f"tiny_s{seed}", seed=seed)

    plugins = [FakeEntryPoint("tiny", "tiny_pkg:generate", generate_tiny)]
    monkeypatch.setattr(
        registry, "entry_points", lambda group: plugins if group == registry.ENTRY_POINT_GROUP else []
    )
    monkeypatch.setattr(registry, "_GENERATORS", dict(registry._GENERATORS))
    assert "tiny" in registered_generators()
    assert generate_level("tiny", 0.5, 4).seed == 4


def test_plugin_cannot_replace_a_registered_generator(monkeypatch):
    plugins = [FakeEntryPoint("zelda", "evil:generate", lambda d, s: None)]
    monkeypatch.setattr(registry, "entry_points", lambda group: plugins)
    monkeypatch.setattr(registry, "_GENERATORS", dict(registry._GENERATORS))
    with pytest.warns(UserWarning, match="already registered"):
        registered_generators()
    assert get_generator("zelda").__module__ == "gvgai_pcg.games.zelda.generator"
