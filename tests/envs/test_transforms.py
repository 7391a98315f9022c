"""TorchRL's own transforms compose with GVGAIEnv's observations: their specs are ones those
transforms rewrite (TorchRL's ``Binary`` is not: a cast keeps it 0/1, so normalised tiles fall
outside it), and ``check_env_specs`` holds after each."""

import pytest
import torch
from torchrl.envs import (
    CatFrames,
    Compose,
    DoubleToFloat,
    DTypeCastTransform,
    ObservationNorm,
    Resize,
    ToTensorImage,
    TransformedEnv,
    VecNorm,
)
from torchrl.envs.utils import check_env_specs

from gvgai_pcg.envs import GVGAIEnv


def tiles_env(*transforms) -> TransformedEnv:
    return TransformedEnv(GVGAIEnv("zelda", num_envs=1, max_steps=20, seed=0), Compose(*transforms))


def to_float(key: str = "tiles") -> DTypeCastTransform:
    return DTypeCastTransform(torch.uint8, torch.float32, in_keys=[key])


def test_observation_norm_after_a_cast():
    env = tiles_env(to_float(), ObservationNorm(in_keys=["tiles"], standard_normal=True))
    env.transform[-1].init_stats(num_iter=4, reduce_dim=(0, 1), cat_dim=0)
    check_env_specs(env)
    assert env.rollout(3).get("tiles").dtype == torch.float32


def test_vec_norm_after_a_cast():
    env = tiles_env(to_float(), VecNorm(in_keys=["tiles"]))
    check_env_specs(env)
    tiles = env.rollout(5).get(("next", "tiles"))
    assert tiles.dtype == torch.float32 and not set(tiles.unique().tolist()) <= {0.0, 1.0}


def test_a_cast_alone_and_the_difficulty_as_float32():
    env = tiles_env(to_float(), DoubleToFloat(in_keys=["difficulty"]))
    check_env_specs(env)
    out = env.rollout(2)
    assert out.get("tiles").dtype == torch.float32 and out.get("difficulty").dtype == torch.float32


def test_cat_frames_stacks_tiles():
    env = tiles_env(CatFrames(N=4, dim=-3, in_keys=["tiles"]))
    check_env_specs(env)
    channels = len(env.base_env.game.tile_types)
    assert env.rollout(3).get("tiles").shape[-3] == 4 * channels


def pixels_env(*transforms) -> TransformedEnv:
    base = GVGAIEnv("zelda", num_envs=1, obs="pixels", max_steps=20, seed=0)
    return TransformedEnv(base, Compose(*transforms))


def test_pixels_to_a_float_image():
    """The pixels are already [3, H, W]: ``shape_tolerant`` keeps ToTensorImage from permuting them."""
    env = pixels_env(ToTensorImage(in_keys=["pixels"], shape_tolerant=True))
    check_env_specs(env)
    pixels = env.rollout(2).get("pixels")
    assert pixels.dtype == torch.float32 and pixels.shape[-3] == 3 and 0.0 < pixels.max() <= 1.0


def test_pixels_resized():
    pytest.importorskip("torchvision")  # TorchRL's Resize needs it; gvgai_pcg does not
    env = pixels_env(
        ToTensorImage(in_keys=["pixels"], shape_tolerant=True), Resize(32, 48, in_keys=["pixels"])
    )
    check_env_specs(env)
    assert env.rollout(2).get("pixels").shape[-3:] == (3, 32, 48)


@pytest.mark.parametrize("obs", ["tiles", "pixels"])
def test_the_observation_itself_stays_uint8(obs):
    env = GVGAIEnv("frogs", num_envs=1, obs=obs, seed=0)
    assert env.observation_spec[obs].dtype == torch.uint8 and env.reset().get(obs).dtype == torch.uint8
