"""An episode's outcome depends on its level and the seed, not on the rest of the batch; the
runner asks the policy only for the envs still playing, ticks eagerly where compiling would not
pay back, and gives the records that stepping every env with the policy gave."""

import pytest
import torch

from gvgai_pcg.envs import GVGAIEnv, LevelPerEnv
from gvgai_pcg.evaluation import RandomAgent, play_episodes, runner
from gvgai_pcg.evaluation.checkpoints import run_info
from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.evaluation.runner import (
    SAMPLE_KEY,
    STREAM_ACTIONS,
    EpisodeResults,
    compile_pays_back,
    episode_seeds,
    sample_actions,
)
from gvgai_pcg.games.rng import uniform
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


def _every_env_stepped(game, levels, policy, max_steps, seed) -> EpisodeResults:
    """The runner as it was before its policy was asked for the playing envs alone (2026-11-28):
    the policy acts for every env at every step, finished or not."""
    seeds = episode_seeds(levels, seed).tolist()
    # eager, as compiling takes minutes here; compiled = eager is tested in tests/engine
    env = GVGAIEnv(
        game, len(levels), LevelPerEnv(levels), max_steps=max_steps, seed=seeds, compile_tick=False
    )
    n, seeds = len(levels), env.env_seeds
    scores, lengths = torch.zeros(n), torch.zeros(n, dtype=torch.int64)
    wins, finished = torch.zeros(n, dtype=torch.bool), torch.zeros(n, dtype=torch.bool)
    td = env.reset()
    for step in range(1, max_steps + 1):
        td.set(SAMPLE_KEY, uniform(seeds, torch.full_like(seeds, step), 0, STREAM_ACTIONS))
        td = env.step(td.set("action", policy(td))).get("next")
        done = td.get("done").squeeze(-1) & ~finished
        scores = torch.where(done, td.get("score").squeeze(-1), scores)
        lengths = torch.where(done, torch.full_like(lengths, step), lengths)
        wins = torch.where(done, td.get("won").squeeze(-1), wins)
        finished |= done
        if bool(finished.all()):
            break
    return EpisodeResults(scores, lengths, wins)


class CountingPolicy:
    """A policy that notes how many envs it is asked for at each call, and its torch threads."""

    def __init__(self, policy) -> None:
        self.policy, self.asked, self.threads = policy, [], set()

    def __call__(self, td):
        self.asked.append(td.batch_size[0])
        self.threads.add(torch.get_num_threads())
        return self.policy(td)


@pytest.mark.parametrize("agent", ["random", "trained"])
def test_the_records_are_those_of_stepping_every_env_with_the_policy(agent, tiny_run):
    game, policy = ("frogs", RandomAgent(5, seed=0)) if agent == "random" else ("zelda", None)
    policy = policy or load_policy(run_info(tiny_run), seed=0)
    levels = [human_level(game, 0)] * 4 + [human_level(game, 2)] * 3
    steps = 200 if agent == "random" else 60  # the tiny trained net's Zelda episodes run long
    got = play_episodes(game, levels, policy, max_steps=steps, seed=5, progress=False)
    want = _every_env_stepped(game, levels, policy, steps, seed=5)
    assert _outcomes(got) == _outcomes(want)
    assert len(set(want.lengths.tolist())) > 1 or agent == "trained"  # envs finished at different steps


def test_the_policy_acts_only_for_the_envs_still_playing():
    levels = [human_level("frogs", 0)] * 6 + [human_level("frogs", 1)] * 4
    policy = CountingPolicy(RandomAgent(5, seed=0))
    results = play_episodes("frogs", levels, policy, max_steps=300, seed=1, progress=False)
    lengths = results.lengths
    # each env is asked for exactly once per step of its episode, and no more
    assert sum(policy.asked) == int(lengths.sum())
    assert policy.asked == [int((lengths >= step).sum()) for step in range(1, int(lengths.max()) + 1)]
    assert policy.asked[-1] < len(levels)


def test_an_evaluation_plays_on_one_thread_and_restores_the_callers():
    before = torch.get_num_threads()
    torch.set_num_threads(2)
    try:
        policy = CountingPolicy(RandomAgent(5, seed=0))
        play_episodes("frogs", [human_level("frogs", 0)] * 3, policy, max_steps=20, progress=False)
        assert policy.threads == {runner.EVALUATION_THREADS} == {1}
        assert torch.get_num_threads() == 2
    finally:
        torch.set_num_threads(before)


def test_evaluations_of_the_protocols_length_tick_eagerly(monkeypatch):
    assert not compile_pays_back(2000, "cpu")
    assert compile_pays_back(runner.COMPILE_PAYS_BACK_STEPS, "cpu")
    made = []

    class RecordingEnv(GVGAIEnv):
        def __init__(self, *args, **kwargs) -> None:
            super().__init__(*args, **kwargs)
            made.append(self)

    monkeypatch.setattr(runner, "GVGAIEnv", RecordingEnv)
    play_episodes("zelda", [human_level("zelda", 0)] * 2, RandomAgent(6), max_steps=5, progress=False)
    (env,) = made
    assert not env.step_plan.compiled  # the game's own tick, not the engine's compiled one
    assert env.step_plan.reason == "compile_tick=False"
