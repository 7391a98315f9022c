"""The evaluation protocol of the study (GENERATORS.md §4), with its counts as settings.

Test sets, in the report's column order: ``pcg0.5`` and ``pcg1`` (the frozen generated levels,
each played ``test_episodes`` times, once in the study) and ``lv0`` … ``lv4`` (the human levels,
each played ``human_episodes`` times, 30 in the study); 2000 steps per episode; actions sampled
from the policy (``greedy`` is our addition, the study had none). A run that trained on a set
of levels of its own (``regimen=levels``, ``regimen=pcg`` with ``num_levels``) also plays that
set, as its ``train`` test set (``training_test_set``): train against test is its
generalisation gap.

Two sizes of generated test sets: ``test_sets="study"`` (the 30 frozen levels per difficulty, as in
the study) and ``test_sets="large"`` (the 100 frozen levels of ``gvgai_pcg.levels.large_test_sets``,
for less level-sampling error: ``LARGE_PROTOCOL``). The study size is left out of ``as_dict`` and so
of ``key``, so a study-sized protocol names the same results file as before the option existed,
and a large one another file beside it.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass

from gvgai_pcg.levels import Level, human_levels
from gvgai_pcg.levels.large_test_sets import LARGE_SET_SIZE, frozen_large_test_set
from gvgai_pcg.levels.test_sets import TEST_DIFFICULTIES, TEST_SET_SIZE, frozen_test_set, set_name

HUMAN_SETS = tuple(f"lv{i}" for i in range(5))
# Bumped when the same settings would give other results (2: per-env seeds and action draws, so
# that a level's result does not depend on the rest of the batch); part of ``Protocol.key``, so
# results cached under an older method are not reused.
METHOD_VERSION = 2
TEST_SETS = tuple(set_name(d) for d in TEST_DIFFICULTIES) + HUMAN_SETS
TRAINING_SET = "train"  # a run's own training levels (a level set, a finite generated set)
# The sizes of frozen generated test sets: levels per difficulty.
TEST_SET_SIZES = {"study": TEST_SET_SIZE, "large": LARGE_SET_SIZE}


@dataclass(frozen=True)
class Protocol:
    """How many levels and episodes, how long, and how actions are chosen."""

    test_levels: int = TEST_SET_SIZE  # levels used of each frozen generated test set (30)
    test_episodes: int = 1  # episodes per generated test level
    human_episodes: int = 30  # episodes per human level
    max_steps: int = 2000
    greedy: bool = False  # argmax instead of sampling (not in the study)
    seed: int = 0  # seeds the env and the action sampling
    test_sets: str = "study"  # which frozen generated sets: "study" (30 levels) or "large" (100)

    def __post_init__(self) -> None:
        if self.test_sets not in TEST_SET_SIZES:
            raise ValueError(f"test_sets must be one of {', '.join(TEST_SET_SIZES)}, got {self.test_sets!r}")
        size = TEST_SET_SIZES[self.test_sets]
        if not 1 <= self.test_levels <= size:
            raise ValueError(
                f"test_levels must be in 1..{size} with test_sets={self.test_sets}, got {self.test_levels}"
            )
        for name in ("test_episodes", "human_episodes", "max_steps"):
            if getattr(self, name) < 0 or (name == "max_steps" and self.max_steps < 1):
                raise ValueError(f"{name} must be positive, got {getattr(self, name)}")

    def as_dict(self) -> dict:
        """The settings; ``test_sets`` only when not the study's, so study-sized keys never change."""
        settings = asdict(self)
        if self.test_sets == "study":
            del settings["test_sets"]
        return settings

    @property
    def key(self) -> str:
        """A short stable id of these settings (names cached results and result files)."""
        text = json.dumps({**self.as_dict(), "method": METHOD_VERSION}, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:10]


@dataclass(frozen=True)
class EvalSet:
    """One column of the report: its levels and how often each is played."""

    name: str
    levels: tuple[Level, ...]
    episodes: int


LARGE_PROTOCOL = Protocol(test_levels=LARGE_SET_SIZE, test_sets="large")


def generated_test_set(game: str, difficulty: float, test_sets: str = "study") -> tuple[Level, ...]:
    """The frozen generated levels of ``game`` at ``difficulty``, of the named size."""
    return (
        frozen_large_test_set(game, difficulty) if test_sets == "large" else frozen_test_set(game, difficulty)
    )


def protocol_test_sets(game: str, protocol: Protocol) -> list[EvalSet]:
    """The test sets of ``game`` in column order (a set with 0 episodes is left out)."""
    sets = [
        EvalSet(
            set_name(d),
            generated_test_set(game, d, protocol.test_sets)[: protocol.test_levels],
            protocol.test_episodes,
        )
        for d in TEST_DIFFICULTIES
    ]
    sets += [
        EvalSet(name, (level,), protocol.human_episodes)
        for name, level in zip(HUMAN_SETS, human_levels(game), strict=True)
    ]
    return [s for s in sets if s.episodes > 0]


def training_test_set(levels: Sequence[Level], protocol: Protocol) -> EvalSet | None:
    """A run's own training levels as its ``train`` test set: the first ``test_levels`` of them,
    each played often enough that the set has as many episodes as a generated test set
    (``test_levels * test_episodes``); ``None`` when that is no episode."""
    levels = tuple(levels[: protocol.test_levels])
    episodes = protocol.test_levels * protocol.test_episodes
    if not levels or episodes == 0:
        return None
    return EvalSet(TRAINING_SET, levels, math.ceil(episodes / len(levels)))
