"""Tiny run directories as ``gvgai_pcg.rl`` writes them (config.yaml, model.pt, log.csv), built
directly from an untrained network so that the tests need no training."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
import torch
import yaml

from gvgai_pcg.evaluation.policy import observation_shape
from gvgai_pcg.games import get_game
from gvgai_pcg.rl.models import make_actor_critic
from gvgai_pcg.rundir.run_log import COLUMNS

REGIMENS = {
    "lv0": {"name": "lv", "level": 0, "tag": "lv0"},
    "ppcg": {"name": "ppcg", "alpha": 0.01, "start": 0.0, "win_rule": "game", "tag": "ppcg"},
}


def make_run(
    root: Path,
    regimen: str,
    seed: int,
    frames: int = 1000,
    game: str = "zelda",
    regimen_config: dict | None = None,
) -> Path:
    """A run named ``<game>-<regimen>-seed<seed>``; its regimen section is ``regimen_config`` or
    ``REGIMENS[regimen]``."""
    config = {
        "game": {"name": game},
        "regimen": regimen_config or REGIMENS[regimen],
        "model": {"name": "compact", "hidden": 16},
        "env": {"num_envs": 4, "obs": "tiles", "max_steps": 2000},
        "seed": seed,
        "total_frames": frames,
    }
    run_dir = root / f"{game}-{regimen}-seed{seed}"
    run_dir.mkdir(parents=True)
    (run_dir / "config.yaml").write_text(yaml.safe_dump(config))
    torch.manual_seed(seed)
    net = make_actor_critic(
        "compact", "tiles", observation_shape(game, "tiles"), get_game(game).num_actions, 16
    )
    torch.save({"model": net.state_dict(), "config": config, "frames": frames}, run_dir / "model.pt")
    return run_dir


def write_log(run_dir: Path, rows: list[tuple[int, float, float]]) -> None:
    """``log.csv`` with (frames, mean_score, difficulty) rows; other columns 0."""
    with open(run_dir / "log.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=COLUMNS)
        writer.writeheader()
        for frames, score, difficulty in rows:
            writer.writerow(
                {**dict.fromkeys(COLUMNS, 0), "frames": frames, "mean_score": score, "difficulty": difficulty}
            )


@pytest.fixture
def tiny_run(tmp_path) -> Path:
    return make_run(tmp_path / "runs", "lv0", seed=0)
