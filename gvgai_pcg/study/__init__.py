"""The study end to end: its conditions, budgets, and the pipeline from sweep to published tables."""

from gvgai_pcg.study.conditions import BUDGETS, STUDY_CONDITIONS, Budget, conditions_of
from gvgai_pcg.study.pipeline import reproduce

__all__ = ["BUDGETS", "STUDY_CONDITIONS", "Budget", "conditions_of", "reproduce"]
