"""The training env of each regimen: one natively batched ``GVGAIEnv`` whose level source comes
from the curriculum's run (``CurriculumRun``), wrapped as its curriculum says (a
``DifficultyTransform`` for PCG X and PPCG).

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
from gvgai_pcg.curricula.base import CurriculumRun
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.level_sources import LevelSource
from gvgai_pcg.levels import Level


def training_source(game: str, regimen: Mapping, state: object = None) -> LevelSource:
    """The level source of a regimen (``regimen``: its config section), around its shared
    ``state`` (a ``CurriculumRun``'s)."""
    return get_curriculum(regimen["name"]).make_source(game, regimen, state)


def training_levels(game: str, regimen: Mapping, limit: int | None = None) -> list[Level] | None:
    """The finite set of levels a regimen trains on (at most its first ``limit``), ``None`` when
    it draws a new generated level every episode (PPCG, DR, PCG X without ``num_levels``)."""
    return get_curriculum(regimen["name"]).training_levels(game, regimen, limit)


def curriculum_run(regimen: Mapping, game: str) -> CurriculumRun:
    """A run of the regimen's curriculum (``regimen``: its config section): the one object that
    owns the run's level choice, its shared state made now."""
    return get_curriculum(regimen["name"]).start(game, regimen)


@dataclass
class EnvFactory:
    """A picklable recipe for the training env, so collector workers can build their own.

    ``run`` (the curriculum's run: ``curriculum_run``; one is started when none is given) is
    shared: every env built by this factory takes its level source from it and moves the same
    shared state (PPCG's d, PLR's buffer).
    """

    game: str
    regimen: DictConfig
    num_envs: int
    obs: str
    max_steps: int
    device: str
    seed: int
    run: CurriculumRun | None = None
    compile_tick: bool = True  # False: a job too short for compiling to pay back ticks eagerly

    def __post_init__(self) -> None:
        if self.run is None:
            self.run = curriculum_run(self.regimen, self.game)

    def __call__(self, worker: int = 0) -> EnvBase:
        seed = self.seed + 7919 * worker
        env = GVGAIEnv(
            self.game,
            self.num_envs,
            self.run.source(),
            self.obs,
            self.max_steps,
            self.device,
            seed,
            compile_tick=self.compile_tick,
        )
        return self.run.wrap(env)
