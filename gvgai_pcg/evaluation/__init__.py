"""Evaluation: the study's protocol (frozen test sets, human levels, random agent, max score),
played in one batched env per agent, with results as JSON lines."""

from gvgai_pcg.evaluation.human_levels import LevelSummary, evaluate_levels, format_table
from gvgai_pcg.evaluation.policy import ActorCriticPolicy, load_policy
from gvgai_pcg.evaluation.random_agent import RandomAgent
from gvgai_pcg.evaluation.runner import EpisodeResults, play_episodes

__all__ = [
    "ActorCriticPolicy",
    "EpisodeResults",
    "LevelSummary",
    "RandomAgent",
    "evaluate_levels",
    "format_table",
    "load_policy",
    "play_episodes",
]
