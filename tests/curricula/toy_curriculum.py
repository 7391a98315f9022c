"""A curriculum from outside the package: one module (this) plus one yaml (toy_curriculum.yaml).

``toyreplay`` plays a pool of ``pool`` generated levels at ``difficulty``, each resetting env
the pool level that has finished the fewest episodes so far (the ``env``-th fewest), which it
learns from ``observe``: the count lives in shared memory, so every env and worker sees it."""

from __future__ import annotations

from pathlib import Path

import torch

from gvgai_pcg.config import DIFFICULTY, Integer, Text
from gvgai_pcg.curricula import Curriculum
from gvgai_pcg.curricula.state import SharedState
from gvgai_pcg.envs import LevelSource
from gvgai_pcg.generators import generate_level


class ReplayCounts(SharedState):
    """The shared state: finished episodes per pool level (shared with collector workers, kept
    in checkpoints)."""

    def __init__(self, pool: int) -> None:
        super().__init__()
        self.register_shared("finished", torch.zeros(pool, dtype=torch.int64))


class LeastPlayed(LevelSource):
    """The level source: the least played pool levels first."""

    prepare_ahead = False  # it depends on what it has observed

    def __init__(self, game: str, difficulty: float, state: ReplayCounts) -> None:
        self.game, self.state = game, state
        self.levels = [generate_level(game, difficulty, seed) for seed in range(len(state.finished))]

    def next_levels(self, env_indices, episode_seeds, difficulties):
        order = torch.argsort(self.state.finished, stable=True).tolist()
        return [self.levels[order[i % len(order)]] for i in env_indices.tolist()]

    def observe(self, signals) -> None:
        seeds = signals["level_seed"][signals["finished"]]
        with self.state.lock:
            self.state.finished.index_add_(0, seeds, torch.ones_like(seeds))


class ToyReplay(Curriculum):
    name, summary, label = "toyreplay", "a pool of generated levels, least played first", "Toy replay"
    generated = True
    schema = {"name": Text(), "difficulty": DIFFICULTY, "pool": Integer(1, 64), "tag": Text()}
    config = Path(__file__).with_name("toy_curriculum.yaml")

    def make_state(self, game, section):
        return ReplayCounts(int(section["pool"]))

    def make_source(self, game, section, state=None):
        return LeastPlayed(game, float(section["difficulty"]), state or self.make_state(game, section))


CURRICULUM = ToyReplay()
