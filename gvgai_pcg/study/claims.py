"""The study's claims, tested on our runs: each one holds, does not hold, or is inconclusive.

Every verdict comes from the evaluation records and training logs of the runs (a results folder
of ``gvgai-pcg reproduce``, published or not) by a rule stated next to it, so that anyone can
recompute it. Scores are compared *normalised*, ``(score - random) / (max - random)`` per test
set, and differences count when they exceed two standard errors: across seeds where a condition
has two or more, else across episodes (which leaves out the seed-to-seed spread: marked).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

GENERATED_SETS = ("pcg0.5", "pcg1")
HUMAN_SETS = tuple(f"lv{i}" for i in range(5))
NEAR = 0.2  # "near the maximum" / "near random": within a fifth of the max-random gap
MARGINAL = 0.15  # "only marginally better": a normalised gain below this
LARGE_SHARE = 0.25  # "a large share" of levels won


@dataclass
class SetResult:
    """One condition on one test set: per-seed mean scores and win rates, all episode scores."""

    seed_means: list[float] = field(default_factory=list)
    seed_wins: list[float] = field(default_factory=list)
    scores: list[float] = field(default_factory=list)

    @property
    def mean(self) -> float:
        return sum(self.seed_means) / len(self.seed_means)

    @property
    def win_rate(self) -> float:
        return sum(self.seed_wins) / len(self.seed_wins)

    def standard_error(self) -> tuple[float, bool]:
        """The standard error of ``mean`` and whether it is across seeds (else across episodes)."""
        values, by_seed = (self.seed_means, True) if len(self.seed_means) > 1 else (self.scores, False)
        if len(values) < 2:
            return math.inf, by_seed
        mean = sum(values) / len(values)
        variance = sum((v - mean) ** 2 for v in values) / (len(values) - 1)
        return math.sqrt(variance / len(values)), by_seed


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

    def normalised(self, label: str, test_set: str) -> tuple[float, float, bool]:
        """Normalised mean score of a condition on a set, its standard error, and whether the
        error is across seeds."""
        result = self.conditions[label][test_set]
        gap = self.maximum[test_set] - self.random[test_set]
        gap = gap if gap > 0 else 1.0
        se, by_seed = result.standard_error()
        return (result.mean - self.random[test_set]) / gap, se / gap, by_seed


@dataclass
class Verdict:
    claim: str
    verdict: str  # "holds", "does not hold", "inconclusive", "not run"
    evidence: str


def collect(
    runs: Iterable[Path], random_cache: Path | None, protocol, target_frames: int | None = None
) -> dict[str, GameResults]:
    """Every game's results from run directories (their evaluation records for ``protocol``, and
    for PPCG the highest difficulty in their logs); runs without records are left out. With
    ``target_frames``, a condition with runs at the target is judged on those alone: a later
    seed still training would otherwise pull its mean back (its frames go to ``training``)."""
    from gvgai_pcg.evaluation.checkpoints import run_info
    from gvgai_pcg.evaluation.evaluator import random_results_path, read_records, run_results_path
    from gvgai_pcg.rl.run_log import read_log

    evaluated = []
    for path in runs:
        info = run_info(path)
        results_path = run_results_path(info.path, protocol)
        if results_path.is_file():
            evaluated.append((info, read_records(results_path)))
    finished = {
        (info.game, info.label)
        for info, records in evaluated
        if target_frames is not None and int(records[0].frames) >= target_frames
    }
    games: dict[str, GameResults] = {}
    for info, records in evaluated:
        frames = int(records[0].frames)  # of the model the records were made from
        if info.game not in games:
            random_path = random_results_path(info.game, protocol, random_cache)
            baseline = read_records(random_path) if random_path.is_file() else []
            games[info.game] = GameResults(
                info.game, {}, {}, _set_means(baseline, "scores"), _set_means(records, "max_score"), {}
            )
        game = games[info.game]
        if (info.game, info.label) in finished and frames < target_frames:
            game.training.setdefault(info.label, []).append(frames)
            continue
        game.frames.setdefault(info.label, []).append(frames)
        sets = game.conditions.setdefault(info.label, {})
        for test_set in {record.test_set for record in records}:
            of_set = [record for record in records if record.test_set == test_set]
            scores = [score for record in of_set for score in record.scores]
            wins = [win for record in of_set for win in record.wins]
            result = sets.setdefault(test_set, SetResult())
            result.seed_means.append(sum(scores) / len(scores))
            result.seed_wins.append(sum(wins) / len(wins))
            result.scores.extend(scores)
        if info.regimen["name"] == "ppcg" and (info.path / "log.csv").is_file():
            difficulties = [row["difficulty"] for row in read_log(info.path / "log.csv")]
            game.max_difficulty.setdefault(info.label, []).append(max(difficulties, default=0.0))
    return games


def _set_means(records, attribute: str) -> dict[str, float]:
    """The mean of a record attribute (``scores``: every episode; ``max_score``: every level) per set."""
    values: dict[str, list[float]] = {}
    for record in records:
        value = getattr(record, attribute)
        values.setdefault(record.test_set, []).extend(value if isinstance(value, list) else [value])
    return {test_set: sum(v) / len(v) for test_set, v in values.items()}


def _compare(game: GameResults, a: str, b: str, test_set: str) -> tuple[float, float, bool]:
    """Normalised ``a - b`` on a set, two standard errors of it, and whether both are by seed."""
    na, sa, seeds_a = game.normalised(a, test_set)
    nb, sb, seeds_b = game.normalised(b, test_set)
    return na - nb, 2 * math.sqrt(sa**2 + sb**2), seeds_a and seeds_b


def _seed_note(by_seed: bool) -> str:
    return "" if by_seed else " (errors across episodes: one seed)"


def one_level_overfits(game: GameResults) -> Verdict:
    claim = "A policy trained on one human level scores near the maximum there and near random on the others."
    lines, verdicts = [], []
    for level in (0, 4):
        label = f"Lv {level}"
        if label not in game.conditions:
            continue
        own, _, _ = game.normalised(label, f"lv{level}")
        others = [game.normalised(label, s)[0] for s in HUMAN_SETS if s != f"lv{level}"]
        near_max, near_random = own >= 1 - NEAR, all(o <= NEAR for o in others)
        # generalising to the other levels refutes it; falling short of the max on its own level
        # only says the run has not converged
        verdicts.append("does not hold" if not near_random else "holds" if near_max else "inconclusive")
        lines.append(
            f"{label}: {own:.2f} of the way from random to max on level {level}; "
            f"on the others {', '.join(f'{o:.2f}' for o in others)}"
        )
    if not verdicts:
        return Verdict(claim, "not run", "no Lv 0 / Lv 4 runs")
    verdict = verdicts[0] if len(set(verdicts)) == 1 else "inconclusive"
    return Verdict(claim, verdict, "; ".join(lines) + f" (near: within {NEAR} of the gap)")


def four_levels_marginal(game: GameResults) -> Verdict:
    claim = "Lv 0-3 does only marginally better than Lv 0 on the held-out level 4 and on generated levels."
    if not {"Lv 0-3", "Lv 0"} <= set(game.conditions):
        return Verdict(claim, "not run", "needs Lv 0-3 and Lv 0")
    lines, outcomes, by_seed = [], [], True
    for test_set in ("lv4", *GENERATED_SETS):
        diff, two_se, seeds = _compare(game, "Lv 0-3", "Lv 0", test_set)
        by_seed &= seeds
        lines.append(f"{test_set}: {diff:+.2f} ± {two_se:.2f}")
        outcomes.append(
            "large" if diff - two_se > MARGINAL else "marginal" if diff + two_se <= MARGINAL else "?"
        )
    verdict = (
        "does not hold"
        if "large" in outcomes
        else "holds"
        if all(o == "marginal" for o in outcomes)
        else "inconclusive"
    )
    return Verdict(claim, verdict, "normalised gain, " + "; ".join(lines) + _seed_note(by_seed))


def generated_generalise(game: GameResults) -> Verdict:
    claim = (
        "Training on generated levels generalises better to held-out generated levels than training on "
        "human ones."
    )
    generated = [c for c in game.conditions if c.startswith(("PCG", "PPCG"))]
    human = [c for c in game.conditions if c.startswith("Lv")]
    if not generated or not human:
        missing = "human-level" if generated else "generated-level"
        return Verdict(
            claim,
            "not run",
            f"no {missing} condition was trained for this game (the study trained only PCG 1 and PPCG "
            "on Solarfox, Frogs and Boulderdash; `reproduce --extra` adds Lv 0, Lv 4, Lv 0-3, PCG 0.5)",
        )
    lines, outcomes, by_seed = [], [], True
    for test_set in GENERATED_SETS:
        best_gen = max(generated, key=lambda c: game.normalised(c, test_set)[0])
        best_hum = max(human, key=lambda c: game.normalised(c, test_set)[0])
        diff, two_se, seeds = _compare(game, best_gen, best_hum, test_set)
        by_seed &= seeds
        lines.append(
            f"{test_set}: best generated {best_gen} vs best human {best_hum}: {diff:+.2f} ± {two_se:.2f}"
        )
        outcomes.append(1 if diff > two_se else -1 if diff < -two_se else 0)
    verdict = (
        "holds" if all(o == 1 for o in outcomes) else "does not hold" if -1 in outcomes else "inconclusive"
    )
    return Verdict(claim, verdict, "normalised, " + "; ".join(lines) + _seed_note(by_seed))


def ppcg_best(game: GameResults) -> Verdict:
    claim = "In Zelda, PPCG is the best condition across generated and human levels."
    if "PPCG" not in game.conditions or len(game.conditions) < 2:
        return Verdict(claim, "not run", "needs PPCG and other conditions")
    lines, outcomes, by_seed = [], [], True
    for test_set in (*GENERATED_SETS, *HUMAN_SETS):
        rivals = [c for c in game.conditions if c != "PPCG" and test_set not in _trained_sets(c)]
        if not rivals:
            continue
        best = max(rivals, key=lambda c: game.normalised(c, test_set)[0])
        diff, two_se, seeds = _compare(game, "PPCG", best, test_set)
        by_seed &= seeds
        lines.append(f"{test_set}: vs {best} {diff:+.2f} ± {two_se:.2f}")
        outcomes.append(1 if diff > two_se else -1 if diff < -two_se else 0 if diff >= 0 else -0.5)
    # holds: never below the best other row, and clearly above it somewhere
    verdict = "inconclusive"
    if -1 in outcomes:
        verdict = "does not hold"
    elif min(outcomes) >= 0 and 1 in outcomes:
        verdict = "holds"
    return Verdict(
        claim,
        verdict,
        "normalised, PPCG minus the best other held-out row: " + "; ".join(lines) + _seed_note(by_seed),
    )


def _trained_sets(label: str) -> tuple[str, ...]:
    if label == "Lv 0-3":
        return ("lv0", "lv1", "lv2", "lv3")
    if label.startswith("Lv "):
        return (f"lv{label.split()[1]}",)
    return ()


def frogs_ppcg_wins_hard(game: GameResults) -> Verdict:
    claim = "In Frogs, PPCG wins a large share of the d = 1 held-out levels while PCG 1 wins none."
    if not {"PPCG", "PCG 1"} <= set(game.conditions):
        return Verdict(claim, "not run", "needs PPCG and PCG 1")
    ppcg, pcg = game.conditions["PPCG"]["pcg1"].win_rate, game.conditions["PCG 1"]["pcg1"].win_rate
    holds = ppcg >= LARGE_SHARE and pcg == 0
    fails = ppcg < LARGE_SHARE / 2 or pcg >= LARGE_SHARE
    verdict = "holds" if holds else "does not hold" if fails else "inconclusive"
    return Verdict(
        claim,
        verdict,
        f"win rate on the d = 1 set: PPCG {ppcg:.2f}, PCG 1 {pcg:.2f} (large: >= {LARGE_SHARE})",
    )


def ppcg_stalls(game: GameResults) -> Verdict:
    claim = (
        f"In {game.game.capitalize()}, PPCG never reaches d = 1 in training, and PCG 1 scores higher "
        "than PPCG."
    )
    if not {"PPCG", "PCG 1"} <= set(game.conditions):
        return Verdict(claim, "not run", "needs PPCG and PCG 1")
    reached = game.max_difficulty.get("PPCG", [])
    diffs = [_compare(game, "PCG 1", "PPCG", s) for s in GENERATED_SETS]
    never = bool(reached) and max(reached) < 1.0
    higher = all(d > e for d, e, _ in diffs)
    lower = any(d < -e for d, e, _ in diffs)
    verdict = "holds" if never and higher else "does not hold" if (not never or lower) else "inconclusive"
    evidence = (
        f"highest d reached per PPCG run: {', '.join(f'{d:.2f}' for d in reached)}; PCG 1 minus PPCG, "
        f"normalised: "
        + "; ".join(f"{s}: {d:+.2f} ± {e:.2f}" for s, (d, e, _) in zip(GENERATED_SETS, diffs, strict=True))
    )
    return Verdict(claim, verdict, evidence + _seed_note(all(seeds for *_, seeds in diffs)))


STUDY_LABELS = {
    "zelda": ("Lv 0", "Lv 4", "Lv 0-3", "PCG 0.5", "PCG 1", "PPCG"),
    "solarfox": ("PCG 1", "PPCG"),
    "frogs": ("PCG 1", "PPCG"),
    "boulderdash": ("PCG 1", "PPCG"),
}
USES = {
    "one_level_overfits": ("Lv 0", "Lv 4"),
    "four_levels_marginal": ("Lv 0-3", "Lv 0"),
    "frogs_ppcg_wins_hard": ("PPCG", "PCG 1"),
    "ppcg_stalls": ("PPCG", "PCG 1"),
}


def pending(verdict: Verdict, game: GameResults, uses: Sequence[str], target_frames: int) -> Verdict:
    """``verdict`` marked pending while a condition it rests on is missing or short of
    ``target_frames`` (the evidence on the runs there are is kept)."""
    short = [
        f"{label} {'not evaluated' if label not in game.frames else f'at {min(game.frames[label]):,} frames'}"
        for label in uses
        if label not in game.frames or min(game.frames[label]) < target_frames
    ]
    if not short or verdict.verdict == "not run":
        return verdict
    return Verdict(
        verdict.claim,
        f"pending ({verdict.verdict} so far)",
        f"runs unfinished: {', '.join(short)}. So far: {verdict.evidence}",
    )


def study_claims(
    games: dict[str, GameResults], target_frames: int | None = None
) -> list[tuple[str, Verdict]]:
    """Each claim of the study on the game it is about; with ``target_frames``, a claim whose
    conditions have not all reached it is pending."""
    checks = []
    if "zelda" in games:
        checks += [("zelda", one_level_overfits), ("zelda", four_levels_marginal)]
    checks += [(name, generated_generalise) for name in STUDY_LABELS if name in games]
    if "zelda" in games:
        checks.append(("zelda", ppcg_best))
    if "frogs" in games:
        checks.append(("frogs", frogs_ppcg_wins_hard))
    checks += [(name, ppcg_stalls) for name in ("solarfox", "boulderdash") if name in games]
    verdicts = []
    for name, check in checks:
        game = games[name]
        verdict = check(game)
        if target_frames is not None:
            uses = USES.get(check.__name__, STUDY_LABELS.get(name, tuple(game.conditions)))
            verdict = pending(verdict, game, uses, target_frames)
        verdicts.append((name, verdict))
    return verdicts


def claims_markdown(verdicts: Sequence[tuple[str, Verdict]], games: dict[str, GameResults]) -> str:
    """The verdicts as a Markdown table, with the seeds and frames behind each game."""
    lines = ["| game | claim | verdict | evidence |", "|---|---|---|---|"]
    for game, verdict in verdicts:
        lines.append(f"| {game} | {verdict.claim} | **{verdict.verdict}** | {verdict.evidence} |")
    lines.append("")
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
    return "\n".join(lines) + "\n"
