"""Models kept along a run (``checkpoint.keep_every_frames``), so that held-out test scores can be
measured over training and the generalisation gap seen as it opens.

A snapshot is a final-model file (``save_model``'s format: weights, config, frames), written
atomically as ``snapshots/model-<frames>.pt`` the first update at or past each multiple of the
period. It is written before any checkpoint past it, so a resumed run that crosses the multiple
again rewrites the same snapshot rather than missing it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import torch

from gvgai_pcg.rundir.checkpoint import save_model

SNAPSHOT_DIR = "snapshots"


def snapshot_path(run_dir: Path, frames: int) -> Path:
    return Path(run_dir) / SNAPSHOT_DIR / f"model-{int(frames):010d}.pt"


def snapshot_frames(path: Path) -> int:
    """The frames in a snapshot's name, ``model-0001000000.pt`` -> 1000000; a ``ValueError`` naming
    the file for any other name."""
    digits = Path(path).stem.removeprefix("model-")
    if not digits.isdigit() or not digits.isascii():
        raise ValueError(
            f"{path}: not a snapshot's name (model-<frames>.pt, written by training); rename or remove it"
        )
    return int(digits)


def snapshot_paths(run_dir: Path) -> list[Path]:
    """A run's snapshots, oldest first."""
    return sorted((Path(run_dir) / SNAPSHOT_DIR).glob("model-*.pt"))


class Snapshots:
    """Keeps the model every ``every`` frames (0: never), from a run now at ``frames``."""

    def __init__(self, run_dir: Path, every: int, frames: int) -> None:
        self.run_dir, self.every = Path(run_dir), int(every)
        self.next = (frames // self.every + 1) * self.every if self.every > 0 else None

    def maybe_keep(self, frames: int, net: torch.nn.Module, config: dict[str, Any]) -> Path | None:
        if self.next is None or frames < self.next:
            return None
        path = snapshot_path(self.run_dir, frames)
        path.parent.mkdir(parents=True, exist_ok=True)
        save_model(path, net.state_dict(), config, frames)
        self.next = (frames // self.every + 1) * self.every
        return path
