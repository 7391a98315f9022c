"""A run directory's earlier outputs set aside: a fresh start over the outputs of a session that
left no checkpoint to resume from moves them to ``previous-runs/<time>/``, never deletes them.

Read by the evaluation too (it never takes a set-aside model for the run's), so it lives apart
from the training session that calls it (``run_session``).
"""

from __future__ import annotations

import logging
import os
import time
from pathlib import Path

from gvgai_pcg.rundir.atomic_files import fsync_directory
from gvgai_pcg.rundir.run_lock import LOCK_NAME
from gvgai_pcg.rundir.run_log import LOG_NAME, read_log

log = logging.getLogger(__name__)

ASIDE_DIR = "previous-runs"
# Left in place when an earlier session's outputs are moved aside: the lock, the folder they go
# to, and Hydra's log (this session's log is already open there; it tells every session's story).
STAYS = {LOCK_NAME, ASIDE_DIR, "train.log"}
# An earlier session that wrote only these (and empty folders) left nothing worth keeping.
BOOKKEEPING = {"config.yaml", ".hydra", "shared", "sessions.csv"}


def set_aside_earlier_outputs(run_dir: Path) -> Path | None:
    """Move the outputs of an earlier session that has no checkpoint to resume from (a log, a
    model, results...) into ``previous-runs/<time>/``, so that a fresh start deletes nothing."""
    entries = [entry for entry in sorted(run_dir.iterdir()) if entry.name not in STAYS]
    if not any(_worth_keeping(entry) for entry in entries):
        return None
    aside = run_dir / ASIDE_DIR / stamp()
    while aside.exists():  # a second fresh start within the same second
        aside = aside.with_name(aside.name + "+")
    aside.mkdir(parents=True)
    for entry in entries:
        os.replace(entry, aside / entry.name)
    fsync_directory(run_dir)
    log.warning(
        "%s held the outputs of an earlier session but no checkpoint to resume from; starting afresh, "
        "with those outputs moved to %s",
        run_dir,
        aside,
    )
    return aside


def _worth_keeping(entry: Path) -> bool:
    if entry.name in BOOKKEEPING:
        return False
    if entry.name == LOG_NAME:
        try:
            return bool(read_log(entry))  # more than a header
        except (ValueError, KeyError):
            return True  # unreadable: keep it all the same
    if entry.is_dir():
        return any(path.is_file() and path.stat().st_size > 0 for path in entry.rglob("*"))
    return True


def stamp() -> str:
    """The time now, as a folder name's suffix (a set-aside session's, an unusable checkpoint's)."""
    return time.strftime("%Y%m%d-%H%M%S")
