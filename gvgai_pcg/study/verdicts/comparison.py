"""The curricula comparison, answered from the runs: does any curriculum beat PPCG on the human levels,
and on the tail (CVaR) of newly generated ones?

Per game and curriculum, each run (seed) gives: its mean score over the five human levels and on
each generated test set (the study's protocol), and where the UED protocol evaluated it
(``gvgai_pcg.evaluation.ued``), its solved rate, mean score and bias-corrected score CVaR at
alpha 1 % and 10 % on the UED levels, and with the tail protocol's records the win-rate CVaR at
1 % and 10 % too (SFL's headline; shown and judged only where a run has it). Every cell of the
tables is a mean over seeds with its 95 % Student t interval over seeds
(``gvgai_pcg.study.verdicts.intervals``).

The question is three comparisons of each curriculum with PPCG per game (``QUESTIONS``; five
with the tail protocol's win-rate CVaRs): the difference of means with its Welch t interval,
Holm's correction over every comparison of the page together (family-wise alpha 0.05). "beats
PPCG" **holds** when Holm rejects "no difference" with the curriculum ahead, **does not hold**
when it rejects with PPCG ahead, or when every seed of both is the same value and the curriculum
is not ahead (no spread: equal, or behind, on every seed), and is **inconclusive** otherwise;
**not measured** where either side lacks the metric.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.evaluator import read_records, run_results_path
from gvgai_pcg.study.verdicts.claim_rules import Comparison
from gvgai_pcg.study.verdicts.intervals import ALPHA, LEVEL, MOST_SEEDS, POWER, Estimate, estimate
from gvgai_pcg.study.verdicts.judging import (
    AGAINST,
    CLAIM,
    DOES_NOT_HOLD,
    HOLDS,
    INCONCLUSIVE,
    UNDECIDED,
    decide,
)
from gvgai_pcg.study.verdicts.table1 import GENERATED_SETS, HUMAN_SETS

BASELINE = "PPCG"
# the tables' row order, by curriculum (``regimen``): the comparison's, others after
REGIMEN_ORDER = ("pcg", "ppcg", "dr", "plr", "accel", "sfl")
# Controls (gvgai_pcg.study.sweeps.conditions.CURRICULA_CONTROLS): shown in the tables, never judged
# against the baseline, so that they do not widen Holm's family of the comparison's questions.
CONTROL_REGIMENS = frozenset({"accel-noselect"})
ALPHAS = (0.01, 0.1)
# The UED metrics of a run: key -> (column title, how it is read from a summary).
UED_METRICS = {
    "solved": "UED solved rate",
    "ued_score": "UED mean score",
    "cvar1": "UED score CVaR 1 %",
    "cvar10": "UED score CVaR 10 %",
}
# The tail protocol's win-rate CVaR (SFL's headline), shown and judged where a run has it: the first
# protocol's one-episode win ranking is a tie over most of the tail, so its records leave it out.
WIN_METRICS = {
    "wincvar1": "UED win-rate CVaR 1 %",
    "wincvar10": "UED win-rate CVaR 10 %",
}
# The question's comparisons with PPCG: metric -> what it says.
QUESTIONS = {
    "human": "the human levels (mean score over levels 0-4)",
    "cvar1": "the worst 1 % of the UED levels (score CVaR, bias-corrected)",
    "cvar10": "the worst 10 % of the UED levels (score CVaR, bias-corrected)",
    "wincvar1": "the worst 1 % of the UED levels by win rate (SFL's CVaR, 10 + 10 episodes)",
    "wincvar10": "the worst 10 % of the UED levels by win rate (SFL's CVaR, 10 + 10 episodes)",
}
NOT_MEASURED = "not measured"  # the other verdict words are the claims' (``judging``)


@dataclass
class CurriculumRuns:
    """One curriculum on one game: per metric, one value per seed (run)."""

    label: str
    regimen: str = ""
    frames: list[int] = field(default_factory=list)
    values: dict[str, list[float]] = field(default_factory=dict)

    def add(self, metric: str, value: float) -> None:
        self.values.setdefault(metric, []).append(float(value))


@dataclass(frozen=True)
class Verdict:
    """One comparison of a curriculum with PPCG on one game and metric."""

    game: str
    label: str
    metric: str
    outcome: str
    difference: Estimate | None = None
    adjusted_p: float = math.nan
    decides: str = ""  # inconclusive: what would decide it (``intervals.seeds_to_decide``)


def ued_values(summary: dict) -> dict[str, float]:
    """The UED metrics of one run from its summary (``UEDSummary.as_dict()``)."""
    values = {"solved": summary["solved_rate"], "ued_score": summary["mean_score"]}
    tail = summary.get("rank_episodes") is not None  # the tail protocol's record
    for cvar in summary.get("cvars", []):
        if float(cvar["alpha"]) not in ALPHAS:
            continue
        percent = round(float(cvar["alpha"]) * 100)
        if cvar["metric"] == "score":
            values[f"cvar{percent}"] = cvar["corrected"]
        elif cvar["metric"] == "solved" and tail:
            values[f"wincvar{percent}"] = cvar["corrected"]
    return values


def _measured(games: dict[str, dict[str, CurriculumRuns]]) -> set[str]:
    return {metric for curricula in games.values() for runs in curricula.values() for metric in runs.values}


def questions_of(games: dict[str, dict[str, CurriculumRuns]]) -> dict[str, str]:
    """The questions asked of these runs: every one but the win-rate CVaRs no run has."""
    measured = _measured(games)
    return {m: what for m, what in QUESTIONS.items() if m not in WIN_METRICS or m in measured}


def ued_record(run: Path, settings: dict) -> tuple[Path, dict] | None:
    """The newest UED record in ``run/eval`` whose protocol has ``settings``: its ``ued-*.json``
    path (the per-level CSV shares its stem) and its contents, read as data: the page needs no
    ``gvgai_pcg.evaluation.ued``."""
    found = []
    for path in sorted((run / "eval").glob("ued-*.json")):
        record = json.loads(path.read_text())
        protocol = record.get("protocol", {})
        if "summary" in record and all(protocol.get(k) == v for k, v in settings.items()):
            found.append((int(record.get("frames", 0)), path, record))
    if not found:
        return None
    _, path, record = max(found, key=lambda item: item[0])
    return path, record


def read_ued_summary(run: Path, settings: dict) -> dict | None:
    """The summary of ``ued_record``'s record, or None."""
    found = ued_record(run, settings)
    return found[1]["summary"] if found else None


def collect_runs(
    runs: Iterable[Path], protocol, ued_settings: dict, ued_summaries: Mapping[Path, dict] | None = None
) -> dict[str, dict[str, CurriculumRuns]]:
    """``game -> label -> CurriculumRuns`` from run directories with the study protocol's records
    (runs without are left out) and, where present, UED summaries: a run's in ``ued_summaries``
    (by its path, as just evaluated), else its newest record with ``ued_settings``."""
    games: dict[str, dict[str, CurriculumRuns]] = {}
    for path in sorted(runs):
        info = run_info(path)
        results = run_results_path(info.path, protocol)
        if not results.is_file():
            continue
        records = read_records(results)
        entry = games.setdefault(info.game, {}).setdefault(
            info.label, CurriculumRuns(info.label, info.regimen["name"])
        )
        entry.frames.append(int(records[0].frames))
        set_means = {}
        for test_set in {record.test_set for record in records}:
            scores = [s for record in records if record.test_set == test_set for s in record.scores]
            set_means[test_set] = sum(scores) / len(scores)
        human = [set_means[s] for s in HUMAN_SETS if s in set_means]
        if human:
            entry.add("human", sum(human) / len(human))
        for test_set in GENERATED_SETS:
            if test_set in set_means:
                entry.add(test_set, set_means[test_set])
        summary = (ued_summaries or {}).get(Path(info.path))
        if summary is None and ued_settings:
            summary = read_ued_summary(info.path, ued_settings)
        for metric, value in (ued_values(summary) if summary else {}).items():
            entry.add(metric, value)
    return games


def judge(games: dict[str, dict[str, CurriculumRuns]], baseline: str = BASELINE) -> list[Verdict]:
    """Every curriculum against ``baseline`` on every game and question, one family for Holm: each
    is the claim "the curriculum's mean is above the baseline's", judged as the study's claims are
    (``judging.decide``: decided on its side, against it, which includes no spread on either side
    with the curriculum not ahead, or undecided with the seeds that would decide it)."""
    verdicts: list[Verdict] = []
    tested: list[tuple[int, Comparison]] = []
    for game, curricula in sorted(games.items()):
        base = curricula.get(baseline)
        for label, runs in sorted(curricula.items()):
            if label == baseline or runs.regimen in CONTROL_REGIMENS:
                continue
            for metric in questions_of(games):
                ours, theirs = runs.values.get(metric), base.values.get(metric) if base else None
                if not ours or not theirs:
                    verdicts.append(Verdict(game, label, metric, NOT_MEASURED))
                    continue
                tested.append(
                    (len(verdicts), Comparison(metric, tuple(ours), tuple(theirs), 0.0, above=True))
                )
                verdicts.append(Verdict(game, label, metric, INCONCLUSIVE))
    outcomes = {CLAIM: HOLDS, AGAINST: DOES_NOT_HOLD, UNDECIDED: INCONCLUSIVE}
    for (i, _), decision in zip(tested, decide([c for _, c in tested]), strict=True):
        v = verdicts[i]
        decides = ""
        if decision.need is not None and decision.value.has_interval:
            seeds, why = decision.need
            decides = why or (
                f"about {seeds} seeds each would decide it at {POWER * 100:.0f} % power, if the means and "
                "spreads seen held"
            )
        verdicts[i] = Verdict(
            v.game, v.label, v.metric, outcomes[decision.side], decision.value, decision.adjusted_p, decides
        )
    return verdicts


def cell(values: Sequence[float] | None) -> str:
    """``mean [low, high]`` over seeds (95 % t), or the mean and its one seed, or ``-``."""
    if not values:
        return "-"
    value = estimate(values, None, 0.0)
    if not value.has_interval:
        return f"{value.value:.2f} (1 seed)"
    return f"{value.value:.2f} [{value.low:.2f}, {value.high:.2f}]"


def _difference_text(verdict: Verdict) -> str:
    d = verdict.difference
    if d is None:
        return "no data on one side"
    if not d.has_interval:
        return f"difference {d.value:+.2f}, one seed: no interval, Holm p {verdict.adjusted_p:.3g}"
    interval = f"{LEVEL * 100:.0f} % Welch t interval [{d.low:+.2f}, {d.high:+.2f}]"
    decides = f"; {verdict.decides}" if verdict.decides else ""
    return f"difference {d.value:+.2f}, {interval}, Holm p {verdict.adjusted_p:.3g}{decides}"


def answer_sentences(
    verdicts: Sequence[Verdict], labels: dict[str, str] | None = None, baseline: str = BASELINE
) -> list[str]:
    """The question's answer per game and question, then each curriculum's verdict with its
    interval, as sentences (each compared with ``baseline``)."""
    lines: list[str] = []
    by_game: dict[str, list[Verdict]] = {}
    for v in verdicts:
        by_game.setdefault(v.game, []).append(v)
    asked = {v.metric for v in verdicts}
    for game, ours in sorted(by_game.items()):
        for metric, what in QUESTIONS.items():
            of_metric = [v for v in ours if v.metric == metric]
            if metric not in asked:
                continue
            winners = [v.label for v in of_metric if v.outcome == HOLDS]
            open_ = [v.label for v in of_metric if v.outcome == INCONCLUSIVE]
            if winners:
                head = f"yes: {', '.join(winners)} beat{'s' if len(winners) == 1 else ''} {baseline}"
            elif open_:
                head = f"none shown to beat {baseline} at this budget ({', '.join(open_)} inconclusive)"
            elif all(v.outcome == NOT_MEASURED for v in of_metric):
                head = "not measured"
            else:
                head = f"no: none beats {baseline}"
            lines.append(f"- **{game.capitalize()}, on {what}**: {head}.")
            for v in of_metric:
                lines.append(f"  - {v.label} beats {baseline}: **{v.outcome}** ({_difference_text(v)}).")
    return lines


def _order(runs: CurriculumRuns) -> tuple[int, str]:
    rank = REGIMEN_ORDER.index(runs.regimen) if runs.regimen in REGIMEN_ORDER else len(REGIMEN_ORDER)
    return rank, runs.label


def tables_markdown(games: dict[str, dict[str, CurriculumRuns]]) -> str:
    """Per game, each curriculum's scores (study protocol) and UED metrics over seeds."""
    measured = _measured(games)
    wins = {m: title for m, title in WIN_METRICS.items() if m in measured}
    columns = {"human": "human levels 0-4", **{s: f"test {s}" for s in GENERATED_SETS}, **UED_METRICS, **wins}
    out = []
    for game, curricula in sorted(games.items()):
        out += [f"#### {game.capitalize()}", ""]
        out.append("| curriculum | runs | frames | " + " | ".join(columns.values()) + " |")
        out.append("|---|---:|---:|" + "---:|" * len(columns))
        for runs in sorted(curricula.values(), key=_order):
            frames = f"{min(runs.frames):,}" + (
                "" if min(runs.frames) == max(runs.frames) else f"-{max(runs.frames):,}"
            )
            cells = " | ".join(cell(runs.values.get(metric)) for metric in columns)
            out.append(f"| {runs.label} | {len(runs.frames)} | {frames} | {cells} |")
        out.append("")
    return "\n".join(out)


def comparison_markdown(games: dict[str, dict[str, CurriculumRuns]], baseline: str = BASELINE) -> str:
    """The tables, then the answer: what ``report/curricula.md`` and the page's block hold (and,
    against any ``baseline`` label, ``gvgai-pcg report --ued``'s ``ued.md``)."""
    verdicts = judge(games, baseline)
    tested = sum(v.outcome != NOT_MEASURED for v in verdicts)
    return "\n".join(
        [
            "Scores are raw game scores (mean over each run's episodes, then over seeds); each cell is the",
            f"mean over seeds with its {LEVEL * 100:.0f} % Student t interval over seeds in brackets.",
            "",
            tables_markdown(games),
            f"#### Does any curriculum beat {baseline}?",
            "",
            f"Each curriculum against {baseline} per game: the difference of means with its "
            f"{LEVEL * 100:.0f} % Welch t interval over seeds; Holm's correction over all {tested} "
            "comparisons together "
            f"(family-wise alpha {ALPHA:.2f}). holds: decided with the curriculum ahead; does not hold: "
            f"decided with {baseline} ahead, or no spread on either side and the curriculum not ahead; "
            "inconclusive: not decided, with the seeds per side that would decide it with "
            f"{POWER * 100:.0f} % power (the noncentral t power of the one-sided Welch t test in the "
            f"direction seen, at half of Bonferroni's alpha / {tested}: decided there, Holm decides it "
            f"whatever the others do) if the means and spreads seen held ({MOST_SEEDS} at most).",
            "",
            *answer_sentences(verdicts, baseline=baseline),
            "",
        ]
    )
