"""``reproduce --status``: each planned run's state, and the run-hours left from the runs' own pace."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import pytest

from gvgai_pcg.rundir.run_lock import FolderLock
from gvgai_pcg.rundir.run_log import COLUMNS
from gvgai_pcg.study import BUDGETS
from gvgai_pcg.study.sweep_status import RunStatus, run_status, status_text, sweep_status, with_estimates
from tests.evaluation.conftest import make_run


def _trained(root: Path, regimen: str, seed: int, frames: int, hours: float) -> Path:
    """A run with a model at ``frames`` and a log whose last row is ``frames`` after ``hours``."""
    run = make_run(root, regimen, seed, frames=frames)
    with open(run / "log.csv", "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=COLUMNS)
        writer.writeheader()
        writer.writerow({**dict.fromkeys(COLUMNS, 0), "frames": frames, "time": hours * 3600})
    return run


def test_each_state_is_told_apart_and_a_lock_means_training(tmp_path):
    out = tmp_path / "out"
    finished = _trained(out / "runs", "lv0", 0, 1000, 0.5)
    stopped = _trained(out / "runs", "lv0", 1, 400, 0.2)
    training = _trained(out / "runs", "lv0", 2, 250, 0.1)
    (make_run(out / "runs", "ppcg", 0) / "borrowed.json").write_text("{}")

    def status(name: str) -> RunStatus:
        return run_status("zelda-lv0", 0, name, 1000, out)

    assert status(finished.name).state == "finished" and status(finished.name).hours == 0.5
    assert status(stopped.name).state == "stopped" and status(stopped.name).frames == 400
    with FolderLock(training, "a test holds it"):
        assert status(training.name).state == "training"
    assert status(training.name).state == "stopped"  # the lock went with its holder
    assert status("zelda-ppcg-seed0").state == "borrowed"
    assert status("zelda-lv0-seed9").state == "not started"


def test_a_run_published_elsewhere_is_finished_and_a_run_of_the_other_sweep_is_to_borrow(tmp_path):
    published, other = tmp_path / "published", tmp_path / "other"
    run = _trained(published / "runs", "lv0", 0, 1000, 0.4)
    (run / "published.json").write_text('{"checkpoint": "model.pt", "frames": 1000}')
    _trained(other / "runs", "ppcg", 0, 300, 0.1)
    here = tmp_path / "out"
    assert run_status("zelda-lv0", 0, run.name, 1000, here, published).state == "finished"
    to_borrow = run_status("zelda-ppcg", 0, "zelda-ppcg-seed0", 1000, here, published, other)
    assert (to_borrow.state, to_borrow.frames, to_borrow.left) == ("to borrow", 300, None)


def test_the_estimate_is_a_runs_own_pace_else_its_conditions_else_its_games():
    def run(condition, seed, frames, state, hours, target=1000):
        return RunStatus(condition, seed, f"{condition}-{seed}", target, frames, state, hours, None)

    runs = with_estimates(
        [
            run("zelda-lv0", 0, 1000, "finished", 1.0),
            run("zelda-lv0", 1, 1000, "finished", 3.0),
            run("zelda-lv0", 2, 250, "stopped", 0.5),  # its own pace: 0.5 h per 250 frames
            run("zelda-lv0", 3, 0, "not started", 0.0),  # the condition's median: 2 h per 1000
            run("zelda-lv4", 0, 0, "not started", 0.0, target=500),  # the game's: 1 h per 500
            run("frogs-ppcg", 0, 0, "not started", 0.0),  # no Frogs run has finished
        ]
    )
    assert [r.left for r in runs] == [None, None, 1.5, 2.0, 1.0, None]
    text = status_text(runs, jobs=2)
    assert "6 runs: 2 finished, 1 stopped, 3 not started; 4.50 run-hours trained." in text
    assert "about 4.50 run-hours left, 2.25 h on 2 job(s) side by side (and 1 run(s) with no estimate" in text


def test_the_status_of_a_fresh_sweep_lists_every_planned_run_in_order_and_trains_nothing(tmp_path):
    budget = BUDGETS["smoke"]
    runs = sweep_status(budget, ["zelda-lv0", "frogs-pcg1"], tmp_path / "out")
    assert [(r.condition, r.seed) for r in runs] == [
        (c, s) for s in budget.all_seeds for c in ["zelda-lv0", "frogs-pcg1"] if s in budget.seeds_of(c)
    ]
    assert {r.state for r in runs} == {"not started"} and not (tmp_path / "out").exists()
    assert runs[0].name == "zelda-lv0-tiles-compact-seed0"


def test_reproduce_status_prints_the_table_and_exits_0(tmp_path):
    command = [sys.executable, "-m", "gvgai_pcg.cli", "reproduce", "--budget", "smoke", "--status"]
    command += ["--conditions", "zelda-lv0", "--out", str(tmp_path / "out")]
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert "zelda-lv0-tiles-compact-seed0" in done.stdout and "not started" in done.stdout
    assert "1 run(s) left to train, 1 run(s) with no estimate yet" in done.stdout
    assert not (tmp_path / "out").exists()


def test_a_run_whose_checkpoint_cannot_be_read_is_counted_by_its_log(tmp_path):
    run = _trained(tmp_path / "out" / "runs", "lv0", 0, 400, 0.2)
    (run / "model.pt").write_bytes(b"not a checkpoint")
    status = run_status("zelda-lv0", 0, run.name, 1000, tmp_path / "out")
    assert (status.state, status.frames) == ("unreadable", 400)


def test_a_run_whose_model_and_checkpoints_cannot_be_read_is_not_finished_at_its_logs_frames(tmp_path):
    run = _trained(tmp_path / "out" / "runs", "lv0", 0, 1000, 0.5)
    (run / "model.pt").write_bytes(b"not a checkpoint")
    (run / "checkpoints").mkdir()
    (run / "checkpoints" / "last.pt").write_bytes(b"\x00" * 64)
    status = run_status("zelda-lv0", 0, run.name, 1000, tmp_path / "out")
    assert (status.state, status.frames) == ("unreadable", 1000)
    assert "1 runs: 1 unreadable;" in status_text(with_estimates([status]))


def test_a_run_that_a_process_trains_is_training_even_past_the_budgets_frames(tmp_path):
    run = _trained(tmp_path / "out" / "runs", "lv0", 0, 1600, 0.2)  # trains on to total_frames=3200
    with FolderLock(run, "a test holds it"):
        status = run_status("zelda-lv0", 0, run.name, 1600, tmp_path / "out")
    assert (status.state, status.frames) == ("training", 1600)
    assert with_estimates([status])[0].left == 0.0  # none left: never a negative estimate


def _planned_run(out: Path, frames: int) -> Path:
    """The smoke budget's zelda-lv0 seed 0, trained to ``frames``."""
    run = _trained(out / "runs", "lv0", 0, frames, 0.1)
    return run.rename(out / "runs" / "zelda-lv0-tiles-compact-seed0")


def test_the_status_finishes_a_run_at_the_total_frames_of_an_override(tmp_path):
    out = tmp_path / "out"
    _planned_run(out, 1600)  # the smoke budget's frames
    (plain,) = sweep_status(BUDGETS["smoke"], ["zelda-lv0"], out)
    (longer,) = sweep_status(BUDGETS["smoke"], ["zelda-lv0"], out, ["total_frames=3200"])
    assert (plain.state, plain.target) == ("finished", 1600)
    assert (longer.state, longer.frames, longer.target) == ("stopped", 1600, 3200)
    assert longer.left == pytest.approx(0.1)  # its own pace, for the 1600 frames left


def test_a_file_for_a_sweep_folder_or_a_missing_sweep_to_borrow_from_is_one_line(tmp_path):
    """With and without --status: refused before anything is read or written."""
    afile = tmp_path / "afile"
    afile.write_text("")
    command = [
        sys.executable,
        "-m",
        "gvgai_pcg.cli",
        "reproduce",
        "--budget",
        "smoke",
        "--conditions",
        "zelda-lv0",
    ]
    for extra, message in (
        (["--out", str(afile), "--no-train"], f"--out {afile}: a file; expected a folder"),
        (["--publish", str(afile), "--status"], f"--publish {afile}: a file; expected a folder"),
        (
            ["--borrow-from", str(tmp_path / "none"), "--status"],
            f"--borrow-from {tmp_path / 'none'}: no such sweep folder",
        ),
    ):
        done = subprocess.run([*command, *extra], capture_output=True, text=True, check=False)
        assert done.returncode == 2 and message in done.stderr and len(done.stderr.splitlines()) == 1


def test_seeds_replace_the_budgets_for_the_conditions_run_and_bad_seeds_are_one_line(tmp_path):
    command = [sys.executable, "-m", "gvgai_pcg.cli", "reproduce", "--budget", "smoke", "--status"]
    command += ["--conditions", "zelda-lv0", "--out", str(tmp_path / "out")]
    done = subprocess.run([*command, "--seeds", "3,7"], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    listed = [line.split()[0] for line in done.stdout.splitlines() if line.startswith("zelda-lv0-")]
    assert listed == ["zelda-lv0-tiles-compact-seed3", "zelda-lv0-tiles-compact-seed7"]
    for seeds, message in (("a,b", "expected comma-separated whole numbers"), ("1,1", "expected distinct")):
        done = subprocess.run([*command, "--seeds", seeds], capture_output=True, text=True, check=False)
        assert done.returncode == 2 and message in done.stderr and "--seeds" in done.stderr


def test_runs_at_seeds_beyond_the_plan_are_listed_as_extra_and_others_are_not(tmp_path):
    """A publish judges every run in the sweep's folder, so the status shows a seed trained with
    --seeds even when asked without it; a run of another condition, or a hidden folder, is not."""
    budget, out = BUDGETS["smoke"], tmp_path / "out"
    target = budget.frames_of("zelda-lv0")
    for seed, name in ((5, "zelda-lv0-tiles-compact-seed5"), (1, "frogs-lv0-tiles-compact-seed1")):
        _trained(out / "runs", "lv0", seed, target, 0.3).rename(out / "runs" / name)
    (out / "runs" / ".staging-zelda-lv0-tiles-compact-seed6").mkdir()
    runs = sweep_status(budget, ["zelda-lv0"], out)
    extra = [run for run in runs if run.extra]
    assert [(r.name, r.seed, r.state) for r in extra] == [("zelda-lv0-tiles-compact-seed5", 5, "finished")]
    assert not any(run.extra for run in runs if run.seed in budget.seeds_of("zelda-lv0"))
    text = status_text(runs)
    assert "zelda-lv0-tiles-compact-seed5 *" in text
    assert "* 1 run(s) at seeds beyond the budget's (--seeds): the publish judges them too." in text
    assert "frogs-lv0" not in text
