"""A plain-text summary of one agent's protocol records: one line per test set."""

from __future__ import annotations

from collections.abc import Sequence

from gvgai_pcg.evaluation.evaluator import LevelRecord


def format_protocol_table(title: str, records: Sequence[LevelRecord]) -> str:
    header = f"{'test set':<10}{'levels':>7}{'episodes':>9}{'mean score':>12}"
    header += f"{'win rate':>10}{'mean len':>10}{'max':>8}"
    lines = [title, header, "-" * len(header)]
    names = list(dict.fromkeys(r.test_set for r in records))
    for name in names:
        part = [r for r in records if r.test_set == name]
        scores = [s for r in part for s in r.scores]
        wins = [w for r in part for w in r.wins]
        lengths = [v for r in part for v in r.lengths]
        top = sum(r.max_score for r in part) / len(part)
        lines.append(
            f"{name:<10}{len(part):>7}{len(scores):>9}{sum(scores) / len(scores):>12.2f}"
            f"{sum(wins) / len(wins):>10.2f}{sum(lengths) / len(lengths):>10.1f}{top:>8.2f}"
        )
    return "\n".join(lines)
