"""Writes that a kill cannot leave half done: a temporary file, fsync, rename, fsync of the folder.

A reader of ``path`` sees either the old content or the new, never a mix, after a kill at any
moment (SIGKILL, a crash, a power cut once the fsyncs have returned). Temporary names carry the
writer's PID, so two processes never write into one temporary file, and the temporary file of a
writer killed mid-write (SIGKILL leaves no chance to remove it) is recognised as stale by its
dead PID: ``remove_stale_temporaries`` deletes those.

A folder (a published run, a report) is built beside its place and swapped in by two renames
(``swap_in_folder``); what a kill between them leaves, ``recover_folders`` repairs. One writer per
parent folder at a time: a second one's staging folder counts as stale.
"""

from __future__ import annotations

import os
import re
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

from gvgai_pcg.rundir.stop_signal import stop_signals_deferred


def fsync_directory(directory: Path) -> None:
    """Make a rename or a new file in ``directory`` durable."""
    fd = os.open(directory, os.O_RDONLY)
    try:
        os.fsync(fd)
    except OSError:  # some filesystems cannot fsync a folder; the rename is still atomic
        pass
    finally:
        os.close(fd)


def fsync_file(path: Path) -> None:
    """Force what other handles have written (and flushed) to ``path`` onto the disk."""
    with open(path, "rb") as handle:
        os.fsync(handle.fileno())


def temporary_path(path: Path) -> Path:
    """A temporary name beside ``path``, private to this process."""
    return path.with_name(f".{path.name}.{os.getpid()}.tmp")


TEMPORARY_NAME = re.compile(r"^\..+\.(\d+)\.tmp$")  # what temporary_path names


def remove_stale_temporaries(folder: Path) -> list[Path]:
    """Delete the temporary files in ``folder`` whose writer (by the PID in the name) is no longer
    running; returns them. Another process's file is kept while that process lives."""
    removed = []
    for path in sorted(folder.iterdir()) if folder.is_dir() else []:
        match = TEMPORARY_NAME.match(path.name)
        if match is None or not path.is_file() or _running(int(match.group(1))):
            continue
        path.unlink(missing_ok=True)
        removed.append(path)
    return removed


def _running(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except (ProcessLookupError, OverflowError):  # no such process; a number no PID can be
        return False
    except PermissionError:  # another user's process
        return True
    return True


def atomic_write(path: Path, write: Callable[[BinaryIO], object]) -> Path:
    """Replace ``path`` by what ``write(handle)`` writes, atomically and durably."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = temporary_path(path)
    try:
        with open(tmp, "wb") as handle:
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    fsync_directory(path.parent)
    return path


def atomic_write_text(path: Path, text: str) -> Path:
    return atomic_write(path, lambda handle: handle.write(text.encode()))


def atomic_copy(source: Path, target: Path) -> Path:
    """Copy ``source`` (with its times) over ``target`` atomically, so a reader never sees half of it."""

    def copy(handle: BinaryIO) -> None:
        with open(source, "rb") as reader:
            shutil.copyfileobj(reader, handle)

    atomic_write(Path(target), copy)
    shutil.copystat(source, target)
    return Path(target)


def copy_tree(source: Path, target: Path, **copytree_kwargs) -> None:
    """``shutil.copytree``, but a failure (a full disk) is one ``OSError`` line naming the first
    file that could not be copied, not the repr of ``shutil.Error``'s list of every failure."""
    try:
        shutil.copytree(source, target, **copytree_kwargs)
    except shutil.Error as error:
        failures = error.args[0] if error.args and isinstance(error.args[0], list) else []
        if not failures or not isinstance(failures[0], tuple) or len(failures[0]) != 3:
            raise
        copied_from, copied_to, why = failures[0]
        more = f"; and {len(failures) - 1} more" if len(failures) > 1 else ""
        raise OSError(f"{copied_to} could not be copied from {copied_from} ({why}){more}") from None


def atomic_savefig(fig, path: Path, **savefig_kwargs) -> Path:
    """``fig.savefig(path)`` through a temporary file: a kill mid-render leaves the old figure."""
    path = Path(path)
    return atomic_write(path, lambda handle: fig.savefig(handle, format=path.suffix[1:], **savefig_kwargs))


def staging_folder(target: Path) -> Path:
    """Where a new ``target`` folder is built before ``swap_in_folder`` puts it in place."""
    return target.with_name(f".staging-{target.name}")


def _moved_aside(target: Path) -> Path:
    return target.with_name(f".replaced-{target.name}")


def swap_in_folder(staged: Path, target: Path) -> Path:
    """Put the folder ``staged`` in ``target``'s place: the old one is renamed aside, ``staged``
    renamed in, the old one removed. SIGINT and SIGTERM wait for the two renames; only a SIGKILL
    between them leaves ``target`` missing, and ``recover_folders`` then puts the old one back."""
    aside = _moved_aside(target)
    shutil.rmtree(aside, ignore_errors=True)
    with stop_signals_deferred():
        if target.exists():
            os.replace(target, aside)
        os.replace(staged, target)
    fsync_directory(target.parent)
    shutil.rmtree(aside, ignore_errors=True)
    return target


def recover_folders(parent: Path) -> None:
    """Undo what a killed ``swap_in_folder`` or staging left in ``parent``: a folder moved aside
    whose replacement never arrived goes back; stale staging and moved-aside folders go."""
    if not parent.is_dir():
        return
    for path in sorted(parent.iterdir()):
        for prefix in (".replaced-", ".staging-"):
            if not (path.name.startswith(prefix) and path.is_dir()):
                continue
            target = path.with_name(path.name.removeprefix(prefix))
            if prefix == ".replaced-" and not target.exists():
                os.replace(path, target)
            else:
                shutil.rmtree(path, ignore_errors=True)
