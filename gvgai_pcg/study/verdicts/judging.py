"""The claims judged: Holm's correction over their comparisons, and what would decide the rest.

On our runs (per-seed values) each comparison gets its two-sided 95 % t interval over seeds
(Welch's for a difference), and Holm's correction runs over every comparison of every claim judged
together (family-wise alpha 0.05, ``gvgai_pcg.study.verdicts.intervals``). With ``level_sampling``, a
comparison that carries per-level values also carries the level-sampling variance of those sets,
from the per-level records (``gvgai_pcg.study.verdicts.intervals``, module docstring); a maximum or minimum
over sets keeps the interval over seeds. On the study's own Table 1 (point estimates) each
comparison is decided by the estimate's side.

A claim **holds** when every comparison is decided on the claim's side (Holm-adjusted p <= 0.05,
so its 95 % interval excludes the bound), **does not hold** when one is decided against it, and
is **inconclusive** otherwise. Claims about training dynamics ("PPCG never reaches d = 1") are
**cannot be tested at this budget** while the runs have fewer frames than the study's.

``decide`` is the one verdict system: the curricula comparison (``gvgai_pcg.study.verdicts.comparison``)
judges "a curriculum beats PPCG" through it too, with the same words, Holm and seeds to decide.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from gvgai_pcg.study.verdicts.claim_rules import Claim, Comparison, claims_of
from gvgai_pcg.study.verdicts.intervals import (
    ALPHA,
    POWER,
    Estimate,
    agents_estimate,
    estimate,
    holm,
    seeds_to_decide,
)
from gvgai_pcg.study.verdicts.results import GameResults, study_table, table_of
from gvgai_pcg.study.verdicts.table1 import TABLE1


@dataclass
class Verdict:
    claim: str
    verdict: (
        str  # "holds", "does not hold", "inconclusive", "not run", "does not apply", "cannot be tested..."
    )
    evidence: str
    comparisons: int = 0  # how many comparisons it counted in Holm's family


def _estimate_text(comparison: Comparison, value: Estimate, adjusted: float | None, note: str = "") -> str:
    """One comparison's evidence; ``note``: said after its claim (what would decide it)."""
    text = f"{comparison.what}: {value.value:+.2f}"
    claim = f"(claim {comparison.claim_text()}{f'; {note}' if note else ''})"
    if value.seeds == 0:
        return f"{text} {claim}"
    if not value.has_interval:
        return f"{text}, no interval (one seed) {claim}"
    if value.low == value.high:  # no t statistic: its p (0 or 1) is a decision, not a test's
        return f"{text}, no spread in the data, so decided without a test {claim}"
    interval = f"[{value.low:+.2f}, {value.high:+.2f}]"
    return f"{text} {interval}, Holm p {adjusted:.3g} {claim}"


HOLDS, DOES_NOT_HOLD, INCONCLUSIVE = "holds", "does not hold", "inconclusive"
CLAIM, AGAINST, UNDECIDED = "claim", "against", "?"  # a comparison's side once judged


@dataclass(frozen=True)
class Decision:
    """One comparison judged within its family: its estimate, Holm-adjusted p (nan for point
    estimates), the side it is decided on, and for an undecided one what would decide it."""

    value: Estimate
    adjusted_p: float
    side: str  # CLAIM, AGAINST or UNDECIDED
    need: tuple[int | None, str] | None = None  # ``intervals.seeds_to_decide``'s answer

    @property
    def on_claim_side(self) -> bool:
        return self.side == CLAIM


def decide(comparisons: Sequence[Comparison], point: bool = False) -> list[Decision]:
    """Every comparison of one family. Per-seed values: Holm's correction over them all, and an
    undecided one's seeds to decide it at Bonferroni's alpha / K (Holm never needs more). Point
    estimates: decided by the estimate's side. Data with no spread that sit on a (strict) claim's
    bound are decided against it without a test."""
    values = [
        agents_estimate(c.agents, c.bound)
        if c.agents and not point
        else estimate(c.a, c.b, c.bound, point, c.levels)
        for c in comparisons
    ]
    adjusted, rejected = holm([v.p for v in values]) if not point else ([math.nan] * len(values), [])
    decisions = []
    for k, (comparison, value) in enumerate(zip(comparisons, values, strict=True)):
        on_claim_side = value.value > comparison.bound if comparison.above else value.value < comparison.bound
        decided = value.value != comparison.bound if point else rejected[k]
        if decided:
            decisions.append(Decision(value, adjusted[k], CLAIM if on_claim_side else AGAINST))
        elif not point and value.has_interval and value.low == value.high:
            decisions.append(Decision(value, adjusted[k], AGAINST))  # no spread, on the bound
        elif point:
            decisions.append(Decision(value, adjusted[k], UNDECIDED))
        else:
            need = (
                (None, "each agent's own episodes, not more seeds, decide it")
                if comparison.agents
                else seeds_to_decide(
                    comparison.a, comparison.b, comparison.bound, ALPHA / len(comparisons), comparison.levels
                )
            )
            decisions.append(Decision(value, adjusted[k], UNDECIDED, need))
    return decisions


def judge(claims: Sequence[Claim], point: bool = False) -> list[Verdict]:
    """Each claim's verdict. Per-seed tables: every comparison of every claim is one family for
    Holm's correction (``decide``). Point estimates: each comparison is decided by the estimate's
    side."""
    tested = [(i, c) for i, claim in enumerate(claims) if not claim.status for c in claim.comparisons]
    decisions = decide([c for _, c in tested], point)
    outcomes: dict[int, list[str]] = {}
    texts: dict[int, list[str]] = {}
    needs: dict[int, list[tuple[int | None, str]]] = {}
    against: dict[int, list[str]] = {}  # undecided comparisons whose estimate lies against the claim
    for (i, comparison), decision in zip(tested, decisions, strict=True):
        value = decision.value
        outcomes.setdefault(i, []).append(decision.side)
        note = ""
        if decision.need is not None:
            needs.setdefault(i, []).append(decision.need)
            note = _need_text(*decision.need)
            on_claim_side = (
                value.value > comparison.bound if comparison.above else value.value < comparison.bound
            )
            if value.value != comparison.bound and not on_claim_side:
                against.setdefault(i, []).append(comparison.what)
                note = f"the estimate lies against the claim; {note}"
        texts.setdefault(i, []).append(
            _estimate_text(comparison, value, None if point else decision.adjusted_p, note)
        )
    verdicts = []
    for i, claim in enumerate(claims):
        if claim.status:
            verdicts.append(Verdict(claim.text, claim.status, claim.reason))
            continue
        outcome = outcomes.get(i, [])
        verdict = (
            DOES_NOT_HOLD
            if AGAINST in outcome
            else HOLDS
            if outcome and set(outcome) == {CLAIM}
            else INCONCLUSIVE
        )
        evidence = "; ".join(texts.get(i, []))
        if verdict == INCONCLUSIVE and needs.get(i):
            evidence += f". Undecided at this budget: {seeds_needed_text(needs[i])}"
            if against.get(i):
                evidence += (
                    f" Where the estimate lies against the claim ({'; '.join(against[i])}), more seeds "
                    "would, at the means seen, decide that it does not hold."
                )
        verdicts.append(Verdict(claim.text, verdict, evidence, len(outcome)))
    return verdicts


def _need_text(seeds: int | None, why: str) -> str:
    """One undecided comparison's projection, short, for its place in the evidence."""
    if seeds is not None:
        return f"{POWER * 100:.0f} % power at about {seeds} seeds"
    if why.startswith("the test sets' level sampling"):
        return "held open by the test sets' level sampling"
    return why


def seeds_needed_text(needs: Sequence[tuple[int | None, str]]) -> str:
    """What would decide a claim's undecided comparisons (``intervals.seeds_to_decide`` each):
    all of them, so the most seeds any needs, or every reason none would."""
    reasons = sorted({why for seeds, why in needs if seeds is None})
    if reasons:
        return "; ".join(reasons) + "."
    most = max(seeds for seeds, _ in needs if seeds is not None)
    return (
        f"about {most} seeds per condition would decide it at {POWER * 100:.0f} % power, if the means "
        "and spreads seen held."
    )


def study_verdicts() -> list[tuple[str, Verdict]]:
    """The rules on the study's own Table 1 (its cells as point estimates): every claim holds."""
    claims = claims_of({game: study_table(game) for game in TABLE1})
    return [(claim.game, verdict) for claim, verdict in zip(claims, judge(claims, point=True), strict=True)]


def pending(verdict: Verdict, game: GameResults, uses: Sequence[str], target_frames: int) -> Verdict:
    """``verdict`` marked pending while a condition it rests on is missing or has a run short of
    its planned frames (``target_frames`` where none are recorded); the evidence so far is kept."""

    def unfinished(label: str) -> bool:
        planned = game.planned.get(label) or [target_frames] * len(game.frames[label])
        return any(f < p for f, p in zip(game.frames[label], planned, strict=True))

    short = [
        f"{label} {'not evaluated' if label not in game.frames else f'at {min(game.frames[label]):,} frames'}"
        for label in uses
        if label not in game.frames or unfinished(label)
    ]
    if not short or verdict.verdict in ("not run", "does not apply"):
        return verdict
    return Verdict(
        verdict.claim,
        f"pending ({verdict.verdict} so far)",
        f"runs unfinished: {', '.join(short)}. So far: {verdict.evidence}",
        verdict.comparisons,
    )


def study_claims(
    games: dict[str, GameResults], target_frames: int | None = None, level_sampling: bool = False
) -> list[tuple[str, Verdict]]:
    """Each claim of the study on the game it is about, judged on our runs (one Holm family);
    with ``target_frames``, a claim whose conditions have not all reached it is pending; with
    ``level_sampling``, intervals include the generated sets' level-sampling variance."""
    claims = claims_of({name: table_of(game, level_sampling) for name, game in games.items()})
    verdicts = []
    for claim, verdict in zip(claims, judge(claims), strict=True):
        uses = [label for label in claim.uses if label in games[claim.game].conditions] or list(claim.uses)
        if target_frames is not None:
            verdict = pending(verdict, games[claim.game], uses, target_frames)
        verdicts.append((claim.game, verdict))
    return verdicts
