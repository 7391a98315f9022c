"""The study end to end, in three layers and the sweep on top of them.

``sweeps/`` (conditions, budgets, borrowed runs, publishing), ``verdicts/`` (the runs read into
tables, the claims' rules, intervals, one judging system), ``pages/`` (the results pages' blocks,
written from the verdicts); ``pipeline`` runs a sweep from training to its published pages, and
``sweep_status`` says how far one is. The budgets and conditions are named here, so that
``gvgai-pcg reproduce`` reads them for ``--help`` and its refusals without the pipeline (which
imports the evaluation and so torch).
"""

from gvgai_pcg.study.sweeps.conditions import BUDGETS, STUDY_CONDITIONS, Budget, conditions_of

__all__ = ["BUDGETS", "STUDY_CONDITIONS", "Budget", "conditions_of"]
