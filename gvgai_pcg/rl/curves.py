"""The training curve of a run: mean episode score and difficulty over frames, from ``log.csv``
(a run without a row there yet: the policy's entropy from ``updates.csv``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gvgai_pcg.rundir.run_log import read_log
from gvgai_pcg.rundir.update_log import UPDATES_NAME, read_updates


def smooth(values: np.ndarray, window: int) -> np.ndarray:
    """Trailing mean over ``window`` rows (shorter at the start)."""
    cumsum = np.cumsum(np.insert(values, 0, 0.0))
    counts = np.minimum(np.arange(1, len(values) + 1), window)
    return (cumsum[1:] - cumsum[np.arange(1, len(values) + 1) - counts]) / counts


def plot_curve(log_path: Path, out_path: Path, title: str = "") -> Path:
    """Write a PNG: mean score (raw and smoothed, left axis) and difficulty (right axis, 0-1)."""
    import matplotlib.pyplot as plt

    fig = curve_figure(log_path, title)
    fig.savefig(out_path)
    plt.close(fig)
    return out_path


def curve_figure(log_path: Path, title: str = ""):
    """The curve's figure. Points carry markers, so a short run's one or two rows still show."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = read_log(log_path)
    frames = np.array([row["frames"] for row in rows])
    score = np.array([row["mean_score"] for row in rows])
    difficulty = np.array([row["difficulty"] for row in rows])
    fig, ax = plt.subplots(figsize=(7, 4), dpi=120)
    marker = "o" if len(rows) < 20 else None
    if len(rows):
        ax.plot(frames, score, color="tab:blue", alpha=0.25, linewidth=0.8)
        smoothed = smooth(score, max(1, len(rows) // 20))
        ax.plot(frames, smoothed, color="tab:blue", marker=marker, label="mean score")
    ax.set_xlabel("frames")
    ax.set_ylabel("mean episode score", color="tab:blue")
    updates_path = log_path.parent / UPDATES_NAME
    if not rows:  # a short run: no episode row yet, the updates' entropy where there is one
        updates = read_updates(updates_path) if updates_path.is_file() else []
        note = "no episode row in log.csv yet"
        if updates:
            x = [row["frames"] for row in updates]
            ax.plot(x, [row["entropy"] for row in updates], color="tab:green", marker="o")
            ax.set_ylabel("policy entropy", color="tab:green")
            note += f": the policy's entropy from {UPDATES_NAME} ({len(updates)} row(s))"
        ax.text(0.5, 0.5, note, transform=ax.transAxes, ha="center", va="center", wrap=True)
    if len(rows) and not np.isnan(difficulty).all():
        ax2 = ax.twinx()
        ax2.plot(frames, difficulty, color="tab:red", marker=marker, label="difficulty")
        ax2.set_ylim(0.0, 1.0)
        ax2.set_ylabel("difficulty", color="tab:red")
    ax.set_title(title or log_path.parent.name)
    fig.tight_layout()
    return fig
