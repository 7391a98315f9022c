"""From a budget to the study's tables: the sweep, the evaluation, the report, the published data.

Every step is resumable, so running the pipeline again continues where it stopped: a run that
was cut off resumes from its checkpoint and a finished one returns at once; a run whose results
are current for the protocol (same checkpoint, same frames) is not evaluated again.

The sweep is a Hydra multirun of ``gvgai-pcg train`` over ``condition`` x ``seed``, so any
Hydra launcher runs it unchanged (``launcher="ray"``, ``"slurm"``). With the basic launcher,
``jobs`` multiruns run side by side, each over a share of the conditions (balanced by their
expected cost), which is how two runs share a 2-core machine.

The published folder carries the study across machines: a run published as finished (at the
budget's frames, with the protocol's records) is not trained again where its run directory is
missing (a new machine, a fresh clone); its published records and log go into the report as they
are. So ``make reproduce BUDGET=small`` in a fresh clone trains only what ``results/small`` lacks.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import threading
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from gvgai_pcg.games.registry import find_game_spec
from gvgai_pcg.study.conditions import Budget

MODEL_LIMIT_BYTES = 1_000_000  # a trained model is published only below this size
WRITER_LOCKS = shutil.ignore_patterns(".lock", ".*.lock")  # the evaluator's, never published


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
    seeds: Sequence[int] | None = None,
) -> list[str]:
    """The ``gvgai-pcg train -m`` arguments of one multirun over ``conditions`` x ``seeds`` (the
    budget's by default). Seeds vary slowest, so a sweep cut short holds every condition at its
    first seed."""
    arguments = [
        "-m",
        "seed=" + ",".join(map(str, budget.seeds if seeds is None else seeds)),
        "condition=" + ",".join(conditions),
        f"total_frames={budget.frames}",
        f"out_dir={runs_dir}",
        *budget.overrides,
    ]
    if launcher:
        arguments.append(f"hydra/launcher={launcher}")
    return [*arguments, *overrides]


def sweep_plan(
    budget: Budget, conditions: Sequence[str], skip: Iterable[tuple[str, int]] = ()
) -> list[tuple[tuple[int, ...], list[str]]]:
    """The multiruns that train ``conditions`` x the budget's seeds less the ``(condition, seed)``
    pairs in ``skip``, in order: seeds in turn, consecutive seeds with the same conditions in one
    multirun (so nothing skipped is one multirun over every seed)."""
    skip = set(skip)
    plan: list[tuple[tuple[int, ...], list[str]]] = []
    for seed in budget.seeds:
        left = [c for c in conditions if (c, seed) not in skip]
        if not left:
            continue
        if plan and plan[-1][1] == left:
            plan[-1] = ((*plan[-1][0], seed), left)
        else:
            plan.append(((seed,), left))
    return plan


def run_sweep(
    budget: Budget,
    conditions: Sequence[str],
    out: Path,
    jobs: int = 1,
    launcher: str | None = None,
    overrides: Sequence[str] = (),
    skip: Iterable[tuple[str, int]] = (),
) -> float:
    """Train every run of the budget but the ``(condition, seed)`` pairs in ``skip`` (resuming
    those that exist); returns the wall seconds. Each job runs its multiruns one after another,
    with their output in ``out/logs/sweep-<i>.log``."""
    runs_dir, logs = out / "runs", out / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    shares = [list(conditions)] if launcher else share_conditions(conditions, jobs)
    skip = set(skip)
    start = time.perf_counter()
    failed: list[str] = []

    def run_share(i: int, share: list[str]) -> None:
        log_path = logs / f"sweep-{i}.log"
        for seeds, left in sweep_plan(budget, share, skip):
            arguments = sweep_arguments(budget, left, runs_dir, launcher, overrides, seeds)
            with open(log_path, "a") as log:
                log.write(f"$ gvgai-pcg train {' '.join(arguments)}\n")
                log.flush()
                command = [sys.executable, "-m", "gvgai_pcg.cli", "train", *arguments]
                if subprocess.run(command, stdout=log, stderr=subprocess.STDOUT).returncode != 0:
                    failed.append(str(log_path))
                    return

    threads = [threading.Thread(target=run_share, args=(i, share)) for i, share in enumerate(shares)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    if failed:
        raise RuntimeError(f"the sweep failed; see {', '.join(sorted(failed))}")
    return time.perf_counter() - start


def run_names(budget: Budget, conditions: Sequence[str], overrides: Sequence[str] = ()) -> dict:
    """``(condition, seed) -> run name`` as ``gvgai-pcg train`` composes it for the budget (Hydra's
    own ``hydra...`` overrides, which cannot change a name, are left out)."""
    from hydra import compose, initialize_config_dir

    from gvgai_pcg.config import config_dir

    shared = [*budget.overrides, *(o for o in overrides if not o.lstrip("+~").startswith("hydra"))]
    names = {}
    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
        for condition in conditions:
            for seed in budget.seeds:
                cfg = compose("config", overrides=[f"condition={condition}", f"seed={seed}", *shared])
                names[condition, seed] = str(cfg.run_name)
    return names


def published_finished(published: Path, frames: int, protocol) -> dict[str, Path]:
    """``run name -> folder`` of the runs in ``published`` that were published at ``frames`` or
    more, with ``protocol``'s records: what another machine finished and need not train again."""
    from gvgai_pcg.evaluation.checkpoints import PUBLISHED
    from gvgai_pcg.evaluation.evaluator import run_results_path

    runs = Path(published) / "runs"
    finished = {}
    for run in sorted(runs.iterdir()) if runs.is_dir() else []:
        model = run / PUBLISHED
        if model.is_file() and run_results_path(run, protocol).is_file():
            if int(json.loads(model.read_text())["frames"]) >= frames:
                finished[run.name] = run
    return finished


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
    for run in find_runs([out / "runs"]) if (out / "runs").is_dir() else []:
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
    if (out / "report").is_dir():
        shutil.rmtree(dest / "report", ignore_errors=True)  # no figure of an earlier report stays
        shutil.copytree(out / "report", dest / "report", ignore=WRITER_LOCKS)
    if (out / "random").is_dir():
        shutil.copytree(out / "random", dest / "random", dirs_exist_ok=True, ignore=WRITER_LOCKS)
    return dest


def write_claims(
    runs: Sequence[Path], random_cache: Path, protocol, path: Path, target_frames: int | None = None
) -> Path:
    """The study's claims tested on the runs under ``runs`` (``gvgai_pcg.study.claims``)."""
    from gvgai_pcg.evaluation.checkpoints import find_runs
    from gvgai_pcg.study.claims import claims_markdown, collect, study_claims

    games = collect(find_runs(list(runs)), random_cache, protocol, target_frames)
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
    finished_only: bool = False,
) -> Outcome:
    """The whole study at ``budget``: sweep, evaluate, report into ``out``, publish to
    ``publish_to``. Runs that ``publish_to`` holds as finished and ``out`` lacks are reported from
    there, not trained again. ``finished_only`` leaves out runs short of the budget's frames (a
    report taken while the sweep still trains evaluates no model that will change)."""
    from gvgai_pcg.evaluation.protocol import Protocol
    from gvgai_pcg.report import build_report

    out = Path(out).resolve()
    protocol = Protocol(**budget.protocol)
    elsewhere: dict[tuple[str, int], Path] = {}
    if publish_to is not None:
        finished = published_finished(Path(publish_to), budget.frames, protocol)
        names = run_names(budget, conditions, overrides) if finished else {}
        elsewhere = {
            pair: finished[name].resolve()
            for pair, name in names.items()
            if name in finished and not (out / "runs" / name).exists()
        }
        if (Path(publish_to) / "random").is_dir():
            shutil.copytree(
                Path(publish_to) / "random", out / "random", dirs_exist_ok=True, copy_function=_keep
            )
    seconds = run_sweep(budget, conditions, out, jobs, launcher, overrides, elsewhere) if train else 0.0
    report_dir = out / "report"
    report_dir.mkdir(parents=True, exist_ok=True)
    runs = [*_trained_here(out / "runs", budget.frames if finished_only else 0), *elsewhere.values()]
    build_report(runs, report_dir, protocol, cache_dir=out / "random", progress=progress)
    write_claims(runs, out / "random", protocol, report_dir / "claims.md", budget.frames)
    published = publish(out, Path(publish_to), protocol) if publish_to is not None else None
    return Outcome(out, out / "runs", report_dir, published, seconds)


def _trained_here(runs_dir: Path, frames: int) -> list[Path]:
    """The runs under ``runs_dir`` that have trained ``frames`` or more."""
    from gvgai_pcg.evaluation.checkpoints import find_runs
    from gvgai_pcg.report.build import usable_run

    if not runs_dir.is_dir():
        return []
    if frames <= 0:
        return [runs_dir]
    return [run for run in find_runs([runs_dir]) if (info := usable_run(run)) and info.frames >= frames]


def _keep(source: str, target: str) -> str:
    """Copy ``source`` to ``target`` unless ``target`` exists (what is here already wins)."""
    return target if Path(target).exists() else shutil.copy2(source, target)
