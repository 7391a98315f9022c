"""One writer per folder: an OS lock that a second process is refused, by name of the holder.

A training run directory, a run's evaluation results, the random agent's cache and a report
folder are each written by one process at a time. ``FolderLock`` takes ``filelock.FileLock`` on
``<folder>/.lock`` (an exclusive ``flock``) before anything is written there and keeps it until it
is released or its process dies: the kernel drops the lock with the process (also after SIGKILL),
so a killed run never leaves a stale lock behind. The file names its holder (PID, host, start
time), so that a process that is refused can say who has the folder; a refused process leaves the
file as it was. Two processes on different machines are kept apart too where the shared
filesystem supports ``flock`` (NFSv4, Lustre with ``flock``); where it does not, the lock is
refused rather than emulated (filelock's soft fallback, a marker file that a killed process leaves
behind, is turned off).
"""

from __future__ import annotations

import os
import socket
import sys
import time
from pathlib import Path

from filelock import FileLock, Timeout

LOCK_NAME = ".lock"


class FolderInUseError(OSError):
    """Another process holds the folder's lock."""


class FolderLock:
    """An exclusive lock on ``folder`` (the file ``folder/.lock``), as a context manager.

    Args:
        folder: the folder to own (created if missing).
        purpose: what it protects, for the refusal (``"two trainings would corrupt each other"``).
        hint: what the refused user can do instead (``"choose another run_name"``).
        lock_name: the lock file's name, for a lock on one file of a shared folder (a cache).
    """

    def __init__(self, folder: Path, purpose: str, hint: str = "", lock_name: str | None = None) -> None:
        self.folder, self.purpose, self.hint = Path(folder), purpose, hint
        self.path = self.folder / (lock_name or LOCK_NAME)
        self._lock = FileLock(self.path, timeout=0, mode=0o644, thread_local=False, fallback_to_soft=False)
        self._fd: int | None = None  # the lock file, opened apart for the holder's note
        self._previous_note = b""

    def acquire(self) -> FolderLock:
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as error:
            raise OSError(
                f"cannot create the lock file {self.path} ({error.strerror}): {self.folder} is not "
                "writable; fix its permissions, or write somewhere else"
            ) from error
        try:
            self._lock.acquire()
        except Timeout:
            holder = describe_holder(_read(fd))
            os.close(fd)
            hint = f", or {self.hint}" if self.hint else ""
            raise FolderInUseError(
                f"{self.folder} is in use by {holder}: {self.purpose}; wait for it to end or stop it{hint}"
            ) from None
        except OSError as error:
            os.close(fd)
            raise OSError(
                f"cannot lock {self.path} ({error.strerror}): its filesystem does not support file "
                "locks, so two processes could write this folder at once; use a local or a "
                "flock-capable filesystem"
            ) from error
        self._fd = fd
        self._previous_note = _read(fd)
        _write(fd, holder_note())
        return self

    def restore_note(self) -> None:
        """Put back the previous holder's note (a session that was refused changes no file)."""
        if self._fd is not None:
            _write(self._fd, self._previous_note)

    def release(self) -> None:
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None
            self._lock.release()

    def __enter__(self) -> FolderLock:
        return self.acquire()

    def __exit__(self, *exc_info: object) -> None:
        self.release()


def holder_note() -> bytes:
    since = time.strftime("%Y-%m-%d %H:%M:%S %Z")
    command = " ".join([Path(sys.argv[0]).name, *sys.argv[1:3]]) if sys.argv else "python"
    return f"pid={os.getpid()}\nhost={socket.gethostname()}\nsince={since}\ncommand={command}\n".encode()


def describe_holder(note: bytes) -> str:
    """``PID 123 on host node7 since 2026-01-02 10:00:00 UTC (gvgai-pcg train ...)``."""
    fields = dict(line.split("=", 1) for line in note.decode(errors="replace").splitlines() if "=" in line)
    if "pid" not in fields:
        return "another process (it has not written its name yet)"
    since = f" since {fields['since']}" if fields.get("since") else ""
    command = f" ({fields['command']})" if fields.get("command") else ""
    return f"PID {fields['pid']} on host {fields.get('host', '?')}{since}{command}"


def _read(fd: int) -> bytes:
    return os.pread(fd, 4096, 0)


def _write(fd: int, data: bytes) -> None:
    os.pwrite(fd, data, 0)
    os.ftruncate(fd, len(data))
