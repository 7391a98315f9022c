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


def test_a_compiled_draw_equals_the_eager_one_on_every_stream():
    def bits(seed, tick, stream: int):
        return rng.hash_bits(seed, tick, torch.arange(4), stream)

    compiled = torch.compile(bits, dynamic=True, fullgraph=True)
    seeds, ticks = torch.arange(8) * 31, torch.full((8,), 7)
    for stream in (1, 2, 3):
        assert torch.equal(compiled(seeds, ticks, stream), bits(seeds, ticks, stream))
