"""Environments: the batched TorchRL env, its level sources and the Gymnasium ids' registration
(the Gymnasium envs themselves live in ``gvgai_pcg.gym``, above the curricula they train on).

Names are loaded on first use (PEP 562), so that ``import gvgai_pcg`` can register the
Gymnasium ids without importing torch.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

_EXPORTS = {
    "OBSERVATION_KINDS": "gvgai_pcg.envs.inputs",
    "GVGAIEnv": "gvgai_pcg.envs.gvgai_env",
    "FixedLevel": "gvgai_pcg.envs.level_sources",
    "GeneratedLevels": "gvgai_pcg.envs.level_sources",
    "GeneratedLevelSet": "gvgai_pcg.envs.level_sources",
    "LevelPerEnv": "gvgai_pcg.envs.level_sources",
    "LevelSource": "gvgai_pcg.envs.level_sources",
    "RandomDifficultyLevels": "gvgai_pcg.envs.level_sources",
    "UniformLevels": "gvgai_pcg.envs.level_sources",
    "as_level_source": "gvgai_pcg.envs.level_sources",
    "DifficultyTransform": "gvgai_pcg.envs.difficulty",
}
__all__ = [
    "OBSERVATION_KINDS",
    "DifficultyTransform",
    "FixedLevel",
    "GVGAIEnv",
    "GeneratedLevelSet",
    "GeneratedLevels",
    "LevelPerEnv",
    "LevelSource",
    "RandomDifficultyLevels",
    "UniformLevels",
    "as_level_source",
]

if TYPE_CHECKING:
    from gvgai_pcg.envs.difficulty import DifficultyTransform
    from gvgai_pcg.envs.gvgai_env import GVGAIEnv
    from gvgai_pcg.envs.inputs import OBSERVATION_KINDS
    from gvgai_pcg.envs.level_sources import (
        FixedLevel,
        GeneratedLevels,
        GeneratedLevelSet,
        LevelPerEnv,
        LevelSource,
        RandomDifficultyLevels,
        UniformLevels,
        as_level_source,
    )


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'gvgai_pcg.envs' has no attribute {name!r}")
    value = getattr(importlib.import_module(_EXPORTS[name]), name)
    globals()[name] = value
    return value
