"""The study's conditions (Table 1's rows) and the budgets to run them at.

A condition is one ``conf/condition/<game>-<regimen>.yaml`` (a game and a regimen); a budget
says which conditions run, with how many seeds, frames and overrides, and with which evaluation
protocol. ``smoke`` tests the pipeline in minutes; ``small`` is what a 2-core machine does over
a few sittings; ``paper`` is the study's own setting, for a GPU or a cluster.
"""

from __future__ import annotations

from dataclasses import dataclass, field

GAMES = ("zelda", "solarfox", "frogs", "boulderdash")
# Table 1 of the study: every regimen on Zelda; PCG 1 and PPCG on the other games (the study
# skipped the rest for lack of compute).
STUDY_CONDITIONS = (
    "zelda-lv0",
    "zelda-lv4",
    "zelda-lv0-3",
    "zelda-pcg0.5",
    "zelda-pcg1",
    "zelda-ppcg",
    "solarfox-pcg1",
    "solarfox-ppcg",
    "frogs-pcg1",
    "frogs-ppcg",
    "boulderdash-pcg1",
    "boulderdash-ppcg",
)
# What the study did not run: the other regimens on Solarfox, Frogs and Boulderdash.
EXTRA_CONDITIONS = tuple(
    f"{game}-{regimen}" for game in GAMES[1:] for regimen in ("lv0", "lv4", "lv0-3", "pcg0.5")
)


@dataclass(frozen=True)
class Budget:
    """How much of the study to run.

    Args:
        name: ``smoke``, ``small`` or ``paper``.
        conditions: the conditions (names of ``conf/condition`` files).
        seeds: the training seeds of every condition.
        frames: training frames per run.
        overrides: Hydra overrides for every run (a preset, the env batch, checkpoints).
        protocol: the evaluation protocol's settings (``gvgai_pcg.evaluation.Protocol``).
    """

    name: str
    conditions: tuple[str, ...]
    seeds: tuple[int, ...]
    frames: int
    overrides: tuple[str, ...] = ()
    protocol: dict = field(default_factory=dict)

    @property
    def runs(self) -> int:
        return len(self.conditions) * len(self.seeds)


BUDGETS = {
    "smoke": Budget(
        "smoke",
        STUDY_CONDITIONS,
        seeds=(0,),
        frames=1_600,
        overrides=(
            "env.num_envs=16",
            "env.max_steps=200",
            "checkpoint.every_frames=800",
            "log.every_episodes=4",
        ),
        protocol={"test_levels": 2, "human_episodes": 1, "max_steps": 100},
    ),
    "small": Budget("small", STUDY_CONDITIONS, seeds=(0, 1, 2), frames=5_000_000),
    # The study: pixels and the Nature CNN, 12 envs, 40M frames (GENERATORS.md §3), 4 seeds.
    "paper": Budget(
        "paper", STUDY_CONDITIONS, seeds=(0, 1, 2, 3), frames=40_000_000, overrides=("preset=paper",)
    ),
}


def conditions_of(budget: Budget, extra: bool = False) -> tuple[str, ...]:
    """The budget's conditions, and the ones the study skipped if ``extra``."""
    return budget.conditions + (EXTRA_CONDITIONS if extra else ())


def known_conditions() -> tuple[str, ...]:
    """Every condition there is a config for (``conf/condition/*.yaml``)."""
    return STUDY_CONDITIONS + EXTRA_CONDITIONS
