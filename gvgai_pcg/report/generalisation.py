"""Generalisation against the number of training levels (Procgen's view of PCG X).

Runs of ``regimen=pcg`` that differ only in ``regimen.num_levels`` (a sweep) are a curve: at each
set size N, the mean score on the run's own training levels (``train``) and on the held-out
generated test sets (``pcg0.5``, ``pcg1``), over the runs (seeds) of that N. The gap between the
train and test lines is the generalisation gap; unlimited levels (``num_levels=0``) are drawn as
flat lines, the score the finite sets approach.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import RunInfo
from gvgai_pcg.evaluation.protocol import TRAINING_SET
from gvgai_pcg.levels.test_sets import TEST_DIFFICULTIES, set_name
from gvgai_pcg.report.curves import save_figure
from gvgai_pcg.report.table import RunResults, differing_keys, format_frames, mean_scores, training_config

CURVE_SETS = (TRAINING_SET, *(set_name(d) for d in TEST_DIFFICULTIES))
LEVEL_COUNT_FIGURE = "generalisation"  # the report's generalisation-<game>.png/.svg


@dataclass(frozen=True)
class LevelCountPoint:
    """The score of the runs with one training-set size on one test set."""

    num_levels: int  # 0: a new level every episode
    test_set: str
    mean: float  # over runs of each run's mean score
    std: float  # across runs (population, as the table's cells)
    runs: int


@dataclass
class LevelCountCurve:
    """One sweep over ``num_levels``: PCG runs of one difficulty and frame count."""

    game: str
    difficulty: float
    frames: int
    points: list[LevelCountPoint]
    variant: str = ""  # the training keys that set this sweep apart from another of the same d and frames

    @property
    def label(self) -> str:
        variant = f"; {self.variant}" if self.variant else ""
        return f"PCG {self.difficulty:g} ({format_frames(self.frames)}{variant})"

    def sizes(self) -> list[int]:
        return sorted({p.num_levels for p in self.points if p.num_levels > 0})

    def series(self, test_set: str) -> list[LevelCountPoint]:
        """The finite sizes' points on ``test_set``, by size."""
        return sorted(
            (p for p in self.points if p.test_set == test_set and p.num_levels > 0),
            key=lambda p: p.num_levels,
        )

    def unlimited(self, test_set: str) -> LevelCountPoint | None:
        return next((p for p in self.points if p.test_set == test_set and p.num_levels == 0), None)


def level_count_curves(runs: Sequence[tuple[RunInfo, RunResults]]) -> list[LevelCountCurve]:
    """The curves in ``runs`` (a run's info with its results): one per (game, difficulty,
    frames, training config but the set size) of PCG runs with at least two different finite set
    sizes; sweeps that differ in another training key are separate curves named by those keys."""
    pcg = [(info, results) for info, results in runs if info.regimen["name"] == "pcg"]
    sweep_configs = [_without_count(info.config) for info, _ in pcg]
    groups: dict[tuple[str, float, int, str], dict[int, list[RunResults]]] = {}
    for (info, results), config in zip(pcg, sweep_configs, strict=True):
        keys = differing_keys(
            [c for (i, _), c in zip(pcg, sweep_configs, strict=True) if i.game == info.game]
        )
        flat = training_config(config)
        variant = ", ".join(f"{k}={flat.get(k, '<missing>')}" for k in keys)
        key = (info.game, float(info.regimen["difficulty"]), info.frames, variant)
        count = int(info.regimen.get("num_levels", 0) or 0)
        groups.setdefault(key, {}).setdefault(count, []).append(results)
    curves = []
    for (game, difficulty, frames, variant), by_count in groups.items():
        if len([count for count in by_count if count > 0]) < 2:
            continue
        points = []
        for count, group in sorted(by_count.items()):
            per_run = [mean_scores(r.records) for r in group]
            for test_set in CURVE_SETS:
                values = [means[test_set] for means in per_run if test_set in means]
                if values:
                    mean = sum(values) / len(values)
                    std = math.sqrt(sum((v - mean) ** 2 for v in values) / len(values))
                    points.append(LevelCountPoint(count, test_set, mean, std, len(values)))
        curves.append(LevelCountCurve(game, difficulty, frames, points, variant))
    return curves


def _without_count(config: dict) -> dict:
    """``config`` less what a level-count sweep varies: the set size (and the difficulty and
    frames, which key the curve anyway)."""
    regimen = {k: v for k, v in config.get("regimen", {}).items() if k not in ("num_levels", "difficulty")}
    return {**config, "regimen": regimen}


def plot_level_counts(curves: Sequence[LevelCountCurve], out_stem: Path) -> list[Path]:
    """One panel per curve: score against the number of training levels (log axis), train and
    test lines with ±1 std bands, unlimited levels as dashed lines. Writes ``.png`` and ``.svg``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = {TRAINING_SET: "tab:blue", "pcg0.5": "tab:orange", "pcg1": "tab:red"}
    fig, axes = plt.subplots(1, len(curves), figsize=(5 * len(curves), 3.8), squeeze=False)
    for ax, curve in zip(axes[0], curves, strict=True):
        for test_set in CURVE_SETS:
            series = curve.series(test_set)
            colour = colours.get(test_set)
            name = "train (own levels)" if test_set == TRAINING_SET else f"test {test_set}"
            if series:
                x = [p.num_levels for p in series]
                mean = [p.mean for p in series]
                ax.plot(x, mean, marker="o", color=colour, label=name)
                ax.fill_between(
                    x,
                    [p.mean - p.std for p in series],
                    [p.mean + p.std for p in series],
                    color=colour,
                    alpha=0.2,
                )
            flat = curve.unlimited(test_set)
            if flat is not None and test_set != TRAINING_SET:
                ax.axhline(flat.mean, color=colour, linestyle="--", label=f"{name}, unlimited levels")
        values = [p.mean for p in curve.points]
        if max(values) - min(values) < 1e-9:  # one flat score: a readable axis around it
            ax.set_ylim(values[0] - 1, values[0] + 1)
        ax.set_xscale("log")
        ax.set_xticks(curve.sizes(), [str(n) for n in curve.sizes()])
        ax.minorticks_off()
        ax.set_xlabel("training levels (regimen.num_levels)")
        ax.set_ylabel("mean episode score")
        ax.set_title(f"{curve.game}: {curve.label}")
        ax.legend(fontsize="small")
    return save_figure(fig, out_stem)
