"""The training env of each regimen: one natively batched ``GVGAIEnv``, wrapped in a
``DifficultyTransform`` for the generated-level regimens (PCG X, PPCG).

Lv X and Lv 0-3 play human-designed levels; PCG X and PPCG play a new generated level every
episode at the difficulty the transform writes into the reset tensordict.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from omegaconf import DictConfig
from torchrl.envs import EnvBase

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.reset_rows import RowResetTransformedEnv
from gvgai_pcg.levels import human_level

REGIMENS = ("lv", "lv0-3", "pcg", "ppcg")


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
        name = self.regimen.name
        seed = self.seed + 7919 * worker
        if name in ("lv", "lv0-3"):
            indices = [self.regimen.level] if name == "lv" else list(self.regimen.levels)
            levels = [human_level(self.game, int(i)) for i in indices]
            return GVGAIEnv(self.game, self.num_envs, levels, self.obs, self.max_steps, self.device, seed)
        from gvgai_pcg.envs.level_sources import GeneratedLevels

        env = GVGAIEnv(
            self.game, self.num_envs, GeneratedLevels(self.game), self.obs, self.max_steps, self.device, seed
        )
        return RowResetTransformedEnv(env, self.difficulty)


def make_difficulty(regimen: DictConfig, game: str):
    """The ``DifficultyTransform`` of a generated-level regimen, ``None`` for Lv X / Lv 0-3."""
    if regimen.name not in REGIMENS:
        raise ValueError(f"unknown regimen {regimen.name!r}; valid regimens are: {', '.join(REGIMENS)}")
    if regimen.name in ("lv", "lv0-3"):
        return None
    from gvgai_pcg.envs.difficulty import DifficultyTransform

    if regimen.name == "pcg":
        return DifficultyTransform(
            "fixed", start=float(regimen.difficulty), win_rule=regimen.win_rule, game=game
        )
    return DifficultyTransform(
        "progressive",
        alpha=float(regimen.alpha),
        start=float(regimen.start),
        win_rule=regimen.win_rule,
        game=game,
    )


def share_through_files(difficulty, directory: Path) -> None:
    """Back the transform's buffers by memory-mapped files in ``directory``, so collector worker
    processes (which receive a pickled copy of the factory) read and move the very same
    difficulty as the main process; in-process shared memory does not survive that pickling.
    The files start from the transform's current values (a resumed run's are restored first), and
    a lock file there serialises the moves of all processes."""
    from tensordict import MemoryMappedTensor

    directory.mkdir(parents=True, exist_ok=True)
    for name, buffer in list(difficulty.named_buffers()):
        path = directory / f"{name}.memmap"
        path.unlink(missing_ok=True)  # left by an earlier session of the run
        setattr(difficulty, name, MemoryMappedTensor.from_tensor(buffer, filename=path))
    difficulty.lock_path = directory / "difficulty.lock"
