"""The frozen test sets of the evaluation protocol (GENERATORS.md §4): per game, 30 generated levels
at d = 0.5 and 30 at d = 1, shipped as package data with a manifest (file, game, d, seed, sha256).

The levels were generated once and are read from their files, never regenerated on the fly, so a
change to a generator cannot move the goalposts of an evaluation: ``tests/evaluation`` regenerates
them and fails if any file differs. Rewriting them is a deliberate act:
``python -m gvgai_pcg.levels.test_sets --write``.

Seeds: every test seed is at least ``TEST_SEED_BASE`` (2^40), and a training episode only ever
draws level seeds below ``TRAINING_SEED_SPACE`` (2^31), so no training run can meet a test level.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import io
from dataclasses import dataclass
from functools import cache
from importlib.resources import files
from pathlib import Path

from gvgai_pcg.envs.level_sources import TEST_SEED_BASE, TRAINING_SEED_SPACE
from gvgai_pcg.levels.level import Level

TEST_SET_SIZE = 30
TEST_DIFFICULTIES = (0.5, 1.0)
MANIFEST_NAME = "manifest.csv"
MANIFEST_COLUMNS = ("file", "game", "difficulty", "seed", "sha256")
# Each (game, difficulty) gets its own block of seeds above TEST_SEED_BASE.
_GAME_BLOCK = {"zelda": 0, "solarfox": 1, "frogs": 2, "boulderdash": 3}
_BLOCK_SIZE = 1_000_000

assert TEST_SEED_BASE >= TRAINING_SEED_SPACE, "test seeds must lie above every training seed"


@dataclass(frozen=True)
class FrozenEntry:
    """One manifest row: which file holds which generated level."""

    file: str
    game: str
    difficulty: float
    seed: int
    sha256: str


def set_name(difficulty: float) -> str:
    """``pcg0.5`` / ``pcg1``: the name of a test set (and of its column in the report)."""
    return f"pcg{difficulty:g}"


def frozen_seeds(game: str, difficulty: float, count: int = TEST_SET_SIZE) -> list[int]:
    """The fixed generator seeds of a test set, all in ``[TEST_SEED_BASE, TEST_SEED_BASE + 2^24)``."""
    if game not in _GAME_BLOCK:
        raise ValueError(f"no test set for game {game!r}; games with test sets are: {', '.join(_GAME_BLOCK)}")
    if difficulty not in TEST_DIFFICULTIES:
        raise ValueError(f"test sets exist at d in {TEST_DIFFICULTIES}, got {difficulty!r}")
    block = 2 * _GAME_BLOCK[game] + TEST_DIFFICULTIES.index(difficulty)
    return [TEST_SEED_BASE + block * _BLOCK_SIZE + i for i in range(count)]


def level_file_name(game: str, difficulty: float, index: int) -> str:
    return f"{game}_{set_name(difficulty)}_{index:02d}.txt"


def sha256(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def _data_dir():
    return files("gvgai_pcg.levels").joinpath("test_sets")


@cache
def manifest() -> tuple[FrozenEntry, ...]:
    """Every row of the shipped manifest, in file order."""
    text = _data_dir().joinpath(MANIFEST_NAME).read_text()
    return tuple(
        FrozenEntry(row["file"], row["game"], float(row["difficulty"]), int(row["seed"]), row["sha256"])
        for row in csv.DictReader(io.StringIO(text))
    )


@cache
def frozen_test_set(game: str, difficulty: float) -> tuple[Level, ...]:
    """The frozen levels of ``game`` at ``difficulty``, each named (``zelda_pcg0.5_07``) and seeded.

    A file whose content no longer matches its manifest hash is refused."""
    entries = [e for e in manifest() if e.game == game and e.difficulty == float(difficulty)]
    if not entries:
        raise ValueError(
            f"no frozen test set for {game!r} at d={difficulty}; the manifest has "
            f"{sorted({(e.game, e.difficulty) for e in manifest()})}"
        )
    levels = []
    for entry in entries:
        text = _data_dir().joinpath(entry.file).read_text()
        if sha256(text) != entry.sha256:
            raise ValueError(
                f"test level {entry.file} does not match its manifest sha256; the frozen test sets were "
                f"edited by hand. Restore them (git checkout) or regenerate them deliberately."
            )
        level = Level.parse(
            text, game, source=f"test_sets/{entry.file}", name=entry.file.removesuffix(".txt")
        )
        levels.append(Level(game, level.rows, name=level.name, seed=entry.seed))
    return tuple(levels)


def generate_test_set(game: str, difficulty: float, count: int = TEST_SET_SIZE) -> list[Level]:
    """The test set as the generator makes it now (to write it, or to check it has not moved)."""
    from gvgai_pcg.generators import generate_level

    return [generate_level(game, difficulty, seed) for seed in frozen_seeds(game, difficulty, count)]


def write_test_sets(out_dir: Path, games: tuple[str, ...] = tuple(_GAME_BLOCK)) -> list[FrozenEntry]:
    """Generate every test set into ``out_dir`` (level files and ``manifest.csv``)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    entries = []
    for game in games:
        for difficulty in TEST_DIFFICULTIES:
            for i, level in enumerate(generate_test_set(game, difficulty)):
                name = level_file_name(game, difficulty, i)
                text = str(level)
                (out_dir / name).write_text(text)
                entries.append(FrozenEntry(name, game, difficulty, int(level.seed or 0), sha256(text)))
    with open(out_dir / MANIFEST_NAME, "w", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(MANIFEST_COLUMNS)
        for e in entries:
            writer.writerow((e.file, e.game, f"{e.difficulty:g}", e.seed, e.sha256))
    return entries


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Regenerate the frozen test sets (a deliberate act).")
    parser.add_argument("--write", action="store_true", help="overwrite the shipped level files and manifest")
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "test_sets")
    args = parser.parse_args(argv)
    if not args.write:
        parser.error("pass --write to overwrite the frozen test sets")
    entries = write_test_sets(args.out)
    print(f"wrote {len(entries)} test levels and {MANIFEST_NAME} to {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
