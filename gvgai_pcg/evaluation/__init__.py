"""Evaluation: the study's protocol (frozen test sets, human levels, random agent, max score),
played in one batched env per agent, with results as JSON lines."""

from gvgai_pcg.evaluation.human_levels import LevelSummary, evaluate_levels, format_table
from gvgai_pcg.evaluation.random_agent import RandomAgent
from gvgai_pcg.evaluation.runner import EpisodeResults, play_episodes

__all__ = [
    "EpisodeResults",
    "LevelSummary",
    "RandomAgent",
    "evaluate_levels",
    "format_table",
    "play_episodes",
]
