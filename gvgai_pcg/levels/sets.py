"""Level sets: a folder of level files, or a list of files and folders, read as one list.

A set is read whole and up front, so a bad file stops a run before it starts, with its file,
line and column (``LevelFormatError``). In a folder the level files are its ``*.txt`` files
(not its subfolders, nor hidden files), in name order; the set's order is that of ``path``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from gvgai_pcg.levels.human import check_named_game
from gvgai_pcg.levels.level import Level

LEVEL_SUFFIX = ".txt"
LevelSetPath = str | Path | Sequence[str | Path]


def level_set_files(path: LevelSetPath) -> list[Path]:
    """The level files of ``path`` (a folder, a file, or a list of them), each once."""
    paths = [path] if isinstance(path, str | Path) else list(path)
    if not paths:
        raise ValueError("an empty level set: give a folder of level files or a list of files")
    files: list[Path] = []
    for entry in map(Path, paths):
        if entry.is_dir():
            found = sorted(
                f
                for f in entry.iterdir()
                if f.suffix == LEVEL_SUFFIX and f.is_file() and not f.name.startswith(".")
            )
            if not found:
                raise ValueError(f"{entry}: no level files (*{LEVEL_SUFFIX}) in this folder")
            files += found
        elif entry.is_file():
            files.append(entry)
        else:
            raise FileNotFoundError(f"{entry}: no such level file or folder")
    return list(dict.fromkeys(files))


def load_level_set(game: str, path: LevelSetPath) -> list[Level]:
    """Every level of the set at ``path``, parsed as ``game`` levels and named after its file."""
    levels = []
    for file in level_set_files(path):
        try:
            check_named_game(file.stem, game)
        except ValueError as error:
            raise ValueError(f"{file}: {error}") from None
        levels.append(Level.load(file, game))
    return levels
