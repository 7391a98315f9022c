"""Gymnasium ids ``gvgai_pcg/<Game>-v0`` for the four games, registered when this module is imported.

Gymnasium 1.x loads no plugins by itself, so the ids exist once this module has been imported
(``import gvgai_pcg.envs.gym_registration``), or when an id is written with its module,
``gymnasium.make("gvgai_pcg.envs.gym_registration:gvgai_pcg/Zelda-v0")``. Registration only
records entry-point strings: the engine is imported when an env is made.
"""

from __future__ import annotations

import gymnasium as gym

NAMESPACE = "gvgai_pcg"
VERSION = 0
# Gymnasium name -> game name. The step limit lives in the env itself (max_steps), so no
# TimeLimit wrapper is registered on top of it.
GAMES = {"Zelda": "zelda", "Solarfox": "solarfox", "Frogs": "frogs", "Boulderdash": "boulderdash"}


def env_id(name: str) -> str:
    """The Gymnasium id of a game, e.g. ``env_id("Zelda") == "gvgai_pcg/Zelda-v0"``."""
    return f"{NAMESPACE}/{name}-v{VERSION}"


def register_envs() -> list[str]:
    """Register every game (idempotent); returns the ids."""
    ids = []
    for name, game in GAMES.items():
        ids.append(env_id(name))
        if env_id(name) in gym.registry:
            continue
        gym.register(
            id=env_id(name),
            entry_point="gvgai_pcg.envs.gym_adapter:GVGAIGymEnv",
            vector_entry_point="gvgai_pcg.envs.gym_vector:GVGAIVectorEnv",
            kwargs={"game": game},
        )
    return ids


ENV_IDS = register_envs()
