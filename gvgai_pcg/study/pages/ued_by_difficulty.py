"""Where on the difficulty axis each curriculum fails: the UED protocol's levels solved, by d.

The UED protocol plays 1,000 new levels spread evenly over d in [0, 1] (``gvgai_pcg.evaluation.ued``)
and keeps one row per level (``ued-<key>.csv``: its d and, per evaluation seed, its score, win
and length). The page's tables give one number per run; this figure bins the levels by d and
shows, per game, each curriculum's solved rate in every bin: the mean over its runs, and the
range over them. Read from the published CSVs alone.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from pathlib import Path

from gvgai_pcg.rundir.atomic_files import atomic_savefig
from gvgai_pcg.study.verdicts.comparison import ued_record

BINS = 10  # bins of d: [0, 0.1), [0.1, 0.2), ..., [0.9, 1]


def solved_by_bin(rows: Sequence[dict], bins: int = BINS) -> list[float | None]:
    """The solved rate of the levels in each of ``bins`` equal bins of d (None for an empty bin):
    over every level of the bin and every evaluation seed (``won_<i>`` columns), d = 1 in the last."""
    wins, counts = [0] * bins, [0] * bins
    for row in rows:
        index = min(int(float(row["difficulty"]) * bins), bins - 1)
        for key, value in row.items():
            if key.startswith("won_"):
                wins[index] += int(value)
                counts[index] += 1
    return [w / c if c else None for w, c in zip(wins, counts, strict=True)]


def read_level_rows(csv_path: Path) -> list[dict]:
    with open(csv_path, newline="") as handle:
        return list(csv.DictReader(handle))


def write_solved_by_difficulty(
    runs: Sequence[tuple[str, str, Path]], settings: dict, folder: Path
) -> list[Path]:
    """Per game, ``ued-solved-by-d-<game>.png`` from the runs (``(game, label, run dir)``) that
    have a UED record of ``settings``; the written paths (none without records)."""
    curves: dict[str, dict[str, list[list[float | None]]]] = {}
    for game, label, run in runs:
        found = ued_record(run, settings) if settings else None
        if found is None or not found[0].with_suffix(".csv").is_file():
            continue
        rows = read_level_rows(found[0].with_suffix(".csv"))
        curves.setdefault(game, {}).setdefault(label, []).append(solved_by_bin(rows))
    if curves:
        folder.mkdir(parents=True, exist_ok=True)
    return [_figure(game, by_label, folder) for game, by_label in sorted(curves.items())]


def _figure(game: str, by_label: dict[str, list[list[float | None]]], folder: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    centres = [(i + 0.5) / BINS for i in range(BINS)]
    fig, ax = plt.subplots(figsize=(6.5, 3.6))
    for i, (label, runs) in enumerate(sorted(by_label.items())):
        points = [(x, [run[b] for run in runs if run[b] is not None]) for b, x in enumerate(centres)]
        points = [(x, values) for x, values in points if values]
        xs = [x for x, _ in points]
        mean = [sum(v) / len(v) for _, v in points]
        ax.plot(
            xs,
            mean,
            color=f"C{i}",
            marker="o",
            markersize=3,
            label=f"{label} ({len(runs)} run{'s' if len(runs) > 1 else ''})",
        )
        if len(runs) > 1:
            ax.fill_between(
                xs, [min(v) for _, v in points], [max(v) for _, v in points], color=f"C{i}", alpha=0.15
            )
    ax.set_xlim(0, 1)
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlabel("difficulty d of the generated level (bins of 0.1)")
    ax.set_ylabel("solved rate")
    ax.legend(fontsize="small")
    ax.set_title(
        f"{game}: UED levels solved by d (line: mean over runs; band: their range)", fontsize="medium"
    )
    fig.tight_layout()
    path = folder / f"ued-solved-by-d-{game}.png"
    atomic_savefig(fig, path, dpi=80)
    plt.close(fig)
    return path
