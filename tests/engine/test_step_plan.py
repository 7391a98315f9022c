"""An env chooses how it steps once, when it is made, and the choice is the documented one
(docs/concepts/games.md, "How an env steps")."""

import pytest
import torch

import gvgai_pcg.engine.compiled as compiled_module
import gvgai_pcg.envs.gvgai_env as env_module
from gvgai_pcg.engine.compiled import COMPILE_VARIABLE
from gvgai_pcg.engine.step_plan import StepPlan, choose_step_plan
from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.games import get_game

CPU, CUDA = torch.device("cpu"), torch.device("cuda")

# game, envs, device, observation, torch threads -> the plan (its repr without the reason)
PLANS = [
    ("zelda", 12, CPU, "tiles", 1, "compiled: tick+tiles fused, resets compiled"),
    ("zelda", 64, CPU, "tiles", 2, "compiled: tick+tiles fused, resets compiled"),
    ("zelda", 64, CPU, "pixels", 1, "compiled: tick, resets compiled"),
    ("zelda", 1024, CPU, "tiles", 1, "compiled: tick, resets compiled"),
    ("zelda", 1024, CPU, "tiles", 2, "compiled: tick, large-batch graph, resets compiled"),
    ("zelda", 64, CUDA, "tiles", 1, "compiled: tick, resets compiled"),
    ("zelda", 1, CPU, "tiles", 1, "eager: a single env"),
    ("frogs", 64, CPU, "tiles", 1, "compiled: tick+tiles fused"),  # its own, lighter reset tick
    ("frogs", 128, CPU, "tiles", 1, "compiled: tick"),
    ("frogs", 64, CUDA, "tiles", 1, "eager: frogs is not compiled on cuda"),
    ("solarfox", 2048, CPU, "tiles", 2, "compiled: tick, large-batch graph, resets compiled"),
    ("solarfox", 4096, CPU, "tiles", 2, "eager: 4096 envs, above solarfox's 2048"),
    ("boulderdash", 1024, CPU, "tiles", 2, "compiled: tick, resets compiled"),  # no parallel graph
    ("boulderdash", 4096, CPU, "tiles", 1, "eager: 4096 envs, above boulderdash's 1024"),
]


def plan_of(game: str, envs: int, device: torch.device, obs: str, threads: int, **kwargs) -> StepPlan:
    before = torch.get_num_threads()
    torch.set_num_threads(threads)
    try:
        return choose_step_plan(get_game(game), envs, device, obs, **kwargs)
    finally:
        torch.set_num_threads(before)


@pytest.mark.parametrize(("game", "envs", "device", "obs", "threads", "expected"), PLANS)
def test_the_plan_is_the_documented_one(game, envs, device, obs, threads, expected):
    plan = plan_of(game, envs, device, obs, threads)
    assert repr(plan).removeprefix("StepPlan(").split(";")[0].rstrip(")") == expected


def test_the_documented_plans_are_the_ones_tested():
    from pathlib import Path

    page = (Path(__file__).parents[2] / "docs/concepts/games.md").read_text()
    for game, envs, device, obs, threads, expected in PLANS:
        row = f"| {game} | {envs:,} | {device.type} | {obs} | {threads} | {expected} |"
        assert row in page, row


def test_switches_that_make_every_plan_eager(monkeypatch):
    assert plan_of("zelda", 64, CPU, "tiles", 1, shards=2) == StepPlan(False, reason="2 shards")
    assert not plan_of("zelda", 64, CPU, "tiles", 1, compile_tick=False).compiled
    monkeypatch.setenv(COMPILE_VARIABLE, "0")
    assert repr(plan_of("zelda", 64, CPU, "tiles", 1)) == "StepPlan(eager: GVGAI_PCG_COMPILE=0)"


def test_an_env_chooses_its_plan_once_and_never_again(monkeypatch):
    chosen = []

    def counting(*args, **kwargs):
        chosen.append(args)
        return choose_step_plan(*args, **kwargs)

    monkeypatch.setattr(env_module, "choose_step_plan", counting)
    env = GVGAIEnv("zelda", num_envs=8, levels="human", seed=1, max_steps=10)
    assert len(chosen) == 1 and env.step_plan.fused
    plan = env.step_plan

    def refused(*args, **kwargs):
        pytest.fail("a batch or thread check ran while stepping")

    # the checks a generic caller of the compiled tick goes through are never asked again
    monkeypatch.setattr(compiled_module, "compiled_batch", refused)
    monkeypatch.setattr(compiled_module, "large_batch", refused)
    td = env.reset()
    generator = torch.Generator().manual_seed(0)
    resets = 0
    for _ in range(40):
        td.set("action", torch.randint(0, env.game.num_actions, (8,), generator=generator))
        stepped, td = env.step_and_maybe_reset(td)
        resets += bool(stepped.get(("next", "done")).any())
    assert resets >= 3  # partial resets happened (the step limit is 10)
    assert len(chosen) == 1 and env.step_plan is plan


def test_the_plan_prints_on_one_line():
    text = repr(GVGAIEnv("boulderdash", num_envs=4).step_plan)
    assert "\n" not in text and text.startswith("StepPlan(compiled: tick+tiles fused")
