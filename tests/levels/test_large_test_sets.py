"""The 100-level frozen test sets: distinct, winnable, seeded apart from training and from the
30-level sets, loaded from their bundles with their hashes checked, and exactly regenerable."""

import pytest

import gvgai_pcg.levels.large_test_sets as large
from gvgai_pcg.levels.large_test_sets import (
    LARGE_MANIFEST_NAME,
    LARGE_SET_SIZE,
    bundle_name,
    frozen_large_test_set,
    game_large_manifest,
    generate_large_test_set,
    write_large_test_set,
)
from gvgai_pcg.levels.seeds import LARGE_TEST_SEED_BASE, TEST_SEED_BASE, TRAINING_SEED_SPACE
from gvgai_pcg.levels.test_sets import TEST_DIFFICULTIES, frozen_test_set, manifest, source_folder
from gvgai_pcg.levels.winnable import missing_to_win

GAMES = ("zelda", "solarfox", "frogs", "boulderdash")


@pytest.mark.parametrize("game", GAMES)
def test_each_set_holds_a_hundred_distinct_winnable_levels(game):
    for d in TEST_DIFFICULTIES:
        levels = frozen_large_test_set(game, d)
        assert len(levels) == LARGE_SET_SIZE
        assert len({lv.rows for lv in levels}) == LARGE_SET_SIZE  # distinct
        assert [lv.name for lv in levels if missing_to_win(lv)] == []
        assert levels[7].name == f"{game}_pcg{d:g}_large_007"
        assert not {lv.rows for lv in levels} & {lv.rows for lv in frozen_test_set(game, d)}


def test_large_seeds_lie_apart_from_training_and_from_the_thirty_level_sets():
    small = {e.seed for e in manifest()}
    seeds = [e.seed for game in GAMES for e in game_large_manifest(game)]
    assert len(seeds) == len(set(seeds)) == len(GAMES) * len(TEST_DIFFICULTIES) * LARGE_SET_SIZE
    assert TRAINING_SEED_SPACE <= TEST_SEED_BASE < max(small) < LARGE_TEST_SEED_BASE <= min(seeds)
    assert not small & set(seeds)


def test_a_level_edited_by_hand_is_refused(tmp_path, monkeypatch):
    folder = tmp_path / "frogs"
    write_large_test_set("frogs", folder)
    bundle = folder / bundle_name("frogs", 1.0)
    bundle.write_text(bundle.read_text().replace("w", "g", 1))
    monkeypatch.setattr(large, "_data_dir", lambda game: folder)
    large.game_large_manifest.cache_clear()
    large.frozen_large_test_set.cache_clear()
    try:
        assert len(frozen_large_test_set("frogs", 0.5)) == LARGE_SET_SIZE  # the untouched set loads
        with pytest.raises(ValueError, match="frogs_pcg1_large_000 .* does not match its manifest sha256"):
            frozen_large_test_set("frogs", 1.0)
    finally:
        large.game_large_manifest.cache_clear()
        large.frozen_large_test_set.cache_clear()


@pytest.mark.parametrize("game", GAMES)
def test_regenerating_gives_exactly_the_shipped_files(game, tmp_path):
    """Fails when a generator change would alter a frozen level: rewrite them deliberately with
    ``python -m gvgai_pcg.levels.large_test_sets --write`` and say so in the commit."""
    write_large_test_set(game, tmp_path)
    shipped = source_folder(game)
    for name in (LARGE_MANIFEST_NAME, *(bundle_name(game, d) for d in TEST_DIFFICULTIES)):
        assert (tmp_path / name).read_text() == (shipped / name).read_text(), name


def test_the_generator_skips_a_repeated_level(monkeypatch):
    """Seeds are taken in order and a level equal to an earlier one is skipped."""
    from gvgai_pcg.games.registry import generate_level

    start = large.seed_block("solarfox", 0.5)
    monkeypatch.setattr(
        large,
        "generate_level",
        lambda game, d, seed: generate_level(game, d, start if seed == start + 1 else seed),
    )
    levels = generate_large_test_set("solarfox", 0.5, count=3)
    assert [lv.seed for lv in levels] == [start, start + 2, start + 3]
