"""PPCG on Zelda learns: after a fixed budget the agent beats the random agent on generated
levels of difficulty 0.5 (slow: about 10 minutes on 2 CPU cores; run with ``-m slow``); PPO does
the same on the easiest generated levels."""

from __future__ import annotations

import pytest

from gvgai_pcg.evaluation import RandomAgent, play_episodes
from gvgai_pcg.evaluation.policy import load_policy
from gvgai_pcg.rl import train
from tests.rl.conftest import needs_generated_levels

BUDGET_FRAMES = 500_000
TEST_LEVELS = 64


@pytest.mark.slow
@needs_generated_levels
def test_ppcg_on_zelda_beats_the_random_agent_on_generated_levels(make_config, tmp_path):
    from gvgai_pcg.generators import generate_level

    cfg = make_config(["game=zelda", "regimen=ppcg", f"total_frames={BUDGET_FRAMES}", f"out_dir={tmp_path}"])
    result = train(cfg, tmp_path / cfg.run_name)
    levels = [generate_level("zelda", 0.5, 10_000 + i) for i in range(TEST_LEVELS)]
    agent = play_episodes("zelda", levels, load_policy(result.model_path, seed=1), seed=1, progress=False)
    random = play_episodes("zelda", levels, RandomAgent(6, seed=1), seed=1, progress=False)
    print(
        f"\nPPCG zelda after {result.frames} frames, {TEST_LEVELS} generated d=0.5 levels: "
        f"agent mean score {agent.scores.mean():.3f} (wins {agent.wins.float().mean():.2f}), "
        f"random {random.scores.mean():.3f} (wins {random.wins.float().mean():.2f})"
    )
    assert agent.scores.mean() > random.scores.mean()


PPO_BUDGET_FRAMES = 200_000


@pytest.mark.slow
@needs_generated_levels
def test_ppo_on_easy_zelda_levels_beats_the_random_agent(make_config, tmp_path):
    """PPO learns through the shared loop: trained on generated Zelda levels at d = 0 (the easiest)
    with shorter rollouts (64 steps, so that 200k frames are a dozen updates of 3 x 8 steps),
    it scores more than the random agent on new ones."""
    from gvgai_pcg.generators import generate_level

    overrides = ["algo=ppo", "algo.n_steps=64", "regimen=pcg", "regimen.difficulty=0.0", "env.max_steps=500"]
    cfg = make_config([*overrides, f"total_frames={PPO_BUDGET_FRAMES}", f"out_dir={tmp_path}"])
    result = train(cfg, tmp_path / cfg.run_name)
    levels = [generate_level("zelda", 0.0, 10_000 + i) for i in range(TEST_LEVELS)]
    agent = play_episodes("zelda", levels, load_policy(result.model_path, seed=1), seed=1, progress=False)
    random = play_episodes("zelda", levels, RandomAgent(6, seed=1), seed=1, progress=False)
    print(
        f"\nPPO zelda d=0 after {result.frames} frames: agent mean score {agent.scores.mean():.3f}, "
        f"random {random.scores.mean():.3f}"
    )
    assert agent.scores.mean() > random.scores.mean()
