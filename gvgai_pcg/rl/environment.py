"""The training env of each regimen: one natively batched ``GVGAIEnv``, wrapped in a
``DifficultyTransform`` for the generated-level regimens (PCG X, PPCG).

The regimens are the table of ``gvgai_pcg.envs.regimens`` (shared with the Gymnasium API). Lv X,
Lv 0-3 and ``human`` play human-designed levels, ``levels`` a level set of your own (a folder or a
list of files); PCG X and PPCG play generated levels at the difficulty the transform writes
into the reset tensordict: a new one every episode, or with ``num_levels`` >= 1 (PCG X only) a
fixed set of that many. ``training_levels`` names the finite set a regimen trains on, which
the evaluation plays as the run's training set.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from omegaconf import DictConfig
from torchrl.envs import EnvBase

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.difficulty import DifficultyTransform
from gvgai_pcg.envs.level_sources import LevelSource
from gvgai_pcg.envs.regimens import regimen_curriculum, regimen_kind, regimen_source
from gvgai_pcg.envs.reset_rows import RowResetTransformedEnv
from gvgai_pcg.levels import Level, human_level, human_levels


def training_source(game: str, regimen: Mapping) -> LevelSource:
    """The level source of a regimen (``regimen``: its config section)."""
    name = regimen["name"]
    if regimen_kind(name).generated:
        return regimen_source(
            game,
            name,
            difficulty=float(regimen.get("difficulty", 0.0)),
            num_levels=int(regimen.get("num_levels", 0)),
            start_seed=int(regimen.get("start_seed", 0)),
        )
    return regimen_source(game, name, training_levels(game, regimen))


def training_levels(game: str, regimen: Mapping, limit: int | None = None) -> list[Level] | None:
    """The finite set of levels a regimen trains on (at most its first ``limit``), ``None`` when
    it draws a new generated level every episode (PPCG, PCG X without ``num_levels``)."""
    name = regimen["name"]
    if name == "lv":
        levels = [human_level(game, int(regimen["level"]))]
    elif name == "lv0-3":
        levels = [human_level(game, int(i)) for i in regimen["levels"]]
    elif name == "human":
        levels = human_levels(game)
    elif name == "levels":
        from gvgai_pcg.levels.sets import load_level_set

        levels = load_level_set(game, regimen["path"])
    elif name == "pcg" and int(regimen.get("num_levels", 0)) > 0:
        return training_source(game, regimen).first(
            limit if limit is not None else int(regimen["num_levels"])
        )
    else:
        regimen_kind(name)  # an unknown name is refused with the valid ones
        return None
    return levels if limit is None else levels[:limit]


@dataclass
class EnvFactory:
    """A picklable recipe for the training env, so collector workers can build their own.

    ``difficulty`` (a ``DifficultyTransform`` or ``None``) is shared: every env built by this
    factory moves the same shared-memory value.
    """

    game: str
    regimen: DictConfig
    num_envs: int
    obs: str
    max_steps: int
    device: str
    seed: int
    difficulty: object = None

    def __call__(self, worker: int = 0) -> EnvBase:
        seed = self.seed + 7919 * worker
        source = training_source(self.game, self.regimen)
        env = GVGAIEnv(self.game, self.num_envs, source, self.obs, self.max_steps, self.device, seed)
        if not regimen_kind(self.regimen.name).generated:
            return env
        return RowResetTransformedEnv(env, self.difficulty)


def make_difficulty(regimen: DictConfig, game: str) -> DifficultyTransform | None:
    """The ``DifficultyTransform`` of a generated-level regimen, ``None`` for given levels."""
    return regimen_curriculum(
        game,
        regimen.name,
        difficulty=float(regimen.difficulty if regimen.name == "pcg" else regimen.get("start", 0.0)),
        alpha=float(regimen.get("alpha", 0.01)),
        win_rule=regimen.get("win_rule", "game"),
    )
