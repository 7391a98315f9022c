"""A stop signal ends a run with a checkpoint where it stopped; a diverged update ends it before
anything non-finite is saved."""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time

import pytest
import torch

from gvgai_pcg.cli import main
from gvgai_pcg.rl import train
from gvgai_pcg.rl.divergence import DivergenceError, DivergenceGuard
from gvgai_pcg.rundir.run_log import EpisodeTracker, read_log
from tests.rl.conftest import needs_generated_levels
from tests.waiting import PATIENCE_S

TINY = ["regimen=lv", "env.num_envs=8", "env.max_steps=10", "log.every_episodes=8", "log.curve=false"]


def test_sigterm_stops_after_the_current_update_with_a_checkpoint(make_config, tmp_path, monkeypatch):
    updates = {"seen": 0}
    record = EpisodeTracker.update

    def update_then_signal(self, rollout):  # the signal arrives while the third batch is in hand
        updates["seen"] += 1
        if updates["seen"] == 3:
            os.kill(os.getpid(), signal.SIGTERM)
        return record(self, rollout)

    monkeypatch.setattr(EpisodeTracker, "update", update_then_signal)
    cfg = make_config([*TINY, "total_frames=4000", "checkpoint.every_frames=100000", f"out_dir={tmp_path}"])
    result = train(cfg, tmp_path / "run")
    assert result.stopped_by == "SIGTERM" and result.frames == 3 * 40  # the update was finished
    assert result.model_path is None and not (tmp_path / "run" / "model.pt").exists()
    saved = torch.load(result.checkpoint_path, weights_only=True)
    assert saved["frames"] == 120 and saved["log_rows"] == len(read_log(result.log_path))
    assert signal.getsignal(signal.SIGTERM) is not None  # the handler was put back
    monkeypatch.setattr(EpisodeTracker, "update", record)
    more = make_config([*TINY, "total_frames=200", "checkpoint.every_frames=100000", f"out_dir={tmp_path}"])
    assert train(more, tmp_path / "run").frames == 200


def test_the_guard_passes_finite_updates_and_names_the_first_bad_quantity(tmp_path):
    guard = DivergenceGuard(tmp_path / "last.pt")
    guard.check_update(torch.tensor(1.5), torch.tensor(0.25), frames=40)
    with pytest.raises(DivergenceError, match="at 80 frames: the gradient norm is nan"):
        guard.check_update(torch.tensor(1.5), torch.tensor(math.nan), frames=80)
    with pytest.raises(DivergenceError, match="the loss is inf; .* no checkpoint was written before it"):
        guard.check_update(torch.tensor(math.inf), torch.tensor(math.nan), frames=80)


def test_a_diverging_run_stops_before_saving_non_finite_weights(tmp_path, capsys):
    argv = ["train", *TINY, "algo.lr=1e6", "checkpoint.every_frames=40", "total_frames=4000"]
    with pytest.raises(SystemExit) as exit_info:
        main([*argv, f"out_dir={tmp_path}", "run_name=run"])
    assert exit_info.value.code == 3
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert err.startswith("gvgai-pcg train: training diverged at ") and "the last good checkpoint is" in err
    checkpoint = tmp_path / "run" / "checkpoints" / "last.pt"
    assert str(checkpoint) in err
    weights = torch.load(checkpoint, weights_only=True)["model"]
    assert all(bool(value.isfinite().all()) for value in weights.values())
    assert not (tmp_path / "run" / "model.pt").exists()


@pytest.mark.slow  # two worker processes and a real SIGTERM to the whole process group: ~1 min
@needs_generated_levels
def test_sigterm_to_a_run_with_collector_workers_stops_it_and_it_resumes(tmp_path):
    overrides = ["regimen=ppcg", "regimen.win_rule=study", "collector.workers=2", "env.num_envs=8"]
    overrides += ["env.max_steps=20", "log.every_episodes=16", "log.curve=false", f"out_dir={tmp_path}"]
    run_dir = tmp_path / "zelda-ppcg-tiles-compact-seed0"
    command = [sys.executable, "-m", "gvgai_pcg.cli", "train", *overrides]
    first = subprocess.Popen(
        [*command, "total_frames=10000000"], stderr=subprocess.PIPE, text=True, start_new_session=True
    )
    try:
        deadline = time.monotonic() + 300
        while time.monotonic() < deadline and first.poll() is None:
            if (run_dir / "log.csv").exists() and len(read_log(run_dir / "log.csv")) >= 2:
                break
            time.sleep(0.2)
        os.killpg(first.pid, signal.SIGTERM)  # as a terminal or SLURM does: every process of the job
        _, err = first.communicate(timeout=PATIENCE_S)
    finally:
        if first.poll() is None:
            os.killpg(first.pid, signal.SIGKILL)
    assert first.returncode == 143, err[-3000:]
    assert err.strip().splitlines()[-1].startswith("gvgai-pcg train: stopped by SIGTERM at ")
    saved = torch.load(run_dir / "checkpoints" / "last.pt", weights_only=True)
    assert saved["curriculum"]["shared_difficulty"][0] > 0
    second = subprocess.run(
        [*command, f"total_frames={saved['frames'] + 160}"], capture_output=True, text=True, timeout=300
    )
    assert second.returncode == 0, second.stderr[-3000:]
    assert (
        torch.load(run_dir / "checkpoints" / "last.pt", weights_only=True)["frames"] == saved["frames"] + 160
    )


# A stand-in for submitit's job process: SIGTERM is logged and ignored, SIGUSR1 checkpoints the
# submission, requeues it and exits (submitit.core.job_environment.SignalHandler).
FAKE_SUBMITIT = """
import signal, sys
from pathlib import Path
marker = Path(sys.argv[1])
def bypass(signum, frame):
    print("submitit: bypassing", signal.Signals(signum).name, file=sys.stderr, flush=True)
def checkpoint_and_requeue(signum, frame):
    marker.write_text("requeued")
    sys.exit(-1)
signal.signal(signal.SIGTERM, bypass)
signal.signal(signal.SIGUSR1, checkpoint_and_requeue)
from gvgai_pcg.cli import main
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.slow  # two real runs under a stand-in launcher: ~30 s
@pytest.mark.parametrize("signals", [("SIGTERM", "SIGUSR1"), ("SIGUSR1",)], ids=["preempted", "timed-out"])
def test_a_launcher_that_requeues_on_its_own_signal_gets_it_after_the_checkpoint(tmp_path, signals):
    marker = tmp_path / "requeued"
    overrides = [*TINY, "checkpoint.every_frames=1000000", "total_frames=10000000", f"out_dir={tmp_path}"]
    run_dir = tmp_path / "zelda-lv0-tiles-compact-seed0"
    command = [sys.executable, "-c", FAKE_SUBMITIT, str(marker), "train", *overrides]
    job = subprocess.Popen(command, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + PATIENCE_S
        while not (run_dir / "log.csv").exists() and job.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        for name in signals:
            job.send_signal(getattr(signal, name))
            time.sleep(3)
            assert not marker.exists() or name == signals[-1]  # a SIGTERM alone is not a requeue
        _, err = job.communicate(timeout=PATIENCE_S)
    finally:
        if job.poll() is None:
            job.kill()
    assert job.returncode == 255 and marker.read_text() == "requeued", err[-3000:]
    stop_line = next(line for line in err.splitlines() if "stopped by" in line)
    frames = int(stop_line.split(" at ")[1].split(" frames")[0])
    assert torch.load(run_dir / "checkpoints" / "last.pt", weights_only=True)["frames"] == frames > 0
