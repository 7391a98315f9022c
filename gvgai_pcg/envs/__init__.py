"""Environments: the batched TorchRL env and its level sources."""

from gvgai_pcg.envs.gvgai_env import OBSERVATION_KINDS, GVGAIEnv
from gvgai_pcg.envs.level_sources import FixedLevel, LevelPerEnv, LevelSource, UniformLevels, as_level_source

__all__ = [
    "OBSERVATION_KINDS",
    "FixedLevel",
    "GVGAIEnv",
    "LevelPerEnv",
    "LevelSource",
    "UniformLevels",
    "as_level_source",
]
