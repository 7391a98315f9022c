"""Counter-based draws: any stream and slot, given as a Python int or a tensor, is a key."""

import torch

from gvgai_pcg.games import rng


def test_every_stream_and_int_slot_draws_and_an_int_slot_equals_its_tensor():
    seeds, ticks = torch.arange(64) * 31, torch.full((64,), 7)
    by_stream = [rng.hash_bits(seeds, ticks, 3, stream) for stream in range(1, 6)]
    assert len({tuple(bits.tolist()) for bits in by_stream}) == 5  # streams 2+ no longer overflow
    slots = torch.arange(5)
    table = rng.hash_bits(seeds, ticks, slots, 2)
    for slot in range(5):
        assert torch.equal(rng.hash_bits(seeds, ticks, slot, 2), table[:, slot])
