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

import contextlib
import shutil
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from omegaconf import OmegaConf

from gvgai_pcg.config import check_jobs, config_dir, sweep_jobs
from gvgai_pcg.config_rules import SEARCHPATH, searchpath_dirs
from gvgai_pcg.evaluation.checkpoints import (
    PUBLISHED,
    find_runs,
    is_run_dir,
    published_run_info,
    read_run_config,
    run_info,
)
from gvgai_pcg.evaluation.evaluator import run_results_path
from gvgai_pcg.evaluation.protocol import Protocol
from gvgai_pcg.games.registry import find_game_spec
from gvgai_pcg.report import build_report
from gvgai_pcg.report.build import usable_run
from gvgai_pcg.rundir.atomic_files import atomic_write_text, copy_tree
from gvgai_pcg.rundir.checkpoint import config_differences
from gvgai_pcg.study.pages.claims_page import claims_markdown
from gvgai_pcg.study.sweeps.borrowed_runs import borrow_runs
from gvgai_pcg.study.sweeps.conditions import Budget, unregistered
from gvgai_pcg.study.sweeps.curricula_runs import (
    evaluate_ued,
    write_curves,
    write_replay_picture,
    write_replay_stats,
)
from gvgai_pcg.study.sweeps.publish import publish, refuse_publishing_into_the_sweep
from gvgai_pcg.study.verdicts.comparison import collect_runs, comparison_markdown
from gvgai_pcg.study.verdicts.judging import study_claims
from gvgai_pcg.study.verdicts.results import collect
from gvgai_pcg.study.verdicts.table1 import STUDY_REACHED

# A trained model (weights, config, frames: no optimizer) is published only below this size: the
# compact CNN's 295k float32 weights are 1.2 MB, the Nature CNN's on pixels far more.


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
    run hours of the small sweep, docs/results.md; 1 for an unknown game): only
    used to share the conditions fairly between parallel jobs."""
    spec = find_game_spec(condition.split("-")[0])
    return 1.0 if spec is None else spec.frame_cost


def share_conditions(conditions: Sequence[str], jobs: int, budget: Budget | None = None) -> list[list[str]]:
    """``conditions`` split into at most ``jobs`` shares of about equal expected cost (greedy,
    most expensive first; with ``budget``, a condition costs its frames and seeds there too); each
    share keeps the conditions' given order."""

    def cost(condition: str) -> float:
        runs = 1.0 if budget is None else budget.frames_of(condition) * len(budget.seeds_of(condition))
        return frame_cost(condition) * runs

    shares: list[list[str]] = [[] for _ in range(max(1, min(jobs, len(conditions))))]
    costs = [0.0] * len(shares)
    for condition in sorted(conditions, key=lambda c: -cost(c)):
        lightest = costs.index(min(costs))
        shares[lightest].append(condition)
        costs[lightest] += cost(condition)
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
    budget's by default), conditions of one frame budget and the same overrides. Seeds vary
    slowest, so a sweep cut short holds every condition at its first seed."""
    frames = {budget.frames_of(c) for c in conditions}
    if len(frames) > 1:
        raise ValueError(f"one multirun trains one frame budget; {', '.join(conditions)} have several")
    own = {budget.overrides_of(c) for c in conditions}
    if len(own) > 1:
        raise ValueError(f"one multirun has one set of overrides; {', '.join(conditions)} have several")
    arguments = [
        "-m",
        "seed=" + ",".join(map(str, budget.seeds if seeds is None else seeds)),
        "condition=" + ",".join(conditions),
        f"total_frames={frames.pop() if frames else budget.frames}",
        f"out_dir={runs_dir}",
        *(own.pop() if own else budget.overrides),
    ]
    if launcher:
        arguments.append(f"hydra/launcher={launcher}")
    return [*arguments, *overrides]


def sweep_plan(
    budget: Budget, conditions: Sequence[str], skip: Iterable[tuple[str, int]] = ()
) -> list[tuple[tuple[int, ...], list[str]]]:
    """The multiruns that train ``conditions`` x their seeds less the ``(condition, seed)`` pairs
    in ``skip``, in order: seeds in turn, one multirun per frame budget of a seed (longest first)
    and per set of condition overrides (in the conditions' order), consecutive seeds with the same
    conditions in one multirun (so nothing skipped, at one frame budget and no condition
    overrides, is one multirun over every seed)."""
    skip = set(skip)
    plan: list[tuple[tuple[int, ...], list[str]]] = []

    def key(condition: str) -> tuple[int, tuple[str, ...]]:
        return -budget.frames_of(condition), budget.overrides_of(condition)

    for seed in budget.all_seeds:
        left = [c for c in conditions if seed in budget.seeds_of(c) and (c, seed) not in skip]
        # longest first, then in the order the conditions first name them (a stable sort)
        keys = sorted(dict.fromkeys(key(c) for c in left), key=lambda k: k[0])
        for group_key in keys:
            group = [c for c in left if key(c) == group_key]
            if len(keys) == 1 and plan and plan[-1][1] == group:
                plan[-1] = ((*plan[-1][0], seed), group)
            else:
                plan.append(((seed,), group))
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
    those that exist); returns the wall seconds. With the basic launcher each of ``jobs`` runs its
    multiruns one after another; a Hydra launcher gets them all at once. The output of each goes
    to ``out/logs/sweep-<i>.log``. An interrupt (SIGINT, or SIGTERM in the main thread) is passed
    on to the training processes, which checkpoint and stop, and no further multirun starts."""
    runs_dir, logs = out / "runs", out / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    skip = set(skip)
    if launcher:
        queues = [[entry] for entry in sweep_plan(budget, conditions, skip)]
    else:
        queues = [sweep_plan(budget, share, skip) for share in share_conditions(conditions, jobs, budget)]
    start = time.perf_counter()
    failed: list[str] = []
    children: list[subprocess.Popen] = []
    stopping = threading.Event()
    guard = threading.Lock()

    def run_queue(i: int, queue: list[tuple[tuple[int, ...], list[str]]]) -> None:
        log_path = logs / f"sweep-{i}.log"
        try:
            for seeds, left in queue:
                arguments = sweep_arguments(budget, left, runs_dir, launcher, overrides, seeds)
                with open(log_path, "a") as log:
                    log.write(f"$ gvgai-pcg train {' '.join(arguments)}\n")
                    log.flush()
                    command = [sys.executable, "-m", "gvgai_pcg.cli", "train", *arguments]
                    with guard:
                        if stopping.is_set():
                            return
                        child = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT)
                        children.append(child)
                    start_of_run = log.tell()
                    if child.wait() != 0:
                        failed.append(f"{log_path}: {last_line(log_path, start_of_run)}")
                        return
        except Exception as error:  # noqa: BLE001 (reported with the failed multiruns)
            failed.append(f"{log_path} ({error})")

    threads = [threading.Thread(target=run_queue, args=item, daemon=True) for item in enumerate(queues)]
    with _terminate_as_interrupt():
        try:
            for thread in threads:
                thread.start()
            for thread in threads:
                thread.join()
        except BaseException:
            with guard:
                stopping.set()
                live = [child for child in children if child.poll() is None]
            for child in live:
                child.send_signal(signal.SIGTERM)  # train checkpoints and stops (SIGINT may be ignored)
            for child in live:
                child.wait()
            raise
    if failed:  # the cause in one line (a train refusal is its last line), the rest in the log
        raise ValueError(f"the sweep failed; {'; '.join(sorted(failed))}")
    return time.perf_counter() - start


def last_line(path: Path, offset: int = 0) -> str:
    """The last non-empty line written to ``path`` after ``offset``: a failed train's own reason."""
    try:
        with open(path, errors="replace") as log:
            log.seek(offset)
            lines = [line.strip() for line in log.read().splitlines() if line.strip()]
    except OSError:
        return "(its log cannot be read)"
    return lines[-1] if lines else "(nothing written)"


def run_overrides(overrides: Sequence[str]) -> list[str]:
    """``overrides`` less Hydra's own (a launcher's settings), which compose no run's config; but
    ``hydra.searchpath``, which finds the user's conditions."""
    return [
        o for o in overrides if not o.lstrip("+~").startswith("hydra") or o.lstrip("+").startswith(SEARCHPATH)
    ]


def check_planned(budget: Budget, conditions: Sequence[str], overrides: Sequence[str] = ()) -> None:
    """``ConfigError`` for the first planned run whose config cannot train (``algo.lr=-1``), before
    the sweep starts: one seed of each condition (the seeds differ in nothing else)."""
    ours = run_overrides(overrides)
    jobs = [
        job
        for condition in conditions
        for seed in budget.seeds_of(condition)[:1]
        for job in sweep_jobs(sweep_arguments(budget, [condition], Path("."), None, ours, (seed,))[1:], True)
    ]
    check_jobs(jobs)


@contextlib.contextmanager
def _terminate_as_interrupt() -> Iterator[None]:
    """SIGTERM raises ``KeyboardInterrupt`` while inside (main thread only; elsewhere nothing)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum: int, frame: object) -> None:
        raise KeyboardInterrupt(f"signal {signum}")

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def planned_configs(budget: Budget, conditions: Sequence[str], overrides: Sequence[str] = ()) -> dict:
    """``(condition, seed) -> {run name: resolved config}`` of the runs the sweep would train
    (several where ``overrides`` sweep over more values); Hydra's own overrides are left out."""
    from hydra import compose, initialize_config_dir

    ours = run_overrides(overrides)
    configs: dict[tuple[str, int], dict[str, dict]] = {}
    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3", job_name="train"):
        for condition in conditions:
            for seed in budget.seeds_of(condition):
                arguments = sweep_arguments(budget, [condition], Path("."), None, ours, (seed,))[1:]
                for job in sweep_jobs(arguments, multirun=True):
                    cfg = OmegaConf.to_container(compose("config", overrides=job), resolve=True)
                    configs.setdefault((condition, seed), {})[str(cfg["run_name"])] = cfg
    return configs


def published_elsewhere(
    budget: Budget, conditions: Sequence[str], overrides: Sequence[str], out: Path, published: Path, protocol
) -> tuple[set[tuple[str, int]], list[Path]]:
    """The ``(condition, seed)`` pairs not to train because ``published`` holds every run of
    theirs finished (the budget's frames, ``protocol``'s records, the very config the sweep would
    train, ``out_dir`` aside) and ``out`` has no finished copy; and those published runs."""

    def finished_there(name: str, config: dict) -> Path | None:
        run = Path(published) / "runs" / name
        if not (run / PUBLISHED).is_file() or not run_results_path(run, protocol).is_file():
            return None
        if published_run_info(run).frames < int(config["total_frames"]):
            return None
        return run.resolve() if _same_training(read_run_config(run) or {}, config) else None

    runs_there = Path(published) / "runs"
    if not runs_there.is_dir() or not any(runs_there.iterdir()):
        return set(), []
    skip, runs = set(), []
    for pair, planned in planned_configs(budget, conditions, overrides).items():
        found = [finished_there(name, config) for name, config in planned.items()]
        frames = budget.frames_of(pair[0])
        if all(found) and not any(_finished(out / "runs" / name, frames) for name in planned):
            skip.add(pair)
            runs += found
    return skip, runs


def _same_training(published: dict, planned: dict) -> bool:
    """Whether a published run's config trains exactly as ``planned`` does: the same values of
    every key but bookkeeping (checkpoints, logs, where it was written), and keys added since
    it was trained at their old behaviour's value (``ADDED_KEYS``)."""
    if published.get("total_frames") != planned.get("total_frames"):
        return False
    return not config_differences(published, planned)


def _finished(run: Path, frames: int) -> bool:
    """Whether ``run`` is a run directory that has trained ``frames`` or more."""
    return is_run_dir(run) and (info := usable_run(run)) is not None and info.frames >= frames


def write_claims(
    runs: Sequence[Path],
    random_cache: Path,
    protocol,
    path: Path,
    target_frames: int | None = None,
    level_sampling: bool = False,
) -> Path:
    """The study's claims tested on the runs under ``runs`` (``gvgai_pcg.study.verdicts.claim_rules``);
    ``level_sampling``: intervals over seeds and the generated sets' levels (off for the
    published budgets, whose pages rebuild as they were)."""
    games = collect(find_runs(list(runs)), random_cache, protocol, target_frames)
    atomic_write_text(
        path, claims_markdown(study_claims(games, target_frames, level_sampling), games, level_sampling)
    )
    return path


def write_curricula(
    here: Sequence[Path],
    elsewhere: Sequence[Path],
    budget: Budget,
    protocol,
    report_dir: Path,
    progress: bool = True,
) -> Path:
    """The curricula comparison on the runs: the UED protocol (where this checkout has it) and the
    replay picture of each run trained here, then ``report_dir/curricula.md`` (tables and the
    answer, ``gvgai_pcg.study.verdicts.comparison``) and the curves of d over training."""
    here = find_runs(list(here)) if here else []
    for run in here:
        evaluate_ued(run, budget.ued, progress)
        write_replay_picture(run)
        write_replay_stats(run)
    runs = [*here, *(find_runs(list(elsewhere)) if elsewhere else [])]
    games = collect_runs(runs, protocol, budget.ued)
    path = report_dir / "curricula.md"
    atomic_write_text(path, comparison_markdown(games))
    for stale in report_dir.glob("curricula-curves-*.png"):
        stale.unlink()
    infos = [run_info(run) for run in runs]
    write_curves([(info.game, info.label, info.path) for info in infos], report_dir)
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
    borrow_from: Path | None = None,
) -> Outcome:
    """The whole study at ``budget``: sweep, evaluate, report into ``out``, publish to
    ``publish_to``. Runs that ``publish_to`` holds as finished and ``out`` lacks are reported from
    there, not trained again. ``finished_only`` leaves out runs short of the budget's frames (a
    report taken while the sweep still trains evaluates no model that will change). Runs that the
    sweep in ``borrow_from`` trained exactly as this one would are taken, not trained
    (``gvgai_pcg.study.sweeps.borrowed_runs``)."""
    refused = unregistered(conditions, searchpath_dirs(overrides))
    if refused:
        raise ValueError("; ".join(refused.values()))
    out = Path(out).resolve()
    if publish_to is not None:  # before any training: refused now, not after hours of it
        refuse_publishing_into_the_sweep(out, Path(publish_to))
    if train:
        check_planned(budget, conditions, overrides)
    protocol = Protocol(**budget.protocol)
    skip: set[tuple[str, int]] = set()
    elsewhere: list[Path] = []
    if borrow_from is not None:  # before the published ones: a borrowed run here is finished here
        skip |= borrow_runs(planned_configs(budget, conditions, overrides), budget, Path(borrow_from), out)
    if publish_to is not None:
        published_skip, elsewhere = published_elsewhere(
            budget, conditions, overrides, out, Path(publish_to), protocol
        )
        skip |= published_skip
        random = Path(publish_to) / "random"
        if random.is_dir():  # the random agent's records travel too
            copy_tree(random, out / "random", dirs_exist_ok=True, copy_function=_keep)
    seconds = run_sweep(budget, conditions, out, jobs, launcher, overrides, skip) if train else 0.0
    report_dir = out / "report"
    report_dir.mkdir(parents=True, exist_ok=True)
    fewest = budget.frames_range[0] if finished_only else None
    here = _trained_here(out / "runs", fewest, {p.name for p in elsewhere})
    if not here and not elsewhere:
        finished = f" that finished (trained at least {fewest:,} frames)" if fewest is not None else ""
        raise FileNotFoundError(f"no run directories{finished} under {out / 'runs'}")
    build_report(
        [*here, *elsewhere],
        report_dir,
        protocol,
        cache_dir=out / "random",
        progress=progress,
        reached_by_game=STUDY_REACHED,
    )
    target = budget.frames_range[0]
    if budget.comparison == "curricula":
        write_curricula(here, elsewhere, budget, protocol, report_dir, progress)
    else:
        write_claims(
            [*here, *elsewhere],
            out / "random",
            protocol,
            report_dir / "claims.md",
            target,
            budget.level_sampling,
        )
    published = publish(out, Path(publish_to), protocol, here) if publish_to is not None else None
    return Outcome(out, out / "runs", report_dir, published, seconds)


def _trained_here(runs_dir: Path, finished_only: int | None, leave_out: set[str]) -> list[Path]:
    """The runs under ``runs_dir`` (with ``finished_only``, the budget's fewest frames, those that
    have trained their config's ``total_frames`` and at least that many), but those named in
    ``leave_out`` (their published copies are reported instead)."""

    def wanted(run: Path) -> bool:
        frames = 0
        if finished_only is not None:
            frames = max(int((read_run_config(run) or {}).get("total_frames", 0)), finished_only)
        return run.name not in leave_out and _finished(run, frames)

    if not runs_dir.is_dir():
        return []
    return [run for run in find_runs([runs_dir]) if wanted(run)]


def _keep(source: str, target: str) -> str:
    """Copy ``source`` to ``target`` unless ``target`` exists (what is here already wins)."""
    return target if Path(target).exists() else shutil.copy2(source, target)
