"""Path arguments checked before a command reads or writes anything: a file where a folder goes,
or a folder where a file goes, is one line naming the flag, not an errno at the end of the work."""

from __future__ import annotations

from pathlib import Path


def refuse_files_for_folders(flags: dict[str, Path | str | None]) -> None:
    """``ValueError`` for the first ``{flag: path}`` whose path exists and is not a folder."""
    for flag, folder in flags.items():
        if folder is not None and Path(folder).exists() and not Path(folder).is_dir():
            raise ValueError(f"{flag} {folder}: a file; expected a folder")


def refuse_folders_for_files(flags: dict[str, Path | str | None], suffix: str | None = None) -> None:
    """``ValueError`` for the first ``{flag: path}`` of a file to write that is a folder, lies in a
    folder that does not exist, or (with ``suffix``) has another suffix."""
    for flag, file in flags.items():
        if file is None:
            continue
        file = Path(file)
        if file.is_dir():
            raise ValueError(f"{flag} {file}: a folder; expected a file to write")
        if not file.parent.is_dir():
            raise ValueError(f"{flag} {file}: no folder {file.parent} to write it in")
        if suffix is not None and file.suffix.lower() != suffix:
            raise ValueError(f"{flag} {file}: expected a {suffix} file")
