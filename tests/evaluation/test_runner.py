"""An episode's outcome depends on its level and the seed, not on the rest of the batch."""

import pytest
import torch

from gvgai_pcg.evaluation import RandomAgent, play_episodes
from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.evaluation.runner import episode_seeds, sample_actions
from gvgai_pcg.levels import human_level


def _outcomes(results) -> list[tuple[float, int, bool]]:
    return list(zip(results.scores.tolist(), results.lengths.tolist(), results.wins.tolist(), strict=True))


def _play(levels, policy) -> list[tuple[float, int, bool]]:
    game = levels[0].game
    return _outcomes(play_episodes(game, levels, policy, max_steps=300, seed=3, progress=False))


@pytest.mark.parametrize("agent", ["random", "trained"])
def test_a_levels_episodes_do_not_depend_on_the_rest_of_the_batch(agent, tiny_run):
    # Frogs' random episodes are short and varied; the tiny trained run plays Zelda.
    game, policy = ("frogs", RandomAgent(5, seed=0)) if agent == "random" else ("zelda", None)
    policy = policy or load_policy(run_info(tiny_run), seed=0)
    first, second = human_level(game, 0), human_level(game, 3)
    alone = _play([first] * 6, policy)
    assert len(set(alone)) > 1  # the episodes differ
    together = _play([second] * 3 + [first] * 6, policy)
    assert together[3:] == alone
    assert _play([first] * 6 + [second] * 3, policy)[:6] == alone


def test_episode_seeds_follow_the_level_and_its_repeats_not_the_position():
    first, second = human_level("zelda", 0), human_level("zelda", 1)
    seeds = episode_seeds([first, second, first], seed=7).tolist()
    assert seeds[0] != seeds[2] and len(set(seeds)) == 3
    assert episode_seeds([second, first, first], seed=7).tolist() == [seeds[1], seeds[0], seeds[2]]
    assert episode_seeds([first], seed=8).tolist() != seeds[:1]


def test_sampling_by_uniform_draws_follows_the_probabilities():
    probabilities = torch.tensor([[0.2, 0.5, 0.3]]).expand(10_000, 3)
    draws = (torch.arange(10_000, dtype=torch.float64) + 0.5) / 10_000
    counts = torch.bincount(sample_actions(probabilities, draws), minlength=3)
    assert counts.tolist() == [2000, 5000, 3000]
    almost_one = torch.tensor([1.0 - 2**-53])
    assert sample_actions(torch.tensor([[0.5, 0.5, 0.0]]), almost_one).item() == 1  # never p = 0
