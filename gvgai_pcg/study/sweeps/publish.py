"""Publishing a sweep (``reproduce --publish``): what rebuilds its report, copied into a folder
that is committed beside the code (``results/<budget>``).

Each run, and the report, is built in a staging folder beside its place and swapped in
(``gvgai_pcg.rundir.atomic_files``), so a publish cut short by a signal, a full disk or a kill leaves
the published folder as it was, and the next publish repairs what a SIGKILL left.
"""

from __future__ import annotations

import contextlib
import json
import shutil
from collections.abc import Iterator, Sequence
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import (
    FINAL_MODEL,
    PUBLISHED,
    find_runs,
    load_state,
    published_run_info,
    run_info,
)
from gvgai_pcg.evaluation.evaluator import read_records, run_results_path
from gvgai_pcg.rundir.atomic_files import (
    atomic_copy,
    copy_tree,
    recover_folders,
    staging_folder,
    swap_in_folder,
)
from gvgai_pcg.rundir.checkpoint import config_differences
from gvgai_pcg.study.sweeps.borrowed_runs import BORROWED
from gvgai_pcg.study.sweeps.curricula_runs import REPLAY_PICTURE, REPLAY_STATS
from gvgai_pcg.study.sweeps.portable import make_portable, write_portable_model

WRITER_LOCKS = shutil.ignore_patterns(".lock", ".*.lock")  # the evaluator's, never published


def refuse_other_configs(runs: Sequence[Path], published: Path) -> None:
    """``ValueError`` before anything is published when ``published`` holds a run of one of
    ``runs``' names but another training config: kept (it may have trained longer) beside a new
    report, it would leave a folder whose runs no longer rebuild its table."""
    for run in runs:
        target = published / run.name
        if not (target / PUBLISHED).is_file():
            continue
        differences = [
            difference.replace(" in the checkpoint, ", " published, ", 1).removesuffix(" now") + " here"
            for difference in config_differences(published_run_info(target).config, run_info(run).config)
        ]
        if differences:
            raise ValueError(
                f"{target} is a published run of another config ({'; '.join(differences)}); publish "
                "into another folder, or move that run away first"
            )


def refuse_publishing_into_the_sweep(out: Path, dest: Path, runs: Sequence[Path] = ()) -> None:
    """``ValueError`` when ``dest``'s runs would be the sweep's own (``out/runs``, or ``runs``):
    the same folder, or one inside the other. A ``published.json`` written into a training run
    names its model then; once the run trains on, it is still read as the published, older one."""

    def overlap(a: Path, b: Path) -> bool:
        a, b = Path(a).resolve(), Path(b).resolve()
        return a == b or a in b.parents or b in a.parents

    published = Path(dest) / "runs"
    for trained in (Path(out) / "runs", *runs):
        if overlap(trained, published):
            raise ValueError(
                f"--publish {dest}: its runs would be the sweep's own ({trained}), which would then "
                "read as published at the frames of this publish after they train on; publish into "
                "another folder (results/<budget>)"
            )


def publish(out: Path, dest: Path, protocol=None, runs: Sequence[Path] | None = None) -> Path:
    """Copy what rebuilds the report into ``dest``: each run's config, log, evaluation results and
    its model (whatever its size, as weights and plain data only) with a ``published.json`` naming
    it, all naming nothing outside the run folder (``gvgai_pcg.study.sweeps.portable``), the random
    agent's results, and the report.
    ``gvgai-pcg report --no-evaluate DEST/runs --cache-dir DEST/random`` then rebuilds the tables
    and curves from ``dest`` alone. With ``protocol``, only runs with its
    records are published, and the model named is the one they were made from, so a run that
    trained on after its evaluation is published as evaluated. ``runs`` (default: all under
    ``out/runs``) are the runs to publish: those of the report; a published run is never replaced
    by a copy that has trained fewer frames. ``dest`` may not hold the sweep's own runs
    (``refuse_publishing_into_the_sweep``)."""
    refuse_publishing_into_the_sweep(out, dest, runs or ())
    if runs is None:
        runs = [out / "runs"] if (out / "runs").is_dir() else []
    found = find_runs(list(runs)) if runs else []
    refuse_other_configs(found, dest / "runs")
    dest.mkdir(parents=True, exist_ok=True)
    recover_folders(dest / "runs")
    recover_folders(dest)
    for run in found:
        records_path = run_results_path(run, protocol) if protocol is not None else None
        if records_path is not None and not records_path.is_file():
            continue  # not evaluated yet: nothing of it is in the report
        info = run_info(run)
        target = dest / "runs" / run.name
        if (target / PUBLISHED).is_file() and published_run_info(target).frames > info.frames:
            continue  # the published run has trained longer
        model = {"checkpoint": str(info.checkpoint), "frames": info.frames}
        if records_path is not None:
            first = read_records(records_path)[0]
            model = {"checkpoint": first.checkpoint, "frames": first.frames}
        with staged_folder(target) as staged:
            _stage_run(run, staged, model, evaluated_model(info, model))
    if (out / "report").is_dir():  # replaced whole: no figure of an earlier report stays
        with staged_folder(dest / "report", keep=False) as staged:
            copy_tree(out / "report", staged, ignore=WRITER_LOCKS, dirs_exist_ok=True)
    if (out / "random").is_dir():
        copy_tree(
            out / "random",
            dest / "random",
            dirs_exist_ok=True,
            ignore=WRITER_LOCKS,
            copy_function=atomic_copy,
        )
    return dest


@contextlib.contextmanager
def staged_folder(target: Path, keep: bool = True) -> Iterator[Path]:
    """A folder to build ``target``'s new content in (``keep``: starting from a copy of what
    ``target`` holds now), swapped in when the block ends; a block cut short leaves ``target`` as
    it was and removes the staging folder."""
    staged = staging_folder(target)
    shutil.rmtree(staged, ignore_errors=True)
    if keep and target.is_dir():
        copy_tree(target, staged)
    staged.mkdir(parents=True, exist_ok=True)
    try:
        yield staged
    except BaseException:
        shutil.rmtree(staged, ignore_errors=True)
        raise
    swap_in_folder(staged, target)


def evaluated_model(info, model: dict) -> Path | None:
    """The file of the model the run's records were made from (``model``: their checkpoint and
    frames): its final model, or an earlier file of it that is still there; ``None`` when that
    model is on this machine no more."""
    if model["frames"] == info.frames:
        try:
            return info.model_file
        except FileNotFoundError:  # a published run without its model, published again
            return None
    earlier = Path(model["checkpoint"])  # a published run's records name a file of its folder
    earlier = earlier if earlier.is_absolute() else Path(info.path) / earlier
    if earlier.is_file() and int(load_state(earlier).get("frames", -1)) == model["frames"]:
        return earlier
    return None


def _stage_run(run: Path, staged: Path, model: dict, model_file: Path | None) -> None:
    """Into ``staged``: ``run``'s config, logs, pictures and evaluation records, the model they
    were made from (``model_file``, whatever its size) and ``published.json`` naming it, all made
    to name nothing outside the run folder."""
    (staged / "eval").mkdir(parents=True, exist_ok=True)
    for name in (
        "config.yaml",
        "log.csv",
        "sessions.csv",
        "curve.png",
        REPLAY_PICTURE,
        REPLAY_STATS,
        BORROWED,
    ):
        if (run / name).is_file():
            shutil.copy2(run / name, staged / name)
    # the study protocol's records, and the UED protocol's per-level CSV and summary
    for pattern in ("*.jsonl", "ued-*.csv", "ued-*.json"):
        for results in sorted((run / "eval").glob(pattern)):
            shutil.copy2(results, staged / "eval" / results.name)
    # the held-out score over training (``evaluate --snapshots``): records and figure, not the models
    if (run / "eval" / "snapshots").is_dir():
        copy_tree(
            run / "eval" / "snapshots", staged / "eval" / "snapshots", dirs_exist_ok=True, ignore=WRITER_LOCKS
        )
    earlier = staged / FINAL_MODEL  # an earlier publish's: kept only where it is the model evaluated
    if model_file is not None:
        write_portable_model(model_file, staged / FINAL_MODEL)
        model["copied"] = FINAL_MODEL
    elif earlier.is_file() and int(load_state(earlier).get("frames", -1)) == model["frames"]:
        model["copied"] = FINAL_MODEL
    else:
        earlier.unlink(missing_ok=True)
    # the training machine's record of the model, made portable with the rest
    (staged / PUBLISHED).write_text(json.dumps(model, indent=1) + "\n")
    make_portable(staged)
