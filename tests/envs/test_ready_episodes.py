"""Next episodes prepared ahead: the same trajectories as resetting each env on its own turn,
with the reset ticks of many resets run in one batch."""

import pytest
import torch

from gvgai_pcg.envs import GVGAIEnv, prepared_resets
from gvgai_pcg.envs.level_sources import GeneratedLevels, LevelSource
from gvgai_pcg.levels import human_levels


def rollout(env: GVGAIEnv, steps: int, seed: int = 0) -> list[dict]:
    """Every step's output of ``env`` under random actions, with partial resets as a collector does."""
    generator = torch.Generator().manual_seed(seed)
    td = env.reset()
    outputs = []
    for _ in range(steps):
        action = torch.randint(0, env.game.num_actions, (env.num_envs,), generator=generator)
        stepped, td = env.step_and_maybe_reset(td.set("action", action))
        outputs.append(
            {
                "next": stepped.get("next").exclude("action").clone(),
                "root": td.exclude("action").clone(),  # after the partial resets
                "levels": env.current_levels,
            }
        )
    return outputs


def count_prepared(env: GVGAIEnv, ahead: list[bool] | None = None) -> list[int]:
    """Record the batch size of every call that prepares episodes (compiles and reset-ticks), and
    into ``ahead`` whether they were prepared ahead (stored) or were a reset's own envs."""
    sizes = []
    prepare = env._prepare
    if ahead is not None and env._prepared_resets is not None:
        store = env._prepared_resets.episodes.store

        def stored(*args, **kwargs):
            ahead[-1] = True
            return store(*args, **kwargs)

        env._prepared_resets.episodes.store = stored

    def counted(index, observe, episodes=None):
        sizes.append(len(index))
        if ahead is not None:
            ahead.append(False)
        return prepare(index, observe, episodes)

    env._prepare = counted
    return sizes


@pytest.mark.parametrize(
    ("game", "keeps_observations", "obs"),
    [
        ("frogs", True, "tiles"),
        ("zelda", True, "tiles"),
        ("zelda", False, "tiles"),
        ("solarfox", True, "pixels"),
    ],
)
def test_prepared_episodes_give_the_same_trajectories(game, keeps_observations, obs, monkeypatch):
    if not keeps_observations:
        monkeypatch.setattr(prepared_resets, "READY_OBSERVATIONS_MAX_BYTES", 0)
    ahead = GVGAIEnv(game, num_envs=24, levels="human", seed=5, max_steps=60, obs=obs)
    plain = GVGAIEnv(game, num_envs=24, levels="human", seed=5, max_steps=60, obs=obs)
    plain._prepared_resets = None  # every reset compiles and ticks its own envs
    assert (
        ahead._prepared_resets is not None
        and ahead._prepared_resets.episodes.keeps_observations == keeps_observations
    )
    ahead_sizes, plain_sizes = count_prepared(ahead), count_prepared(plain)
    for got, want in zip(rollout(ahead, 150), rollout(plain, 150), strict=True):
        assert (got["next"] == want["next"]).all() and (got["root"] == want["root"]).all()
        assert got["levels"] == want["levels"]
    assert len(plain_sizes) > 10  # many steps ended episodes...
    assert len(ahead_sizes) < len(plain_sizes) / 1.5  # ...whose reset ticks ran in fewer batches
    # At most the episodes prepared but not reached: depth per env, and the first reset's own.
    assert sum(ahead_sizes) <= sum(plain_sizes) + (ahead._prepared_resets.episodes.depth + 1) * 24


def test_large_resets_tick_their_own_envs_and_both_kinds_mix(monkeypatch):
    monkeypatch.setattr(prepared_resets, "PREPARED_RESETS_MAX", 2)  # resets of 3+ envs tick their own
    mixed = GVGAIEnv("frogs", num_envs=16, levels="human", seed=7, max_steps=40)
    plain = GVGAIEnv("frogs", num_envs=16, levels="human", seed=7, max_steps=40)
    plain._prepared_resets = None
    ahead = []
    sizes = count_prepared(mixed, ahead)
    for got, want in zip(rollout(mixed, 120), rollout(plain, 120), strict=True):
        assert (got["root"] == want["root"]).all() and got["levels"] == want["levels"]
    own = [size for size, stored in zip(sizes[1:], ahead[1:], strict=True) if not stored]
    assert own and min(own) > 2  # the resets of 3+ envs ticked their own envs...
    assert any(ahead[1:])  # ...and smaller ones took episodes prepared ahead


def test_the_kept_observations_are_only_the_stores_own():
    from gvgai_pcg.envs.ready_episodes import ReadyEpisodes

    env = GVGAIEnv("zelda", num_envs=4, levels="human", seed=0)
    states, levels, observed = env._prepare(torch.arange(4), observe=True)
    ready = ReadyEpisodes(4, keeps_observations=True)
    ones = torch.ones(4, dtype=torch.int64)
    ready.store(torch.arange(4), ones, states, levels, observed)
    kept = observed.clone()
    observed.zero_()  # the caller's tensor is not the store's
    merged, taken, first = ready.take_into(states.clone(), torch.tensor([1, 3]), ones[:2])
    assert torch.equal(first, kept[[1, 3]]) and taken == [levels[1], levels[3]]
    assert torch.equal(merged.get("score"), states.get("score"))
    with pytest.raises(RuntimeError, match="before it was prepared"):  # used up
        ready.take_into(states.clone(), torch.tensor([1]), ones[:1])
    with pytest.raises(ValueError, match="keeps observations"):
        ready.store(torch.tensor([1]), ones[:1], states[:1], levels[:1])


def test_episodes_are_prepared_several_ahead_in_their_own_rows():
    from gvgai_pcg.envs.ready_episodes import ReadyEpisodes

    ready = ReadyEpisodes(3, depth=2)
    envs, episodes = ready.missing(torch.tensor([0, 5, 2]))
    # Row (slot, env): slot 0 holds each env's next even episode, slot 1 its next odd one.
    assert envs.tolist() == [0, 1, 2, 0, 1, 2] and episodes.tolist() == [0, 6, 2, 1, 5, 3]
    env = GVGAIEnv("zelda", num_envs=3, levels="human", seed=0)
    states, levels, _ = env._prepare(envs, observe=False, episodes=episodes)
    ready.store(envs, episodes, states, levels)
    assert ready.ready(torch.tensor([1, 1]), torch.tensor([5, 6]))
    ready.take_into(states[:3].clone(), torch.tensor([1]), torch.tensor([5]))
    assert not ready.ready(torch.tensor([1]), torch.tensor([5]))
    envs, episodes = ready.missing(torch.tensor([0, 6, 2]))  # env 1 is on to episode 6: it needs 7
    assert envs.tolist() == [1] and episodes.tolist() == [7]


def test_a_new_seed_drops_the_prepared_episodes():
    env = GVGAIEnv("frogs", num_envs=8, levels="human", seed=1, max_steps=30)
    rollout(env, 40)  # prepares episodes under seed 1
    env.set_seed(2)
    fresh = GVGAIEnv("frogs", num_envs=8, levels="human", seed=2, max_steps=30)
    for got, want in zip(rollout(env, 40), rollout(fresh, 40), strict=True):
        assert (got["root"] == want["root"]).all()


def test_sources_that_keep_state_of_their_own_are_not_prepared_ahead():
    class Counting(LevelSource):  # the levels of a source with state depend on when it is asked
        game = "zelda"

        def next_levels(self, env_indices, episode_seeds, difficulties):
            return [human_levels("zelda")[0]] * len(env_indices)

    assert GVGAIEnv("zelda", num_envs=2, levels=Counting())._prepared_resets is None
    assert GVGAIEnv("zelda", num_envs=2, levels=list(human_levels("zelda")[:2]))._prepared_resets is not None
    generated = GVGAIEnv("zelda", num_envs=2, levels=GeneratedLevels("zelda"))
    assert generated._prepared_resets is not None and generated._prepared_resets.by_difficulty


def ppcg_env(game: str, num_envs: int, alpha: float, **kwargs):
    """A generated-level env whose difficulty a DifficultyTransform moves (PPCG) or holds (alpha 0)."""
    from torchrl.envs import TransformedEnv

    from gvgai_pcg.envs.difficulty import DifficultyTransform

    base = GVGAIEnv(game, num_envs=num_envs, levels=GeneratedLevels(game), seed=11, max_steps=40, **kwargs)
    return TransformedEnv(base, DifficultyTransform("progressive", alpha=alpha, win_rule="study", game=game))


@pytest.mark.parametrize(("game", "alpha"), [("frogs", 0.0), ("solarfox", 0.0), ("frogs", 0.05)])
def test_generated_episodes_prepared_at_their_difficulty_give_the_same_trajectories(game, alpha):
    """At a difficulty that holds (PCG X, PPCG at 0) generated episodes are prepared ahead in
    bulk; where it moves (here PPCG with alpha 0.05 and the study's win rule, under which a
    timeout raises it) each prepared episode counts only at its own difficulty. Either way the
    trajectories, levels and difficulties are those of an env that prepares nothing ahead."""
    ahead, plain = ppcg_env(game, 16, alpha), ppcg_env(game, 16, alpha)
    plain.base_env._prepared_resets = None
    ahead_sizes, plain_sizes = count_prepared(ahead.base_env), count_prepared(plain.base_env)
    got_all, want_all = rollout(ahead, 120), rollout(plain, 120)
    for got, want in zip(got_all, want_all, strict=True):
        assert (got["next"] == want["next"]).all() and (got["root"] == want["root"]).all()
        assert got["levels"] == want["levels"]
    moved = {float(d) for out in want_all for d in out["root"].get("difficulty").flatten()}
    if alpha == 0.0:
        assert moved == {0.0}
        assert len(ahead_sizes) < len(plain_sizes) / 1.5  # bulk preparation...
    else:
        assert len(moved) > 3  # the difficulty moved...
        assert max(ahead_sizes[1:]) <= 16  # ...and while it moves, nothing is prepared in bulk


def test_a_prepared_episode_counts_only_at_its_difficulty():
    from gvgai_pcg.envs.ready_episodes import ReadyEpisodes

    ready = ReadyEpisodes(2, depth=1)
    env = GVGAIEnv("zelda", num_envs=2, levels=GeneratedLevels("zelda"), seed=0, difficulty=0.25)
    envs, episodes = ready.missing(torch.tensor([0, 0]), torch.tensor([0.25, 0.25], dtype=torch.float64))
    states, levels, _ = env._prepare(envs, observe=False, episodes=episodes)
    ready.store(envs, episodes, states, levels, difficulties=torch.tensor([0.25, 0.25]))
    at = torch.tensor([0.25, 0.5], dtype=torch.float64)
    assert ready.ready(torch.tensor([0]), torch.tensor([0]), at)
    assert not ready.ready(torch.tensor([1]), torch.tensor([0]), at)  # env 1 is at 0.5 now
    assert ready.ready(torch.tensor([1]), torch.tensor([0]))  # a source without difficulties
    envs, episodes = ready.missing(torch.tensor([0, 0]), at)
    assert envs.tolist() == [1] and episodes.tolist() == [0]


def test_episodes_prepared_ahead_tick_in_the_steps_graph(monkeypatch):
    """Hundreds of episodes prepared at once tick and draw in the one graph the steps use: the
    tick alone would be another graph to compile, seconds for a few calls."""
    from gvgai_pcg.engine.compiled import CompiledTick

    alone = []
    original = CompiledTick.run
    monkeypatch.setattr(CompiledTick, "run", lambda self, *args: alone.append(1) or original(self, *args))
    env = GVGAIEnv("zelda", num_envs=64, levels="human", seed=3)
    assert env.step_plan.fused and env.step_plan.compiled_resets and env._prepared_resets.episodes.depth == 8
    sizes = count_prepared(env)
    rollout(env, 60)
    assert max(sizes[1:]) > 256  # prepared ahead, more than the step's graph draws in a step...
    assert not alone  # ...in that same graph


def test_episodes_prepared_before_the_difficulty_moved_are_not_played_after_it():
    """A bulk prepared while the difficulty held at 0 is stale once it moves to 0.5: every reset
    after that plays a level of 0.5, as an env that prepares nothing ahead does."""
    ahead, plain = ppcg_env("frogs", 16, 0.0), ppcg_env("frogs", 16, 0.0)
    plain.base_env._prepared_resets = None
    stored = []
    store = ahead.base_env._prepared_resets.episodes.store
    ahead.base_env._prepared_resets.episodes.store = lambda *args, **kwargs: (
        stored.append(len(args[0])) or store(*args, **kwargs)
    )

    def play(env):
        generator = torch.Generator().manual_seed(0)
        td, outputs = env.reset(), []
        for step in range(80):
            if step == 40:
                env.transform.shared_difficulty[0] = 0.5
            action = torch.randint(0, env.game.num_actions, (env.num_envs,), generator=generator)
            stepped, td = env.step_and_maybe_reset(td.set("action", action))
            outputs.append((stepped.get("next").exclude("action").clone(), td.exclude("action").clone()))
        return outputs, env.current_levels

    (got, got_levels), (want, want_levels) = play(ahead), play(plain)
    assert stored and max(stored) > 16  # a bulk ran while d held at 0...
    for (got_next, got_root), (want_next, want_root) in zip(got, want, strict=True):
        assert (got_next == want_next).all() and (got_root == want_root).all()
    assert got_levels == want_levels
    difficulties = want[-1][1].get("difficulty").flatten().tolist()
    assert 0.5 in difficulties  # ...and later resets ran at the new difficulty


def test_a_bulk_of_generated_levels_is_bounded(monkeypatch):
    """At most READY_ROWS episodes besides the resetting envs' own are generated in one bulk (a
    bulk is lost when the difficulty moves), and a first bulk smaller than the store works."""
    monkeypatch.setattr(prepared_resets, "READY_ROWS", 4)
    ahead, plain = ppcg_env("frogs", 16, 0.0), ppcg_env("frogs", 16, 0.0)
    plain.base_env._prepared_resets = None
    assert ahead.base_env._prepared_resets.episodes.depth == 1
    bulks = []  # (resetting envs, episodes missing, episodes prepared)
    bound = ahead.base_env._prepared_resets.bounded_bulk

    def bounded(index, next_episodes, envs, episodes):
        kept = bound(index, next_episodes, envs, episodes)
        bulks.append((len(index), len(envs), len(kept[0])))
        return kept

    ahead.base_env._prepared_resets.bounded_bulk = bounded
    for got, want in zip(rollout(ahead, 80), rollout(plain, 80), strict=True):
        assert (got["next"] == want["next"]).all() and (got["root"] == want["root"]).all()
        assert got["levels"] == want["levels"]
    assert len(bulks) > 1 and all(prepared <= own + 4 for own, _, prepared in bulks)
    assert bulks[0][1] == 16 and bulks[0][2] < 16  # the first bulk was cut, below the store's rows
