"""Checkpoints hold tensors and plain data only, say what model they are, and are refused (never
run) when crafted; the files of format 1 still load."""

from __future__ import annotations

import random
from pathlib import Path

import numpy as np
import pytest
import torch

from gvgai_pcg.curricula import get_curriculum
from gvgai_pcg.rundir.checkpoint import (
    FORMAT_VERSION,
    CheckpointError,
    NonFiniteModelError,
    UnsafeCheckpointError,
    UnusableCheckpointError,
    check_identity,
    load_checkpoint,
    read_file,
    restore,
    save_checkpoint,
    save_model,
    set_rng_states,
)

CONFIG = {
    "game": {"name": "zelda"},
    "env": {"obs": "tiles", "num_envs": 4},
    "model": {"name": "compact", "hidden": 16},
    "algo": {"lr": 7e-4},
    "seed": 0,
}


def _state(frames: int = 40, weight: float = 0.5) -> dict:
    net = torch.nn.Linear(3, 2)
    torch.nn.init.constant_(net.weight, weight)
    optimizer = torch.optim.RMSprop(net.parameters(), lr=7e-4)
    net(torch.ones(1, 3)).sum().backward()
    optimizer.step()
    return {
        "frames": frames,
        "episodes": 3,
        "elapsed": 1.5,
        "model": net.state_dict(),
        "optimizer": optimizer.state_dict(),
        "curriculum": None,
        "config": CONFIG,
        "log_rows": 2,
    }


def test_a_checkpoint_loads_weights_only_and_carries_its_identity(tmp_path):
    path = tmp_path / "checkpoints" / "last.pt"
    save_checkpoint(path, _state())
    state = torch.load(path, weights_only=True)  # no allow-list needed
    assert state["format"] == FORMAT_VERSION
    assert state["identity"] == {"game": "zelda", "obs": "tiles", "model": "compact", "hidden": 16}
    numpy_before = np.random.random()
    set_rng_states(state["rng"])
    assert np.random.random() == numpy_before and isinstance(random.random(), float)


def test_saving_keeps_the_previous_checkpoint(tmp_path):
    path = tmp_path / "last.pt"
    save_checkpoint(path, _state(frames=40))
    save_checkpoint(path, _state(frames=80))
    assert read_file(path)["frames"] == 80
    assert read_file(tmp_path / "prev.pt")["frames"] == 40
    assert sorted(p.name for p in tmp_path.iterdir()) == ["last.pt", "prev.pt"]  # no temporary left


def test_a_crafted_checkpoint_is_refused_and_runs_nothing(tmp_path):
    marker = tmp_path / "written-by-the-checkpoint"

    class Payload:
        def __reduce__(self):
            return (Path.write_text, (marker, "ran"))

    crafted = tmp_path / "crafted.pt"
    torch.save({"model": Payload(), "config": CONFIG, "frames": 1}, crafted)
    with pytest.raises(UnsafeCheckpointError, match="refused to load: it holds a Python object"):
        read_file(crafted)
    assert not marker.exists()


def test_a_format_1_checkpoint_still_loads(tmp_path):
    # format 1 stored NumPy's legacy RNG tuple (an ndarray) and no identity
    old = {**_state(), "format": 1}
    del old["log_rows"]
    old["rng"] = {"torch": torch.get_rng_state(), "numpy": np.random.get_state(), "python": random.getstate()}
    path = tmp_path / "last.pt"
    torch.save(old, path)
    state = load_checkpoint(path, CONFIG)
    set_rng_states(state["rng"])
    check_identity(
        state, path, {"game": "zelda", "obs": "tiles", "model": "compact", "hidden": 16}, "the run"
    )


def test_a_newer_format_and_a_non_checkpoint_are_refused(tmp_path):
    path = tmp_path / "last.pt"
    torch.save({**_state(), "format": FORMAT_VERSION + 1}, path)
    with pytest.raises(UnusableCheckpointError, match="newer gvgai-pcg"):
        read_file(path)
    torch.save({"weights": torch.zeros(2)}, path)
    with pytest.raises(UnusableCheckpointError, match="not a gvgai-pcg model or checkpoint"):
        read_file(path)
    path.write_bytes(b"PK\x03\x04 cut short")
    with pytest.raises(UnusableCheckpointError, match="corrupt or truncated"):
        read_file(path)


def test_non_finite_weights_are_refused(tmp_path):
    path = tmp_path / "last.pt"
    save_checkpoint(path, _state(weight=float("nan")))
    with pytest.raises(NonFiniteModelError, match="weights are not finite .* its run diverged"):
        load_checkpoint(path, CONFIG)


def test_a_model_of_another_game_or_observation_is_refused(tmp_path):
    path = tmp_path / "model.pt"
    frogs = {**CONFIG, "game": {"name": "frogs"}}
    save_model(path, _state()["model"], frogs, 40)
    state = read_file(path)
    expected = {"game": "zelda", "obs": "pixels", "model": "compact", "hidden": 16}
    with pytest.raises(
        CheckpointError, match="is a frogs model .* but the run needs a zelda model .* differ in game, obs"
    ):
        check_identity(state, path, expected, "the run")


def test_a_checkpoint_from_before_level_sets_resumes_under_the_pcg_defaults():
    from gvgai_pcg.rundir.checkpoint import config_differences

    before = {"regimen": {"name": "pcg", "difficulty": 1.0, "win_rule": "game", "tag": "pcg1.0"}}
    now = {"regimen": {**before["regimen"], "num_levels": 0, "start_seed": 0}}
    assert config_differences(before, now) == []
    fixed_set = {"regimen": {**now["regimen"], "num_levels": 100}}
    assert config_differences(before, fixed_set) == [
        "regimen.num_levels: '<missing>' in the checkpoint, 100 now"
    ]


PPCG = {"name": "ppcg", "alpha": 0.01, "start": 0.0, "win_rule": "game", "tag": "ppcg"}


def _resumed_ppcg(path: Path) -> float:
    """The d a PPCG run resumes at from the checkpoint at ``path``."""
    run = get_curriculum("ppcg").start("zelda", PPCG)
    net = torch.nn.Linear(3, 2)
    restore(load_checkpoint(path, CONFIG), net, torch.optim.RMSprop(net.parameters(), lr=7e-4), run)
    return run.difficulty


def test_a_checkpoint_keeps_the_curriculum_state_under_its_name_and_an_older_one_resumes(tmp_path):
    moved = get_curriculum("ppcg").start("zelda", PPCG)
    moved.state.update([True] * 37)  # d = 0.37
    path = tmp_path / "checkpoints" / "last.pt"
    save_checkpoint(path, {**_state(), "curriculum": moved.state_dict()})
    assert set(read_file(path)) >= {"curriculum"} and "difficulty" not in read_file(path)
    assert _resumed_ppcg(path) == pytest.approx(0.37)
    # written before the key was named for what it holds: the state under "difficulty"
    old = {key: value for key, value in _state().items() if key != "curriculum"}
    save_checkpoint(path, {**old, "difficulty": moved.state_dict()})
    assert _resumed_ppcg(path) == pytest.approx(0.37)
    save_checkpoint(path, old)  # a run with state, a checkpoint with none: refused in one line
    with pytest.raises(CheckpointError, match="holds no state of the curriculum 'ppcg'"):
        _resumed_ppcg(path)
