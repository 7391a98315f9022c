"""The UED evaluation protocol, beside the study's: many newly generated levels over d in [0, 1].

The unsupervised-environment-design papers (Jiang et al. 2021, robust PLR; Rutherford et al.
2024, "No Regrets", SFL; JaxUED) judge a curriculum by its agent on many fresh levels of the
generator: the solved (won) rate, the mean score, and the tail, alpha-CVaR, the mean over the
worst alpha fraction of levels.

Levels: ``levels`` (1,000) generated levels, level i at d_i = i / (levels - 1) (evenly from 0 to
1, both included) with generator seed ``UED_SEED_BASE + i``. That block lies above every training
seed (``TRAINING_SEED_SPACE``) and above the frozen study test sets' block
(``[TEST_SEED_BASE, TEST_SEED_BASE + 2^24)``), so no training run and no study test set meets one.

Play: every level is played once per evaluation seed (``seeds``, 2), all in ONE batched env with
the study's runner (``play_episodes``: 2,000 steps, actions sampled with per-env draws). The
copies of a level get different env seeds (``episode_seeds``), so evaluation seed k of a level is
its (k+1)-th copy in the batch.

Bias-corrected alpha-CVaR (as the SFL repository's evaluation does): rank the levels by their
result under evaluation seed 0, take the worst ``k = max(1, floor(alpha * levels))``, and report
their mean result under the other seeds (seed 1; the mean of seeds 1.. when there are more). The
naive estimate, the same levels scored with the seed that chose them, is biased low (the worst
draws of a noisy policy look worse than the levels are) and is reported beside it. Ties in the
ranking (every unsolved level has the same solved value) are broken by a fixed random order of
the levels (seeded by the protocol seed), not by index, which would favour low d.

Intervals (95 %): the solved rate's is Wilson's score interval over levels (each level counted
once, with its solved fraction over the seeds, so the correlated episodes of one level do not
narrow it); the mean score's is Student's t over the levels' mean scores; a CVaR's are the same
kinds over its k levels (conditional on the selection).

Records: ``<run>/eval/ued-<key>.csv`` (one row per level: index, d, level seed, then score,
won and length per evaluation seed) and ``<run>/eval/ued-<key>.json`` (settings, frames,
checkpoint and the summary), written atomically and reused while the run's model is unchanged;
the random agent's go to the cache (``<cache>/random/ued-<game>-<key>.csv``).
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import torch

from gvgai_pcg.evaluation.checkpoints import RunInfo
from gvgai_pcg.evaluation.runner import Policy, play_episodes
from gvgai_pcg.games.registry import generate_level
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.seeds import TEST_SEED_BASE, TRAINING_SEED_SPACE

# Generator seeds of the UED levels: level i has seed UED_SEED_BASE + i. The frozen test sets use
# [TEST_SEED_BASE, TEST_SEED_BASE + 2^24), training seeds lie below TRAINING_SEED_SPACE.
UED_SEED_BASE = TEST_SEED_BASE + 2**32
MAX_UED_LEVELS = 2**24
DEFAULT_ALPHAS = (0.01, 0.1)
METRICS = ("score", "solved")
# Bumped when the same settings would give other results; part of ``UEDProtocol.key``.
UED_METHOD_VERSION = 1
CONFIDENCE = 0.95

assert UED_SEED_BASE >= TEST_SEED_BASE + 2**24 and UED_SEED_BASE > TRAINING_SEED_SPACE


@dataclass(frozen=True)
class UEDProtocol:
    """How many generated levels, how many evaluation seeds, how long, how actions are chosen."""

    levels: int = 1000
    seeds: int = 2  # episodes per level, one per evaluation seed; CVaR ranks with 0, scores with 1..
    max_steps: int = 2000
    greedy: bool = False
    seed: int = 0  # the protocol seed: env seeds, action draws, CVaR tie-breaks

    def __post_init__(self) -> None:
        if not 1 <= self.levels <= MAX_UED_LEVELS:
            raise ValueError(f"levels must be in 1..{MAX_UED_LEVELS}, got {self.levels}")
        if self.seeds < 2:
            raise ValueError(
                f"seeds must be at least 2 (CVaR ranks with one, scores with another), got {self.seeds}"
            )
        if self.max_steps < 1:
            raise ValueError(f"max_steps must be positive, got {self.max_steps}")

    def as_dict(self) -> dict:
        return asdict(self)

    @property
    def key(self) -> str:
        """A short stable id of these settings (names the record files)."""
        text = json.dumps({**self.as_dict(), "ued_method": UED_METHOD_VERSION}, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:10]


def check_alphas(alphas: Sequence[float]) -> tuple[float, ...]:
    """``alphas`` as floats, or one ValueError naming the first outside (0, 1]."""
    if not alphas:
        raise ValueError("alphas: give at least one CVaR fraction in (0, 1], e.g. 0.01,0.1")
    for alpha in alphas:
        if isinstance(alpha, bool) or not (isinstance(alpha, int | float) and 0 < alpha <= 1):
            raise ValueError(f"alpha must be in (0, 1] (the CVaR's worst fraction of levels), got {alpha!r}")
    return tuple(float(a) for a in alphas)


def ued_difficulties(count: int) -> list[float]:
    """``count`` difficulties evenly from 0 to 1, both included (0.5 alone for one level)."""
    return [0.5] if count == 1 else [i / (count - 1) for i in range(count)]


def ued_seeds(count: int) -> list[int]:
    return [UED_SEED_BASE + i for i in range(count)]


def ued_levels(game: str, count: int) -> list[Level]:
    """The protocol's ``count`` generated levels of ``game``, in order of d; always the same."""
    return [
        generate_level(game, d, s) for d, s in zip(ued_difficulties(count), ued_seeds(count), strict=True)
    ]


@dataclass
class UEDLevelResult:
    """One level's row: where it came from and its result under each evaluation seed."""

    index: int
    difficulty: float
    level_seed: int
    scores: list[float]
    wins: list[bool]
    lengths: list[int]


def play_ued(
    game: str,
    policy: Policy,
    protocol: UEDProtocol,
    obs: str = "tiles",
    device: str = "cpu",
    progress: bool = True,
) -> list[UEDLevelResult]:
    """Play every level once per evaluation seed, all in one batched env."""
    levels = ued_levels(game, protocol.levels)
    batch = [level for level in levels for _ in range(protocol.seeds)]
    results = play_episodes(game, batch, policy, protocol.max_steps, protocol.seed, obs, device, progress)
    shape = (protocol.levels, protocol.seeds)
    scores = results.scores.reshape(shape).tolist()
    wins = results.wins.reshape(shape).tolist()
    lengths = results.lengths.reshape(shape).tolist()
    return [
        UEDLevelResult(
            i, d, s, [float(v) for v in scores[i]], [bool(v) for v in wins[i]], [int(v) for v in lengths[i]]
        )
        for i, (d, s) in enumerate(
            zip(ued_difficulties(protocol.levels), ued_seeds(protocol.levels), strict=True)
        )
    ]


# --- statistics -----------------------------------------------------------------------------


def wilson_interval(fraction: float, n: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """Wilson's score interval of a proportion ``fraction`` observed over ``n`` trials."""
    from scipy import stats

    z = float(stats.norm.ppf(0.5 + confidence / 2))
    centre = (fraction + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(fraction * (1 - fraction) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return max(0.0, centre - half), min(1.0, centre + half)


def t_interval(values: Sequence[float], confidence: float = CONFIDENCE) -> tuple[float, float]:
    """Student's t interval of the mean of ``values`` (the mean itself, twice, for one value or no
    spread)."""
    from scipy import stats

    n = len(values)
    mean = sum(values) / n
    if n < 2:
        return mean, mean
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    half = float(stats.t.ppf(0.5 + confidence / 2, n - 1)) * sd / math.sqrt(n)
    return mean - half, mean + half


def cvar_count(alpha: float, levels: int) -> int:
    """How many levels the worst ``alpha`` fraction of ``levels`` is: ``floor(alpha * levels)`` as the
    SFL evaluation takes it, at least one."""
    return max(1, math.floor(alpha * levels + 1e-9))


def tie_break_order(count: int, seed: int) -> torch.Tensor:
    """A fixed random permutation of ``count`` levels, the ranking's tie-breaker."""
    return torch.randperm(count, generator=torch.Generator().manual_seed(seed))


def worst_levels(ranking: Sequence[float], alpha: float, seed: int = 0) -> list[int]:
    """The indices of the worst ``cvar_count(alpha)`` levels by ``ranking`` (lowest first), ties
    broken by ``tie_break_order``."""
    count = len(ranking)
    order = tie_break_order(count, seed).tolist()
    position = {level: place for place, level in enumerate(order)}
    ranked = sorted(range(count), key=lambda i: (ranking[i], position[i]))
    return ranked[: cvar_count(alpha, count)]


@dataclass(frozen=True)
class CVaR:
    """alpha-CVaR of one metric: bias-corrected (ranked with one seed, scored with another) and
    naive (ranked and scored with the same seed)."""

    metric: str  # "score" or "solved"
    alpha: float
    levels: int  # k, the worst levels averaged
    corrected: float
    naive: float
    interval: tuple[float, float]  # 95 % of ``corrected`` over its k levels (Wilson or t)


def alpha_cvar(
    ranking: Sequence[float], scoring: Sequence[float], alpha: float, seed: int = 0, proportion: bool = False
) -> CVaR:
    """The mean of ``scoring`` over the worst ``alpha`` of the levels by ``ranking`` (corrected),
    and of ``ranking`` over them (naive). ``proportion``: the values are solved fractions (Wilson
    interval) rather than scores (t interval)."""
    if len(ranking) != len(scoring) or not ranking:
        raise ValueError(
            f"ranking and scoring need one value per level, got {len(ranking)} and {len(scoring)}"
        )
    (alpha,) = check_alphas([alpha])
    chosen = worst_levels(ranking, alpha, seed)
    corrected = [scoring[i] for i in chosen]
    mean = sum(corrected) / len(corrected)
    interval = wilson_interval(mean, len(corrected)) if proportion else t_interval(corrected)
    naive = sum(ranking[i] for i in chosen) / len(chosen)
    return CVaR("solved" if proportion else "score", alpha, len(chosen), mean, naive, interval)


@dataclass
class UEDSummary:
    """What the protocol says of one agent."""

    levels: int
    episodes: int
    solved_rate: float
    solved_interval: tuple[float, float]  # Wilson, over levels
    mean_score: float
    score_interval: tuple[float, float]  # Student's t, over the levels' mean scores
    cvars: list[CVaR] = field(default_factory=list)

    def as_dict(self) -> dict:
        return asdict(self)


def summarise(
    rows: Sequence[UEDLevelResult], alphas: Sequence[float] = DEFAULT_ALPHAS, seed: int = 0
) -> UEDSummary:
    """Rates, means, their intervals and the alpha-CVaRs of ``rows``."""
    alphas = check_alphas(alphas)
    if not rows:
        raise ValueError("no levels to summarise")
    solved = [sum(r.wins) / len(r.wins) for r in rows]
    scores = [sum(r.scores) / len(r.scores) for r in rows]
    n = len(rows)
    cvars = []
    for metric in METRICS:
        rank = [float(r.wins[0]) if metric == "solved" else r.scores[0] for r in rows]
        rest = [(r.wins[1:] if metric == "solved" else r.scores[1:]) for r in rows]
        score = [sum(map(float, values)) / len(values) for values in rest]
        cvars += [alpha_cvar(rank, score, a, seed, proportion=metric == "solved") for a in alphas]
    return UEDSummary(
        levels=n,
        episodes=sum(len(r.wins) for r in rows),
        solved_rate=sum(solved) / n,
        solved_interval=wilson_interval(sum(solved) / n, n),
        mean_score=sum(scores) / n,
        score_interval=t_interval(scores),
        cvars=cvars,
    )


# --- records --------------------------------------------------------------------------------


def csv_columns(seeds: int) -> list[str]:
    per_seed = [f"{name}_{k}" for k in range(seeds) for name in ("score", "won", "length")]
    return ["index", "difficulty", "level_seed", *per_seed]


def rows_to_csv(rows: Sequence[UEDLevelResult]) -> str:
    seeds = len(rows[0].scores) if rows else 0
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(csv_columns(seeds))
    for r in rows:
        cells: list = [r.index, f"{r.difficulty:.6g}", r.level_seed]
        for k in range(seeds):
            cells += [f"{r.scores[k]:g}", int(r.wins[k]), r.lengths[k]]
        writer.writerow(cells)
    return out.getvalue()


def rows_from_csv(text: str) -> list[UEDLevelResult]:
    reader = csv.DictReader(io.StringIO(text))
    seeds = sum(1 for name in reader.fieldnames or () if name.startswith("score_"))
    return [
        UEDLevelResult(
            int(row["index"]),
            float(row["difficulty"]),
            int(row["level_seed"]),
            [float(row[f"score_{k}"]) for k in range(seeds)],
            [row[f"won_{k}"] == "1" for k in range(seeds)],
            [int(row[f"length_{k}"]) for k in range(seeds)],
        )
        for row in reader
    ]


def ued_paths(folder: Path, stem: str) -> tuple[Path, Path]:
    """The per-level CSV and the summary JSON of one evaluation."""
    return folder / f"{stem}.csv", folder / f"{stem}.json"


def write_ued_records(
    folder: Path, stem: str, rows: Sequence[UEDLevelResult], header: dict, summary: UEDSummary
) -> tuple[Path, Path]:
    """The CSV, then the summary (each atomically): a summary on disk always has its CSV."""
    from gvgai_pcg.rl.atomic_files import atomic_write_text

    table, record = ued_paths(folder, stem)
    atomic_write_text(table, rows_to_csv(rows))
    atomic_write_text(record, json.dumps({**header, "summary": summary.as_dict()}, indent=1) + "\n")
    return table, record


def read_cached(folder: Path, stem: str, header: dict) -> list[UEDLevelResult] | None:
    """The cached rows, when both files exist and the summary's header equals ``header``."""
    table, record = ued_paths(folder, stem)
    if not (table.is_file() and record.is_file()):
        return None
    saved = json.loads(record.read_text())
    if {k: saved.get(k) for k in header} != header:
        return None
    return rows_from_csv(table.read_text())


def run_ued_stem(protocol: UEDProtocol) -> str:
    return f"ued-{protocol.key}"


def evaluate_run_ued(
    info: RunInfo,
    protocol: UEDProtocol,
    alphas: Sequence[float] = DEFAULT_ALPHAS,
    device: str = "cpu",
    progress: bool = True,
    force: bool = False,
) -> tuple[UEDSummary, Path]:
    """The UED protocol on a trained run: its summary and the path of its per-level CSV, from the
    run's ``eval/`` when they were made from its present model."""
    from gvgai_pcg.evaluation.evaluator import EVAL_DIR, writer_lock
    from gvgai_pcg.evaluation.policy import load_policy

    alphas = check_alphas(alphas)
    folder, stem = Path(info.path) / EVAL_DIR, run_ued_stem(protocol)
    header = {
        "agent": info.agent,
        "game": info.game,
        "protocol": protocol.as_dict(),
        "frames": info.frames,
        "checkpoint": str(info.checkpoint),
    }
    rows = None if force else read_cached(folder, stem, header)
    if rows is None:
        policy = load_policy(info, greedy=protocol.greedy, seed=protocol.seed, device=device)
        with writer_lock(folder, f"the evaluation results of {info.path}"):
            rows = play_ued(info.game, policy, protocol, info.obs, device, progress)
            summary = summarise(rows, alphas, protocol.seed)
            write_ued_records(folder, stem, rows, header, summary)
    return summarise(rows, alphas, protocol.seed), ued_paths(folder, stem)[0]


def evaluate_random_ued(
    game: str,
    protocol: UEDProtocol,
    alphas: Sequence[float] = DEFAULT_ALPHAS,
    cache_dir: Path | None = None,
    device: str = "cpu",
    progress: bool = True,
    force: bool = False,
) -> tuple[UEDSummary, Path]:
    """The random agent under the UED protocol, cached per game and settings."""
    from gvgai_pcg.evaluation.evaluator import default_cache_dir, writer_lock
    from gvgai_pcg.evaluation.random_agent import RandomAgent
    from gvgai_pcg.games import get_game

    alphas = check_alphas(alphas)
    folder, stem = (cache_dir or default_cache_dir()) / "random", f"ued-{game}-{protocol.key}"
    header = {"agent": "random", "game": game, "protocol": protocol.as_dict()}
    rows = None if force else read_cached(folder, stem, header)
    if rows is None:
        agent = RandomAgent(get_game(game).num_actions, seed=protocol.seed, device=device)
        with writer_lock(folder, f"the random agent's cache {stem}", lock_name=f".{stem}.lock"):
            rows = play_ued(game, agent, protocol, "tiles", device, progress)
            summary = summarise(rows, alphas, protocol.seed)
            write_ued_records(folder, stem, rows, header, summary)
    return summarise(rows, alphas, protocol.seed), ued_paths(folder, stem)[0]


def format_ued_summary(title: str, summary: UEDSummary) -> str:
    """A few lines: rate and mean with intervals, then one line per CVaR."""
    low, high = summary.solved_interval
    s_low, s_high = summary.score_interval
    lines = [
        title,
        f"  {summary.levels} generated levels, d in [0, 1], {summary.episodes} episodes",
        f"  solved rate {summary.solved_rate:.3f}  (95 % Wilson {low:.3f}-{high:.3f})",
        f"  mean score  {summary.mean_score:.3f}  (95 % t {s_low:.3f}-{s_high:.3f})",
        f"  {'CVaR':<8}{'alpha':>7}{'levels':>8}{'corrected':>11}{'naive':>9}{'95 % interval':>22}",
    ]
    for c in summary.cvars:
        lines.append(
            f"  {c.metric:<8}{c.alpha:>7g}{c.levels:>8}{c.corrected:>11.3f}{c.naive:>9.3f}"
            f"{f'{c.interval[0]:.3f}-{c.interval[1]:.3f}':>22}"
        )
    return "\n".join(lines)
