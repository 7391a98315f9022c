"""Our runs read from disk into the claims' tables, and the study's Table 1 as one.

``collect`` reads every run directory's evaluation records (and, for PPCG, the difficulty in its
log) into per-game ``GameResults``: per condition and test set, each seed's mean score and win
rate. ``table_of`` turns those into the ``Table`` the claim rules read (``claim_rules``): scores
normalised per test set, ``(score - random) / (max - random)``, with each side's own Random and
Max rows; ``study_table`` does the same for the study's own Table 1 (``gvgai_pcg.study.verdicts.table1``),
whose cells are point estimates over 120 episodes (the paper gives no per-seed values).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.evaluator import random_results_path, read_records, run_results_path
from gvgai_pcg.report.table import differing_keys, training_config
from gvgai_pcg.rundir.run_log import read_log
from gvgai_pcg.study.verdicts.table1 import (
    GENERATED_SETS,
    LATE_FRAMES,
    STUDY_FRAMES,
    STUDY_REACHED,
    study_normalised,
)


@dataclass
class SetResult:
    """One condition on one test set: per-seed mean scores and win rates, all episode scores."""

    seed_means: list[float] = field(default_factory=list)
    seed_wins: list[float] = field(default_factory=list)
    scores: list[float] = field(default_factory=list)
    # per level (by name, in the records' order), each seed's mean score on it
    level_means: dict[str, list[float]] = field(default_factory=dict)
    seed_episodes: list[int] = field(default_factory=list)  # each seed's episodes on the set

    @property
    def mean(self) -> float:
        return sum(self.seed_means) / len(self.seed_means)

    @property
    def win_rate(self) -> float:
        return sum(self.seed_wins) / len(self.seed_wins)


@dataclass
class DifficultyLog:
    """One PPCG run's difficulty in training, up to the frames of its evaluated model."""

    frames: list[float]
    difficulty: list[float]

    @property
    def highest(self) -> float:
        return max(self.difficulty, default=0.0)

    def first_at(self, level: float) -> float | None:
        """The frames at which the difficulty first reached ``level`` (``None``: never)."""
        return next((f for f, d in zip(self.frames, self.difficulty, strict=True) if d >= level), None)

    def late(self, window: int = LATE_FRAMES) -> float:
        """The mean difficulty over the last ``window`` frames logged."""
        if not self.frames:
            return 0.0
        late = [d for f, d in zip(self.frames, self.difficulty, strict=True) if f > self.frames[-1] - window]
        return sum(late) / len(late)


@dataclass
class GameResults:
    """A game's conditions (by label: ``Lv 0``, ``PPCG``, ...), random agent and max score."""

    game: str
    conditions: dict[str, dict[str, SetResult]]
    frames: dict[str, list[int]]
    random: dict[str, float]
    maximum: dict[str, float]
    max_difficulty: dict[str, list[float]]  # PPCG: the highest d each run reached in training
    # runs left out because a run of their condition has reached the target and they have not yet
    training: dict[str, list[int]] = field(default_factory=dict)
    difficulty: dict[str, list[DifficultyLog]] = field(default_factory=dict)
    # per counted run (as ``frames``), the frames it is to train: its config's total_frames, at
    # least the target (a budget's conditions may train different frames: medium's Zelda 20M)
    planned: dict[str, list[int]] = field(default_factory=dict)
    # the random agent's every episode score per test set (its own interval: ``random_estimate``)
    random_scores: dict[str, list[float]] = field(default_factory=dict)

    def normalised_seeds(self, label: str, test_set: str) -> list[float]:
        """Each seed's normalised mean score of a condition on a set."""
        gap = self.maximum[test_set] - self.random[test_set]
        gap = gap if gap > 0 else 1.0
        return [(m - self.random[test_set]) / gap for m in self.conditions[label][test_set].seed_means]

    def normalised_levels(self, label: str, test_set: str) -> list[float]:
        """Per level of a set, a condition's normalised mean over seeds (empty: no per-level data,
        or seeds that did not all play the same levels)."""
        gap = self.maximum[test_set] - self.random[test_set]
        gap = gap if gap > 0 else 1.0
        result = self.conditions[label][test_set]
        seeds = len(result.seed_means)
        if not result.level_means or any(len(v) != seeds for v in result.level_means.values()):
            return []
        return [(sum(v) / seeds - self.random[test_set]) / gap for v in result.level_means.values()]

    def normalised(self, label: str, test_set: str) -> float:
        """The normalised mean over seeds of a condition on a set."""
        values = self.normalised_seeds(label, test_set)
        return sum(values) / len(values)


@dataclass
class Table:
    """What the rules read: per condition and test set, the normalised score of each seed (the
    study's: one point estimate), and PPCG's highest difficulty per run in training."""

    game: str
    cells: dict[str, dict[str, list[float]]]
    point: bool  # the cells are point estimates (the study's), not per-seed values
    frames: dict[str, list[int]]
    reached: dict[str, list[float]] = field(default_factory=dict)
    late: dict[str, list[float]] = field(default_factory=dict)  # PPCG: mean d over the last 0.5M frames
    # per condition and generated set, the per-level normalised mean over seeds (level sampling)
    levels: dict[str, dict[str, list[float]]] = field(default_factory=dict)
    # per condition and set, each seed's (episodes won, episodes played): an agent's own test
    wins: dict[str, dict[str, list[tuple[int, int]]]] = field(default_factory=dict)

    def level_values(self, terms: Sequence[tuple[str, str, float]]) -> tuple[tuple[float, ...], ...]:
        """A linear statistic's per-level values on each generated set: for each ``(label, set,
        weight)`` term, ``weight`` times the condition's per-level mean, summed over the terms of a
        set (the same levels for every condition). Empty when a term has no per-level data."""
        by_set: dict[str, list[float]] = {}
        for label, test_set, weight in terms:
            column = self.levels.get(label, {}).get(test_set)
            if not column or (test_set in by_set and len(by_set[test_set]) != len(column)):
                return ()
            old = by_set.get(test_set, [0.0] * len(column))
            by_set[test_set] = [o + weight * v for o, v in zip(old, column, strict=True)]
        return tuple(tuple(values) for values in by_set.values())

    def seeds(self, label: str, test_set: str) -> list[float]:
        return self.cells[label][test_set]

    def per_seed(
        self, label: str, sets: Sequence[str], combine: Callable[[list[float]], float]
    ) -> list[float]:
        """Per seed, ``combine`` of the condition's values over ``sets`` (e.g. its mean over the
        human levels): one value per seed, so the interval is still over seeds."""
        columns = [self.cells[label][s] for s in sets]
        return [combine(list(values)) for values in zip(*columns, strict=True)]


def table_of(game: GameResults, level_sampling: bool = False) -> Table:
    """Our runs of a game as the rules' table; ``level_sampling``: with the generated sets'
    per-level means, so the comparisons carry their level-sampling variance."""
    cells = {
        label: {s: game.normalised_seeds(label, s) for s in sets if s in game.random and s in game.maximum}
        for label, sets in game.conditions.items()
    }
    late = {label: [log.late() for log in logs] for label, logs in game.difficulty.items()}
    levels = {
        label: {s: game.normalised_levels(label, s) for s in GENERATED_SETS if s in cells[label]}
        for label in cells
        if level_sampling
    }
    wins = {
        label: {
            s: [(round(rate * n), n) for rate, n in zip(r.seed_wins, r.seed_episodes, strict=True)]
            for s, r in sets.items()
            if len(r.seed_episodes) == len(r.seed_wins)
        }
        for label, sets in game.conditions.items()
    }
    return Table(game.game, cells, False, dict(game.frames), dict(game.max_difficulty), late, levels, wins)


def study_table(game: str) -> Table:
    """The study's Table 1 of a game as the rules' table: point estimates at its frames."""
    cells = {label: {s: [v] for s, v in row.items()} for label, row in study_normalised(game).items()}
    frames = {label: [STUDY_FRAMES[game]] for label in cells}
    reached = STUDY_REACHED[game]
    return Table(game, cells, True, frames, {"PPCG": [] if reached is None else [reached]})


def collect(
    runs: Iterable[Path], random_cache: Path | None, protocol, target_frames: int | None = None
) -> dict[str, GameResults]:
    """Every game's results from run directories (their evaluation records for ``protocol``, and
    for PPCG the difficulty in their logs up to the evaluated model); runs without records are
    left out. With ``target_frames``, a run's goal is the larger of it and its config's
    ``total_frames``, and a condition with runs at their goal is judged on those alone: a later
    seed still training would otherwise pull its mean back (its frames go to ``training``)."""
    evaluated = []
    for path in runs:
        info = run_info(path)
        results_path = run_results_path(info.path, protocol)
        if results_path.is_file():
            evaluated.append((info, read_records(results_path)))
    labels = _labels_by_config(info for info, _ in evaluated)

    def goal(info) -> int:
        return max(target_frames or 0, int(info.config.get("total_frames", 0) or 0))

    finished = {
        (info.game, labels[info.path])
        for info, records in evaluated
        if target_frames is not None and int(records[0].frames) >= goal(info)
    }
    games: dict[str, GameResults] = {}
    for info, records in sorted(evaluated, key=lambda item: str(item[0].path)):
        frames = int(records[0].frames)  # of the model the records were made from
        if info.game not in games:
            random_path = random_results_path(info.game, protocol, random_cache)
            baseline = read_records(random_path) if random_path.is_file() else []
            games[info.game] = GameResults(
                info.game, {}, {}, _set_means(baseline, "scores"), _set_means(records, "max_score"), {}
            )
            for record in baseline:
                games[info.game].random_scores.setdefault(record.test_set, []).extend(record.scores)
        game = games[info.game]
        label = labels[info.path]
        if (info.game, label) in finished and frames < goal(info):
            game.training.setdefault(label, []).append(frames)
            continue
        game.frames.setdefault(label, []).append(frames)
        game.planned.setdefault(label, []).append(goal(info))
        sets = game.conditions.setdefault(label, {})
        for test_set in {record.test_set for record in records}:
            of_set = [record for record in records if record.test_set == test_set]
            scores = [score for record in of_set for score in record.scores]
            wins = [win for record in of_set for win in record.wins]
            result = sets.setdefault(test_set, SetResult())
            result.seed_means.append(sum(scores) / len(scores))
            result.seed_wins.append(sum(wins) / len(wins))
            result.seed_episodes.append(len(wins))
            result.scores.extend(scores)
            for record in of_set:
                result.level_means.setdefault(record.level, []).append(record.mean_score)
        if info.regimen["name"] == "ppcg" and (info.path / "log.csv").is_file():
            rows = [row for row in read_log(info.path / "log.csv") if row["frames"] <= frames]
            log = DifficultyLog([row["frames"] for row in rows], [row["difficulty"] for row in rows])
            game.difficulty.setdefault(label, []).append(log)
            game.max_difficulty.setdefault(label, []).append(log.highest)
    return games


def _labels_by_config(infos) -> dict[Path, str]:
    """Each run's condition label; where runs of one game and label differ in a training key (a
    learning rate, say), each keeps its label with the differing keys' values appended, so runs
    of different configs are never pooled as seeds (and the rules, which read the plain labels,
    judge none of them)."""
    groups: dict[tuple[str, str], list] = {}
    for info in infos:
        groups.setdefault((info.game, info.label), []).append(info)
    labels = {}
    for (_, label), group in groups.items():
        keys = differing_keys([info.config for info in group])
        for info in group:
            flat = training_config(info.config)
            variant = ", ".join(f"{k}={flat.get(k, '<missing>')}" for k in keys)
            labels[info.path] = f"{label} ({variant})" if variant else label
    return labels


def _set_means(records, attribute: str) -> dict[str, float]:
    """The mean of a record attribute (``scores``: every episode; ``max_score``: every level) per set."""
    values: dict[str, list[float]] = {}
    for record in records:
        value = getattr(record, attribute)
        values.setdefault(record.test_set, []).extend(value if isinstance(value, list) else [value])
    return {test_set: sum(v) / len(v) for test_set, v in values.items()}
