"""Gymnasium ids ``gvgai_pcg/<Game>-v0`` for every registered game (``<Game>`` is its
``GameSpec.title``), registered when this module is imported.

Gymnasium 1.x loads no plugins by itself, so the ids exist once this module has been imported
(``import gvgai_pcg.envs.gym_registration``), or when an id is written with its module,
``gymnasium.make("gvgai_pcg.envs.gym_registration:gvgai_pcg/Zelda-v0")``. A game registered later
gets its id from ``register_envs()``. Registration only records entry-point strings: the engine
is imported when an env is made. The GVGAI corpus games (``gvgai_pcg.vgdl.corpus_games``) have
their ids even without the corpus folder, so that making one says in one line what to set.
"""

from __future__ import annotations

import gymnasium as gym

from gvgai_pcg.games.registry import get_game_spec, registered_games
from gvgai_pcg.vgdl import corpus_games

NAMESPACE = "gvgai_pcg"
VERSION = 0


def env_id(name: str) -> str:
    """The Gymnasium id of a game, e.g. ``env_id("Zelda") == "gvgai_pcg/Zelda-v0"``."""
    return f"{NAMESPACE}/{name}-v{VERSION}"


def register_envs() -> list[str]:
    """Register every registered game (idempotent); returns the ids. The step limit lives in the
    env itself (``max_steps``), so no TimeLimit wrapper is registered on top of it."""
    ids = []
    games = registered_games()
    titles = [(game, get_game_spec(game).title) for game in games]
    for stem in corpus_games.CORPUS_GAMES:  # their ids say what to set where they are not registered
        if corpus_games.game_name(stem) not in games:
            titles.append((corpus_games.game_name(stem), corpus_games.game_title(stem)))
    for game, name in titles:
        ids.append(env_id(name))
        if env_id(name) in gym.registry:
            continue
        gym.register(
            id=env_id(name),
            entry_point="gvgai_pcg.gym.adapter:GVGAIGymEnv",
            vector_entry_point="gvgai_pcg.gym.vector:GVGAIVectorEnv",
            kwargs={"game": game},
        )
    return ids


ENV_IDS = register_envs()
