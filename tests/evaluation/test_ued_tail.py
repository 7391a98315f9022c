"""The UED tail protocol: separate ranking and scoring episodes, the win-rate CVaR, ties averaged so
that no order of the tied levels decides the tail."""

import json
import random
import statistics

import pytest

from gvgai_pcg.cli import main
from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.ued import (
    UED_SEED_BASE,
    UEDLevelResult,
    UEDProtocol,
    alpha_cvar,
    evaluate_run_ued,
    summarise,
    tail_protocol,
    tail_weights,
)


def _cvar(summary, metric: str, alpha: float):
    return next(c for c in summary.cvars if c.metric == metric and c.alpha == alpha)


def zelda_like_rows(
    levels: int = 1000, rank: int = 10, score: int = 10, seed: int = 0
) -> list[UEDLevelResult]:
    """Levels whose outcomes tie heavily at the worst value, as Zelda's do: a level's win chance is
    0 on 8 % of the levels, else spread over (0, 1]; an episode not won scores -1 or 0 (dies, or
    times out), a won one 2 to 6."""
    draw = random.Random(seed)
    rows = []
    for i in range(levels):
        p_win = 0.0 if draw.random() < 0.08 else draw.random()
        p_die = draw.random()
        wins = [draw.random() < p_win for _ in range(rank + score)]
        scores = [float(draw.randint(2, 6)) if w else (-1.0 if draw.random() < p_die else 0.0) for w in wins]
        rows.append(UEDLevelResult(i, i / (levels - 1), UED_SEED_BASE + i, scores, wins, [100] * len(wins)))
    return rows


def test_tail_weights_share_the_boundary_among_the_tied_levels():
    # ten levels; the worst 30 % is level 4 (strictly worst) and two of the four tied at 1.0
    ranking = [3.0, 1.0, 1.0, 2.0, 0.0, 1.0, 1.0, 5.0, 4.0, 2.0]
    tail = tail_weights(ranking, 0.3)
    assert (tail.k, tail.below, tail.tied) == (3, 1, 4)
    assert tail.weights == {4: 1.0, 1: 0.5, 2: 0.5, 5: 0.5, 6: 0.5}
    scoring = [0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0]
    result = alpha_cvar(ranking, scoring, 0.3, average_ties=True)
    # level 4 scores 0, the tied ones 1, 0, 1, 1 (mean 0.75) share two places: (0 + 2 * 0.75) / 3
    assert result.corrected == pytest.approx(0.5) and (result.below, result.tied) == (1, 4)
    assert result.naive == pytest.approx((0.0 + 2 * 1.0) / 3)
    assert result.interval[0] <= result.corrected <= result.interval[1]


def test_without_ties_the_averaged_cvar_is_the_plain_one():
    ranking = [float(v) for v in (7, 3, 9, 1, 5, 8, 2, 6, 4, 0)]
    scoring = [v + 0.5 for v in ranking]
    plain, averaged = alpha_cvar(ranking, scoring, 0.2), alpha_cvar(ranking, scoring, 0.2, average_ties=True)
    assert averaged.corrected == plain.corrected == pytest.approx(1.0)
    assert (averaged.below, averaged.tied) == (1, 1)


def test_the_win_rate_cvar_ranks_and_scores_with_separate_episodes():
    # four levels, 2 + 2 episodes: level 0 never won; level 1 lost both ranking episodes but won
    # both scoring ones (an unlucky ranking); levels 2 and 3 won every ranking episode
    wins = [[0, 0, 0, 0], [0, 0, 1, 1], [1, 1, 1, 0], [1, 1, 1, 1]]
    rows = [
        UEDLevelResult(i, i / 3, UED_SEED_BASE + i, [float(v) for v in w], [bool(v) for v in w], [9] * 4)
        for i, w in enumerate(wins)
    ]
    summary = summarise(rows, (0.25, 0.5), rank_episodes=2)
    assert summary.rank_episodes == 2 and summary.episodes == 16
    worst = _cvar(summary, "solved", 0.25)  # one place shared by levels 0 and 1: (0 + 1) / 2
    assert (worst.levels, worst.below, worst.tied) == (1, 0, 2)
    assert worst.corrected == pytest.approx(0.5) and worst.naive == 0.0
    half = _cvar(summary, "solved", 0.5)  # both levels fully: their scoring win rates 0 and 1
    assert half.corrected == pytest.approx(0.5) and (half.below, half.tied) == (0, 2)
    assert 0.0 <= half.interval[0] < 0.5 < half.interval[1] <= 1.0


def test_the_tail_no_longer_depends_on_the_tie_breaks_permutation():
    rows = zelda_like_rows()
    never_won = sum(not any(r.wins[:10]) for r in rows)
    assert never_won > 10  # the worst 1 % (10 levels) lies inside a tie, as in Zelda

    # the first protocol: one ranking episode, ties broken by the protocol seed's order
    first = [_cvar(summarise(rows, (0.01,), seed=s), "solved", 0.01).corrected for s in range(40)]
    assert statistics.stdev(first) > 0.05

    # the tail protocol: whatever order the levels come in, the same CVaRs, to rounding
    tail = summarise(rows, (0.01, 0.1), rank_episodes=10)
    shuffle = random.Random(1)
    for _ in range(40):
        order = rows[:]
        shuffle.shuffle(order)
        again = summarise(order, (0.01, 0.1), rank_episodes=10)
        for c, d in zip(tail.cvars, again.cvars, strict=True):
            assert d.corrected == pytest.approx(c.corrected, abs=1e-12) and (d.below, d.tied) == (
                c.below,
                c.tied,
            )

    # and it is the mean of the tie-broken CVaR over the orders of the tied levels
    ranking = [sum(r.wins[:10]) / 10 for r in rows]
    scoring = [sum(r.wins[10:]) / 10 for r in rows]
    broken = [alpha_cvar(ranking, scoring, 0.01, seed=s, proportion=True).corrected for s in range(400)]
    assert statistics.mean(broken) == pytest.approx(_cvar(tail, "solved", 0.01).corrected, abs=0.02)


def test_the_first_protocols_records_keep_their_key():
    # the published curricula records are ued-9b4390cbf2.*: their settings must still name them
    first = UEDProtocol(levels=1000, seeds=2)
    assert first.key == "9b4390cbf2" and not first.tail
    assert first.as_dict() == {"levels": 1000, "seeds": 2, "max_steps": 2000, "greedy": False, "seed": 0}
    tail = tail_protocol()
    assert (tail.levels, tail.rank_episodes, tail.score_episodes, tail.seeds) == (1000, 10, 10, 20)
    assert "seeds" not in tail.as_dict() and tail.key != first.key
    assert UEDProtocol(**tail.as_dict()) == tail  # a record's settings make the same protocol


@pytest.mark.parametrize(
    "settings, culprit",
    [
        ({"rank_episodes": 10}, "rank_episodes and score_episodes go together"),
        ({"rank_episodes": 0, "score_episodes": 10}, "rank_episodes must be at least 1"),
        (
            {"rank_episodes": 10, "score_episodes": 10, "seeds": 2},
            "seeds is rank_episodes \\+ score_episodes",
        ),
    ],
)
def test_bad_tail_settings_are_refused(settings, culprit):
    with pytest.raises(ValueError, match=culprit):
        UEDProtocol(**settings)


def test_tail_protocol_on_a_tiny_run(tiny_run):
    protocol = tail_protocol(levels=4, rank_episodes=2, score_episodes=3, max_steps=10)
    summary, table = evaluate_run_ued(run_info(tiny_run), protocol, progress=False)
    record = json.loads(table.with_suffix(".json").read_text())
    assert record["protocol"]["rank_episodes"] == 2 and "seeds" not in record["protocol"]
    assert summary.episodes == 4 * 5 and summary.rank_episodes == 2
    assert {c.metric for c in summary.cvars} == {"score", "solved"}
    assert all(c.below + c.tied >= 1 for c in summary.cvars)


def test_cli_tail_options(tiny_run, capsys):
    options = [
        "--ued-levels",
        "3",
        "--ued-rank-episodes",
        "2",
        "--ued-score-episodes",
        "2",
        "--max-steps",
        "8",
    ]
    assert main(["evaluate", str(tiny_run), "--ued", *options, "--no-progress"]) == 0
    assert "ranked by 2 episodes per level, scored by the others, ties averaged" in capsys.readouterr().out
    with pytest.raises(SystemExit) as exit_info:
        main(["evaluate", str(tiny_run), "--ued", "--ued-seeds", "2", "--ued-rank-episodes", "2"])
    err = capsys.readouterr().err.strip()
    assert (
        exit_info.value.code == 2
        and "--ued-seeds is the first protocol" in err
        and len(err.splitlines()) == 1
    )
