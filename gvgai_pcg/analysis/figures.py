"""The analysis figures: the study's Figure 3 scatter and the representative levels drawn.

The scatter follows the study's notebook (GENERATORS.md §5): 5x5 inches, one Spectral colour per
cluster, noise black, each cluster's representative drawn large, the human levels as numbered
white circles, no axis ticks. With several difficulties the points are coloured by difficulty
instead. Levels are drawn with the game's own renderer, so they look as the agent sees them.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from gvgai_pcg.analysis.clustering import NOISE  # noqa: E402
from gvgai_pcg.analysis.distribution import LevelDistribution  # noqa: E402
from gvgai_pcg.analysis.encoding import padded_rows  # noqa: E402
from gvgai_pcg.games.registry import get_game_spec  # noqa: E402
from gvgai_pcg.games.render import level_pictures
from gvgai_pcg.levels import Level  # noqa: E402

POINT_SIZE = 6  # marker sizes in points, as in the notebook
REPRESENTATIVE_SIZE = 12
PANEL_COLUMNS = 5


def game_title(game: str) -> str:
    """The game's name as people write it (``GameSpec.title``)."""
    return get_game_spec(game).title


def scatter_figure(analysis: LevelDistribution, path: Path, by: str = "cluster") -> Path:
    """Write the PCA scatter of ``analysis`` to ``path`` (PNG or PDF by suffix); ``by`` is
    ``"cluster"`` or ``"difficulty"``."""
    if by not in ("cluster", "difficulty"):
        raise ValueError(f"scatter colouring must be 'cluster' or 'difficulty', got {by!r}")
    coords = analysis.projection.coords
    generated = slice(0, analysis.generated_count)
    fig, ax = plt.subplots(figsize=(5, 5))
    if by == "cluster":
        _draw_clusters(ax, analysis)
    else:
        _draw_difficulties(ax, analysis, coords[generated])
    if analysis.humans:
        ax.update_datalim(
            np.array([human.coords for human in analysis.humans])
        )  # annotations do not autoscale
        ax.margins(0.06)
        ax.autoscale_view()
    for human in analysis.humans:
        ax.annotate(
            str(human.index),
            xy=human.coords,
            ha="center",
            va="center",
            fontsize=7,
            fontweight="bold",
            bbox={
                "boxstyle": "circle,pad=0.25",
                "facecolor": "white",
                "edgecolor": "black",
                "linewidth": 0.8,
            },
            zorder=5,
        )
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(f"PCA on {game_title(analysis.game)} levels")
    return _save(fig, path, dpi=150)


def _draw_clusters(ax: plt.Axes, analysis: LevelDistribution) -> None:
    coords, labels = analysis.projection.coords, analysis.labels
    colours = plt.get_cmap("Spectral")(np.linspace(0, 1, max(len(analysis.clusters), 1)))
    noise = labels == NOISE
    ax.plot(*coords[noise].T, "o", color="black", markersize=POINT_SIZE / 2, linestyle="none", label="noise")
    for cluster, colour in zip(analysis.clusters, colours, strict=False):
        ax.plot(
            *coords[cluster.members].T,
            "o",
            markerfacecolor=colour,
            markeredgecolor="black",
            markeredgewidth=0.3,
            markersize=POINT_SIZE,
            linestyle="none",
        )
        ax.plot(
            *coords[cluster.representative],
            "o",
            markerfacecolor=colour,
            markeredgecolor="black",
            markersize=REPRESENTATIVE_SIZE,
        )
        ax.annotate(
            f"c{cluster.label}",
            coords[cluster.representative],
            xytext=(5, 5),
            textcoords="offset points",
            fontsize=6,
        )


def _draw_difficulties(ax: plt.Axes, analysis: LevelDistribution, coords: np.ndarray) -> None:
    values = np.array([np.nan if d is None else d for d in analysis.difficulties[: analysis.generated_count]])
    points = ax.scatter(*coords.T, c=values, cmap="viridis", s=POINT_SIZE**2 / 2, vmin=0.0, vmax=1.0)
    ax.figure.colorbar(points, ax=ax, shrink=0.8, label="difficulty")


def level_images(levels: list[Level]) -> np.ndarray:
    """``[N, 10H, 10W, 3]`` uint8 RGB pictures of levels of one game, padded to the game's full size."""
    return level_pictures([Level(level.game, tuple(padded_rows(level)), name=level.name) for level in levels])


def representatives_figure(analysis: LevelDistribution, path: Path) -> Path:
    """Write each cluster's representative level, then each human level, drawn, to ``path``."""
    panels = [
        (analysis.levels[c.representative], f"cluster {c.label} (n={c.size})") for c in analysis.clusters
    ]
    for human in analysis.humans:
        status = "outlier" if human.outlier else f"cluster {human.cluster}"
        panels.append((analysis.levels[human.point], f"human {human.index}: {status}"))
    if not panels:  # all noise and no human level: say so rather than draw nothing
        fig, ax = plt.subplots(figsize=(4, 1.2))
        ax.axis("off")
        ax.text(0.5, 0.5, "no clusters and no human levels", ha="center", va="center")
        return _save(fig, path)
    images = level_images([level for level, _ in panels])
    columns = min(PANEL_COLUMNS, len(panels))
    rows = -(-len(panels) // columns)
    height, width = images.shape[1:3]
    panel_width = 2.4
    fig, axes = plt.subplots(
        rows, columns, figsize=(columns * panel_width, rows * panel_width * height / width + rows * 0.35)
    )
    for ax in np.atleast_1d(axes).ravel():
        ax.axis("off")
    for ax, image, (_, title) in zip(np.atleast_1d(axes).ravel(), images, panels, strict=False):
        ax.imshow(image, interpolation="nearest")
        ax.set_title(title, fontsize=8)
    fig.suptitle(f"{game_title(analysis.game)}: cluster representatives and human levels", fontsize=10)
    return _save(fig, path)


def _save(fig, path: Path, dpi: int = 120) -> Path:
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
