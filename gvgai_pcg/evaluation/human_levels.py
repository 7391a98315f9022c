"""Evaluation on the human-designed levels: N episodes per level, summarised per level."""

from __future__ import annotations

from dataclasses import asdict, dataclass

from gvgai_pcg.evaluation.runner import EpisodeResults, Policy, play_episodes
from gvgai_pcg.games import get_game
from gvgai_pcg.levels import Level


@dataclass
class LevelSummary:
    """What one level gave over its episodes (the ``levels`` entries of the evaluation JSON)."""

    level: str
    episodes: int
    mean_score: float
    std_score: float
    win_rate: float
    mean_length: float
    max_score: int
    scores: list[float]
    lengths: list[int]

    def as_dict(self) -> dict:
        return asdict(self)


def summarise(name: str, results: EpisodeResults, max_score: int) -> LevelSummary:
    scores = results.scores.double()
    n = scores.numel()
    return LevelSummary(
        level=name,
        episodes=n,
        mean_score=float(scores.mean()),
        std_score=float(scores.std(unbiased=False)) if n > 1 else 0.0,
        win_rate=float(results.wins.double().mean()),
        mean_length=float(results.lengths.double().mean()),
        max_score=max_score,
        scores=[float(s) for s in results.scores.tolist()],
        lengths=[int(v) for v in results.lengths.tolist()],
    )


def evaluate_levels(
    game: str,
    levels: list[Level],
    policy: Policy,
    episodes: int,
    max_steps: int = 2000,
    seed: int = 0,
    obs: str = "tiles",
    device: str = "cpu",
    progress: bool = True,
) -> list[LevelSummary]:
    """``episodes`` episodes on each level, all in one batch; one summary per level."""
    batch = [level for level in levels for _ in range(episodes)]
    results = play_episodes(game, batch, policy, max_steps, seed, obs, device, progress)
    summaries = []
    for i, level in enumerate(levels):
        part = slice(i * episodes, (i + 1) * episodes)
        one = EpisodeResults(results.scores[part], results.lengths[part], results.wins[part])
        summaries.append(summarise(level.name or f"level{i}", one, get_game(game).max_score(level)))
    return summaries


def format_table(game: str, summaries: list[LevelSummary], agent: str) -> str:
    """A plain-text table, one row per level."""
    header = (
        f"{'level':<16}{'episodes':>9}{'mean score':>12}{'std':>8}{'win rate':>10}{'mean len':>10}{'max':>6}"
    )
    lines = [f"{game}: {agent} agent", header, "-" * len(header)]
    for s in summaries:
        lines.append(
            f"{s.level:<16}{s.episodes:>9}{s.mean_score:>12.2f}{s.std_score:>8.2f}"
            f"{s.win_rate:>10.2f}{s.mean_length:>10.1f}{s.max_score:>6}"
        )
    return "\n".join(lines)
