"""The claims' verdicts as Markdown: the statistics behind them, the thresholds, the runs.

``claims_markdown`` is the ``report/claims.md`` of a published sweep (``gvgai_pcg.study.pipeline``),
rebuilt from the runs by ``tests/study/test_results_page.py``: its text is the page's.
"""

from __future__ import annotations

from collections.abc import Sequence

from gvgai_pcg.study.pages.table1_compare import difficulty_markdown, side_by_side_markdown
from gvgai_pcg.study.verdicts.claim_rules import THRESHOLDS
from gvgai_pcg.study.verdicts.intervals import (
    ALPHA,
    LEVEL,
    MOST_SEEDS,
    POWER,
    SEEDS_AND_LEVELS_INTERVAL,
    random_estimate,
)
from gvgai_pcg.study.verdicts.judging import Verdict, study_verdicts
from gvgai_pcg.study.verdicts.results import GameResults
from gvgai_pcg.study.verdicts.table1 import STUDY_EPISODES


def statistics_note(verdicts: Sequence[tuple[str, Verdict]], level_sampling: bool = False) -> str:
    """What the intervals and the correction are, with the family's size."""
    family = sum(verdict.comparisons for _, verdict in verdicts)
    interval = (
        f"its {SEEDS_AND_LEVELS_INTERVAL}"
        if level_sampling
        else f"its two-sided {LEVEL:.0%} t interval over seeds (Welch's for a difference of two conditions)"
    )
    left_out = (
        [
            "A maximum or minimum over test sets keeps the interval over seeds alone. Not in the",
            "intervals: the random agent's row (see its own interval).",
        ]
        if level_sampling
        else [
            "Not in the intervals: the level sampling (each generated test set is the same 30 levels",
            "for every model) and the random agent's row (one 30-episode draw per set).",
        ]
    )
    return " ".join(
        [
            "Scores normalised per test set, (score - random) / (max - random). Each comparison shows the",
            f"mean over seeds of a per-seed statistic, {interval} and its p value against the claim's bound",
            f"after Holm's correction over all {family} comparisons below (family-wise alpha {ALPHA:.2f}).",
            "A claim holds when every comparison is decided on its side (Holm p <= 0.05), does not hold",
            "when one is decided against it, and is inconclusive otherwise.",
            *(
                [
                    '"No generated-level agent wins a human Frogs level" tests each agent (seed) on',
                    "its own episodes instead: the exact binomial test of its win rate over the five human",
                    "levels, Bonferroni over a condition's agents for some agent winning more often than the",
                    "bound and the largest p for every agent winning less often; its interval is the",
                    "most-winning agent's 95 %",
                    "Clopper-Pearson interval.",
                ]
                if any(verdict.claim.startswith("No generated-level agent") for _, verdict in verdicts)
                else []
            ),
            "An inconclusive claim says what would decide it: the seeds per condition at which each",
            f"undecided comparison would be decided with {POWER * 100:.0f} % power (the noncentral t",
            "power of the one-sided t test in the direction seen, at half of Bonferroni's alpha /",
            f"{family}: a comparison decided there is decided by Holm whatever the others do) if the",
            f"means and per-seed spreads seen were the truth ({MOST_SEEDS} at most), or why no number",
            "of seeds would; where the test sets' level sampling alone keeps one open, the levels per",
            "set (and seeds) that would decide it at the per-level spread seen.",
            *left_out,
        ]
    )


def thresholds_markdown() -> str:
    return "\n".join(f"- `{name}` = {value:g}: {why}." for name, (value, why) in THRESHOLDS.items())


def random_markdown(games: dict[str, GameResults]) -> str:
    """The random agent's mean score per game and test set with its 95 % t interval over episodes."""
    lines = []
    for name, game in games.items():
        cells = []
        for test_set, scores in game.random_scores.items():
            value = random_estimate(scores)
            interval = f" [{value.low:.2f}, {value.high:.2f}]" if value.has_interval else ""
            cells.append(f"{test_set} {value.value:.2f}{interval} ({len(scores)} episodes)")
        if cells:
            lines.append(f"- {name} random agent (95 % t interval over episodes): {'; '.join(cells)}")
    return "\n".join(lines)


def claims_markdown(
    verdicts: Sequence[tuple[str, Verdict]], games: dict[str, GameResults], level_sampling: bool = False
) -> str:
    """The verdicts as a Markdown table, the statistics behind them, the seeds and frames behind
    each game, and the study's Table 1 beside ours; ``level_sampling``: the verdicts were judged
    with it (the note says so, and the random agent's intervals are listed)."""
    study = study_verdicts()
    held = sum(verdict.verdict == "holds" for _, verdict in study)
    lines = [
        statistics_note(verdicts, level_sampling),
        f"The same rules on the study's own Table 1 (its cells as point estimates of {STUDY_EPISODES} "
        f"episodes each; the paper gives no per-seed values): {held} of {len(study)} claims hold.",
        "",
        "| game | claim | verdict | evidence |",
        "|---|---|---|---|",
    ]
    for game, verdict in verdicts:
        lines.append(f"| {game} | {verdict.claim} | **{verdict.verdict}** | {verdict.evidence} |")
    lines += ["", "Thresholds (fractions of the gap from random to max):", "", thresholds_markdown(), ""]
    for name, game in games.items():
        runs = ", ".join(
            f"{label} {len(frames)} run(s) at {min(frames):,}-{max(frames):,} frames"
            + (
                f" (and {len(game.training[label])} still training, left out: at "
                f"{', '.join(f'{f:,}' for f in game.training[label])} frames)"
                if label in game.training
                else ""
            )
            for label, frames in game.frames.items()
        )
        lines.append(f"- {name}: {runs}")
    if level_sampling and (baseline := random_markdown(games)):
        lines += ["", baseline]
    lines += ["", side_by_side_markdown(games), "", difficulty_markdown(games)]
    return "\n".join(lines).rstrip("\n") + "\n"
