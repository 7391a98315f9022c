"""Sweeps through Hydra's launcher plugins: a two-run sweep on a local Ray instance and through
submitit's local executor (the SLURM launcher's machinery, without SLURM). Slow, and skipped
where the plugin is not installed (``pip install -e '.[ray]'`` / ``'.[slurm]'``)."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

TINY = [
    "game=frogs",
    "regimen=lv",
    "env.num_envs=4",
    "env.max_steps=20",
    "total_frames=80",
    "log.every_episodes=4",
    "log.curve=false",
]
# Ray on one node, its loopback only: never this machine's other addresses (Ray's default).
LOOPBACK_RAY = {**os.environ, "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER": "0"}
LAUNCHERS = {
    # each run asks Ray for one CPU, so both fit at once on a two-core machine
    "ray_local": ("hydra_plugins.hydra_ray_launcher", ["hydra.launcher.ray.remote.num_cpus=1"]),
    # submitit's LocalExecutor runs each job as a process of its own, as SLURM would
    "submitit_local": (
        "hydra_plugins.hydra_submitit_launcher",
        ["hydra.launcher.timeout_min=10", "hydra.launcher.cpus_per_task=1"],
    ),
}


def installed(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except ModuleNotFoundError:
        return False


@pytest.mark.slow
@pytest.mark.parametrize("launcher", sorted(LAUNCHERS))
def test_a_two_run_sweep_through_a_launcher(launcher: str, tmp_path: Path) -> None:
    plugin, settings = LAUNCHERS[launcher]
    if not installed(plugin):
        pytest.skip(f"{plugin} is not installed")
    command = [
        sys.executable,
        "-m",
        "gvgai_pcg.cli",
        "train",
        "-m",
        f"hydra/launcher={launcher}",
        *settings,
        "seed=0,1",
        *TINY,
        f"out_dir={tmp_path}",
    ]
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, env=LOOPBACK_RAY)
    assert done.returncode == 0, done.stdout + done.stderr
    for seed in (0, 1):
        run_dir = tmp_path / f"frogs-lv0-tiles-compact-seed{seed}"
        assert (run_dir / "model.pt").is_file() and (run_dir / "log.csv").is_file()
        assert yaml.safe_load((run_dir / "config.yaml").read_text())["seed"] == seed


@pytest.mark.slow
def test_a_sweep_with_a_bad_value_starts_no_job(tmp_path: Path) -> None:
    if not installed("hydra_plugins.hydra_submitit_launcher"):
        pytest.skip("hydra_plugins.hydra_submitit_launcher is not installed")
    command = [sys.executable, "-m", "gvgai_pcg.cli", "train", "-m", "hydra/launcher=submitit_local"]
    command += ["seed=0,1", "algo.lr=0.001,-1", f"out_dir={tmp_path}"]
    done = subprocess.run(command, capture_output=True, text=True, timeout=300)
    assert (
        done.returncode == 2
        and done.stderr == "gvgai-pcg train: error: algo.lr=-1: expected a finite number > 0\n"
    )
    assert list(tmp_path.iterdir()) == []
