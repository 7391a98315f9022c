"""The training benchmark (``python -m gvgai_pcg.bench.training``): it times the network both
ways, splits a batch, and refuses what it cannot measure in one line (its numbers are never
asserted)."""

import pytest
import torch

from gvgai_pcg.bench import training


def test_the_training_benchmark_times_the_network_both_ways_and_splits_a_batch(make_small_config):
    cfg = make_small_config
    costs = training.network_costs(cfg, seconds=0.2)
    assert set(costs) == {"acting_and_update", "reused_graph"}
    assert all(cost.wall > 0 and cost.cpu > 0 for cost in costs.values())
    parts = training.batch_breakdown(cfg, batches=3)
    assert {"acting", "env", "update", "rest", "total"} <= set(parts)
    named = parts["acting"].cpu + parts["env"].cpu + parts["update"].cpu
    assert 0 < named <= parts["total"].cpu + 1e-9
    assert abs(named + parts["rest"].cpu - parts["total"].cpu) < 1e-9
    layouts = training.layout_costs(cfg, seconds=0.2)
    assert set(layouts) == {"own", "contiguous"} and all(c.cpu > 0 for c in layouts.values())
    text = training.describe("run", {**dict.fromkeys(NUMBERS, 1.0), "layout_cpu_speedup": 1.25})
    assert "updates 1.25x as fast as contiguous" in text
    assert "keeps the acting passes' graph" in text
    text = training.describe("run", {**dict.fromkeys(NUMBERS, 1.0), "keeps_acting_graph": 0.0})
    assert "recomputes the acting passes" in text


@pytest.mark.slow  # a few PPO updates and a batch of the loop (~5 s on a quiet machine)
def test_the_training_benchmark_measures_ppo_against_its_epochs_of_minibatches(monkeypatch):
    monkeypatch.setenv("GVGAI_PCG_COMPILE", "0")  # a compiled tick would take minutes to build here
    from hydra import compose, initialize_config_dir

    from gvgai_pcg.config import config_dir

    small = ["env.num_envs=4", "regimen=lv", "model.hidden=16", "algo=ppo", "algo.n_steps=4"]
    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
        cfg = compose("config", overrides=[*small, "algo.epochs=2", "algo.minibatches=2"])
    assert training.update_shape(cfg.algo) == (2, 2)
    steps = []
    original = torch.optim.Adam.step
    monkeypatch.setattr(torch.optim.Adam, "step", lambda self, *a, **k: steps.append(1) or original(self))
    once = lambda work, seconds: work() or training.Cost(1.0, 1.0)  # noqa: E731 (one call, no timing)
    monkeypatch.setattr(training, "time_calls", once)
    costs = training.network_costs(cfg)
    assert set(costs) == {"acting_and_update"}  # PPO has no reused-graph shape
    assert len(steps) == 2 * 2 * 2  # two timed rounds, each epochs x minibatches Adam steps
    parts = training.batch_breakdown(cfg, batches=1)
    assert parts["update"].cpu > 0 and parts["acting"].cpu > 0
    numbers = {**dict.fromkeys(NUMBERS[:8], 1.0), "keeps_acting_graph": 0.0}
    text = training.describe("ppo-run", numbers)
    assert "network's whole work" in text and "reused-graph" not in text


NUMBERS = ("frames_per_batch", "load", "end_to_end_fps", "end_to_end_cpu_fps", "limit_fps", "limit_cpu_fps")
NUMBERS += ("ratio", "cpu_ratio", "reused_limit_fps", "reused_limit_cpu_fps", "reused_ratio")
NUMBERS += ("reused_cpu_ratio", "keeps_acting_graph")


@pytest.fixture
def make_small_config():
    from hydra import compose, initialize_config_dir

    from gvgai_pcg.config import config_dir

    with initialize_config_dir(config_dir=str(config_dir()), version_base="1.3"):
        return compose("config", overrides=["env.num_envs=4", "regimen=lv", "model.hidden=16"])


def test_the_training_benchmark_prints_its_usage_for_help(capsys):
    assert training.main(["--help"]) == 0
    assert "python -m gvgai_pcg.bench.training [hydra overrides]" in capsys.readouterr().out


def test_the_training_benchmark_refuses_a_learner_it_does_not_model_in_one_line(capsys, monkeypatch):
    monkeypatch.setattr(training, "MODELLED", ("a2c",))  # as a plug-in learner would be
    assert training.main(["algo=ppo"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "algo=ppo" in err and "modelled for algo=a2c only" in err


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("torch_threads=1", "torch_threads=1: unknown key"),
        ("algo.lr=-1", "algo.lr=-1"),
        ("algo.lr==", "algo.lr=="),
    ],
)
def test_the_training_benchmark_refuses_a_bad_override_in_one_line_before_any_work(
    capsys, monkeypatch, override, named
):
    monkeypatch.setattr(training, "benchmark", lambda cfg: pytest.fail("measured a bad config"))
    assert training.main([override]) == 2
    err = capsys.readouterr().err.strip()
    assert (
        len(err.splitlines()) == 1 and named in err and err.startswith("python -m gvgai_pcg.bench.training: ")
    )
