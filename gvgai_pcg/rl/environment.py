"""The training env of each regimen: one natively batched ``GVGAIEnv``, wrapped as its
curriculum says (a ``DifficultyTransform`` for PCG X and PPCG).

The regimens are the registered curricula (``gvgai_pcg.curricula``, shared with the Gymnasium
API). Lv X, Lv 0-3 and ``human`` play human-designed levels, ``levels`` a level set of your own
(a folder or a list of files); PCG X and PPCG play generated levels at the difficulty the
transform writes into the reset tensordict: a new one every episode, or with ``num_levels`` >= 1
(PCG X only) a fixed set of that many; DR a new one at a difficulty drawn every episode.
``training_levels`` names the finite set a regimen trains on, which the evaluation plays as the
run's training set.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from omegaconf import DictConfig
from torchrl.envs import EnvBase

from gvgai_pcg.curricula import get_curriculum
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.difficulty import DifficultyTransform
from gvgai_pcg.envs.level_sources import LevelSource
from gvgai_pcg.levels import Level


def training_source(game: str, regimen: Mapping, state: object = None) -> LevelSource:
    """The level source of a regimen (``regimen``: its config section), around its shared
    ``state`` (``make_difficulty``)."""
    return get_curriculum(regimen["name"]).make_source(game, regimen, state)


def training_levels(game: str, regimen: Mapping, limit: int | None = None) -> list[Level] | None:
    """The finite set of levels a regimen trains on (at most its first ``limit``), ``None`` when
    it draws a new generated level every episode (PPCG, DR, PCG X without ``num_levels``)."""
    return get_curriculum(regimen["name"]).training_levels(game, regimen, limit)


@dataclass
class EnvFactory:
    """A picklable recipe for the training env, so collector workers can build their own.

    ``difficulty`` (the curriculum's shared state: PPCG's ``DifficultyTransform``, or ``None``)
    is shared: every env built by this factory moves the same shared-memory value.
    """

    game: str
    regimen: DictConfig
    num_envs: int
    obs: str
    max_steps: int
    device: str
    seed: int
    difficulty: object = None
    compile_tick: bool = True  # False: a job too short for compiling to pay back ticks eagerly

    def __call__(self, worker: int = 0) -> EnvBase:
        seed = self.seed + 7919 * worker
        source = self.level_source()
        env = GVGAIEnv(
            self.game,
            self.num_envs,
            source,
            self.obs,
            self.max_steps,
            self.device,
            seed,
            compile_tick=self.compile_tick,
        )
        return get_curriculum(self.regimen.name).wrap(env, self.difficulty)

    def level_source(self) -> LevelSource:
        """A level source around the shared state: the training loop calls its ``observe``
        (where it has one) with each batch's ``gvgai_pcg.curricula.signals``."""
        return training_source(self.game, self.regimen, self.difficulty)


def make_difficulty(regimen: DictConfig, game: str) -> DifficultyTransform | None:
    """The curriculum's shared state (PCG X and PPCG: their ``DifficultyTransform``), ``None``
    where it has none."""
    return get_curriculum(regimen.name).make_state(game, regimen)
