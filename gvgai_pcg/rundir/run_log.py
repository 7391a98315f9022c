"""The run's log: one CSV row per group of finished episodes, in the study's columns.

``EpisodeTracker`` follows the B envs of a rollout and collects the score, length and outcome
of every finished episode. ``RunLog`` appends rows to ``log.csv`` and mirrors them to TorchRL
loggers (csv, tensorboard, wandb). On resume the log is cut back to the checkpoint's frame
count, so a run that was killed and started again has no duplicated rows. ``sync`` puts the rows
on disk before a checkpoint is written, so every row up to a checkpoint survives any kill, and
the cuts replace the files atomically.
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import torch
from tensordict import TensorDictBase

from gvgai_pcg.rundir.atomic_files import atomic_write_text, fsync_file

COLUMNS = (
    "frames",
    "episodes",
    "mean_score",
    "std_score",
    "min_score",
    "max_score",
    "win_rate",
    "difficulty",
    "policy_loss",
    "value_loss",
    "entropy",
    "episode_length",
    "fps",
    "time",
)
LOG_NAME = "log.csv"


class EpisodeTracker:
    """Finished episodes of a batch of ``num_envs`` envs, across rollouts."""

    def __init__(self, num_envs: int) -> None:
        self.lengths = torch.zeros(num_envs, dtype=torch.int64)
        self.scores: list[float] = []
        self.episode_lengths: list[int] = []
        self.wins: list[bool] = []

    def update(self, rollout: TensorDictBase) -> None:
        """Record the episodes that ended in ``rollout [B, T]``."""
        done = rollout.get(("next", "done")).squeeze(-1).cpu()
        score = rollout.get(("next", "score")).squeeze(-1).cpu()
        won = rollout.get(("next", "won")).squeeze(-1).cpu()
        for t in range(done.shape[1]):
            self.lengths += 1
            ended = done[:, t]
            if ended.any():
                self.scores += score[ended, t].tolist()
                self.wins += won[ended, t].tolist()
                self.episode_lengths += self.lengths[ended].tolist()
                self.lengths[ended] = 0

    def __len__(self) -> int:
        return len(self.scores)

    def take(self) -> dict[str, float]:
        """Statistics of the episodes recorded since the last ``take`` (then forgets them)."""
        scores = torch.tensor(self.scores, dtype=torch.float64)
        stats = {
            "episodes": len(scores),
            "mean_score": scores.mean().item(),
            "std_score": scores.std(unbiased=False).item(),
            "min_score": scores.min().item(),
            "max_score": scores.max().item(),
            "win_rate": sum(self.wins) / len(self.wins),
            "episode_length": sum(self.episode_lengths) / len(self.episode_lengths),
        }
        self.scores, self.episode_lengths, self.wins = [], [], []
        return stats


class RunLog:
    """Appends rows to ``run_dir/log.csv`` and mirrors them to TorchRL loggers."""

    def __init__(self, run_dir: Path, backends: list[str], resume_frames: int | None) -> None:
        self.path = run_dir / LOG_NAME
        self.episodes = 0
        if resume_frames is None:
            self.path.unlink(missing_ok=True)
        else:
            self.episodes = cut_log(self.path, resume_frames)
            cut_torchrl_csv(run_dir / "torchrl" / "scalars", resume_frames)
        self.rows = len(read_log(self.path)) if self.path.exists() else 0
        self.loggers = [make_torchrl_logger(name, run_dir) for name in backends]
        self.scalars_dir = run_dir / "torchrl" / "scalars"
        self._file = open(self.path, "a", newline="")
        self._writer = csv.DictWriter(self._file, fieldnames=COLUMNS)
        if self.path.stat().st_size == 0:
            self._writer.writeheader()
            self._file.flush()

    def write(self, row: dict[str, float]) -> None:
        self.episodes = int(row["episodes"])
        self._writer.writerow({key: row.get(key, math.nan) for key in COLUMNS})
        self._file.flush()
        self.rows += 1
        for logger in self.loggers:
            for key in COLUMNS[1:]:
                value = row.get(key, math.nan)
                if not math.isnan(value):
                    logger.log_scalar(key, value, step=int(row["frames"]))

    def sync(self) -> None:
        """Force the rows written so far (``log.csv`` and TorchRL's CSV files) onto the disk."""
        if not self._file.closed:
            self._file.flush()
        fsync_file(self.path)
        for path in self.scalars_dir.glob("*.csv") if self.scalars_dir.is_dir() else []:
            fsync_file(path)

    def close(self) -> None:
        """Close ``log.csv`` and the TorchRL loggers (their writers flush what they hold)."""
        self._file.close()
        for logger in self.loggers:
            logger.close()


def read_log(path: Path) -> list[dict[str, float]]:
    """The rows of a ``log.csv`` as floats; a last row cut short (a run killed while writing it)
    is left out."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if rows and any(value in (None, "") for value in rows[-1].values()):
        rows.pop()
    values = []
    for line, row in enumerate(rows, start=2):  # line 1 is the header
        try:
            values.append({k: float(v) for k, v in row.items()})
        except (TypeError, ValueError) as error:  # a value not a number; a row with extra fields
            bad = next((f"{k}={v!r}" for k, v in row.items() if not _is_number(v)), "a malformed row")
            raise ValueError(
                f"{path}, line {line}: {bad} is not a number ({error}); the log was changed outside the "
                "run: restore it, or delete the bad rows"
            ) from None
    return values


def _is_number(value: object) -> bool:
    try:
        float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return False
    return True


def cut_log(path: Path, frames: int) -> int:
    """Drop the rows written after ``frames``; returns the episode count of the last kept row."""
    if not path.exists():
        return 0
    rows = [row for row in read_log(path) if row["frames"] <= frames]
    text = io.StringIO(newline="")
    writer = csv.DictWriter(text, fieldnames=COLUMNS)
    writer.writeheader()
    for row in rows:
        writer.writerow({k: int(row[k]) if k in ("frames", "episodes") else row[k] for k in COLUMNS})
    atomic_write_text(path, text.getvalue())
    return int(rows[-1]["episodes"]) if rows else 0


def cut_torchrl_csv(scalars_dir: Path, frames: int) -> None:
    """Drop the ``step,value`` lines after ``frames`` from TorchRL's CSV logger files (and a last
    line cut short)."""
    for path in scalars_dir.glob("*.csv") if scalars_dir.is_dir() else []:
        text = path.read_text()
        lines = text.splitlines()
        if lines and not text.endswith("\n"):
            lines.pop()  # the run was killed while writing it
        kept = [line for line in lines if line and float(line.split(",")[0]) <= frames]
        atomic_write_text(path, "".join(line + "\n" for line in kept))


def make_torchrl_logger(name: str, run_dir: Path):
    """A TorchRL logger writing into the run directory (``csv``, ``tensorboard`` or ``wandb``)."""
    from torchrl.record.loggers import get_logger

    if name not in ("csv", "tensorboard", "wandb"):
        raise ValueError(f"unknown log backend {name!r}; valid backends are: csv, tensorboard, wandb")
    if name == "wandb":
        wandb_kwargs = {"id": run_dir.name, "resume": "allow", "project": "gvgai-pcg"}
        return get_logger(
            "wandb", logger_name=str(run_dir), experiment_name=run_dir.name, wandb_kwargs=wandb_kwargs
        )
    return get_logger(name, logger_name=str(run_dir), experiment_name="torchrl")
