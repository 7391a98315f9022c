"""The study end to end: its conditions, budgets, and the pipeline from sweep to published tables.

``reproduce`` (the pipeline, which imports the evaluation and so torch) is loaded on first use:
``gvgai-pcg reproduce`` reads the budgets and conditions for ``--help`` and its refusals without it.
"""

from typing import Any

from gvgai_pcg.study.conditions import BUDGETS, STUDY_CONDITIONS, Budget, conditions_of

__all__ = ["BUDGETS", "STUDY_CONDITIONS", "Budget", "conditions_of", "reproduce"]


def __getattr__(name: str) -> Any:
    if name == "reproduce":
        from gvgai_pcg.study.pipeline import reproduce

        return reproduce
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
