"""Training curves of pooled runs (the study's Figure 2): per condition, the smoothed mean episode
score of its runs with a ±1 std band across runs, and the mean difficulty on a second axis, with
where the caller gives it, the highest d a published PPCG reached (the study's text) dashed
beside ours.

Each run's ``log.csv`` (``gvgai_pcg.rundir.run_log``) is smoothed with a trailing mean over its rows,
then all runs of a condition are interpolated onto one frame grid, up to the shortest run's last
row, so the band only covers frames every run has reached.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from gvgai_pcg.report.table import format_frames
from gvgai_pcg.rl.curves import smooth
from gvgai_pcg.rundir.atomic_files import atomic_savefig
from gvgai_pcg.rundir.run_log import LOG_NAME, read_log

GRID_POINTS = 200


@dataclass
class PooledCurve:
    """One condition's curve on a shared frame grid (``[N]`` arrays)."""

    label: str
    runs: int
    frames: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    difficulty: np.ndarray  # mean over runs; all NaN for the regimens without a difficulty


def pool_runs(label: str, run_dirs: Sequence[Path], window: int | None = None) -> PooledCurve | None:
    """Pool the logs of ``run_dirs``; ``None`` when no run has a logged row yet."""
    logs = [read_log(Path(d) / LOG_NAME) for d in run_dirs if (Path(d) / LOG_NAME).is_file()]
    logs = [rows for rows in logs if rows]
    if not logs:
        return None
    end = min(rows[-1]["frames"] for rows in logs)
    start = max(rows[0]["frames"] for rows in logs)
    grid = np.linspace(start, end, GRID_POINTS) if end > start else np.array([end])
    scores, difficulties = [], []
    for rows in logs:
        frames = np.array([r["frames"] for r in rows])
        score = np.array([r["mean_score"] for r in rows])
        n = window or max(1, len(rows) // 20)
        scores.append(np.interp(grid, frames, smooth(score, n)))
        difficulties.append(np.interp(grid, frames, np.array([r["difficulty"] for r in rows])))
    scores_arr, diff_arr = np.stack(scores), np.stack(difficulties)
    return PooledCurve(label, len(logs), grid, scores_arr.mean(0), scores_arr.std(0), diff_arr.mean(0))


def plot_curves(
    game: str,
    curves: Sequence[PooledCurve],
    out_stem: Path,
    reached_by_game: Mapping[str, float | None] | None = None,
) -> list[Path]:
    """One panel per condition; writes ``<out_stem>.png`` and ``.svg`` and returns their paths.
    ``reached_by_game``: per game, the highest d a published PPCG reached (the study's, from
    ``gvgai_pcg.study.verdicts.table1.STUDY_REACHED``), dashed beside ours; given by the caller, so the report
    layer stays below the study's."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter

    fig, axes = plt.subplots(1, max(1, len(curves)), figsize=(4.5 * max(1, len(curves)), 3.6), squeeze=False)
    for ax, curve in zip(axes[0], curves, strict=False):
        marker = "o" if len(curve.frames) < 3 else None  # a run too short for a line still shows
        ax.plot(curve.frames, curve.mean, color="tab:blue", marker=marker, label="score")
        ax.fill_between(
            curve.frames, curve.mean - curve.std, curve.mean + curve.std, color="tab:blue", alpha=0.25
        )
        ax.set_title(f"{game}: {curve.label} ({curve.runs} run{'s' if curve.runs != 1 else ''})")
        ax.set_xlim(left=0)
        ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: format_frames(int(x))))
        ax.set_xlabel("frames")
        ax.set_ylabel("mean episode score", color="tab:blue")
        if not np.isnan(curve.difficulty).all():
            twin = ax.twinx()
            twin.plot(curve.frames, curve.difficulty, color="tab:red", marker=marker)
            twin.set_ylim(0.0, 1.0)
            twin.set_ylabel("difficulty", color="tab:red")
            reached = (reached_by_game or {}).get(game) if curve.label.startswith("PPCG") else None
            if reached is not None:  # the study's Figure 2, as its text states it
                twin.axhline(reached, color="tab:red", linestyle="--", alpha=0.6)
                twin.annotate(
                    f"the study's highest d ({reached:g})",
                    (0.02, reached),
                    xycoords=("axes fraction", "data"),
                    textcoords="offset points",
                    xytext=(0, -10 if reached > 0.9 else 3),
                    color="tab:red",
                    fontsize=8,
                )
    return save_figure(fig, out_stem)


def save_figure(fig, out_stem: Path) -> list[Path]:
    """Write ``fig`` as ``out_stem.png`` and ``.svg`` (the report links the PNG, the SVG scales) and
    close it."""
    import matplotlib.pyplot as plt

    fig.tight_layout()
    out_stem.parent.mkdir(parents=True, exist_ok=True)
    paths = [out_stem.with_suffix(".png"), out_stem.with_suffix(".svg")]
    for path in paths:
        atomic_savefig(fig, path, dpi=120)
    plt.close(fig)
    return paths
