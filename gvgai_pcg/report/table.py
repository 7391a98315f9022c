"""The results table of one game, shaped like the study's Table 1.

Rows: Max, Random, then one row per training condition (regimen, frames trained and training
config: runs of one regimen and frames that differ in another training key, a learning rate say,
are split into rows named by the differing keys, never averaged as seeds), in the
order Lv X, Lv 0-3, PCG X (unlimited, then finite sets by their size), PPCG, level sets. Columns:
the test sets ``pcg0.5``, ``pcg1``, ``lv0`` … ``lv4``, and ``train`` (each run's own training
levels, marked as trained on) when a run has a training set of its own.
A condition's cell is the mean over its runs (seeds) of each run's mean score on the test set,
with the std across those run means (population std, as the study's ``calculate_mean_std.py``
computed it with numpy; none for a single run), each run's mean, and the two-sided 95 % t
interval of the mean over runs (Student's t, n - 1 degrees of freedom; none for a single run).
A cell on a test set the runs trained on is marked ``training``; the best held-out mean of each
column (over the condition rows) is marked ``best``, unless every held-out cell of the column
ties with it (all zeros in Frogs: nothing is best).
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from gvgai_pcg.evaluation.evaluator import LevelRecord
from gvgai_pcg.evaluation.max_score import mean_max_score
from gvgai_pcg.evaluation.protocol import TEST_SETS, TRAINING_SET, EvalSet
from gvgai_pcg.rundir.checkpoint import ADDED_KEYS

COLUMN_LABELS = {name: name.replace("pcg", "PCG ").replace("lv", "Lv ") for name in TEST_SETS}
COLUMN_LABELS[TRAINING_SET] = "Train"
_REGIMEN_ORDER = ("Lv", "Lv 0-3", "PCG", "PPCG")
_NUMBER = re.compile(r"(\d+(?:\.\d+)?)")


@dataclass
class Cell:
    mean: float
    std: float | None = None  # across runs (population); None for Max, Random and a single run
    runs: int = 1
    training: bool = False  # the row's runs trained on this test set's levels
    best: bool = False  # the best held-out mean of its column
    seed_means: tuple[float, ...] = ()  # each run's mean, in run order
    ci95: tuple[float, float] | None = None  # 95 % t interval of the mean over runs; None below 2 runs


def t_interval(values: Sequence[float], level: float = 0.95) -> tuple[float, float] | None:
    """The two-sided t interval of the mean of ``values`` (None for fewer than two)."""
    if len(values) < 2:
        return None
    from scipy import stats

    mean = sum(values) / len(values)
    if max(values) == min(values):  # scipy wants a positive scale
        return mean, mean
    low, high = stats.t.interval(level, len(values) - 1, loc=mean, scale=float(stats.sem(values)))
    return float(low), float(high)


@dataclass
class Row:
    name: str  # "Max", "Random", "PPCG (100k)"
    kind: str  # "max", "random" or "trained"
    cells: dict[str, Cell]
    regimen: str = ""
    frames: int = 0
    runs: list[str] = field(default_factory=list)


@dataclass
class RunResults:
    """One trained run's records, with what the table needs to place them."""

    label: str  # "Lv 0", "PPCG" …
    frames: int
    training_sets: tuple[str, ...]
    records: list[LevelRecord]
    path: str = ""
    config: dict = field(default_factory=dict, repr=False)  # the run's resolved training config


# Keys that do not change what a run learns (bookkeeping, where it ran) and the seed, which
# replicates: runs differing only in these are seeds of one condition.
NOT_TRAINING = (
    "seed",
    "total_frames",
    "device",
    "threads",
    "rollout",
    "checkpoint",
    "log",
    "out_dir",
    "run_name",
)
NAMES = ("regimen.tag",)  # a name derived from the regimen's other keys


def _flatten(config: dict, prefix: str = "") -> dict[str, object]:
    flat: dict[str, object] = {}
    for key, value in config.items():
        if isinstance(value, dict):
            flat.update(_flatten(value, f"{prefix}{key}."))
        else:
            flat[f"{prefix}{key}"] = value
    return flat


def training_config(config: dict) -> dict[str, object]:
    """The dotted keys of ``config`` that shape what a run learns (``NOT_TRAINING`` left out;
    keys added since older runs at their old behaviour's value, so those runs still match)."""
    flat = {
        k: v for k, v in _flatten(config).items() if k.split(".")[0] not in NOT_TRAINING and k not in NAMES
    }
    return {**ADDED_KEYS, **flat} if flat else {}


def differing_keys(configs: Sequence[dict]) -> list[str]:
    """The dotted training keys whose values are not the same in every config."""
    flats = [training_config(c) for c in configs]
    keys = sorted({k for flat in flats for k in flat})
    return [k for k in keys if len({repr(flat.get(k, "<missing>")) for flat in flats}) > 1]


def split_by_config(runs: Sequence[RunResults]) -> dict[str, list[RunResults]]:
    """``runs`` (one condition at one frame count) split into groups of one training config each,
    keyed by the differing keys' values (``""`` when all share one config)."""
    keys = differing_keys([run.config for run in runs])
    groups: dict[str, list[RunResults]] = {}
    for run in runs:
        flat = training_config(run.config)
        groups.setdefault(", ".join(f"{k}={flat.get(k, '<missing>')}" for k in keys), []).append(run)
    return groups


@dataclass
class GameTable:
    game: str
    columns: list[str]
    rows: list[Row]


def format_frames(frames: int) -> str:
    """``40M``, ``1.5M``, ``200k``, ``640`` (three significant digits, the unit chosen after
    rounding: 999,600 is ``1M``, not ``1e+03k``)."""
    rounded = float(f"{frames:.3g}")
    for unit, size in (("M", 1_000_000), ("k", 1_000)):
        if rounded >= size:
            return f"{rounded / size:g}{unit}"
    return str(frames)


def mean_scores(records: Sequence[LevelRecord]) -> dict[str, float]:
    """Mean score over all episodes of each test set."""
    scores: dict[str, list[float]] = {}
    for record in records:
        scores.setdefault(record.test_set, []).extend(record.scores)
    return {name: sum(values) / len(values) for name, values in scores.items()}


def _condition_order(row: Row) -> tuple:
    prefix = row.regimen if row.regimen == "Lv 0-3" else row.regimen.split(" ")[0]
    rank = _REGIMEN_ORDER.index(prefix) if prefix in _REGIMEN_ORDER else len(_REGIMEN_ORDER)
    # numbers in order: "PCG 1, 2 levels" before "PCG 1, 10 levels"
    natural = tuple(
        (0, float(part), "") if _NUMBER.fullmatch(part) else (1, 0.0, part)
        for part in _NUMBER.split(row.regimen)
    )
    return (rank, natural, row.frames)


def condition_row(
    label: str, frames: int, runs: Sequence[RunResults], columns: Sequence[str], variant: str = ""
) -> Row:
    """The row of the runs of one condition: mean and std across their per-run means. ``variant``
    names the training keys that set these runs apart from others of the same label and frames."""
    per_run = [mean_scores(run.records) for run in runs]
    cells = {}
    for column in columns:
        values = [means[column] for means in per_run if column in means]
        if not values:
            continue
        mean = sum(values) / len(values)
        std = math.sqrt(sum((v - mean) ** 2 for v in values) / len(values)) if len(values) > 1 else None
        cells[column] = Cell(
            mean,
            std,
            len(values),
            training=any(column in run.training_sets for run in runs),
            seed_means=tuple(values),
            ci95=t_interval(values),
        )
    name = f"{label} ({format_frames(frames)}{'; ' + variant if variant else ''})"
    return Row(name, "trained", cells, regimen=label, frames=frames, runs=[run.path for run in runs])


def mark_best(rows: Sequence[Row], columns: Sequence[str]) -> None:
    """Mark, per column, the held-out cells of the trained rows that have the highest mean; none
    where every held-out cell ties with the highest (a column of zeros has no best)."""
    for column in columns:
        held_out = [r.cells[column] for r in rows if r.kind == "trained" and column in r.cells]
        held_out = [cell for cell in held_out if not cell.training]
        if held_out:
            top = max(cell.mean for cell in held_out)
            best = [math.isclose(cell.mean, top, rel_tol=0, abs_tol=1e-9) for cell in held_out]
            if all(best) and len(held_out) > 1:
                continue
            for cell, is_best in zip(held_out, best, strict=True):
                cell.best = is_best


def build_table(
    game: str,
    sets: Sequence[EvalSet],
    random_records: Sequence[LevelRecord] | None,
    runs: Sequence[RunResults],
) -> GameTable:
    """The table of ``game``: Max (from the levels), Random (if given), one row per condition.
    A ``train`` column (each run's own training levels) follows when any run has one."""
    columns = [s.name for s in sets]
    if any(record.test_set == TRAINING_SET for run in runs for record in run.records):
        columns.append(TRAINING_SET)
    rows = [Row("Max", "max", {s.name: Cell(mean_max_score(s.levels)) for s in sets})]
    if random_records:
        rows.append(Row("Random", "random", {k: Cell(v) for k, v in mean_scores(random_records).items()}))
    groups: dict[tuple[str, int], list[RunResults]] = {}
    for run in runs:
        groups.setdefault((run.label, run.frames), []).append(run)
    conditions = [
        condition_row(label, frames, split, columns, variant)
        for (label, frames), group in groups.items()
        for variant, split in split_by_config(group).items()
    ]
    rows += sorted(conditions, key=_condition_order)
    mark_best(rows, columns)
    return GameTable(game, columns, rows)
