"""From run directories to the report: evaluate what is not evaluated yet, then write the tables
(Markdown, CSV, HTML), the pooled training curves of every game found, and, for a sweep over
``regimen.num_levels``, the score against the number of training levels."""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import RunInfo, find_runs, run_info
from gvgai_pcg.evaluation.evaluator import (
    evaluate_random,
    evaluate_run,
    random_results_path,
    read_records,
    records_are_current,
    run_results_path,
    writer_lock,
)
from gvgai_pcg.evaluation.protocol import Protocol, protocol_test_sets
from gvgai_pcg.report.curves import plot_curves, pool_runs
from gvgai_pcg.report.generalisation import LEVEL_COUNT_FIGURE, level_count_curves, plot_level_counts
from gvgai_pcg.report.render import html_report, markdown_report, write_csv
from gvgai_pcg.report.table import GameTable, RunResults, build_table
from gvgai_pcg.rundir.atomic_files import atomic_write_text
from gvgai_pcg.rundir.checkpoint import NonFiniteModelError

log = logging.getLogger(__name__)


@dataclass
class Report:
    tables: list[GameTable]
    markdown: Path
    csv: Path
    html: Path
    figures: dict[str, list[Path]] = field(default_factory=dict)


def run_results(
    info: RunInfo, protocol: Protocol, evaluate: bool, device: str, progress: bool, force: bool = False
) -> RunResults | None:
    """A run's protocol records (evaluating it when allowed), or ``None`` if it has none."""
    path = run_results_path(info.path, protocol)
    if evaluate:
        records = evaluate_run(info, protocol, device, progress, force)
    elif not path.is_file():
        log.warning(
            "%s has no results for protocol %s; left out (run without --no-evaluate)", info.path, protocol.key
        )
        return None
    else:
        records = read_records(path)
        if not records_are_current(records, info):
            log.warning(
                "%s: its results for protocol %s are of another model than its %s (%d frames); "
                "left out (run without --no-evaluate)",
                info.path,
                protocol.key,
                info.checkpoint.name,
                info.frames,
            )
            return None
    return RunResults(info.label, info.frames, info.training_sets, records, str(info.path), info.config)


def random_records(
    game: str,
    protocol: Protocol,
    cache_dir: Path | None,
    evaluate: bool,
    device: str,
    progress: bool,
    force: bool,
):
    """The random agent's records of ``game``; a cache that lacks some of the protocol's levels is
    evaluated again (with ``--no-evaluate``: said, and its Random row keeps the gaps)."""
    path = random_results_path(game, protocol, cache_dir)
    if evaluate:
        records = evaluate_random(game, protocol, cache_dir, device, progress, force)
    elif not path.is_file():
        return None
    else:
        records = read_records(path)
    missing = missing_sets(records, protocol_test_sets(game, protocol))
    if missing and evaluate:
        log.warning(
            "%s lacks the random agent's records of %s; evaluating it again", path, ", ".join(missing)
        )
        records = evaluate_random(game, protocol, cache_dir, device, progress, force=True)
    elif missing:
        log.warning(
            "%s lacks the random agent's records of %s: the Random row is blank there (run without "
            "--no-evaluate to complete it)",
            path,
            ", ".join(missing),
        )
    return records


def missing_sets(records: Sequence, sets: Sequence) -> list[str]:
    """The test sets of ``sets`` of which ``records`` lack a level, with how many they hold."""
    held: dict[str, int] = {}
    for record in records:
        held[record.test_set] = held.get(record.test_set, 0) + 1
    return [
        f"{s.name} ({held.get(s.name, 0)} of {len(s.levels)} levels)"
        for s in sets
        if held.get(s.name, 0) < len(s.levels)
    ]


def build_report(
    paths: Sequence[Path],
    out_dir: Path,
    protocol: Protocol,
    cache_dir: Path | None = None,
    evaluate: bool = True,
    device: str = "cpu",
    progress: bool = True,
    force: bool = False,
    reached_by_game: Mapping[str, float | None] | None = None,
) -> Report:
    """Find the runs under ``paths``, evaluate them (and the random agent) as needed, write the report.

    ``force`` evaluates again even where current results exist; ``reached_by_game`` is drawn on
    the PPCG curves (``plot_curves``)."""
    runs = [info for path in find_runs([Path(p) for p in paths]) if (info := usable_run(path))]
    if not runs:
        raise FileNotFoundError(
            f"no run directories (config.yaml and a usable model) under {', '.join(map(str, paths))}"
        )
    with writer_lock(out_dir, f"the report {out_dir}"):
        return _build_report(
            runs, out_dir, protocol, cache_dir, evaluate, device, progress, force, reached_by_game
        )


def usable_run(path: Path) -> RunInfo | None:
    """The run at ``path``, or ``None`` (with a warning) when its model diverged."""
    try:
        return run_info(path)
    except NonFiniteModelError as error:
        log.warning("%s left out of the report: %s", path, error)
        return None


def _build_report(
    runs: list[RunInfo],
    out_dir: Path,
    protocol: Protocol,
    cache_dir: Path | None,
    evaluate: bool,
    device: str,
    progress: bool,
    force: bool,
    reached_by_game: Mapping[str, float | None] | None = None,
) -> Report:
    games = sorted({info.game for info in runs})  # one order, however the runs were found
    tables, figures = [], {}
    for game in games:
        game_runs = [info for info in runs if info.game == game]
        evaluated = [
            (info, r)
            for info in game_runs
            if (r := run_results(info, protocol, evaluate, device, progress, force))
        ]
        results = [r for _, r in evaluated]
        baseline = random_records(game, protocol, cache_dir, evaluate, device, progress, force)
        tables.append(build_table(game, protocol_test_sets(game, protocol), baseline, results))
        # One figure panel per row of the table: a regimen, a frame count and a training config.
        conditions = {row.name: [Path(p) for p in row.runs] for row in tables[-1].rows if row.runs}
        curves = [c for label, dirs in conditions.items() if (c := pool_runs(label, dirs)) is not None]
        if curves:
            figures[game] = plot_curves(game, curves, out_dir / f"curves-{game}", reached_by_game)
        level_counts = level_count_curves(evaluated)
        if level_counts:
            stem = out_dir / f"{LEVEL_COUNT_FIGURE}-{game}"
            figures.setdefault(game, []).extend(plot_level_counts(level_counts, stem))
    markdown = out_dir / "results.md"
    atomic_write_text(markdown, markdown_report(tables, figures) + "\n")
    html = out_dir / "results.html"
    atomic_write_text(html, html_report(tables, figures) + "\n")
    return Report(tables, markdown, write_csv(tables, out_dir / "results.csv"), html, figures)
