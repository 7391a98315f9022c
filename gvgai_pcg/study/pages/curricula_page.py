"""The curricula comparison's page: ``docs/results-curricula.md``'s block between
``<!-- curricula:start -->`` and ``<!-- curricula:end -->``, written from the published folder
(``results/curricula``) alone: the runs, the tables and the answer (``gvgai_pcg.study.verdicts.comparison``,
recomputed from the published records), the curves of d over training and the levels each
curriculum replays at the end, and what the levels it holds contain beside the generator's and the
human ones.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import find_runs, run_info
from gvgai_pcg.evaluation.protocol import Protocol
from gvgai_pcg.games.registry import get_game_spec
from gvgai_pcg.generators import get_generator
from gvgai_pcg.levels import human_levels
from gvgai_pcg.rundir.atomic_files import atomic_copy
from gvgai_pcg.study.pages.page import _runs_table, replace_block
from gvgai_pcg.study.pages.ued_by_difficulty import write_solved_by_difficulty
from gvgai_pcg.study.sweeps.borrowed_runs import borrowed_lines
from gvgai_pcg.study.sweeps.conditions import Budget
from gvgai_pcg.study.sweeps.curricula_runs import (
    REPLAY_PICTURE,
    REPLAY_STATS,
    level_count_summary,
    write_curves,
)
from gvgai_pcg.study.verdicts.comparison import collect_runs, comparison_markdown

START, END = "<!-- curricula:start -->", "<!-- curricula:end -->"


# The generated levels the curricula's held levels are set beside: this many at d = 1 per game.
REFERENCE_LEVELS = 100


def _summary_cells(summary: dict, names: list[str]) -> str:
    counts = summary.get("counts", {})
    cells = [
        f"{counts[name]['median']:g} ({counts[name]['p90']:g}, {counts[name]['max']})"
        if name in counts
        else "-"
        for name in names
    ]
    return " | ".join(cells)


def _reference_summaries(game: str) -> list[tuple[str, dict]]:
    """The human levels' and the generator's at d = 1 (seeds 0 to ``REFERENCE_LEVELS`` - 1)."""
    generate = get_generator(game)
    return [
        (
            f"generator, d = 1 ({REFERENCE_LEVELS} levels)",
            level_count_summary([generate(1.0, seed) for seed in range(REFERENCE_LEVELS)]),
        ),
        ("human levels", level_count_summary(human_levels(game))),
    ]


def _held_levels_tables(runs: list) -> list[str]:
    """Per game, what the levels each replaying curriculum holds at the end contain (its
    ``replay-levels.json``), beside the generator's at d = 1 and the human levels."""
    import json

    held: dict[str, list[tuple[str, dict]]] = {}
    for info in runs:
        path = info.path / REPLAY_STATS
        if path.is_file():
            summary = json.loads(path.read_text())
            held.setdefault(info.game, []).append(
                (f"{info.label} seed {info.seed}, {summary['levels']:,} held", summary)
            )
    lines = []
    for game, rows in sorted(held.items()):
        rows = [*rows, *_reference_summaries(game)]
        names = sorted({name for _, summary in rows for name in summary.get("counts", {})})
        lines += [
            "",
            f"{get_game_spec(game).title}: each count of the game's level checks (`GameSpec.counts`), "
            "median (90th percentile, most) over the levels.",
            "",
            "| levels | " + " | ".join(names) + " |",
            "|---|" + "---:|" * len(names),
            *[f"| {label} | {_summary_cells(summary, names)} |" for label, summary in rows],
        ]
    return lines


def _replay_section(runs: list, images: Path, prefix: str) -> list[str]:
    """The replay pictures of the published runs, copied into ``images``, one line each, then the
    tables of what the levels each curriculum holds contain."""
    lines = []
    for info in runs:
        picture = info.path / REPLAY_PICTURE
        if picture.is_file():
            name = f"replay-{info.path.name}.png"
            atomic_copy(picture, images / name)
            lines.append(
                f"- {info.game}, {info.label} (seed {info.seed}): ![levels it replays]({prefix}/{name})"
            )
    if not lines:
        return ["No run's curriculum replays levels yet (PCG 1, PPCG and DR play a new level every episode)."]
    return lines + _held_levels_tables(runs)


def curricula_block(published: Path, budget: Budget, images: Path, prefix: str, commit: str) -> str:
    """The page's block from ``published``; figures go to ``images``, linked as ``prefix/<name>``."""
    runs_dir = published / "runs"
    runs = find_runs([runs_dir]) if runs_dir.is_dir() and any(runs_dir.iterdir()) else []
    infos = [run_info(run) for run in runs]
    images.mkdir(parents=True, exist_ok=True)
    stale_figures = ("curricula-curves-*.png", "replay-*.png", "ued-solved-by-d-*.png")
    for stale in [path for pattern in stale_figures for path in images.glob(pattern)]:
        stale.unlink()
    games = collect_runs(runs, Protocol(**budget.protocol), budget.ued)
    borrowed = borrowed_lines(runs)
    labelled = [(info.game, info.label, info.path) for info in infos]
    curves = write_curves(labelled, images)
    by_difficulty = write_solved_by_difficulty(labelled, budget.ued, images)
    machine = f"{platform.machine()} Linux, {os.cpu_count()} cores, torch CPU, one torch thread per run"
    ued = "the UED protocol's records where a run has them" if budget.ued else "no UED protocol"
    return "\n".join(
        [
            START,
            f"Data: `{published}` (budget `{budget.name}`; commit `{commit}` of the code that evaluated it, "
            f"and trained every run whose own record below names no other; {machine}; {ued}).",
            "",
            "### Runs",
            "",
            _runs_table(published, budget.frames_range[0]) if runs else "No runs published yet.",
            "",
            *borrowed,
            *([""] if borrowed else []),
            "### Scores and the answer",
            "",
            comparison_markdown(games) if games else "No run evaluated yet.",
            "### The UED levels solved, by difficulty",
            "",
            f"Each run's {budget.ued.get('levels', 0):,} UED levels binned by d (every evaluation "
            "seed of a level counts): where each curriculum's tail lies."
            if by_difficulty
            else "No run has per-level UED records yet.",
            "",
            *[f"![{path.stem}]({prefix}/{path.name})" for path in by_difficulty],
            "",
            "### Curves over training",
            "",
            *(
                [f"![{path.stem}]({prefix}/{path.name})" for path in curves]
                or ["No curriculum logged d yet."]
            ),
            "",
            "### Levels each curriculum replays at the end",
            "",
            *_replay_section(infos, images, prefix),
            END,
        ]
    )


def write_curricula_page(page: Path, published: Path, budget: Budget, commit: str) -> Path:
    """Rewrite ``page``'s curricula block from ``published`` (figures in ``images/<page stem>``)."""
    images, prefix = page.parent / "images" / page.stem, f"images/{page.stem}"
    return replace_block(page, curricula_block(published, budget, images, prefix, commit), START, END)
