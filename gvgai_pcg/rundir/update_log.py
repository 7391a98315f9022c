"""The update log: the learner's statistics (losses, entropy, speed) from the first update on.

``log.csv`` (``run_log``) gets a row when ``log.every_episodes`` episodes have finished, so a
short run (or the first 40k frames of any run) has no row there. ``updates.csv`` beside it gets a
row after the first update and then whenever ``log.every_update_frames`` more frames have been
trained, with the update statistics averaged since its previous row; the same values go to the
TorchRL loggers as ``update_<column>``. Like ``log.csv`` it is cut back to the checkpoint on
resume (the TorchRL files are cut with ``log.csv``'s) and synced before every checkpoint.

An update that trained on no step (PLR⊥'s batch without a replayed level) reports NaN losses:
a row's means leave it out (``mean_losses``), and a row of such updates only has NaN (``nan`` in
the CSV, which ``read_log`` and ``read_updates`` read back as NaN; the loggers skip it).
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path
from typing import TYPE_CHECKING

from gvgai_pcg.rundir.atomic_files import atomic_write_text, fsync_file

UPDATE_COLUMNS = ("frames", "updates", "policy_loss", "value_loss", "entropy", "fps", "time")
UPDATES_NAME = "updates.csv"
LOGGER_PREFIX = "update_"

if TYPE_CHECKING:
    import torch


class UpdateLog:
    """Appends rows to ``run_dir/updates.csv`` and mirrors them to ``loggers`` (TorchRL's)."""

    def __init__(self, run_dir: Path, loggers: list, resume_frames: int | None) -> None:
        self.path = run_dir / UPDATES_NAME
        if resume_frames is None:
            self.path.unlink(missing_ok=True)
        else:
            cut_updates(self.path, resume_frames)
        self.loggers = loggers
        self._file = open(self.path, "a", newline="")
        self._writer = csv.DictWriter(self._file, fieldnames=UPDATE_COLUMNS)
        if self.path.stat().st_size == 0:
            self._writer.writeheader()
            self._file.flush()

    def write(self, row: dict[str, float]) -> None:
        self._writer.writerow({key: row.get(key, math.nan) for key in UPDATE_COLUMNS})
        self._file.flush()
        for logger in self.loggers:
            for key in UPDATE_COLUMNS[1:]:
                value = row.get(key, math.nan)
                if not math.isnan(value):
                    logger.log_scalar(LOGGER_PREFIX + key, value, step=int(row["frames"]))

    def sync(self) -> None:
        if not self._file.closed:
            self._file.flush()
        fsync_file(self.path)

    def close(self) -> None:
        self._file.close()


def mean_losses(stacked: list[torch.Tensor]) -> list[float]:
    """``[policy_loss, value_loss, entropy]`` averaged over the updates of a log row (each an
    ``Update.stacked()``), leaving out those that trained on no step (NaN); NaN if none did."""
    import torch

    return torch.stack(stacked).nanmean(0).tolist()


def read_updates(path: Path) -> list[dict[str, float]]:
    """The rows of an ``updates.csv`` as floats; a last row cut short is left out."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if rows and any(value in (None, "") for value in rows[-1].values()):
        rows.pop()
    return [{k: float(v) for k, v in row.items()} for row in rows]


def cut_updates(path: Path, frames: int) -> None:
    """Drop the rows written after ``frames`` (a resume from the checkpoint at ``frames``)."""
    if not path.exists():
        return
    text = io.StringIO(newline="")
    writer = csv.DictWriter(text, fieldnames=UPDATE_COLUMNS)
    writer.writeheader()
    for row in read_updates(path):
        if row["frames"] <= frames:
            writer.writerow(
                {k: int(row[k]) if k in ("frames", "updates") else row[k] for k in UPDATE_COLUMNS}
            )
    atomic_write_text(path, text.getvalue())
