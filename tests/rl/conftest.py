from __future__ import annotations

import pytest
import torch
from hydra import compose, initialize_config_dir

from gvgai_pcg.config import config_dir  # also registers the configs' resolvers

CONFIG_DIR = config_dir()


def _compose(overrides: list[str]):
    with initialize_config_dir(config_dir=str(CONFIG_DIR), version_base="1.3"):
        return compose("config", overrides=overrides)


@pytest.fixture
def make_config():
    """The training config with Hydra overrides, as ``gvgai-pcg train`` would resolve it."""
    return _compose


def generated_levels_available() -> bool:
    try:
        from gvgai_pcg.envs.difficulty import DifficultyTransform  # noqa: F401
        from gvgai_pcg.envs.level_sources import GeneratedLevels

        GeneratedLevels("zelda")
    except (ImportError, ValueError, KeyError):
        return False
    return True


needs_generated_levels = pytest.mark.skipif(
    not generated_levels_available(),
    reason="GeneratedLevels / DifficultyTransform (gvgai_pcg.envs) or the Zelda generator are not there yet",
)


@pytest.fixture(autouse=True)
def one_torch_thread():
    """Training tests use one intra-op thread (as the runs do): two threads on a shared two-core
    machine spin against each other and can be many times slower."""
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)
