"""From a budget to the study's tables: the sweep, the evaluation, the report, the published data.

Every step is resumable, so running the pipeline again continues where it stopped: a run that
was cut off resumes from its checkpoint and a finished one returns at once; a run whose results
are current for the protocol (same checkpoint, same frames) is not evaluated again.

The sweep is a Hydra multirun of ``gvgai-pcg train`` over ``condition`` x ``seed``, so any
Hydra launcher runs it unchanged (``launcher="ray"``, ``"slurm"``). With the basic launcher,
``jobs`` multiruns run side by side, each over a share of the conditions (balanced by their
expected cost), which is how two runs share a 2-core machine.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from gvgai_pcg.games.registry import find_game_spec
from gvgai_pcg.study.conditions import Budget

MODEL_LIMIT_BYTES = 1_000_000  # a trained model is published only below this size


@dataclass
class Outcome:
    """Where a pipeline run left its outputs."""

    out: Path
    runs: Path
    report: Path
    published: Path | None
    sweep_seconds: float


def frame_cost(condition: str) -> float:
    """The relative cost of a frame of ``condition``'s training (its game's ``GameSpec.frame_cost``,
    measured frames/s of the default training, docs/benchmarks.md; 1 for an unknown game): only
    used to share the conditions fairly between parallel jobs."""
    spec = find_game_spec(condition.split("-")[0])
    return 1.0 if spec is None else spec.frame_cost


def share_conditions(conditions: Sequence[str], jobs: int) -> list[list[str]]:
    """``conditions`` split into at most ``jobs`` shares of about equal expected cost (greedy,
    most expensive first); each share keeps the conditions' given order."""
    shares: list[list[str]] = [[] for _ in range(max(1, min(jobs, len(conditions))))]
    costs = [0.0] * len(shares)
    for condition in sorted(conditions, key=lambda c: -frame_cost(c)):
        lightest = costs.index(min(costs))
        shares[lightest].append(condition)
        costs[lightest] += frame_cost(condition)
    order = {c: i for i, c in enumerate(conditions)}
    return [sorted(share, key=order.__getitem__) for share in shares if share]


def sweep_arguments(
    budget: Budget,
    conditions: Sequence[str],
    runs_dir: Path,
    launcher: str | None = None,
    overrides: Sequence[str] = (),
) -> list[str]:
    """The ``gvgai-pcg train -m`` arguments of one multirun over ``conditions`` x the budget's
    seeds. Seeds vary slowest, so a sweep cut short holds every condition at its first seed."""
    arguments = [
        "-m",
        "seed=" + ",".join(map(str, budget.seeds)),
        "condition=" + ",".join(conditions),
        f"total_frames={budget.frames}",
        f"out_dir={runs_dir}",
        *budget.overrides,
    ]
    if launcher:
        arguments.append(f"hydra/launcher={launcher}")
    return [*arguments, *overrides]


def run_sweep(
    budget: Budget,
    conditions: Sequence[str],
    out: Path,
    jobs: int = 1,
    launcher: str | None = None,
    overrides: Sequence[str] = (),
) -> float:
    """Train every run of the budget (resuming those that exist); returns the wall seconds. The
    output of each multirun goes to ``out/logs/sweep-<i>.log``."""
    runs_dir, logs = out / "runs", out / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    shares = [list(conditions)] if launcher else share_conditions(conditions, jobs)
    start = time.perf_counter()
    processes = []
    for i, share in enumerate(shares):
        arguments = sweep_arguments(budget, share, runs_dir, launcher, overrides)
        log_path = logs / f"sweep-{i}.log"
        with open(log_path, "a") as log:
            log.write(f"$ gvgai-pcg train {' '.join(arguments)}\n")
            log.flush()
            command = [sys.executable, "-m", "gvgai_pcg.cli", "train", *arguments]
            processes.append((subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT), log_path))
    failed = [str(path) for process, path in processes if process.wait() != 0]
    if failed:
        raise RuntimeError(f"the sweep failed; see {', '.join(failed)}")
    return time.perf_counter() - start


def publish(out: Path, dest: Path, protocol=None) -> Path:
    """Copy what rebuilds the report into ``dest``: each run's config, log, evaluation results and
    a ``published.json`` naming its model (the model itself only below 1 MB), the random agent's
    results, and the report. ``gvgai-pcg report --no-evaluate DEST/runs --cache-dir DEST/random``
    then rebuilds the tables and curves from ``dest`` alone. With ``protocol``, only runs with its
    records are published, and the model named is the one they were made from, so a run that
    trained on after its evaluation is published as evaluated."""
    from gvgai_pcg.evaluation.checkpoints import PUBLISHED, find_runs, run_info
    from gvgai_pcg.evaluation.evaluator import read_records, run_results_path

    dest.mkdir(parents=True, exist_ok=True)
    for run in find_runs([out / "runs"]):
        records_path = run_results_path(run, protocol) if protocol is not None else None
        if records_path is not None and not records_path.is_file():
            continue  # not evaluated yet: nothing of it is in the report
        info = run_info(run)
        target = dest / "runs" / run.name
        (target / "eval").mkdir(parents=True, exist_ok=True)
        for name in ("config.yaml", "log.csv", "sessions.csv", "curve.png"):
            if (run / name).is_file():
                shutil.copy2(run / name, target / name)
        for results in sorted((run / "eval").glob("*.jsonl")):
            shutil.copy2(results, target / "eval" / results.name)
        model = {"checkpoint": str(info.checkpoint), "frames": info.frames}
        if records_path is not None:
            first = read_records(records_path)[0]
            model = {"checkpoint": first.checkpoint, "frames": first.frames}
        if model["frames"] == info.frames and info.checkpoint.stat().st_size < MODEL_LIMIT_BYTES:
            shutil.copy2(info.checkpoint, target / info.checkpoint.name)
            model["copied"] = info.checkpoint.name
        (target / PUBLISHED).write_text(json.dumps(model, indent=1) + "\n")
    for folder in ("random", "report"):
        if (out / folder).is_dir():
            shutil.copytree(out / folder, dest / folder, dirs_exist_ok=True)
    return dest


def write_claims(
    runs_dir: Path, random_cache: Path, protocol, path: Path, target_frames: int | None = None
) -> Path:
    """The study's claims tested on the runs under ``runs_dir`` (``gvgai_pcg.study.claims``)."""
    from gvgai_pcg.evaluation.checkpoints import find_runs
    from gvgai_pcg.study.claims import claims_markdown, collect, study_claims

    games = collect(find_runs([runs_dir]), random_cache, protocol, target_frames)
    path.write_text(claims_markdown(study_claims(games, target_frames), games))
    return path


def reproduce(
    budget: Budget,
    conditions: Sequence[str],
    out: Path,
    jobs: int = 1,
    launcher: str | None = None,
    overrides: Sequence[str] = (),
    train: bool = True,
    publish_to: Path | None = None,
    progress: bool = True,
) -> Outcome:
    """The whole study at ``budget``: sweep, evaluate, report into ``out``, publish to
    ``publish_to``."""
    from gvgai_pcg.evaluation.protocol import Protocol
    from gvgai_pcg.report import build_report

    out = Path(out).resolve()
    seconds = run_sweep(budget, conditions, out, jobs, launcher, overrides) if train else 0.0
    report_dir = out / "report"
    protocol = Protocol(**budget.protocol)
    build_report([out / "runs"], report_dir, protocol, cache_dir=out / "random", progress=progress)
    write_claims(out / "runs", out / "random", protocol, report_dir / "claims.md", budget.frames)
    published = publish(out, Path(publish_to), protocol) if publish_to is not None else None
    return Outcome(out, out / "runs", report_dir, published, seconds)
