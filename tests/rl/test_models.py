"""Network shapes and initialisation."""

from __future__ import annotations

import math

import pytest
import torch

from gvgai_pcg.rl.models import make_actor_critic


@pytest.mark.parametrize("shape, flat", [((3, 90, 130), 5376), ((3, 110, 100), 5760)])
def test_nature_cnn_matches_the_study_sizes(shape, flat):
    net = make_actor_critic("nature", "pixels", shape, 6, 512)
    assert net.torso[1].in_features == flat  # Zelda 7x12x64, Solarfox 10x9x64 (GENERATORS.md §3)
    logits, value = net(torch.zeros(2, 4, *shape, dtype=torch.uint8))
    assert logits.shape == (2, 4, 6) and value.shape == (2, 4, 1)


def test_heads_are_initialised_like_baselines():
    torch.manual_seed(0)
    net = make_actor_critic("compact", "tiles", (9, 9, 13), 6, 256)
    w = net.policy_head.weight  # orthogonal rows scaled by 0.01
    assert torch.allclose(w @ w.T, 1e-4 * torch.eye(6), atol=1e-6)
    assert net.value_head.weight.norm().item() == pytest.approx(1.0, rel=1e-5)
    assert net.scale == 1.0 and make_actor_critic("nature", "pixels", (3, 90, 130), 6, 512).scale == 255.0
    assert math.isclose(float(net.policy_head.bias.abs().sum()), 0.0)


def test_unknown_model_names_the_valid_ones():
    with pytest.raises(ValueError, match="nature, compact"):
        make_actor_critic("resnet", "tiles", (9, 9, 13), 6, 256)


def test_the_compact_torso_runs_channels_last_with_the_same_numbers_and_state():
    torch.manual_seed(0)
    net = make_actor_critic("compact", "tiles", (11, 11, 28), 5, 256)
    conv = net.torso[0][0]
    assert conv.weight.is_contiguous(memory_format=torch.channels_last)
    assert make_actor_critic("nature", "pixels", (3, 90, 130), 6, 512).torso[0][0].weight.is_contiguous()
    plain = make_actor_critic("compact", "tiles", (11, 11, 28), 5, 256)
    plain.load_state_dict(net.state_dict())  # checkpoints move between layouts unchanged
    contiguous = {key: value.contiguous() for key, value in plain.state_dict().items()}
    again = make_actor_critic("compact", "tiles", (11, 11, 28), 5, 256)
    again.load_state_dict(contiguous)  # a checkpoint written before the layout changed
    assert again.torso[0][0].weight.is_contiguous(memory_format=torch.channels_last)
    assert all(
        torch.equal(a, b) for a, b in zip(again.state_dict().values(), contiguous.values(), strict=True)
    )
    plain.memory_format = torch.contiguous_format
    plain.to(memory_format=torch.contiguous_format)
    assert plain.torso[0][0].weight.is_contiguous()
    obs = torch.randint(0, 2, (64, 11, 11, 28), dtype=torch.uint8)
    for model in (net, plain):
        logits, value = model(obs)
        (logits.square().sum() + value.sum()).backward()
    assert torch.allclose(net(obs)[0], plain(obs)[0], atol=1e-5)
    for mine, theirs in zip(net.parameters(), plain.parameters(), strict=True):
        assert torch.allclose(mine.grad, theirs.grad, rtol=1e-4, atol=1e-5)
