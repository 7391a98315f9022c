"""The curricula comparison's page: ``docs/results-curricula.md``'s block between
``<!-- curricula:start -->`` and ``<!-- curricula:end -->``, written from the published folder
(``results/curricula``) alone: the runs, the tables and the answer (``gvgai_pcg.study.comparison``,
recomputed from the published records), the curves of d over training and the levels each
curriculum replays at the end.
"""

from __future__ import annotations

import os
import platform
import shutil
from pathlib import Path

from gvgai_pcg.study.borrowed_runs import borrowed_lines
from gvgai_pcg.study.conditions import Budget
from gvgai_pcg.study.page import _runs_table, replace_block

START, END = "<!-- curricula:start -->", "<!-- curricula:end -->"


def _replay_section(runs: list, images: Path, prefix: str) -> list[str]:
    """The replay pictures of the published runs, copied into ``images``, one line each."""
    from gvgai_pcg.study.curricula_runs import REPLAY_PICTURE

    lines = []
    for info in runs:
        picture = info.path / REPLAY_PICTURE
        if picture.is_file():
            name = f"replay-{info.path.name}.png"
            shutil.copy2(picture, images / name)
            lines.append(
                f"- {info.game}, {info.label} (seed {info.seed}): ![levels it replays]({prefix}/{name})"
            )
    if not lines:
        return ["No run's curriculum replays levels yet (PCG 1, PPCG and DR play a new level every episode)."]
    return lines


def curricula_block(published: Path, budget: Budget, images: Path, prefix: str, commit: str) -> str:
    """The page's block from ``published``; figures go to ``images``, linked as ``prefix/<name>``."""
    from gvgai_pcg.evaluation.checkpoints import find_runs, run_info
    from gvgai_pcg.evaluation.protocol import Protocol
    from gvgai_pcg.study.comparison import collect_runs, comparison_markdown
    from gvgai_pcg.study.curricula_runs import write_curves
    from gvgai_pcg.study.ued_by_difficulty import write_solved_by_difficulty

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
