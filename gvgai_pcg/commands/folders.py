"""Folder arguments checked before a command reads or writes anything: a path that names a file
where a folder goes is one line naming the flag, not an errno deep inside the work."""

from __future__ import annotations

from pathlib import Path


def refuse_files_for_folders(flags: dict[str, Path | str | None]) -> None:
    """``ValueError`` for the first ``{flag: path}`` whose path exists and is not a folder."""
    for flag, folder in flags.items():
        if folder is not None and Path(folder).exists() and not Path(folder).is_dir():
            raise ValueError(f"{flag} {folder}: a file; expected a folder")
