"""The large frozen test sets: per game, 100 distinct generated levels at d = 0.5 and 100 at d = 1,
beside the study-sized 30-level sets (``gvgai_pcg.levels.test_sets``), so that an evaluation can
carry less level-sampling error than 30 levels allow.

Stored compactly: one bundle per set (``test_sets/<game>_pcg<d>_large.txt``, the levels in order,
each followed by one blank line) and one manifest per game (``test_sets/manifest_large.csv``: name,
file, game, difficulty, seed, sha256 of each level's text). As with the small sets, the levels are
read from their files, never regenerated on the fly; a level whose text no longer matches its hash
is refused, and ``tests/levels/test_large_test_sets.py`` regenerates them and fails if any differs.
Rewriting them is a deliberate act: ``python -m gvgai_pcg.levels.large_test_sets --write``.

Seeds: each (game, d) has its own block of seeds from ``LARGE_TEST_SEED_BASE`` (above every seed of
the 30-level sets, which lie above every training seed). Seeds are taken in order; a level equal to
one already in the set, or one that cannot be won (``gvgai_pcg.levels.winnable``), is skipped, so the
manifest's seeds are not always consecutive.
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from gvgai_pcg.games.registry import generate_level, get_game_spec, study_games
from gvgai_pcg.levels.level import Level
from gvgai_pcg.levels.seeds import LARGE_TEST_SEED_BASE
from gvgai_pcg.levels.test_sets import (
    _BLOCK_SIZE,
    TEST_DIFFICULTIES,
    TEST_SETS_FOLDER,
    _data_dir,
    regenerate,
    set_name,
    sha256,
    source_folder,
)
from gvgai_pcg.levels.winnable import missing_to_win

LARGE_SET_SIZE = 100
LARGE_MANIFEST_NAME = "manifest_large.csv"
LARGE_MANIFEST_COLUMNS = ("name", "file", "game", "difficulty", "seed", "sha256")
# Seeds tried per set before giving up: a generator that repeats itself this much is broken.
_MAX_TRIES = 20 * LARGE_SET_SIZE


@dataclass(frozen=True)
class LargeEntry:
    """One manifest row: a level of a bundle, its generator seed and the hash of its text."""

    name: str
    file: str
    game: str
    difficulty: float
    seed: int
    sha256: str


def bundle_name(game: str, difficulty: float) -> str:
    return f"{game}_{set_name(difficulty)}_large.txt"


def large_level_name(game: str, difficulty: float, index: int) -> str:
    """``zelda_pcg0.5_large_007``: never the name of a level of the 30-level sets."""
    return f"{game}_{set_name(difficulty)}_large_{index:03d}"


def seed_block(game: str, difficulty: float) -> int:
    """The first seed tried for ``game``'s large set at ``difficulty``."""
    index = get_game_spec(game).study_index
    if index is None:
        raise ValueError(
            f"no large test set for game {game!r}; games with test sets are: {', '.join(study_games())}"
        )
    if difficulty not in TEST_DIFFICULTIES:
        raise ValueError(f"large test sets exist at d in {TEST_DIFFICULTIES}, got {difficulty!r}")
    return LARGE_TEST_SEED_BASE + (2 * index + TEST_DIFFICULTIES.index(difficulty)) * _BLOCK_SIZE


def generate_large_test_set(game: str, difficulty: float, count: int = LARGE_SET_SIZE) -> list[Level]:
    """The set as the generator makes it now: the first ``count`` distinct winnable levels of the
    seed block, each named and seeded."""
    start, levels, seen = seed_block(game, difficulty), [], set()
    for seed in range(start, start + _MAX_TRIES):
        level = generate_level(game, difficulty, seed)
        text = str(level)
        if text in seen or missing_to_win(level):
            continue
        seen.add(text)
        levels.append(
            Level(game, level.rows, name=large_level_name(game, difficulty, len(levels)), seed=seed)
        )
        if len(levels) == count:
            return levels
    raise RuntimeError(
        f"{game} at d={difficulty:g}: only {len(levels)} distinct winnable levels in {_MAX_TRIES} seeds"
    )


def _bundle_text(levels: list[Level]) -> str:
    return "".join(f"{level}\n" for level in levels)


def _split_bundle(text: str) -> list[str]:
    """Each level's text (its rows and final newline) from a bundle."""
    return [block + "\n" for block in text.split("\n\n") if block.strip()]


@cache
def game_large_manifest(game: str) -> tuple[LargeEntry, ...]:
    """Every row of ``game``'s large manifest, in order (none if it ships no large sets)."""
    folder = _data_dir(game)
    if folder is None or not folder.joinpath(LARGE_MANIFEST_NAME).is_file():
        return ()
    text = folder.joinpath(LARGE_MANIFEST_NAME).read_text()
    return tuple(
        LargeEntry(
            row["name"], row["file"], row["game"], float(row["difficulty"]), int(row["seed"]), row["sha256"]
        )
        for row in csv.DictReader(io.StringIO(text))
    )


@cache
def frozen_large_test_set(game: str, difficulty: float) -> tuple[Level, ...]:
    """The 100 frozen levels of ``game`` at ``difficulty``, each named and seeded; a level whose text
    no longer matches its manifest hash is refused."""
    entries = [e for e in game_large_manifest(game) if e.difficulty == float(difficulty)]
    if not entries:
        shipped = sorted({(g, e.difficulty) for g in study_games() for e in game_large_manifest(g)})
        raise ValueError(f"no large test set for {game!r} at d={difficulty}; the manifests have {shipped}")
    folder = _data_dir(game)
    texts = {file: _split_bundle(folder.joinpath(file).read_text()) for file in {e.file for e in entries}}
    if any(len(blocks) != sum(e.file == file for e in entries) for file, blocks in texts.items()):
        raise ValueError(
            f"{game}: a large test set bundle does not hold as many levels as its manifest lists"
        )
    positions: dict[str, int] = {}
    levels = []
    for entry in entries:
        text = texts[entry.file][positions.setdefault(entry.file, 0)]
        positions[entry.file] += 1
        if sha256(text) != entry.sha256:
            raise ValueError(
                f"large test level {entry.name} in {entry.file} does not match its manifest sha256; the "
                "frozen test sets were edited by hand. Restore them (git checkout) or regenerate them "
                "deliberately."
            )
        level = Level.parse(text, game, source=f"{TEST_SETS_FOLDER}/{entry.file}", name=entry.name)
        levels.append(Level(game, level.rows, name=entry.name, seed=entry.seed))
    return tuple(levels)


def write_large_test_set(game: str, out_dir: Path) -> list[LargeEntry]:
    """Generate ``game``'s large sets into ``out_dir`` (one bundle per difficulty and the manifest)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    entries = []
    for difficulty in TEST_DIFFICULTIES:
        levels = generate_large_test_set(game, difficulty)
        file = bundle_name(game, difficulty)
        (out_dir / file).write_text(_bundle_text(levels))
        entries += [
            LargeEntry(lv.name or "", file, game, difficulty, int(lv.seed or 0), sha256(str(lv)))
            for lv in levels
        ]
    with open(out_dir / LARGE_MANIFEST_NAME, "w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(LARGE_MANIFEST_COLUMNS)
        for e in entries:
            writer.writerow((e.name, e.file, e.game, f"{e.difficulty:g}", e.seed, e.sha256))
    return entries


def write_large_test_sets(
    out_dir: Path | None = None, games: tuple[str, ...] | None = None
) -> list[LargeEntry]:
    """The large sets of ``games`` (default: the study's), into ``out_dir / <game>`` or, when
    ``out_dir`` is ``None``, into each game's own ``test_sets/`` folder."""
    entries = []
    for game in games or study_games():
        entries += write_large_test_set(game, source_folder(game) if out_dir is None else out_dir / game)
    return entries


def main(argv: list[str] | None = None) -> int:
    return regenerate(argv, "large frozen test sets", write_large_test_sets, LARGE_MANIFEST_NAME)


if __name__ == "__main__":
    raise SystemExit(main())
