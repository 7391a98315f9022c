"""Where a sweep stands (``reproduce --status``): each planned run, how far it has trained, whether
a process is training it now, and the run-hours left, so that a sweep spread over sittings can be
planned without opening its logs.

The estimate of a run that has started is its own pace (its training wall time over its frames);
of one not started, the pace of the budget's finished runs of its condition, or else of its
game's runs, per frame. It is a plan, not a promise: a run's speed depends on what else runs
beside it.
"""

from __future__ import annotations

import os
import re
import statistics
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import PUBLISHED, published_run_info, run_info
from gvgai_pcg.rundir.run_lock import LOCK_NAME, describe_holder
from gvgai_pcg.rundir.run_log import LOG_NAME, read_log
from gvgai_pcg.study.pipeline import planned_configs
from gvgai_pcg.study.sweeps.borrowed_runs import BORROWED
from gvgai_pcg.study.sweeps.conditions import Budget


@dataclass(frozen=True)
class RunStatus:
    """One planned run: ``state`` is ``finished``, ``training`` (a process holds it, whatever its
    frames), ``stopped``, ``unreadable`` (it wrote a model or checkpoint, and none can be read: its
    frames are its log's), ``not started``, ``borrowed`` or ``to borrow``; ``target`` the frames
    its config trains to (the budget's, or a ``total_frames`` override's); ``hours`` its training
    wall time so far; ``left`` the estimated run-hours to finish it (``None``: no estimate, or none
    needed); ``extra``: a seed beyond the budget's, trained into the sweep's folder (``reproduce
    --seeds``), which its publish judges too."""

    condition: str
    seed: int
    name: str
    target: int
    frames: int
    state: str
    hours: float
    where: Path | None
    left: float | None = None
    extra: bool = False

    @property
    def game(self) -> str:
        return self.condition.split("-", 1)[0]


def training_holder(run: Path) -> str | None:
    """The holder note of ``run``'s lock while a process trains it (``None``: no one does).

    The probe tries the lock the way ``FolderLock`` takes it (filelock's ``flock``, without
    waiting) on a read-only descriptor, so a run folder that is not writable can be read, and
    lets it go at once."""
    from filelock import lock_descriptor, unlock_descriptor

    path = run / LOCK_NAME
    if not path.is_file():
        return None
    fd = os.open(path, os.O_RDONLY)
    try:
        if not lock_descriptor(fd, blocking=False):
            return describe_holder(path.read_bytes())
        unlock_descriptor(fd)
        return None
    finally:
        os.close(fd)


def _progress(run: Path) -> tuple[int, float]:
    """Frames and training wall hours of ``run`` by its log's last row (0, 0.0 without a log)."""
    rows = read_log(run / LOG_NAME) if (run / LOG_NAME).is_file() else []
    return (int(rows[-1]["frames"]), float(rows[-1]["time"]) / 3600) if rows else (0, 0.0)


def _checkpoint_frames(run: Path, logged: int) -> int | None:
    """The frames of ``run``'s newest model or checkpoint (what a resume continues from); its
    log's ``logged`` frames where it has written none yet; ``None`` where it has written some and
    they cannot be read (a status never stops at one bad run: training it says what is wrong)."""
    try:
        return run_info(run).frames
    except FileNotFoundError:  # no model or checkpoint yet
        return logged
    except Exception:  # noqa: BLE001 (a diverged, truncated or foreign one: never "finished")
        return None


def _published_frames(run: Path) -> int:
    return published_run_info(run).frames if (run / PUBLISHED).is_file() else 0


def run_status(
    condition: str,
    seed: int,
    name: str,
    target: int,
    out: Path,
    published: Path | None = None,
    borrow_from: Path | None = None,
) -> RunStatus:
    """The state of the run ``name`` of ``(condition, seed)``, trained into ``out/runs``
    (finished there, or published under ``published/runs``, or in ``borrow_from``'s runs)."""
    here = out / "runs" / name
    status = {"condition": condition, "seed": seed, "name": name, "target": target}
    if here.is_dir():
        logged, hours = _progress(here)
        frames = _checkpoint_frames(here, logged)
        if (here / BORROWED).is_file():
            return RunStatus(**status, frames=frames or logged, state="borrowed", hours=0.0, where=here)
        if training_holder(here):  # it trains now: on past the budget's frames, or again
            state = "training"
        elif frames is None:
            state = "unreadable"
        else:
            state = "finished" if frames >= target else "stopped"
        return RunStatus(
            **status, frames=logged if frames is None else frames, state=state, hours=hours, where=here
        )
    if published is not None and _published_frames(there := published / "runs" / name) >= target:
        frames, hours = _progress(there)
        return RunStatus(**status, frames=target, state="finished", hours=hours, where=there)
    if borrow_from is not None:
        source = borrow_from / "runs" / name if (borrow_from / "runs").is_dir() else borrow_from / name
        if source.is_dir():
            frames, _ = _progress(source)
            return RunStatus(**status, frames=frames, state="to borrow", hours=0.0, where=source)
    return RunStatus(**status, frames=0, state="not started", hours=0.0, where=None)


def with_estimates(runs: Sequence[RunStatus]) -> list[RunStatus]:
    """``runs`` with ``left`` filled in where a pace is known (see the module docstring)."""

    def pace(rows: list[RunStatus]) -> float | None:
        paces = [r.hours / r.frames for r in rows if r.state == "finished" and r.frames and r.hours]
        return statistics.median(paces) if paces else None

    estimated = []
    for run in runs:
        left = None
        if run.state in ("training", "stopped", "unreadable") and run.frames and run.hours:
            left = run.hours / run.frames * max(run.target - run.frames, 0)
        elif run.state == "not started":
            known = pace([r for r in runs if r.condition == run.condition]) or pace(
                [r for r in runs if r.game == run.game]
            )
            left = None if known is None else known * run.target
        estimated.append(RunStatus(**{**run.__dict__, "left": left}))
    return estimated


def sweep_status(
    budget: Budget,
    conditions: Sequence[str],
    out: Path,
    overrides: Sequence[str] = (),
    published: Path | None = None,
    borrow_from: Path | None = None,
) -> list[RunStatus]:
    """Every run the sweep plans, in the order it trains them (seed by seed), with its state; a
    run is finished at the frames its config trains to (``overrides``' ``total_frames`` too)."""
    if borrow_from is not None and not Path(borrow_from).is_dir():
        raise FileNotFoundError(f"--borrow-from {borrow_from}: no such sweep folder to borrow runs from")
    planned = planned_configs(budget, conditions, overrides)
    order = {condition: i for i, condition in enumerate(conditions)}
    runs = [
        run_status(condition, seed, name, int(config["total_frames"]), Path(out), published, borrow_from)
        for (condition, seed), configs in sorted(planned.items(), key=lambda kv: (kv[0][1], order[kv[0][0]]))
        for name, config in configs.items()
    ]
    return with_estimates(runs + extra_seeds(budget, planned, Path(out), order))


SEEDED_NAME = re.compile(r"(?P<base>.+)-seed(?P<seed>\d+)")


def extra_seeds(budget: Budget, planned: dict, out: Path, order: dict[str, int]) -> list[RunStatus]:
    """The runs under ``out/runs`` of the planned conditions at seeds the plan lacks (trained
    with ``--seeds``, or by hand into the folder): the publish judges every run it finds there,
    so the status lists them too, by seed."""
    names = {name for configs in planned.values() for name in configs}
    condition_of = {
        match["base"]: (condition, int(config["total_frames"]))
        for (condition, _), configs in planned.items()
        for name, config in configs.items()
        if (match := SEEDED_NAME.fullmatch(name))
    }
    found = []
    for path in sorted((out / "runs").glob("*-seed*")) if (out / "runs").is_dir() else []:
        match = SEEDED_NAME.fullmatch(path.name)
        if path.is_dir() and path.name not in names and match and match["base"] in condition_of:
            (condition, target), seed = condition_of[match["base"]], int(match["seed"])
            status = run_status(condition, seed, path.name, target, out)
            found.append(replace(status, extra=True))
    return sorted(found, key=lambda run: (run.seed, order[run.condition]))


def status_text(runs: Sequence[RunStatus], jobs: int = 1) -> str:
    """A table of ``runs`` and a summary: how many are in each state, run-hours spent and left,
    and the wall hours left on ``jobs`` runs side by side."""
    lines = [f"{'run':<44} {'frames':>23}  {'state':<11} {'hours':>6} {'left (h)':>8}"]
    for run in runs:
        frames = f"{run.frames:,} / {run.target:,}"
        left = "-" if run.left is None else f"{run.left:.2f}"
        name = run.name + (" *" if run.extra else "")
        lines.append(f"{name:<44} {frames:>23}  {run.state:<11} {run.hours:>6.2f} {left:>8}")
    counts = {state: sum(r.state == state for r in runs) for state in dict.fromkeys(r.state for r in runs)}
    spent = sum(r.hours for r in runs if r.state != "borrowed")
    unfinished = [r for r in runs if r.state in ("training", "stopped", "unreadable", "not started")]
    left = sum(r.left for r in unfinished if r.left is not None)
    unknown = sum(r.left is None for r in unfinished)
    summary = ", ".join(f"{count} {state}" for state, count in counts.items())
    lines += ["", f"{len(runs)} runs: {summary}; {spent:.2f} run-hours trained."]
    if extras := sum(r.extra for r in runs):
        lines.append(
            f"* {extras} run(s) at seeds beyond the budget's (--seeds): the publish judges them too."
        )
    no_estimate = f"{unknown} run(s) with no estimate yet: no run of their game has finished"
    if unfinished and unknown == len(unfinished):
        lines.append(f"{len(unfinished)} run(s) left to train, {no_estimate}.")
    elif unfinished:
        guess = f"about {left:.2f} run-hours left, {left / jobs:.2f} h on {jobs} job(s) side by side"
        lines.append(guess + (f" (and {no_estimate})" if unknown else "") + ".")
    else:
        lines.append("Nothing left to train.")
    return "\n".join(lines)
