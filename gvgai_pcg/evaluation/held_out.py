"""Held-out test scores over training: a run's snapshots
(``snapshots/model-<frames>.pt``, kept every ``checkpoint.keep_every_frames``) each evaluated with
a protocol, by default the 100-level sets (``LARGE_PROTOCOL``), so that the generalisation gap is
seen as it opens rather than only at the end.

Each snapshot's records go to ``<run>/eval/snapshots/protocol-<key>/model-<frames>.jsonl`` (never
the run's own results file) and are reused while current. ``plot_held_out`` draws the training
curve (``log.csv``'s mean episode score, as ``curve.png`` does) with each test set's held-out mean
score per snapshot on the same axis: training and test scores are both episode scores.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.evaluator import EVAL_DIR, LevelRecord, evaluate_run
from gvgai_pcg.evaluation.protocol import HUMAN_SETS, Protocol
from gvgai_pcg.rl.curves import smooth
from gvgai_pcg.rundir.run_log import read_log
from gvgai_pcg.rundir.snapshots import snapshot_frames, snapshot_paths

SNAPSHOT_EVAL_DIR = "snapshots"
HUMAN_MEAN = "human"  # the mean over the five human levels, one line of the plot
# The plot's held-out lines (the training curve is tab:blue, as in curve.png): colour and label.
HELD_OUT_LINES = {
    "pcg0.5": ("tab:orange", "held out: pcg0.5"),
    "pcg1": ("tab:red", "held out: pcg1"),
    HUMAN_MEAN: ("tab:green", "held out: human levels (mean)"),
    "train": ("tab:purple", "its own training levels"),
}


def snapshot_results_path(run_dir: Path, protocol: Protocol, frames: int) -> Path:
    return (
        Path(run_dir)
        / EVAL_DIR
        / SNAPSHOT_EVAL_DIR
        / f"protocol-{protocol.key}"
        / f"model-{frames:010d}.jsonl"
    )


def pick_snapshots(paths: Sequence[Path], every: int = 0) -> list[Path]:
    """The snapshots to evaluate, oldest first: all of them, or with ``every`` the first at or past
    each multiple of ``every`` frames (``every=2_000_000`` on 1M snapshots: every other one)."""
    paths = sorted(paths, key=snapshot_frames)
    if every <= 0:
        return paths
    picked, next_frames = [], every
    for path in paths:
        if snapshot_frames(path) >= next_frames:
            picked.append(path)
            next_frames = (snapshot_frames(path) // every + 1) * every
    return picked


def evaluate_snapshots(
    run_dir: Path,
    protocol: Protocol,
    every: int = 0,
    device: str = "cpu",
    progress: bool = True,
    force: bool = False,
) -> dict[int, list[LevelRecord]]:
    """Each picked snapshot's records under ``protocol``, by its frames."""
    run_dir = Path(run_dir).resolve()
    if every < 0:
        raise ValueError(f"every={every}: expected 0 (every snapshot) or a positive number of frames")
    kept = snapshot_paths(run_dir)
    if not kept:
        raise FileNotFoundError(
            f"{run_dir}: no snapshots (snapshots/model-*.pt) to evaluate; a run keeps them when trained "
            "with checkpoint.keep_every_frames=N"
        )
    paths = pick_snapshots(kept, every)
    if not paths:
        latest = max(map(snapshot_frames, kept))
        raise ValueError(
            f"{run_dir}: one snapshot per {every:,} frames picks none of its {len(kept)} snapshots (the "
            f"latest at {latest:,} frames); give a smaller --every"
        )
    results = {}
    for path in paths:
        info = run_info(run_dir, path)
        out = snapshot_results_path(run_dir, protocol, info.frames)
        results[info.frames] = evaluate_run(info, protocol, device, progress, force, out)
    return results


def held_out_scores(results: dict[int, list[LevelRecord]]) -> dict[str, list[tuple[int, float]]]:
    """Per test set, ``(frames, mean score over its episodes)`` for each snapshot, oldest first;
    with every human level present, also their mean as ``human``."""
    curves: dict[str, list[tuple[int, float]]] = {}
    for frames in sorted(results):
        means: dict[str, list[float]] = {}
        for record in results[frames]:
            means.setdefault(record.test_set, []).extend(record.scores)
        for test_set, scores in means.items():
            curves.setdefault(test_set, []).append((frames, sum(scores) / len(scores)))
        if all(name in means for name in HUMAN_SETS):
            human = [sum(means[name]) / len(means[name]) for name in HUMAN_SETS]
            curves.setdefault(HUMAN_MEAN, []).append((frames, sum(human) / len(human)))
    return curves


def format_held_out_table(title: str, curves: dict[str, list[tuple[int, float]]]) -> str:
    """One row per snapshot, one column per test set: the held-out mean scores."""
    names = list(curves)
    frames = sorted({f for points in curves.values() for f, _ in points})
    header = f"{'frames':>12}" + "".join(f"{name:>9}" for name in names)
    lines = [title, header, "-" * len(header)]
    for f in frames:
        cells = "".join(f"{dict(curves[name]).get(f, float('nan')):>9.2f}" for name in names)
        lines.append(f"{f:>12,}" + cells)
    return "\n".join(lines)


def plot_held_out(
    log_path: Path, curves: dict[str, list[tuple[int, float]]], out_path: Path, title: str = ""
) -> Path:
    """A PNG: the training curve (mean episode score over frames, smoothed) and each test set's
    held-out mean score at each snapshot (markers), on one score axis."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    rows = read_log(log_path) if Path(log_path).is_file() else []
    fig, ax = plt.subplots(figsize=(7, 4), dpi=120)
    if rows:
        frames = np.array([row["frames"] for row in rows])
        score = np.array([row["mean_score"] for row in rows])
        ax.plot(
            frames, smooth(score, max(1, len(rows) // 20)), color="tab:blue", label="training (mean score)"
        )
    for name, (color, label) in HELD_OUT_LINES.items():
        if name in curves:
            xs, ys = zip(*curves[name], strict=True)
            ax.plot(xs, ys, marker="o", linewidth=1.2, color=color, label=label)
    ax.set_xlabel("frames")
    ax.set_ylabel("mean episode score")
    ax.set_title(title or Path(log_path).parent.name)
    ax.legend(fontsize=8)
    fig.tight_layout()
    Path(out_path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out_path)
    plt.close(fig)
    return Path(out_path)


def held_out_plot_path(run_dir: Path, protocol: Protocol) -> Path:
    return Path(run_dir) / EVAL_DIR / SNAPSHOT_EVAL_DIR / f"held_out-{protocol.key}.png"
