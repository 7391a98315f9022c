"""The frozen test sets of the evaluation protocol (GENERATORS.md §4): per game, 30 generated levels
at d = 0.5 and 30 at d = 1, shipped as package data in the game's folder
(``gvgai_pcg/games/<game>/test_sets/``) with a manifest (file, game, d, seed, sha256).

The levels were generated once and are read from their files, never regenerated on the fly, so a
change to a generator cannot move the goalposts of an evaluation: ``tests/evaluation`` regenerates
them and fails if any file differs. Rewriting them is a deliberate act:
``python -m gvgai_pcg.levels.test_sets --write``.

Seeds: every test seed is at least ``TEST_SEED_BASE`` (2^40), and a training episode only ever
draws level seeds below ``TRAINING_SEED_SPACE`` (2^31), so no training run can meet a test level.
Each game of the study has its own block of seeds, chosen by its ``GameSpec.study_index``.

Beside these study-sized sets lie sets of 100 levels per difficulty, for evaluations with less
level-sampling error: ``gvgai_pcg.levels.large_test_sets``.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import io
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from importlib import import_module
from importlib.resources import files
from pathlib import Path
from typing import TYPE_CHECKING

from gvgai_pcg.games.registry import generate_level, get_game_spec, study_games
from gvgai_pcg.levels.level import Level
from gvgai_pcg.levels.seeds import TEST_SEED_BASE, TRAINING_SEED_SPACE

if TYPE_CHECKING:
    from importlib.resources.abc import Traversable

TEST_SET_SIZE = 30
TEST_DIFFICULTIES = (0.5, 1.0)
TEST_SETS_FOLDER = "test_sets"  # in a game's data package
MANIFEST_NAME = "manifest.csv"
MANIFEST_COLUMNS = ("file", "game", "difficulty", "seed", "sha256")
# Each (game, difficulty) gets its own block of seeds above TEST_SEED_BASE.
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
    index = get_game_spec(game).study_index
    if index is None:
        raise ValueError(
            f"no test set for game {game!r}; games with test sets are: {', '.join(study_games())}"
        )
    if difficulty not in TEST_DIFFICULTIES:
        raise ValueError(f"test sets exist at d in {TEST_DIFFICULTIES}, got {difficulty!r}")
    block = 2 * index + TEST_DIFFICULTIES.index(difficulty)
    return [TEST_SEED_BASE + block * _BLOCK_SIZE + i for i in range(count)]


def level_file_name(game: str, difficulty: float, index: int) -> str:
    return f"{game}_{set_name(difficulty)}_{index:02d}.txt"


def sha256(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def _data_dir(game: str) -> Traversable | None:
    """The folder of ``game``'s shipped test sets, or ``None`` if it ships none."""
    package = get_game_spec(game).data_package
    if package is None:
        return None
    folder = files(package).joinpath(TEST_SETS_FOLDER)
    return folder if folder.joinpath(MANIFEST_NAME).is_file() else None


@cache
def game_manifest(game: str) -> tuple[FrozenEntry, ...]:
    """Every row of ``game``'s shipped manifest, in file order (none if it ships no test sets)."""
    folder = _data_dir(game)
    if folder is None:
        return ()
    text = folder.joinpath(MANIFEST_NAME).read_text()
    return tuple(
        FrozenEntry(row["file"], row["game"], float(row["difficulty"]), int(row["seed"]), row["sha256"])
        for row in csv.DictReader(io.StringIO(text))
    )


def manifest() -> tuple[FrozenEntry, ...]:
    """Every row of every study game's manifest, game by game in the study's order."""
    return tuple(entry for game in study_games() for entry in game_manifest(game))


@cache
def frozen_test_set(game: str, difficulty: float) -> tuple[Level, ...]:
    """The frozen levels of ``game`` at ``difficulty``, each named (``zelda_pcg0.5_07``) and seeded.

    A file whose content no longer matches its manifest hash is refused."""
    entries = [e for e in game_manifest(game) if e.difficulty == float(difficulty)]
    if not entries:
        raise ValueError(
            f"no frozen test set for {game!r} at d={difficulty}; the manifests have "
            f"{sorted({(e.game, e.difficulty) for e in manifest()})}"
        )
    folder = _data_dir(game)
    levels = []
    for entry in entries:
        text = folder.joinpath(entry.file).read_text()
        if sha256(text) != entry.sha256:
            raise ValueError(
                f"test level {entry.file} does not match its manifest sha256; the frozen test sets were "
                f"edited by hand. Restore them (git checkout) or regenerate them deliberately."
            )
        level = Level.parse(
            text, game, source=f"{TEST_SETS_FOLDER}/{entry.file}", name=entry.file.removesuffix(".txt")
        )
        levels.append(Level(game, level.rows, name=level.name, seed=entry.seed))
    return tuple(levels)


def generate_test_set(game: str, difficulty: float, count: int = TEST_SET_SIZE) -> list[Level]:
    """The test set as the generator makes it now (to write it, or to check it has not moved)."""
    return [generate_level(game, difficulty, seed) for seed in frozen_seeds(game, difficulty, count)]


def source_folder(game: str) -> Path:
    """Where ``game``'s test sets live in this checkout (or install): its data package's folder."""
    package = get_game_spec(game).data_package
    if package is None:
        raise ValueError(f"game {game!r} has no data package to hold test sets")
    return Path(import_module(package).__file__).parent / TEST_SETS_FOLDER


def write_test_set(game: str, out_dir: Path) -> list[FrozenEntry]:
    """Generate ``game``'s test sets into ``out_dir`` (level files and ``manifest.csv``)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    entries = []
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


def write_test_sets(out_dir: Path | None = None, games: tuple[str, ...] | None = None) -> list[FrozenEntry]:
    """Generate the test sets of ``games`` (default: the study's), each into ``out_dir / <game>``,
    or into the game's own folder when ``out_dir`` is ``None``."""
    entries = []
    for game in games or study_games():
        entries += write_test_set(game, source_folder(game) if out_dir is None else out_dir / game)
    return entries


def regenerate(argv: list[str] | None, what: str, write: Callable[[Path | None], list], manifest: str) -> int:
    """The command line that rewrites ``what`` (a frozen set) with ``write(out_dir)``: refused
    without ``--write``, since the shipped files are the ones every published number used."""
    parser = argparse.ArgumentParser(description=f"Regenerate the {what} (a deliberate act).")
    parser.add_argument("--write", action="store_true", help="overwrite the shipped files and manifests")
    parser.add_argument(
        "--out", type=Path, default=None, help="write into OUT/<game>/ instead of each game's folder"
    )
    args = parser.parse_args(argv)
    if not args.write:
        parser.error(f"pass --write to overwrite the {what}")
    entries = write(args.out)
    print(f"wrote {len(entries)} levels of the {what} and their {manifest} files")
    return 0


def main(argv: list[str] | None = None) -> int:
    return regenerate(argv, "frozen test sets", write_test_sets, MANIFEST_NAME)


if __name__ == "__main__":
    raise SystemExit(main())
