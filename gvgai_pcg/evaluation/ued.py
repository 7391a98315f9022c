"""The UED evaluation protocol, beside the study's: many newly generated levels over d in [0, 1].

The unsupervised-environment-design papers (Jiang et al. 2021, robust PLR; Rutherford et al.
2024, "No Regrets", SFL; JaxUED) judge a curriculum by its agent on many fresh levels of the
generator: the solved (won) rate, the mean score, and the tail, alpha-CVaR, the mean over the
worst alpha fraction of levels.

Levels: ``levels`` (1,000) generated levels, level i at d_i = i / (levels - 1) (evenly from 0 to
1, both included) with generator seed ``UED_SEED_BASE + i``. That block lies above every training
seed (``TRAINING_SEED_SPACE``) and above the frozen study test sets' block
(``[TEST_SEED_BASE, TEST_SEED_BASE + 2^24)``), so no training run and no study test set meets one.

Two protocols share this module; a protocol's settings name which (and its record files' key):

* **the tail protocol** (``rank_episodes`` and ``score_episodes`` set; ``tail_protocol()``:
  ``TAIL_LEVELS`` levels, 10 + 10 episodes): as SFL's evaluation (Rutherford et al. 2024), each
  level is ranked by the mean of its first ``rank_episodes`` episodes and scored by the mean of
  ``score_episodes`` other ones, for the score and for the win rate (SFL's headline CVaR). Ties
  at the boundary of the worst ``k`` are **averaged**: the levels strictly worse than the k-th
  count fully and the levels tied with it share the remaining places equally, which is the mean
  of the CVaR over every order of the tied levels, so no permutation decides it. Zelda's levels
  tie heavily (71 % of the levels are never won in 10 episodes by the published ACCEL seed 0), and
  more levels do not break such ties (the tied share is the policy's, not N's): averaging does.
  Each CVaR keeps its tie structure (``below``: levels strictly worse than the boundary,
  ``tied``: levels at it).
* **the first protocol** (``seeds`` alone, the published curricula records): every level played
  once per evaluation seed, ranked by seed 0 and scored by the mean of the others; ties broken by
  a fixed random order of the levels (seeded by the protocol seed). With one ranking episode most
  of Zelda's tail is a tie, so this CVaR depends on that order; kept so the published records
  still read and rebuild.

Play: all episodes of all levels in ONE batched env with the study's runner (``play_episodes``:
2,000 steps, actions sampled with per-env draws). The copies of a level get different env seeds
(``episode_seeds``), so episode k of a level is its (k+1)-th copy in the batch (the tail
protocol's ranking episodes are copies 0..rank_episodes-1, its scoring ones the rest).

Bias-corrected alpha-CVaR (as the SFL repository's evaluation does): rank the levels by their
ranking episodes, take the worst ``k = max(1, floor(alpha * levels))``, and report their mean
result in the other episodes. The naive estimate, the same levels scored with the episodes that
chose them, is biased low (the worst draws of a noisy policy look worse than the levels are) and
is reported beside it.

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
from gvgai_pcg.evaluation.evaluator import EVAL_DIR, default_cache_dir, writer_lock
from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.evaluation.random_agent import RandomAgent
from gvgai_pcg.evaluation.runner import Policy, play_episodes
from gvgai_pcg.games import get_game
from gvgai_pcg.games.registry import generate_level
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.seeds import TEST_SEED_BASE, TRAINING_SEED_SPACE
from gvgai_pcg.rundir.atomic_files import atomic_write_text

# Generator seeds of the UED levels: level i has seed UED_SEED_BASE + i. The frozen test sets use
# [TEST_SEED_BASE, TEST_SEED_BASE + 2^24), training seeds lie below TRAINING_SEED_SPACE.
UED_SEED_BASE = TEST_SEED_BASE + 2**32
MAX_UED_LEVELS = 2**24
# Every episode of the protocol (levels x seeds) is in one batched env, so their number is bounded
# up front, not by an allocation failing after the levels were generated.
MAX_UED_EPISODES = 2**18
DEFAULT_ALPHAS = (0.01, 0.1)
METRICS = ("score", "solved")
# Bumped when the same settings would give other results; part of ``UEDProtocol.key``. The first
# protocol keeps version 1 so the published records keep their keys.
UED_METHOD_VERSION = 1
TAIL_METHOD_VERSION = 2
# The tail protocol's defaults (docs/evaluation.md says why these).
TAIL_LEVELS = 1000
TAIL_RANK_EPISODES = 10
TAIL_SCORE_EPISODES = 10
CONFIDENCE = 0.95

assert UED_SEED_BASE >= TEST_SEED_BASE + 2**24 and UED_SEED_BASE > TRAINING_SEED_SPACE


@dataclass(frozen=True)
class UEDProtocol:
    """How many generated levels, how many episodes of each rank and score it, how long, how
    actions are chosen. ``rank_episodes`` and ``score_episodes`` set: the tail protocol (``seeds``
    is then their sum); unset: the first protocol (``seeds`` episodes, ranked by the first)."""

    levels: int = 1000
    seeds: int | None = None  # episodes per level; the first protocol's default is 2
    max_steps: int = 2000
    greedy: bool = False
    seed: int = 0  # the protocol seed: env seeds, action draws, the first protocol's tie-breaks
    rank_episodes: int | None = None
    score_episodes: int | None = None

    def __post_init__(self) -> None:
        if not 1 <= self.levels <= MAX_UED_LEVELS:
            raise ValueError(f"levels must be in 1..{MAX_UED_LEVELS}, got {self.levels}")
        if (self.rank_episodes is None) != (self.score_episodes is None):
            raise ValueError("rank_episodes and score_episodes go together (the tail protocol): give both")
        if self.tail:
            for name in ("rank_episodes", "score_episodes"):
                if getattr(self, name) < 1:
                    raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")
            episodes = self.rank_episodes + self.score_episodes
            if self.seeds not in (None, episodes):
                raise ValueError(
                    f"seeds is rank_episodes + score_episodes ({episodes}) in the tail protocol, "
                    f"got {self.seeds}"
                )
            object.__setattr__(self, "seeds", episodes)
        elif self.seeds is None:
            object.__setattr__(self, "seeds", 2)
        if self.seeds < 2:
            raise ValueError(
                f"seeds must be at least 2 (CVaR ranks with one, scores with another), got {self.seeds}"
            )
        if self.levels * self.seeds > MAX_UED_EPISODES:
            raise ValueError(
                f"levels x seeds = {self.levels} x {self.seeds} = {self.levels * self.seeds:,} episodes, "
                f"more than the {MAX_UED_EPISODES:,} that one batched env holds; give fewer"
            )
        if self.max_steps < 1:
            raise ValueError(f"max_steps must be positive, got {self.max_steps}")

    @property
    def tail(self) -> bool:
        """Whether this is the tail protocol (separate ranking and scoring episodes, ties averaged)."""
        return self.rank_episodes is not None

    def as_dict(self) -> dict:
        """The settings as records keep them: the first protocol's as they always were."""
        settings = asdict(self)
        if self.tail:
            del settings["seeds"]
        else:
            del settings["rank_episodes"], settings["score_episodes"]
        return settings

    @property
    def key(self) -> str:
        """A short stable id of these settings (names the record files)."""
        method = TAIL_METHOD_VERSION if self.tail else UED_METHOD_VERSION
        text = json.dumps({**self.as_dict(), "ued_method": method}, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:10]


def tail_protocol(
    levels: int = TAIL_LEVELS,
    rank_episodes: int = TAIL_RANK_EPISODES,
    score_episodes: int = TAIL_SCORE_EPISODES,
    **settings,
) -> UEDProtocol:
    """The tail protocol, with its defaults."""
    return UEDProtocol(levels=levels, rank_episodes=rank_episodes, score_episodes=score_episodes, **settings)


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
    """Wilson's score interval of a proportion ``fraction`` observed over ``n`` trials: scipy's
    (``binomtest``) on a whole count of successes; written out for a fractional count (a weighted
    tail's effective count, or a mean of solved fractions), which ``binomtest`` refuses."""
    from scipy import stats

    successes = fraction * n
    if abs(successes - round(successes)) <= 1e-9 * max(1, n):
        ci = stats.binomtest(round(successes), n).proportion_ci(confidence, method="wilson")
        return max(0.0, float(ci.low)), min(1.0, float(ci.high))
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
    if n < 2 or max(values) == min(values):  # scipy wants a positive scale
        return mean, mean
    low, high = stats.t.interval(confidence, n - 1, loc=mean, scale=float(stats.sem(values)))
    return float(low), float(high)


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
class TailWeights:
    """The worst ``k`` places shared out: ``weights`` (level -> share), ``below`` levels strictly
    worse than the k-th value, ``tied`` levels equal to it."""

    k: int
    weights: dict[int, float]
    below: int
    tied: int


def tail_weights(ranking: Sequence[float], alpha: float) -> TailWeights:
    """Level -> its share of the worst ``k = cvar_count(alpha)`` places by ``ranking``, ties
    averaged: 1 for each level strictly worse than the k-th value, ``(k - below) / tied`` for each
    of the ``tied`` levels equal to it. The weights sum to k, and the weighted mean of any values is
    their CVaR's mean over every order of the tied levels."""
    count = len(ranking)
    k = cvar_count(alpha, count)
    rounded = [round(float(v), 9) for v in ranking]  # means of the same outcomes compare equal
    boundary = sorted(rounded)[k - 1]
    below = [i for i in range(count) if rounded[i] < boundary]
    tied = [i for i in range(count) if rounded[i] == boundary]
    share = (k - len(below)) / len(tied)
    return TailWeights(k, {**dict.fromkeys(below, 1.0), **dict.fromkeys(tied, share)}, len(below), len(tied))


def weighted_interval(
    values: Sequence[float], weights: Sequence[float], proportion: bool, confidence: float = CONFIDENCE
) -> tuple[float, float]:
    """The 95 % interval of a weighted mean: Wilson (``proportion``) or Student's t, over the
    effective number of levels ``(sum w)^2 / sum w^2`` (k when no level is shared)."""
    from scipy import stats

    total = sum(weights)
    mean = sum(w * v for w, v in zip(weights, values, strict=True)) / total
    n = total * total / sum(w * w for w in weights)
    if proportion:
        return wilson_interval(mean, max(1, round(n)), confidence)
    if n < 1.5:
        return mean, mean
    variance = sum(w * (v - mean) ** 2 for w, v in zip(weights, values, strict=True)) / total * n / (n - 1)
    if variance == 0:  # scipy wants a positive scale
        return mean, mean
    low, high = stats.t.interval(confidence, n - 1, loc=mean, scale=math.sqrt(variance / n))
    return float(low), float(high)


@dataclass(frozen=True)
class CVaR:
    """alpha-CVaR of one metric: bias-corrected (ranked with some episodes, scored with others)
    and naive (ranked and scored with the same episodes)."""

    metric: str  # "score" or "solved"
    alpha: float
    levels: int  # k, the worst levels averaged
    corrected: float
    naive: float
    interval: tuple[float, float]  # 95 % of ``corrected`` over its k levels (Wilson or t)
    below: int = 0  # levels ranked strictly worse than the k-th (the tail protocol)
    tied: int = 0  # levels ranked equal to the k-th, sharing the rest of the k places


def alpha_cvar(
    ranking: Sequence[float],
    scoring: Sequence[float],
    alpha: float,
    seed: int = 0,
    proportion: bool = False,
    average_ties: bool = False,
) -> CVaR:
    """The mean of ``scoring`` over the worst ``alpha`` of the levels by ``ranking`` (corrected),
    and of ``ranking`` over them (naive). ``proportion``: the values are solved fractions (Wilson
    interval) rather than scores (t interval). Ties at the boundary: averaged (``average_ties``,
    ``tail_weights``), else broken by the fixed order ``tie_break_order(seed)``."""
    if len(ranking) != len(scoring) or not ranking:
        raise ValueError(
            f"ranking and scoring need one value per level, got {len(ranking)} and {len(scoring)}"
        )
    (alpha,) = check_alphas([alpha])
    metric = "solved" if proportion else "score"
    if average_ties:
        tail = tail_weights(ranking, alpha)
        weights = tail.weights
        corrected = sum(w * scoring[i] for i, w in weights.items()) / tail.k
        naive = sum(w * ranking[i] for i, w in weights.items()) / tail.k
        interval = weighted_interval([scoring[i] for i in weights], list(weights.values()), proportion)
        return CVaR(metric, alpha, tail.k, corrected, naive, interval, tail.below, tail.tied)
    chosen = worst_levels(ranking, alpha, seed)
    values = [scoring[i] for i in chosen]
    mean = sum(values) / len(values)
    interval = wilson_interval(mean, len(values)) if proportion else t_interval(values)
    naive = sum(ranking[i] for i in chosen) / len(chosen)
    return CVaR(metric, alpha, len(chosen), mean, naive, interval)


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
    rank_episodes: int | None = None  # the tail protocol's; None: the first protocol

    def as_dict(self) -> dict:
        return asdict(self)


def _mean(values: Sequence) -> float:
    return sum(map(float, values)) / len(values)


def summarise(
    rows: Sequence[UEDLevelResult],
    alphas: Sequence[float] = DEFAULT_ALPHAS,
    seed: int = 0,
    rank_episodes: int | None = None,
) -> UEDSummary:
    """Rates, means, their intervals and the alpha-CVaRs of ``rows``: each level ranked by the
    mean of its first ``rank_episodes`` episodes and scored by the mean of the rest, ties averaged
    (the tail protocol), or, with ``rank_episodes`` None (the first protocol), ranked by its first
    episode with ties broken by the fixed order of ``seed``."""
    alphas = check_alphas(alphas)
    if not rows:
        raise ValueError("no levels to summarise")
    first = 1 if rank_episodes is None else rank_episodes
    if not 1 <= first < min(len(r.wins) for r in rows):
        raise ValueError(f"rank_episodes must leave scoring episodes on every level, got {rank_episodes}")
    solved = [sum(r.wins) / len(r.wins) for r in rows]
    scores = [sum(r.scores) / len(r.scores) for r in rows]
    n = len(rows)
    cvars = []
    for metric in METRICS:
        outcomes = [r.wins if metric == "solved" else r.scores for r in rows]
        rank = [_mean(values[:first]) for values in outcomes]
        score = [_mean(values[first:]) for values in outcomes]
        cvars += [
            alpha_cvar(rank, score, a, seed, metric == "solved", average_ties=rank_episodes is not None)
            for a in alphas
        ]
    return UEDSummary(
        levels=n,
        episodes=sum(len(r.wins) for r in rows),
        solved_rate=sum(solved) / n,
        solved_interval=wilson_interval(sum(solved) / n, n),
        mean_score=sum(scores) / n,
        score_interval=t_interval(scores),
        cvars=cvars,
        rank_episodes=rank_episodes,
    )


def summarise_protocol(
    rows: Sequence[UEDLevelResult], alphas: Sequence[float], protocol: UEDProtocol
) -> UEDSummary:
    """``summarise`` as ``protocol`` ranks and breaks ties."""
    return summarise(rows, alphas, protocol.seed, protocol.rank_episodes)


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
            summary = summarise_protocol(rows, alphas, protocol)
            write_ued_records(folder, stem, rows, header, summary)
    return summarise_protocol(rows, alphas, protocol), ued_paths(folder, stem)[0]


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
    alphas = check_alphas(alphas)
    folder, stem = (cache_dir or default_cache_dir()) / "random", f"ued-{game}-{protocol.key}"
    header = {"agent": "random", "game": game, "protocol": protocol.as_dict()}
    rows = None if force else read_cached(folder, stem, header)
    if rows is None:
        agent = RandomAgent(get_game(game).num_actions, seed=protocol.seed, device=device)
        with writer_lock(folder, f"the random agent's cache {stem}", lock_name=f".{stem}.lock"):
            rows = play_ued(game, agent, protocol, "tiles", device, progress)
            summary = summarise_protocol(rows, alphas, protocol)
            write_ued_records(folder, stem, rows, header, summary)
    return summarise_protocol(rows, alphas, protocol), ued_paths(folder, stem)[0]


def format_ued_summary(title: str, summary: UEDSummary) -> str:
    """A few lines: rate and mean with intervals, then one line per CVaR."""
    low, high = summary.solved_interval
    s_low, s_high = summary.score_interval
    rank = summary.rank_episodes
    how = (
        f"ranked by {rank} episodes per level, scored by the others, ties averaged"
        if rank is not None
        else "ranked by one episode per level, scored by the others, ties by a fixed order"
    )
    lines = [
        title,
        f"  {summary.levels} generated levels, d in [0, 1], {summary.episodes} episodes; CVaR {how}",
        f"  solved rate {summary.solved_rate:.3f}  (95 % Wilson {low:.3f}-{high:.3f})",
        f"  mean score  {summary.mean_score:.3f}  (95 % t {s_low:.3f}-{s_high:.3f})",
        f"  {'CVaR':<8}{'alpha':>7}{'levels':>8}{'corrected':>11}{'naive':>9}{'95 % interval':>22}"
        + ("  ties (below + tied)" if rank is not None else ""),
    ]
    for c in summary.cvars:
        ties = f"  {c.below} + {c.tied}" if rank is not None else ""
        lines.append(
            f"  {c.metric:<8}{c.alpha:>7g}{c.levels:>8}{c.corrected:>11.3f}{c.naive:>9.3f}"
            f"{f'{c.interval[0]:.3f}-{c.interval[1]:.3f}':>22}{ties}"
        )
    return "\n".join(lines)
