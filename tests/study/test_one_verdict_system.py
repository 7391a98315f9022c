"""The curricula comparison and the study's claims share one verdict system (``judging.decide``):
the same words, Holm's correction over one family, and the same seeds to decide."""

from __future__ import annotations

from gvgai_pcg.study.verdicts import comparison, judging
from gvgai_pcg.study.verdicts.claim_rules import Claim, Comparison
from gvgai_pcg.study.verdicts.comparison import CurriculumRuns


def _runs(label: str, values: list[float]) -> CurriculumRuns:
    return CurriculumRuns(label, label.lower(), [100] * len(values), {"human": values})


def test_a_curriculum_against_ppcg_is_judged_as_the_claim_that_it_is_above():
    games = {
        "zelda": {
            "PPCG": _runs("PPCG", [1.0, 1.2, 1.1]),
            "DR": _runs("DR", [3.0, 3.1, 2.9]),
            "SFL": _runs("SFL", [1.0, 1.5, 0.8]),
            "PLR": _runs("PLR", [1.0, 1.0, 1.0]),
        }
    }
    base = games["zelda"]["PPCG"].values["human"]
    claims = [
        Claim(
            "zelda", f"{label} beats PPCG", (label,), [Comparison("human", tuple(v), tuple(base), 0.0, True)]
        )
        for label, v in (("DR", [3.0, 3.1, 2.9]), ("PLR", [1.0, 1.0, 1.0]), ("SFL", [1.0, 1.5, 0.8]))
    ]
    judged = judging.judge(claims)
    from_claims = [v.verdict for v in judged]
    from_comparison = [v.outcome for v in comparison.judge(games) if v.metric == "human"]
    assert from_comparison == from_claims == [judging.HOLDS, judging.INCONCLUSIVE, judging.INCONCLUSIVE]
    by_label = {v.label: v for v in comparison.judge(games) if v.metric == "human"}
    assert by_label["SFL"].decides and by_label["SFL"].decides in judged[2].evidence


def test_no_spread_on_the_bound_is_decided_against_a_strict_claim():
    same = (1.0, 1.0, 1.0)
    (decision,) = judging.decide([Comparison("x", same, same, 0.0, True)])
    assert decision.side == judging.AGAINST and decision.need is None
    games = {"frogs": {"PPCG": _runs("PPCG", list(same)), "DR": _runs("DR", list(same))}}
    assert [v.outcome for v in comparison.judge(games) if v.metric == "human"] == [judging.DOES_NOT_HOLD]
