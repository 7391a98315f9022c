"""The frozen test sets: manifest, hashes, seed separation from training, and that a generator
change cannot alter them silently."""

import torch

from gvgai_pcg.envs.level_sources import GeneratedLevels
from gvgai_pcg.levels.seeds import TEST_SEED_BASE, TRAINING_SEED_SPACE
from gvgai_pcg.levels.test_sets import (
    MANIFEST_NAME,
    TEST_DIFFICULTIES,
    TEST_SET_SIZE,
    frozen_seeds,
    frozen_test_set,
    manifest,
    write_test_sets,
)

GAMES = ("zelda", "solarfox", "frogs", "boulderdash")


def test_manifest_lists_thirty_levels_per_game_and_difficulty():
    entries = manifest()
    assert len(entries) == len(GAMES) * len(TEST_DIFFICULTIES) * TEST_SET_SIZE
    for game in GAMES:
        for d in TEST_DIFFICULTIES:
            mine = [e for e in entries if e.game == game and e.difficulty == d]
            assert [e.seed for e in mine] == frozen_seeds(game, d)
            assert len({e.sha256 for e in mine}) == TEST_SET_SIZE  # thirty different levels


def test_levels_load_with_their_seed_and_name():
    levels = frozen_test_set("zelda", 1.0)
    assert len(levels) == TEST_SET_SIZE
    assert levels[7].name == "zelda_pcg1_07"
    assert levels[7].seed == frozen_seeds("zelda", 1.0)[7]


def test_test_seeds_never_overlap_training_seeds():
    seeds = [e.seed for e in manifest()]
    assert len(set(seeds)) == len(seeds)
    assert TRAINING_SEED_SPACE <= TEST_SEED_BASE <= min(seeds)
    # Training levels come from GeneratedLevels, which folds any episode seed below 2^31 -
    # even an episode seed that equals a test seed.
    source = GeneratedLevels("zelda")
    episode_seeds = torch.tensor([seeds[0], seeds[-1], 2**62 + 5], dtype=torch.int64)
    levels = source.next_levels(torch.arange(3), episode_seeds, torch.ones(3))
    assert all(0 <= level.seed < TRAINING_SEED_SPACE for level in levels)


def test_regenerating_gives_exactly_the_shipped_files(tmp_path):
    """Fails when a generator change would alter a frozen level: rewrite them deliberately with
    ``python -m gvgai_pcg.levels.test_sets --write`` and say so in the commit."""
    write_test_sets(tmp_path)
    from importlib.resources import files

    for game in GAMES:
        shipped = files(f"gvgai_pcg.games.{game}").joinpath("test_sets", MANIFEST_NAME).read_text()
        assert (tmp_path / game / MANIFEST_NAME).read_text() == shipped
