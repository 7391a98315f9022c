"""``gvgai-pcg report --ued``: the UED protocol's table of any runs, judged as the curricula page is.

Each run is evaluated with the UED protocol (``gvgai_pcg.evaluation.ued``; its records are reused
while its model is unchanged, and only read with ``--no-evaluate``). Then, per game, each
curriculum's scores and UED metrics (solved rate, mean score, score CVaR at 1 % and 10 %) over
seeds with their 95 % t intervals, and each curriculum against a baseline (PPCG unless told
otherwise) with Welch intervals and Holm's correction over every comparison: the tables and
verdicts of ``docs/results-curricula.md`` (``gvgai_pcg.study.verdicts.comparison``), on the user's runs.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import find_runs
from gvgai_pcg.evaluation.ued import evaluate_run_ued
from gvgai_pcg.report.build import usable_run
from gvgai_pcg.rundir.atomic_files import atomic_write_text
from gvgai_pcg.study.verdicts.comparison import ALPHAS, BASELINE, collect_runs, comparison_markdown

UED_TABLE = "ued.md"


def write_ued_table(
    runs: Sequence[Path],
    out_dir: Path,
    protocol,
    ued_protocol,
    baseline: str = BASELINE,
    evaluate: bool = True,
    device: str = "cpu",
    progress: bool = True,
    force: bool = False,
) -> Path:
    """``out_dir/ued.md`` for the runs under ``runs`` that have the study ``protocol``'s records:
    ``ued_protocol``'s metrics (evaluated here unless ``evaluate`` is off) beside their scores,
    each curriculum against ``baseline`` (a row label: ``PPCG``, ``DR``, ...)."""
    infos = [info for path in find_runs([Path(p) for p in runs]) if (info := usable_run(path))]
    summaries = {}
    if evaluate:
        for info in infos:
            summary, _ = evaluate_run_ued(info, ued_protocol, ALPHAS, device, progress, force)
            summaries[Path(info.path)] = summary.as_dict()
    games = collect_runs([info.path for info in infos], protocol, ued_protocol.as_dict(), summaries)
    settings = ued_protocol.as_dict()
    episodes = (
        f"({ued_protocol.rank_episodes} episodes to rank + {ued_protocol.score_episodes} to score)"
        if ued_protocol.tail
        else f"{settings['seeds']} evaluation seeds"
    )
    head = [
        f"# UED protocol: {settings['levels']:,} generated levels x {episodes}, "
        f"at most {settings['max_steps']:,} steps; each curriculum against {baseline}",
        "",
    ]
    labels = sorted({label for curricula in games.values() for label in curricula})
    if games and baseline not in labels:
        head += [f"No {baseline} run here to compare with; --baseline takes one of: {', '.join(labels)}.", ""]
    body = comparison_markdown(games, baseline) if games else "No run has the protocol's records yet.\n"
    path = Path(out_dir) / UED_TABLE
    atomic_write_text(path, "\n".join([*head, body]))
    return path
