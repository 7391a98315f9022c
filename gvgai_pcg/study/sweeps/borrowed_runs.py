"""Runs a sweep takes from another sweep instead of training them again (``reproduce
--borrow-from``).

The curricula comparison's PCG 1 and PPCG runs (Zelda and Frogs, A2C with the medium setup, seeds
0-2, 10M frames) train exactly as the ``medium`` sweep's runs of the same names do: their configs
agree key for key but for ``total_frames`` (and bookkeeping: checkpoints, logs). Nothing in
training reads ``total_frames`` but the choice of a compiled or an eager tick, and the two compute
the same (tested per game), so a medium run's model at 10M frames (its final model, or the
snapshot a 20M run kept at 10M) is the model a 10M run would have trained. Taking it saves a third
of the comparison's compute.

A borrowed run is a run folder like any other: the config with the borrowing budget's frames, the
model at those frames, the log and the sessions up to them, the snapshots up to them, and
``borrowed.json`` naming where it came from. It is never trained: the sweep skips it.
"""

from __future__ import annotations

import csv
import json
import os
import shutil
from collections.abc import Sequence
from pathlib import Path

from omegaconf import OmegaConf

from gvgai_pcg.evaluation.checkpoints import FINAL_MODEL, is_run_dir, load_state, read_run_config, run_info
from gvgai_pcg.rundir.checkpoint import config_differences
from gvgai_pcg.rundir.provenance import SESSIONS_NAME
from gvgai_pcg.rundir.snapshots import SNAPSHOT_DIR, snapshot_frames, snapshot_path, snapshot_paths
from gvgai_pcg.study.sweeps.conditions import Budget

BORROWED = "borrowed.json"


def borrow_runs(planned: dict, budget: Budget, source: Path, out: Path) -> set[tuple[str, int]]:
    """The ``(condition, seed)`` pairs of ``planned`` (``pipeline.planned_configs``: each pair's
    run names and configs) whose every run is borrowed into ``out/runs`` from the sweep folder (or
    runs folder) ``source``, at ``budget``'s frames: borrowed now, or on an earlier call. A pair
    with a run of its own in ``out`` (trained there, even in part) is left to the sweep."""
    source = Path(source)
    if not source.is_dir():
        raise FileNotFoundError(f"{source}: no such sweep folder to borrow runs from")
    runs_there = source / "runs" if (source / "runs").is_dir() else source
    borrowed: set[tuple[str, int]] = set()
    for pair, configs in planned.items():
        frames = budget.frames_of(pair[0])
        here = {name: out / "runs" / name for name in configs}
        if all((run / BORROWED).is_file() for run in here.values()):
            borrowed.add(pair)
            continue
        if any(run.exists() for run in here.values()):
            continue
        models = {
            name: borrowable_model(runs_there / name, config, frames) for name, config in configs.items()
        }
        if all(models.values()):
            for name, model in models.items():
                borrow_run(runs_there / name, model, frames, here[name])
            borrowed.add(pair)
    return borrowed


def borrowable_model(run: Path, planned: dict, frames: int) -> Path | None:
    """The model of ``run`` at exactly ``frames`` frames (final model or snapshot) if ``run`` trains
    as ``planned`` does but for its ``total_frames``; else ``None``."""
    if not is_run_dir(run):
        return None
    config = dict(read_run_config(run) or {})
    if int(config.get("total_frames", 0)) < frames:
        return None
    if config_differences(config, {**planned, "total_frames": config["total_frames"]}):
        return None
    info = run_info(run)
    if info.frames == frames:
        return info.model_file
    snapshot = snapshot_path(run, frames)
    if info.frames > frames and snapshot.is_file() and int(load_state(snapshot).get("frames", -1)) == frames:
        return snapshot
    return None


def borrow_run(source: Path, model: Path, frames: int, target: Path) -> Path:
    """``target``: the run ``source`` at ``frames`` frames with ``model`` as its final model, made
    beside ``target`` and renamed into place, so that a stopped borrow leaves no half run."""
    building = target.parent / f".borrowing-{target.name}"
    shutil.rmtree(building, ignore_errors=True)
    building.mkdir(parents=True)
    try:
        _build_borrowed(source, model, frames, target, building)
    except BaseException:
        shutil.rmtree(building, ignore_errors=True)
        raise
    os.replace(building, target)
    return target


def _build_borrowed(source: Path, model: Path, frames: int, target: Path, building: Path) -> None:
    """Into ``building``: the run ``source`` at ``frames`` frames, ``model`` its final model."""
    config = dict(read_run_config(source) or {})
    trained = int(config["total_frames"])
    config.update(total_frames=frames, out_dir=str(target.parent.resolve()))
    OmegaConf.save(OmegaConf.create(config), building / "config.yaml")
    shutil.copy2(model, building / FINAL_MODEL)
    _copy_rows(source / "log.csv", building / "log.csv", lambda at: at <= frames)
    _copy_rows(source / SESSIONS_NAME, building / SESSIONS_NAME, lambda at: at < frames)
    kept = [path for path in snapshot_paths(source) if snapshot_frames(path) <= frames]
    if kept:
        (building / SNAPSHOT_DIR).mkdir()
        for path in kept:
            shutil.copy2(path, building / SNAPSHOT_DIR / path.name)
    record = {"from": str(source.resolve()), "frames": frames, "trained_frames": trained, "model": model.name}
    (building / BORROWED).write_text(json.dumps(record, indent=1) + "\n")


def borrowed_from(run: Path) -> dict | None:
    """``borrowed.json`` of ``run``, or ``None`` for a run it trained itself."""
    path = Path(run) / BORROWED
    return json.loads(path.read_text()) if path.is_file() else None


def borrowed_lines(runs: Sequence[Path]) -> list[str]:
    """One markdown line per borrowed run among ``runs`` (for a results page), or none."""
    lines = []
    for run in runs:
        record = borrowed_from(run)
        if record is not None:
            source = Path(record["from"])
            lines.append(
                f"- `{Path(run).name}`: the `{source.parent.parent.name}` sweep's run of that name at "
                f"{record['frames']:,} of the {record['trained_frames']:,} frames it trained "
                f"(`{record['model']}`)"
            )
    if lines:
        lines.insert(
            0,
            "Borrowed from another sweep that trained them exactly so (`reproduce --borrow-from`), "
            "not trained again:",
        )
        lines.insert(1, "")
    return lines


def _copy_rows(source: Path, target: Path, keep) -> None:
    """The header and the rows of the CSV ``source`` whose ``frames`` ``keep`` accepts, into
    ``target``; a row without a whole number of frames is a ``ValueError`` naming the file."""
    if not source.is_file():
        return
    with open(source, newline="") as file:
        reader = csv.DictReader(file)
        rows = []
        for row in reader:
            frames = row.get("frames")
            if frames is None or not frames.strip().isdigit():
                raise ValueError(
                    f"{source}: line {reader.line_num}: frames {frames!r} is not a whole number; the run's "
                    "file is damaged, so it is not borrowed (restore it, or train the run here)"
                )
            if keep(int(frames)):
                rows.append(row)
        fields = reader.fieldnames or []
    with open(target, "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
