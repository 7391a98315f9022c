"""Training runs end to end: a short run per regimen, resume after SIGKILL, refused checkpoints."""

from __future__ import annotations

import csv
import importlib.util
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import pytest
import torch

from gvgai_pcg.rl import CheckpointError, train
from gvgai_pcg.rundir.provenance import code_commit
from gvgai_pcg.rundir.run_log import COLUMNS, read_log
from tests.rl.conftest import needs_generated_levels
from tests.waiting import PATIENCE_S

SMALL = ["env.num_envs=64", "env.max_steps=50", "checkpoint.every_frames=10000", "log.every_episodes=64"]


def _smoke(make_config, tmp_path: Path, regimen: list[str]) -> None:
    cfg = make_config([*regimen, *SMALL, "total_frames=20000", f"out_dir={tmp_path}"])
    result = train(cfg, tmp_path / cfg.run_name)
    assert result.frames == 20160  # whole batches of 64 envs x 5 steps
    rows = read_log(result.log_path)
    assert len(rows) >= 3 and set(rows[0]) == set(COLUMNS)
    assert all(a["frames"] < b["frames"] for a, b in zip(rows, rows[1:], strict=False))
    assert rows[-1]["episodes"] >= 64 * 3
    checkpoint = torch.load(result.checkpoint_path, weights_only=False)
    assert checkpoint["frames"] == result.frames
    assert result.model_path.exists()
    assert result.curve_path.read_bytes()[:4] == b"\x89PNG"
    assert (result.run_dir / "config.yaml").exists()


@pytest.mark.parametrize(
    "regimen", [["regimen=lv", "regimen.level=2"], ["regimen=lv0-3"]], ids=["lv2", "lv0-3"]
)
def test_smoke_run_on_human_levels(make_config, tmp_path, regimen):
    _smoke(make_config, tmp_path, regimen)


@needs_generated_levels
@pytest.mark.parametrize(
    "regimen", [["regimen=pcg", "regimen.difficulty=0.5"], ["regimen=ppcg"]], ids=["pcg", "ppcg"]
)
def test_smoke_run_on_generated_levels(make_config, tmp_path, regimen):
    _smoke(make_config, tmp_path, regimen)
    if regimen[0] == "regimen=pcg":
        assert {row["difficulty"] for row in read_log(next(tmp_path.glob("*/log.csv")))} == {0.5}


def test_a_corrupt_checkpoint_is_an_error_not_a_fresh_start(make_config, tmp_path):
    cfg = make_config(["regimen=lv", f"out_dir={tmp_path}"])
    checkpoint = tmp_path / cfg.run_name / "checkpoints" / "last.pt"
    checkpoint.parent.mkdir(parents=True)
    checkpoint.write_bytes(b"not a checkpoint")
    with pytest.raises(CheckpointError, match="corrupt"):
        train(cfg, tmp_path / cfg.run_name)
    assert checkpoint.read_bytes() == b"not a checkpoint"


def test_a_checkpoint_of_another_config_is_an_error(make_config, tmp_path):
    cfg = make_config(["regimen=lv", *SMALL, "total_frames=320", f"out_dir={tmp_path}", "log.curve=false"])
    train(cfg, tmp_path / "run")
    written = (tmp_path / "run" / "config.yaml").read_text()
    other = make_config(["regimen=lv", *SMALL, "algo.lr=0.007", f"out_dir={tmp_path}"])
    with pytest.raises(CheckpointError, match="algo.lr"):
        train(other, tmp_path / "run")
    # more workers make larger updates and move the difficulty faster, as more envs do
    more_workers = make_config(["regimen=lv", *SMALL, "collector.workers=2", f"out_dir={tmp_path}"])
    with pytest.raises(CheckpointError, match="collector.workers"):
        train(more_workers, tmp_path / "run")
    assert (tmp_path / "run" / "config.yaml").read_text() == written  # the refused runs wrote nothing


@needs_generated_levels
def test_a_killed_run_resumes_at_its_checkpoint(tmp_path):
    command = [
        sys.executable,
        "-m",
        "gvgai_pcg.cli",
        "train",
        "regimen=ppcg",
        "regimen.win_rule=study",  # step-limit timeouts count as wins, so d moves up
        "env.num_envs=32",
        "env.max_steps=20",
        "total_frames=6400",
        "checkpoint.every_frames=1600",
        "log.every_episodes=32",
        "log.curve=false",
        f"out_dir={tmp_path}",
    ]
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    run_dir = next(iter([tmp_path / "zelda-ppcg-tiles-compact-seed0"]))
    checkpoint = run_dir / "checkpoints" / "last.pt"
    first = subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + PATIENCE_S
        while not checkpoint.exists() and first.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert checkpoint.exists(), "the first run wrote no checkpoint"
        first.send_signal(signal.SIGKILL)
        first.wait()
    finally:
        if first.poll() is None:
            first.kill()
    saved = torch.load(checkpoint, weights_only=False)
    saved_difficulty = float(saved["curriculum"]["shared_difficulty"][0])
    assert saved_difficulty > 0.0
    rows_at_kill = read_log(run_dir / "log.csv")

    second = subprocess.run(command, env=env, capture_output=True, text=True, timeout=180)
    assert second.returncode == 0, second.stderr[-2000:]
    resumed = f"at {saved['frames']} frames (difficulty {saved_difficulty})"
    assert resumed in second.stdout + (run_dir / "train.log").read_text()
    rows = read_log(run_dir / "log.csv")
    kept = [row for row in rows_at_kill if row["frames"] <= saved["frames"]]
    assert rows[: len(kept)] == kept
    assert all(a["frames"] < b["frames"] for a, b in zip(rows, rows[1:], strict=False))
    assert all(a["episodes"] < b["episodes"] for a, b in zip(rows, rows[1:], strict=False))
    assert torch.load(checkpoint, weights_only=False)["frames"] == 6400
    with open(run_dir / "sessions.csv", newline="") as file:
        sessions = list(csv.DictReader(file))
    assert [int(row["frames"]) for row in sessions] == [0, saved["frames"]]  # one row per sitting
    assert sessions[0]["commit"] == sessions[1]["commit"] == code_commit()


@pytest.mark.slow  # spawning two worker processes costs most of a minute on a loaded 2-core machine
@needs_generated_levels
def test_collector_workers_move_one_difficulty(make_config, tmp_path):
    # 2 workers x 8 envs for 100 steps each, episodes cut at 20 steps (a win under the study's rule):
    # about 80 episodes, each moving the one d by 0.01 up, or down for a loss (the random policy now
    # and then dies in a monster, which also shifts that env's episode ends). A worker moving a d of
    # its own would leave the checkpoint's at 0 and its count at 0.
    overrides = ["regimen=ppcg", "regimen.win_rule=study", "collector.workers=2", "env.num_envs=8"]
    cfg = make_config(
        [*overrides, "env.max_steps=20", "total_frames=1600", "log.curve=false", f"out_dir={tmp_path}"]
    )
    train(cfg, tmp_path / "run")
    saved = torch.load(tmp_path / "run" / "checkpoints" / "last.pt", weights_only=False)
    difficulty = float(saved["curriculum"]["shared_difficulty"][0])
    episodes = int(saved["curriculum"]["episodes"][0])
    assert 75 <= episodes <= 100, episodes  # both workers' 8 envs x 5 episodes, give or take deaths
    assert 0.6 < difficulty <= 0.01 * episodes + 1e-9, (difficulty, episodes)
    assert difficulty * 100 == pytest.approx(round(difficulty * 100), abs=1e-6)  # whole steps of 0.01


def test_a_finished_run_started_again_trains_no_further(make_config, tmp_path):
    cfg = make_config(["regimen=lv", *SMALL, "total_frames=320", f"out_dir={tmp_path}", "log.curve=false"])
    first = train(cfg, tmp_path / "run")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        again = train(cfg, tmp_path / "run")
    assert again.frames == first.frames == 320
    with open(tmp_path / "run" / "sessions.csv", newline="") as file:
        assert [row["frames"] for row in csv.DictReader(file)] == ["0"]  # the second sat for nothing
    assert not [w for w in caught if "divisible" in str(w.message)]  # no empty collector set up oddly


def test_code_commit_is_unknown_for_a_copy_git_does_not_track(tmp_path):
    import shutil

    import gvgai_pcg.rundir.provenance as provenance

    inside = Path(provenance.__file__).resolve().parents[2] / ".venv-copy-for-test"
    if not (inside.parent / ".git").exists():
        pytest.skip("not a git checkout")
    try:  # a copy of the package inside the checkout but not tracked (an install in .venv)
        shutil.copytree(Path(provenance.__file__).parent, inside / "rl")
        spec = importlib.util.spec_from_file_location("copied_provenance", inside / "rl" / "provenance.py")
        copied = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(copied)
        assert copied.code_commit() == "unknown"
    finally:
        shutil.rmtree(inside, ignore_errors=True)
    assert provenance.code_commit() not in ("", "unknown")
