"""A training session loses nothing: one writer per run directory, every check before the first
frame (a refusal changes no file), an earlier run set aside rather than deleted, ``prev.pt`` when
``last.pt`` is unusable, a log that agrees with the checkpoint."""

from __future__ import annotations

import hashlib
import logging
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
import torch

from gvgai_pcg.cli import main
from gvgai_pcg.rl import train
from gvgai_pcg.rundir.run_log import read_log
from tests.waiting import PATIENCE_S

# 8 envs x 5 steps = 40 frames a batch; a row per 8 episodes of at most 10 steps
TINY = ["regimen=lv", "env.num_envs=8", "env.max_steps=10", "log.every_episodes=8", "log.curve=false"]


def _tiny(make_config, tmp_path: Path, *extra: str):
    return make_config(
        [*TINY, "checkpoint.every_frames=40", "total_frames=120", f"out_dir={tmp_path}", *extra]
    )


def _files(run_dir: Path) -> dict[str, str]:
    """Every file of the run (but its lock) and a hash of its bytes."""
    return {
        str(path.relative_to(run_dir)): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in sorted(run_dir.rglob("*"))
        if path.is_file() and path.name != ".lock"
    }


def _one_line_error(argv: list[str], capsys, code: int = 2) -> str:
    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == code
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    return err


def test_a_refused_resume_leaves_every_file_of_the_run_as_it_was(tmp_path, capsys):
    argv = ["train", *TINY, "total_frames=80", f"out_dir={tmp_path}", "run_name=run"]
    assert main(argv) == 0
    capsys.readouterr()  # its output (a progress line, on a slow machine)
    run_dir = tmp_path / "run"
    before = _files(run_dir)
    assert {".hydra/config.yaml", ".hydra/overrides.yaml", "config.yaml", "checkpoints/last.pt"} <= set(
        before
    )
    err = _one_line_error([*argv, "algo.lr=0.001"], capsys)
    assert "algo.lr: 0.0007 in the checkpoint, 0.001 now" in err
    assert _files(run_dir) == before


def test_a_second_training_in_a_run_directory_is_refused_and_sigterm_stops_the_first(tmp_path, capsys):
    """Two real processes: the holder trains; the second is refused by name; SIGTERM then stops the
    holder after its current update with a checkpoint, and the run resumes from exactly there."""
    overrides = [*TINY, "checkpoint.every_frames=1000000", f"out_dir={tmp_path}", "run_name=run"]
    run_dir = tmp_path / "run"
    command = [sys.executable, "-m", "gvgai_pcg.cli", "train", *overrides, "total_frames=10000000"]
    holder = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + PATIENCE_S
        while not (run_dir / "log.csv").exists() and holder.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)  # the session is accepted (and has taken the lock) before the log exists
        assert holder.poll() is None, holder.communicate()[1][-2000:]
        written = {name: digest for name, digest in _files(run_dir).items() if "config.yaml" in name}
        # (a budget of one batch: were it not refused, it would return at once, not train for hours)
        err = _one_line_error(["train", *overrides, "total_frames=40", "seed=1"], capsys)
        assert f"{run_dir} is in use by PID {holder.pid} on host " in err
        assert "two trainings in one run directory would corrupt" in err
        assert {name: _files(run_dir)[name] for name in written} == written  # the refused one wrote none
        holder.send_signal(15)
        out, err = holder.communicate(timeout=PATIENCE_S)
    finally:
        if holder.poll() is None:
            holder.kill()
    assert holder.returncode == 143, err[-2000:]
    last_line = err.strip().splitlines()[-1]
    assert last_line.startswith("gvgai-pcg train: stopped by SIGTERM at ")
    frames = int(last_line.split(" at ")[1].split(" frames")[0])
    assert f"checkpoint {run_dir / 'checkpoints' / 'last.pt'}; resume with: gvgai-pcg train " in last_line
    saved = torch.load(run_dir / "checkpoints" / "last.pt", weights_only=True)
    assert saved["frames"] == frames > 0  # the stop wrote a checkpoint where it stopped
    assert not (run_dir / "model.pt").exists()  # an unfinished run has no final model
    rows = read_log(run_dir / "log.csv")
    assert len(rows) == saved["log_rows"] and all(row["frames"] <= frames for row in rows)
    log_at_stop = (run_dir / "log.csv").read_text()

    assert main(["train", *overrides, f"total_frames={frames + 80}"]) == 0
    resumed = torch.load(run_dir / "checkpoints" / "last.pt", weights_only=True)
    assert resumed["frames"] == frames + 80
    assert (run_dir / "log.csv").read_text().startswith(log_at_stop)  # nothing lost, nothing twice


def test_the_run_directory_is_checked_writable_before_the_first_frame(make_config, tmp_path):
    cfg = _tiny(make_config, tmp_path)
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    (run_dir / "checkpoints").write_text("a file where the checkpoint folder goes")
    with pytest.raises(NotADirectoryError, match="checkpoints is not a folder"):
        train(cfg, run_dir)
    assert sorted(path.name for path in run_dir.iterdir()) == [".lock", "checkpoints"]  # no frame, no log


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_checkpoint_folder_is_refused_before_the_first_frame(make_config, tmp_path):
    cfg = _tiny(make_config, tmp_path)
    run_dir = tmp_path / "run"
    (run_dir / "checkpoints").mkdir(parents=True)
    (run_dir / "checkpoints").chmod(0o555)
    try:
        with pytest.raises(OSError, match="checkpoints cannot be written"):
            train(cfg, run_dir)
    finally:
        (run_dir / "checkpoints").chmod(0o755)
    assert not (run_dir / "log.csv").exists()


def test_starting_afresh_over_an_earlier_run_moves_it_aside(make_config, tmp_path, caplog):
    cfg = _tiny(make_config, tmp_path)
    run_dir = tmp_path / "run"
    train(cfg, run_dir)
    (run_dir / "checkpoints" / "last.pt").unlink()  # as the old corrupt-checkpoint message asked
    (run_dir / "checkpoints" / "prev.pt").unlink()
    earlier = _files(run_dir)
    with caplog.at_level(logging.WARNING):
        train(cfg, run_dir)
    (aside,) = (run_dir / "previous-runs").iterdir()
    assert f"moved to {aside}" in caplog.text
    assert _files(aside) == earlier  # the earlier log, model, mirror and config, byte for byte
    assert read_log(run_dir / "log.csv")[0]["frames"] <= 120  # the new run's own log


def test_an_unusable_last_checkpoint_falls_back_to_the_previous_one(make_config, tmp_path, caplog):
    cfg = _tiny(make_config, tmp_path)
    run_dir = tmp_path / "run"
    train(cfg, run_dir)
    checkpoints = run_dir / "checkpoints"
    assert torch.load(checkpoints / "prev.pt", weights_only=True)["frames"] == 80
    (checkpoints / "last.pt").write_bytes(b"cut short by a full disk")
    more = _tiny(make_config, tmp_path, "total_frames=160")
    with caplog.at_level(logging.WARNING):
        result = train(more, run_dir)
    assert "last.pt cannot be used" in caplog.text and "resuming from" in caplog.text
    assert "(80 frames)" in caplog.text
    assert result.frames == 160
    (kept,) = checkpoints.glob("last.pt.unusable-*")
    assert kept.read_bytes() == b"cut short by a full disk"
    frames = [row["frames"] for row in read_log(run_dir / "log.csv")]
    assert frames == sorted(set(frames))  # rows after 80 frames were cut, not duplicated


def test_without_a_usable_checkpoint_the_run_is_refused_not_restarted(make_config, tmp_path):
    cfg = _tiny(make_config, tmp_path)
    run_dir = tmp_path / "run"
    train(cfg, run_dir)
    for name in ("last.pt", "prev.pt"):
        (run_dir / "checkpoints" / name).write_bytes(b"garbage")
    before = _files(run_dir)
    with pytest.raises(ValueError, match="corrupt or truncated.*move .*checkpoints away to start"):
        train(cfg, run_dir)
    assert _files(run_dir) == before


def test_a_resume_says_when_the_log_lost_rows_before_the_checkpoint(make_config, tmp_path, caplog):
    cfg = _tiny(make_config, tmp_path, "total_frames=400")
    run_dir = tmp_path / "run"
    train(cfg, run_dir)
    (run_dir / "log.csv").unlink()
    with caplog.at_level(logging.WARNING):
        train(_tiny(make_config, tmp_path, "total_frames=440"), run_dir)
    assert "log.csv holds 0 of the" in caplog.text and "rows written before the checkpoint" in caplog.text
