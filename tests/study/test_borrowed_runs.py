"""A sweep takes the runs another sweep trained exactly as it would, at its own frames
(``reproduce --borrow-from``), and trains none of them again."""

from __future__ import annotations

import csv
import json
from dataclasses import replace

import torch

from gvgai_pcg.evaluation.checkpoints import load_state, read_run_config, run_info
from gvgai_pcg.study import BUDGETS
from gvgai_pcg.study.pipeline import planned_configs, reproduce, run_sweep
from gvgai_pcg.study.sweeps.borrowed_runs import BORROWED, borrow_runs, borrowed_lines

RUN = "zelda-pcg1.0-tiles-compact-seed0"


def test_a_sweep_borrows_another_sweeps_run_at_its_frames_and_trains_none_of_it(tmp_path):
    long = BUDGETS["smoke"]  # 1,600 frames, 80 a batch
    source = tmp_path / "long"
    short_episodes = ["env.max_steps=40"]  # episodes end, and are logged, before 800 frames
    run_sweep(long, ["zelda-pcg1"], source, overrides=[*short_episodes, "checkpoint.keep_every_frames=800"])
    short, out = replace(long, frames=800), tmp_path / "short"

    planned = planned_configs(short, ["zelda-pcg1"], short_episodes)
    assert borrow_runs(planned, short, source, out) == {("zelda-pcg1", 0)}
    run = out / "runs" / RUN
    assert run_info(run).frames == 800 and int(read_run_config(run)["total_frames"]) == 800
    kept = load_state(source / "runs" / RUN / "snapshots" / "model-0000000800.pt")["model"]
    assert all(torch.equal(kept[k], v) for k, v in load_state(run / "model.pt")["model"].items())
    frames = [int(row["frames"]) for row in csv.DictReader(open(run / "log.csv"))]
    source_frames = [int(row["frames"]) for row in csv.DictReader(open(source / "runs" / RUN / "log.csv"))]
    assert frames and max(frames) <= 800 < max(source_frames)
    assert json.loads((run / BORROWED).read_text())["trained_frames"] == 1600
    assert not list(out.glob("runs/.borrowing-*"))

    published = tmp_path / "published"
    reproduce(
        short,
        ["zelda-pcg1"],
        out,
        overrides=short_episodes,
        borrow_from=source,
        publish_to=published,
        progress=False,
    )
    assert not (run / "checkpoints").exists()  # never trained here
    assert (published / "runs" / RUN / BORROWED).is_file()
    [line] = [line for line in borrowed_lines([published / "runs" / RUN]) if line.startswith("- ")]
    assert "`long` sweep" in line and "800 of the 1,600 frames" in line


def test_a_run_trained_otherwise_or_short_of_the_frames_is_not_borrowed(tmp_path):
    long = BUDGETS["smoke"]
    source = tmp_path / "long"
    run_sweep(long, ["zelda-pcg1"], source, overrides=["total_frames=800"])
    short = replace(long, frames=800)
    other_lr = borrow_runs(
        planned_configs(short, ["zelda-pcg1"], ["algo.lr=0.001"]), short, source, tmp_path / "a"
    )
    assert other_lr == set() and not (tmp_path / "a" / "runs" / RUN).exists()
    assert (
        borrow_runs(planned_configs(long, ["zelda-pcg1"], []), long, source, tmp_path / "b") == set()
    )  # 800 < 1,600
    # no snapshot at the asked frames: nothing to borrow either
    early = replace(long, frames=400)
    assert borrow_runs(planned_configs(early, ["zelda-pcg1"], []), early, source, tmp_path / "c") == set()
