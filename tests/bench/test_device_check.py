"""The device check: holds a device's tick and env to the CPU's, and names the first difference."""

import pytest
import torch

from gvgai_pcg.bench import device_check
from gvgai_pcg.games import get_game

CPU = torch.device("cpu")


@pytest.mark.slow  # compiling Zelda's tick: 20 CPU-seconds; the harness's verdicts are tested below
@pytest.mark.compiled
def test_the_cpu_passes_against_itself():
    tick = device_check.check_tick("zelda", CPU, ticks=5)
    env = device_check.check_env("zelda", CPU, steps=10, num_envs=4)
    assert tick.passed and tick.what == "compiled tick" and tick.steps == 5
    assert env.passed and env.steps == 10


def test_a_tick_that_computes_otherwise_is_caught(monkeypatch):
    game = get_game("zelda")

    def off_by_one(state, action):
        game.tick(state, action)
        state.set("score", state.get("score") + (state.get("tick") == 3))

    monkeypatch.setattr(device_check, "engine_tick", lambda _: off_by_one)
    check = device_check.check_tick("zelda", CPU, ticks=10)
    assert not check.passed and check.steps == 4
    assert "score" in check.difference and "tick 3" in check.difference


def test_main_says_so_in_its_exit_status(monkeypatch, capsys):
    assert device_check.main(["--device", "cpu", "--games", "zelda", "--ticks", "3", "--env-steps", "3"]) == 0
    assert "identical" in capsys.readouterr().out
    monkeypatch.setattr(device_check, "check_env", lambda *a: device_check.Check("zelda", "env", 1, 0.0, "x"))
    assert device_check.main(["--device", "cpu", "--games", "zelda", "--ticks", "3"]) == 1
