"""Pictures of generated levels: one PNG per level, and the study's Figure 1 (each game at
several difficulties side by side)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from gvgai_pcg.games.registry import generate_level, get_game_spec, study_games  # noqa: E402
from gvgai_pcg.games.render import level_pictures
from gvgai_pcg.levels import Level  # noqa: E402


def write_png(level: Level, path: Path) -> Path:
    """``level`` drawn with the game's tile art (10 px per cell) as a PNG."""
    plt.imsave(path, level_pictures([level])[0])
    return path


def difficulty_figure(
    path: Path,
    games: tuple[str, ...] | None = None,
    difficulties: tuple[float, ...] = (0.0, 0.5, 1.0),
    seed: int = 0,
) -> Path:
    """One row per game (default: the study's, in its order), one column per difficulty: the level
    each (game, d, seed) generates."""
    games = tuple(study_games()) if games is None else games
    fig, axes = plt.subplots(
        len(games), len(difficulties), figsize=(3.2 * len(difficulties), 1.9 * len(games)), squeeze=False
    )
    for row, game in enumerate(games):
        images = level_pictures([generate_level(game, d, seed) for d in difficulties])
        for col, d in enumerate(difficulties):
            ax = axes[row][col]
            ax.imshow(images[col], interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if row == 0:
                ax.set_title(f"d = {d:g}")
            if col == 0:
                ax.set_ylabel(get_game_spec(game).title)
    fig.suptitle(f"Generated levels at increasing difficulty (seed {seed})")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
