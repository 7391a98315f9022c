"""Level sets: a folder of level files, or a list of files and folders, read as one list.

A set is read whole and up front, so a bad file stops a run before it starts, with its file,
line and column (``LevelFormatError``). In a folder the level files are its ``*.txt`` files
(not its subfolders, nor hidden files), in name order; the set's order is that of ``path``. A
``.txt`` entry that cannot be read (a dangling symlink, a symlink loop) is refused, never skipped:
a set that silently lost a level would train on another set than the one named.

A set's fingerprint (``level_set_fingerprint``: its files' names and bytes, hashed) is saved in a
training checkpoint, so a run whose level files changed between sessions is not resumed on the
new levels as if they were the old ones.
"""

from __future__ import annotations

import errno
import hashlib
import os
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
            candidates = [
                f for f in entry.iterdir() if f.suffix == LEVEL_SUFFIX and not f.name.startswith(".")
            ]
            for f in candidates:
                check_readable_entry(f)
            found = sorted(f for f in candidates if f.is_file())
            if not found:
                raise ValueError(f"{entry}: no level files (*{LEVEL_SUFFIX}) in this folder")
            files += found
        elif entry.is_file():
            files.append(entry)
        else:
            check_readable_entry(entry)
            raise FileNotFoundError(f"{entry}: no such level file or folder")
    return list(dict.fromkeys(files))


def check_readable_entry(entry: Path) -> None:
    """``ValueError`` naming ``entry`` when it is a symlink that leads nowhere (dangling, or a loop)."""
    if not entry.is_symlink():
        return
    try:
        entry.stat()
    except OSError as error:
        target = os.readlink(entry)
        why = "a symlink loop" if error.errno == errno.ELOOP else "a dangling symlink"
        raise ValueError(
            f"{entry}: {why} (it points to {target}, which cannot be read); fix or remove it"
        ) from None


def level_set_fingerprint(path: LevelSetPath) -> str:
    """The SHA-256 of the set's files, names and bytes in the set's order: equal for the same levels."""
    digest = hashlib.sha256()
    for file in level_set_files(path):
        digest.update(file.name.encode() + b"\0" + file.read_bytes() + b"\0")
    return digest.hexdigest()


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
