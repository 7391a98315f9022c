"""One training session in a run directory: one writer, checked before the first frame, and
nothing of an earlier session lost.

``open_run`` is what ``train`` does before it builds anything, in this order:

1. lock the run directory (``run_lock``): a second process is refused, naming the holder;
2. check that the directory, ``checkpoints/`` and the log can be written (a read-only folder is
   found now, not at the first checkpoint after the training it would discard), and that the
   packages of the log backends are installed;
3. find the checkpoint to resume from: ``last.pt``, else ``prev.pt`` with a warning when
   ``last.pt`` cannot be used; a checkpoint of another config, or of the same ``regimen.path``
   whose level files have changed since (``level_set``, their fingerprint), is refused; then remove the
   temporary files of writers killed mid-write (``.last.pt.<pid>.tmp``);
4. on a resume, check that the log still holds the rows written before the checkpoint; on a fresh
   start over the outputs of an earlier session (no checkpoint to resume), move them aside to
   ``previous-runs/<time>/`` and say so, never delete them;
5. only then write ``config.yaml`` (and Hydra's ``.hydra/*.yaml``, which the app has Hydra leave
   to us for this reason), atomically.

Any refusal in 1-4 leaves every file of the run as it was. During the session SIGINT/SIGTERM
are turned into a stop request (``stop_signal``) and the divergence guard watches the updates;
``closing`` registers what must be shut down however the session ends (the collector).

Any other stop inside the session (a progress or log write into a closed pipe or a full disk, a
logger backend that raises, a second Ctrl-C) is not allowed to lose the run: the training loop
hands the session its ``saving_last_state`` function once it has a state to save, and the
session saves the last complete update with it before it raises ``TrainingStopped`` (which names
the cause, the frames and the checkpoint). A diverged run is the exception: it keeps its last
good checkpoint (``DivergenceError``).
"""

from __future__ import annotations

import contextlib
import errno
import logging
import os
import shutil
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from gvgai_pcg.log_backends import check_installed
from gvgai_pcg.rl.divergence import DivergenceError, DivergenceGuard
from gvgai_pcg.rundir.atomic_files import atomic_write_text, fsync_directory, remove_stale_temporaries
from gvgai_pcg.rundir.checkpoint import (
    CHECKPOINT_NAME,
    PREVIOUS_NAME,
    CheckpointError,
    UnusableCheckpointError,
    load_checkpoint,
    save_checkpoint,
)
from gvgai_pcg.rundir.earlier_outputs import ASIDE_DIR, set_aside_earlier_outputs, stamp
from gvgai_pcg.rundir.run_lock import FolderLock
from gvgai_pcg.rundir.run_log import LOG_NAME, read_log
from gvgai_pcg.rundir.stop_signal import StopSignal

log = logging.getLogger(__name__)

CHECKPOINT_DIR = "checkpoints"
FULL_DISK_BYTES = 16 * 2**20  # less room than this left: a failed write was most likely for want of it


class TrainingStopped(Exception):
    """The session was stopped by ``cause`` (an error, or a second Ctrl-C); ``checkpoint`` holds
    ``frames`` frames: the last complete update when ``saved``, else the checkpoint before (none,
    with ``frames`` 0, when the run had none)."""

    def __init__(
        self, cause: BaseException, saved: bool, frames: int, checkpoint: Path, full_disk: bool = False
    ) -> None:
        self.cause, self.saved, self.frames, self.checkpoint = cause, saved, frames, checkpoint
        what = f"by {type(cause).__name__}: {cause}" if str(cause) else f"by {type(cause).__name__}"
        if full_disk:  # what the writer said (torch.save: "unexpected pos ...") is in the traceback
            what = f"(no space left on device: {checkpoint.parent.parent})"
        if saved:
            kept = f"the last complete update ({frames} frames) is saved in {checkpoint}"
        elif checkpoint.exists():
            kept = f"the last complete update could not be saved; {checkpoint} ({frames} frames) is intact"
        else:
            kept = "no checkpoint was saved"
        if full_disk and checkpoint.exists():
            kept += "; free some space first"
        super().__init__(f"training stopped {what}; {kept}")


def disk_is_full(error: BaseException, folder: Path) -> bool:
    """Whether ``error`` (or what caused it) is a full disk: ENOSPC, or an error of a writer that
    hides it (torch.save says "unexpected pos") while ``folder``'s disk has almost no room left."""
    while error is not None:
        if isinstance(error, OSError) and error.errno in (errno.ENOSPC, errno.EDQUOT):
            return True
        error = error.__cause__ or error.__context__
    try:
        return shutil.disk_usage(folder).free < FULL_DISK_BYTES
    except OSError:
        return False


@dataclass
class RunSession:
    """What the training loop needs from its session."""

    run_dir: Path
    checkpoint_path: Path
    saved: dict[str, Any] | None  # the checkpoint resumed from (None: a fresh start)
    stop: StopSignal
    guard: DivergenceGuard
    exits: contextlib.ExitStack = field(repr=False)
    save_last_state: Callable[[], None] | None = field(default=None, repr=False)
    frames_saved: int | None = None  # the frames of the last checkpoint this session wrote
    stopping: bool = False  # saving after a failure: a log that cannot be synced does not stop it

    def saving_last_state(self, save: Callable[[], None]) -> None:
        """``save()`` writes the checkpoint of the last complete update; the session calls it when
        anything stops the loop (see the module docstring)."""
        self.save_last_state = save

    def closing(self, collector):
        """Shut ``collector`` down when the session ends, however it ends (once more after its
        own shutdown is harmless: a failure then is only logged)."""
        self.exits.callback(_shut_down, collector)
        return collector

    def save_checkpoint(self, state: dict[str, Any], net, run_log) -> None:
        """The log's rows on disk first, then the checkpoint, and only of a finite model. A state
        already saved (the end of a run that has just checkpointed) is not written again, so that
        ``prev.pt`` stays the checkpoint before it."""
        if int(state["frames"]) == self.guard.checkpoint_frames and self.checkpoint_path.exists():
            self.frames_saved = int(state["frames"])
            return
        try:
            run_log.sync()
        except OSError as error:  # the log's own failure stopped the run: the model still counts
            if not self.stopping:
                raise
            log.warning("the log could not be synced before the last checkpoint: %s", error)
        self.guard.check_parameters(net, int(state["frames"]))
        save_checkpoint(self.checkpoint_path, state)
        self.guard.saved(int(state["frames"]))
        self.frames_saved = int(state["frames"])

    def stopped_by(self, error: BaseException) -> TrainingStopped:
        """Save the last complete update after ``error`` stopped the loop; the error to raise."""
        self.stopping = True
        full = disk_is_full(error, self.run_dir)
        if self.guard.frames == self.guard.checkpoint_frames:  # no update since the last checkpoint
            # (a run that fails before its first update leaves no checkpoint, which a changed
            # config could not start over)
            on_disk = self.checkpoint_path.exists()
            return TrainingStopped(error, on_disk, self.guard.checkpoint_frames, self.checkpoint_path, full)
        try:
            self.save_last_state()
        except BaseException as failure:  # noqa: BLE001 (the first error is the one to report)
            full = full or disk_is_full(failure, self.run_dir)
            if not full:  # (a full disk is the reason the stop line gives)
                log.error(
                    "the last complete update could not be saved: %s: %s", type(failure).__name__, failure
                )
            return TrainingStopped(error, False, self.guard.checkpoint_frames, self.checkpoint_path, full)
        return TrainingStopped(error, True, self.frames_saved or 0, self.checkpoint_path, full)


def _shut_down(collector) -> None:
    try:
        collector.shutdown()
    except Exception as error:  # noqa: BLE001 (the session is ending anyway)
        log.debug("shutting down %s: %s", type(collector).__name__, error)


@contextlib.contextmanager
def open_run(
    run_dir: Path,
    config: dict[str, Any],
    files: dict[str, str],
    stop: StopSignal | None = None,
    level_set: str | None = None,
) -> Iterator[RunSession]:
    """Lock and check ``run_dir``, find the checkpoint, then write ``files`` (name -> text).
    ``stop`` (default: a new one) is armed for the session; ``level_set`` is the fingerprint of
    the run's own level files, which a checkpoint to resume from must share."""
    lock = FolderLock(
        run_dir,
        "two trainings in one run directory would corrupt each other's checkpoints and log",
        "choose another run_name or out_dir",
    )
    with lock:
        try:
            check_writable(run_dir)
            check_installed(config.get("log", {}).get("backends", []))  # not at the first row
            checkpoint_path = run_dir / CHECKPOINT_DIR / CHECKPOINT_NAME
            saved = find_checkpoint(checkpoint_path, config, level_set)
            remove_stale_temporaries_of(run_dir)
            if saved is not None:
                check_log(run_dir / LOG_NAME, saved)
            else:
                set_aside_earlier_outputs(run_dir)
        except BaseException:
            lock.restore_note()
            raise
        for name, text in files.items():
            atomic_write_text(run_dir / name, text)
        guard = DivergenceGuard(checkpoint_path, int(saved["frames"]) if saved else 0)
        with (stop or StopSignal()).arming() as armed, contextlib.ExitStack() as exits:
            session = RunSession(run_dir, checkpoint_path, saved, armed, guard, exits)
            try:
                yield session
            except (Exception, KeyboardInterrupt) as error:
                if session.save_last_state is None or isinstance(error, (DivergenceError, TrainingStopped)):
                    raise
                raise session.stopped_by(error) from error


def remove_stale_temporaries_of(run_dir: Path) -> None:
    """The temporary files of writers killed mid-write (``.last.pt.<pid>.tmp``, megabytes each)."""
    removed = [*remove_stale_temporaries(run_dir), *remove_stale_temporaries(run_dir / CHECKPOINT_DIR)]
    if removed:
        log.info("removed the temporary files of killed writers: %s", ", ".join(str(p) for p in removed))


def check_writable(run_dir: Path) -> None:
    """Refuse now what would fail later: a folder or log file of the run that cannot be written."""
    folders = [run_dir, run_dir / CHECKPOINT_DIR, run_dir / "torchrl" / "scalars"]
    for folder in folders:
        if folder.exists() and not folder.is_dir():
            raise NotADirectoryError(f"{folder} is not a folder, so the run cannot write into it")
        if folder.is_dir():
            probe = folder / f".write-test.{os.getpid()}"
            try:
                os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
                probe.unlink()
            except OSError as error:
                raise _not_writable(folder, error) from None
    files = [run_dir / LOG_NAME, *sorted((run_dir / "torchrl" / "scalars").glob("*.csv"))]
    for path in files:
        if path.exists():
            try:
                open(path, "a").close()  # appending nothing changes nothing
            except OSError as error:
                raise _not_writable(path, error) from None


def _not_writable(path: Path, error: OSError) -> OSError:
    return OSError(
        f"{path} cannot be written ({error.strerror}); the run would fail at its first log row or "
        "checkpoint: fix its permissions, or choose another out_dir/run_name"
    )


def find_checkpoint(
    path: Path, config: dict[str, Any], level_set: str | None = None
) -> dict[str, Any] | None:
    """The checkpoint to resume from: ``last.pt``, or ``prev.pt`` (with a warning) when ``last.pt``
    is missing or cannot be used; ``None`` when there is neither (a fresh start)."""
    previous = path.with_name(PREVIOUS_NAME)
    if not path.exists() and not previous.exists():
        return None
    try:
        return load_checkpoint(path, config, level_set)
    except (UnusableCheckpointError, FileNotFoundError) as error:
        last_error = error
    try:
        saved = load_checkpoint(previous, config, level_set)
    except FileNotFoundError:
        problem = f"and there is no {PREVIOUS_NAME} to fall back to"
    except UnusableCheckpointError as error:
        problem = f"and the previous one cannot be used either ({error})"
    else:
        missing = isinstance(last_error, FileNotFoundError)
        reason = "is missing" if missing else f"cannot be used ({last_error})"
        log.warning("%s %s; resuming from %s (%d frames) instead", path, reason, previous, saved["frames"])
        if path.exists():  # kept for inspection; the next checkpoint must not rotate it into prev.pt
            os.replace(path, path.with_name(f"{CHECKPOINT_NAME}.unusable-{stamp()}"))
            fsync_directory(path.parent)
        return saved
    raise CheckpointError(
        f"{last_error}; {problem}. Restore a good copy to resume, or move {path.parent} away to start "
        f"this run afresh (its log and model are then kept in {ASIDE_DIR}/)"
    )


def check_log(path: Path, saved: dict[str, Any]) -> None:
    """Say so when the log lost rows written before the checkpoint (deleted or cut by hand)."""
    frames, expected = int(saved["frames"]), saved.get("log_rows")
    rows = len([row for row in read_log(path) if row["frames"] <= frames]) if path.exists() else 0
    if expected is None:  # format 1 did not count its rows
        expected = 1 if frames > 0 and not path.exists() else rows
    if rows < expected:
        log.warning(
            "%s holds %d of the %d rows written before the checkpoint at %d frames (deleted or cut "
            "outside the run); resuming, with those rows missing from the log",
            path,
            rows,
            expected,
            frames,
        )
