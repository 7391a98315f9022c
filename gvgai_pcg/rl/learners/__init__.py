"""Learners as plug-ins: the registry (``registry``), what a learner declares (``LearnerSpec``)
and what it implements (``base.Learner``). Built in: A2C (the study's) and PPO."""

from gvgai_pcg.rl.learners.registry import (
    LEARNER_ENTRY_POINT_GROUP,
    get_learner_spec,
    learner_class,
    register_learner,
    registered_learners,
    run_tag,
)
from gvgai_pcg.rl.learners.spec import LearnerSpec

__all__ = [
    "LEARNER_ENTRY_POINT_GROUP",
    "LearnerSpec",
    "get_learner_spec",
    "learner_class",
    "register_learner",
    "registered_learners",
    "run_tag",
]
