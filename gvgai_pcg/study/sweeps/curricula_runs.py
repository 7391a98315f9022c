"""What the curricula comparison adds to each run beyond the study's protocol: the UED protocol's
records, a picture of the levels its curriculum replays at the end, and the figure of d (and of a
buffer's level statistics, where a curriculum logs them) over training.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path

from gvgai_pcg.curricula import registered_curricula
from gvgai_pcg.evaluation import ued
from gvgai_pcg.evaluation.checkpoints import LAST_CHECKPOINT, load_state, read_run_config, run_info
from gvgai_pcg.games.registry import get_game_spec
from gvgai_pcg.games.render import level_pictures
from gvgai_pcg.levels import human_level
from gvgai_pcg.rundir.atomic_files import atomic_savefig
from gvgai_pcg.rundir.checkpoint import curriculum_state
from gvgai_pcg.rundir.run_log import read_log

REPLAY_PICTURE = "replay.png"
REPLAY_LEVELS = 4
# Every level the curriculum holds at the end, summarised per count of the game's ``counts``
# (interior walls, enemies, ...): where its levels lie against the generator's and the human ones.
REPLAY_STATS = "replay-levels.json"
ALL_LEVELS = 1 << 30
# log.csv columns plotted over training: PPCG's d, and any ``buffer_*`` statistic a curriculum logs
CURVE_COLUMNS = ("difficulty",)
BUFFER_PREFIX = "buffer_"


def evaluate_ued(run: Path, settings: dict, progress: bool = True) -> dict | None:
    """The UED protocol on ``run`` (written to ``run/eval/ued-<key>.{csv,json}`` and reused while
    its model is unchanged); its summary as a dict, ``None`` without ``settings``. The one call
    into ``gvgai_pcg.evaluation.ued``: adapt it here if its interface moves."""
    if not settings:
        return None
    protocol = ued.UEDProtocol(**settings)
    summary, _ = ued.evaluate_run_ued(run_info(run), protocol, alphas=(0.01, 0.1), progress=progress)
    return summary.as_dict()


def replay_levels_of(run: Path, k: int = REPLAY_LEVELS) -> list:
    """Up to ``k`` levels the run's curriculum would replay next, from its last checkpoint's state
    (``Curriculum.replay_levels``); none where it replays none, is not registered here, or there is
    no checkpoint."""
    config, checkpoint = read_run_config(run) or {}, run / LAST_CHECKPOINT
    curriculum = registered_curricula().get(config.get("regimen", {}).get("name"))
    if curriculum is None or not checkpoint.is_file():
        return []  # not this checkout's curriculum, or nothing trained
    run = curriculum.start(config["game"]["name"], config["regimen"])
    saved = curriculum_state(load_state(checkpoint))
    if run.state is not None and saved is not None:
        run.load_state_dict(saved)
    return list(curriculum.replay_levels(run.state, k))[:k]


def write_levels_picture(levels: Sequence, path: Path, title: str = "") -> Path | None:
    """``levels`` side by side in one PNG (the game's tile art); nothing without levels."""
    if not levels:
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    images = level_pictures(list(levels))
    fig, axes = plt.subplots(1, len(images), figsize=(3.2 * len(images), 2.2), squeeze=False)
    for ax, image in zip(axes[0], images, strict=True):
        ax.imshow(image)
        ax.set_axis_off()
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    atomic_savefig(fig, path, dpi=80)
    plt.close(fig)
    return path


def write_replay_picture(run: Path, k: int = REPLAY_LEVELS) -> Path | None:
    """``run/replay.png``: the levels its curriculum would replay next (none: no file)."""
    levels = replay_levels_of(run, k)
    return write_levels_picture(levels, run / REPLAY_PICTURE, f"{run.name}: levels it replays next")


def level_count_summary(levels: Sequence) -> dict:
    """``{"levels": n, "counts": {name: {"median", "p90", "max"}}}`` over ``levels`` (one game's),
    each count from the game's ``GameSpec.counts``; ``{"levels": 0}`` without levels."""
    if not levels:
        return {"levels": 0}
    import numpy as np

    counts = [get_game_spec(level.game).counts(level) for level in levels]
    summary = {}
    for name in counts[0]:
        values = np.array([count[name] for count in counts])
        summary[name] = {
            "median": float(np.median(values)),
            "p90": float(np.percentile(values, 90)),
            "max": int(values.max()),
        }
    return {"levels": len(levels), "counts": summary}


def write_replay_stats(run: Path) -> Path | None:
    """``run/replay-levels.json``: :func:`level_count_summary` of every level the run's curriculum
    holds at the end (its whole buffer or pool); none where it holds none. Rebuilding a buffer of
    generated levels takes a while (Zelda PLR⊥'s 4,000: about 20 s), so it is written once per
    last checkpoint and version of the game's counts (their names)."""
    path, checkpoint = run / REPLAY_STATS, run / LAST_CHECKPOINT
    if _summary_is_current(path, checkpoint, run):
        return path
    levels = replay_levels_of(run, ALL_LEVELS)
    if not levels:
        return None
    partial = path.with_suffix(".json.partial")
    partial.write_text(json.dumps(level_count_summary(levels), indent=1) + "\n")
    partial.replace(path)
    return path


def _summary_is_current(path: Path, checkpoint: Path, run: Path) -> bool:
    """Whether ``path`` is newer than ``checkpoint`` and counts what the game counts now."""
    if not (path.is_file() and checkpoint.is_file() and path.stat().st_mtime >= checkpoint.stat().st_mtime):
        return False
    game = (read_run_config(run) or {}).get("game", {}).get("name")
    saved = json.loads(path.read_text()).get("counts", {})
    return game is None or set(saved) == set(get_game_spec(game).counts(human_level(game, 0)))


def curve_columns(rows: Sequence[dict]) -> list[str]:
    """The columns of a log worth a curve: d where it is finite somewhere, and ``buffer_*`` ones."""
    if not rows:
        return []
    names = [c for c in CURVE_COLUMNS if c in rows[0]] + sorted(
        c for c in rows[0] if c.startswith(BUFFER_PREFIX)
    )
    return [c for c in names if any(math.isfinite(row[c]) for row in rows)]


def write_curves(runs: Sequence[tuple[str, str, Path]], folder: Path) -> list[Path]:
    """Per game, ``curricula-curves-<game>.png``: each logged curriculum column over training
    frames, one line per run, coloured by curriculum. ``runs``: ``(game, label, run dir)``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    logs: dict[str, list[tuple[str, list[dict]]]] = {}
    for game, label, run in runs:
        if (run / "log.csv").is_file():
            logs.setdefault(game, []).append((label, read_log(run / "log.csv")))
    written = []
    for game, entries in sorted(logs.items()):
        columns = sorted({c for _, rows in entries for c in curve_columns(rows)})
        if not columns:
            continue
        labels = sorted({label for label, _ in entries})
        colours = {label: f"C{i}" for i, label in enumerate(labels)}
        fig, axes = plt.subplots(1, len(columns), figsize=(5.5 * len(columns), 3.4), squeeze=False)
        for ax, column in zip(axes[0], columns, strict=True):
            shown = set()
            for label, rows in entries:
                if column not in curve_columns(rows):
                    continue
                name = None if label in shown else label
                shown.add(label)
                frames, values = [r["frames"] for r in rows], [r[column] for r in rows]
                ax.plot(frames, values, color=colours[label], label=name, marker=".", markersize=3)
            ax.set_xlabel("training frames")
            ax.set_ylabel(column)
            ax.legend(fontsize="small")
        fig.suptitle(f"{game}: the curricula over training (one line per run)")
        fig.tight_layout()
        path = folder / f"curricula-curves-{game}.png"
        atomic_savefig(fig, path, dpi=80)
        plt.close(fig)
        written.append(path)
    return written
