"""``LevelSignals`` cuts rollouts into level segments and carries episodes across batches."""

from __future__ import annotations

import torch
from tensordict import TensorDict

from gvgai_pcg.curricula.base import Curriculum, CurriculumRun
from gvgai_pcg.curricula.signals import LevelSignals, feedback_for
from gvgai_pcg.envs import LevelSource


def rollout(done: list[list[int]], seeds: list[list[int]], won: list[list[int]] | None = None) -> TensorDict:
    """A ``[B, T]`` rollout with reward 1 every step."""
    done_t = torch.tensor(done, dtype=torch.bool).unsqueeze(-1)
    batch = done_t.shape[:2]
    nxt = {
        "done": done_t,
        "won": torch.tensor(won or done, dtype=torch.bool).unsqueeze(-1),
        "reward": torch.ones(*batch, 1),
        "level_seed": torch.tensor(seeds).unsqueeze(-1),
        "level_difficulty": torch.tensor(seeds, dtype=torch.float64).unsqueeze(-1) / 100,
    }
    return TensorDict({"next": TensorDict(nxt, batch)}, batch)


def test_segments_are_split_at_episode_ends():
    signals = LevelSignals()(
        rollout([[0, 1, 0, 0], [0, 0, 0, 1]], [[5, 5, 6, 6], [9, 9, 9, 9]], won=[[0, 0, 0, 0], [0, 0, 0, 1]]),
        advantage=torch.tensor([[1.0, -1.0, 2.0, 2.0], [0.0, 0.0, 0.0, -4.0]]),
        state_value=torch.ones(2, 4),
        value_target=torch.full((2, 4), 3.0),
    )
    assert signals["env"].tolist() == [0, 0, 1]
    assert signals["level_seed"].tolist() == [5, 6, 9]
    assert signals["level_difficulty"].tolist() == [0.05, 0.06, 0.09]
    assert signals["finished"].tolist() == [True, False, True]
    assert signals["won"].tolist() == [False, False, True]
    assert signals["steps"].tolist() == signals["length"].tolist() == [2, 2, 4]
    assert signals["return"].tolist() == [2.0, 2.0, 4.0]
    assert signals["advantage"].tolist() == [0.0, 2.0, -1.0]
    assert signals["advantage_abs"].tolist() == [1.0, 2.0, 1.0]
    assert signals["advantage_positive"].tolist() == [0.5, 2.0, 0.0]
    assert signals["value_loss"].tolist() == [4.0, 4.0, 4.0]


def test_an_episode_carries_its_return_and_length_into_the_next_batch():
    signals_of = LevelSignals()
    signals_of(rollout([[0, 0, 0]], [[4, 4, 4]]))
    second = signals_of(rollout([[0, 1, 0]], [[4, 4, 8]]))
    assert second["length"].tolist() == [5, 1] and second["return"].tolist() == [5.0, 1.0]
    third = signals_of(rollout([[1, 0, 0]], [[8, 3, 3]]))
    assert third["length"].tolist() == [2, 2] and third["finished"].tolist() == [True, False]


class Plays(LevelSource):
    """A source that learns nothing (``LevelSource``'s defaults)."""

    game = "zelda"

    def next_levels(self, env_indices, episode_seeds, difficulties):
        return []


def run_of(source: LevelSource) -> CurriculumRun:
    """A run of a curriculum whose source is ``source``."""

    class Hands(Curriculum):
        name = "hands"

        def make_source(self, game, section, state=None):
            return source

    return Hands().start("zelda", {})


def test_the_run_gives_signals_only_to_a_source_that_learns():
    seen = []

    class Learns(Plays):
        def observe(self, signals):
            seen.append(len(signals))

    signals = LevelSignals()(rollout([[1]], [[2]]))
    learning, playing = run_of(Learns()), run_of(Plays())
    assert learning.learns and not playing.learns
    learning.observe(signals)
    playing.observe(signals)  # nothing to give it to
    assert seen == [1] and playing.trains_on(signals) is None
    assert not playing.between_updates(None, 0)


def test_feedback_collects_and_observes_for_a_source_that_learns():
    seen = []

    class Learns(Plays):
        def observe(self, signals):
            seen.append(signals["level_seed"].tolist())

    feedback = feedback_for(run_of(Learns()))
    signals = feedback(rollout([[0, 1]], [[3, 3]]), advantage=torch.ones(1, 2))
    assert seen == [[3]] and signals["advantage"].tolist() == [1.0]
    assert feedback_for(run_of(Plays())) is None
