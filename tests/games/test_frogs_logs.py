"""The invariants of Frogs' log machinery (gvgai_pcg/games/frogs/logs.py), each checked against a
brute-force version of what it stands for."""

from __future__ import annotations

import random

import pytest
import torch
from tensordict import TensorDict

from gvgai_pcg.games.frogs import logs as frogs_logs
from gvgai_pcg.games.frogs import rules as frogs
from gvgai_pcg.games.frogs.logs import (
    LOG_SPEED,
    log_key,
    log_layout,
    spawn_schedule,
    spawner_ring_size,
    wrap_around_,
)


def test_log_speed_is_fixed_at_one_pixel_per_tick_because_moving_logs_keep_their_key():
    # Invariant 1: the key adds the tick, so only a log that loses 1 px per tick keeps it. Ring
    # sizes count a log's life as its distance + 2 ticks, and the cleanup finds a leaving log at
    # x = −1, for the same reason.
    assert LOG_SPEED == 1, (
        "frogs_logs.LOG_SPEED is not a parameter: log_key, spawner_ring_size, log_layout and the "
        "cleanup at x = -1 all assume logs move exactly 1 px per tick"
    )
    x, y = torch.arange(-1, 300), torch.full((301,), 30)
    start = log_key(x, y, 7)
    for t in range(1, 40):
        assert torch.equal(log_key(x - LOG_SPEED * t, y, 7 + t), start)
        assert not torch.equal(log_key(x - 2 * t, y, 7 + t), start)


@pytest.mark.parametrize("cooldown", [1, 3, 5, 10, 12])
def test_a_spawner_ring_is_never_full_when_it_fires_and_one_slot_fewer_would_be(cooldown):
    # Invariant 2: a log spawned in tick t occupies its slot up to the end of tick t + x + 2.
    for x in range(0, 400, 10):
        size = int(spawner_ring_size(torch.tensor(x), torch.tensor(cooldown)))

        def first_clash(slots: int, x: int = x) -> int | None:
            freed_after = {}  # slot -> last tick it is occupied
            for t in range(0, 3 * (x + 2) + 4 * cooldown, cooldown):
                slot = (t // cooldown) % slots
                if freed_after.get(slot, -1) >= t:
                    return t
                freed_after[slot] = t + x + 2
            return None

        assert first_clash(size) is None, f"x = {x}, cooldown = {cooldown}: ring of {size} overflows"
        assert size == 1 or first_clash(size - 1) is not None, f"x = {x}: the ring size is not tight"


def test_spawn_schedule_equals_integer_arithmetic_at_every_tick():
    # Invariant 5: float64 division of whole numbers gives the same q, r and slots as // and %.
    generator = torch.Generator().manual_seed(0)
    batch, count = 64, 6
    kind = torch.randint(0, 2, (batch, count), generator=generator)
    x = 10 * torch.randint(0, 100, (batch, count), generator=generator)
    cooldown = torch.tensor(frogs.SPAWN_COOLDOWN)[kind]
    ring = spawner_ring_size(x, cooldown) * (torch.rand(batch, count, generator=generator) > 0.2)
    base = torch.randint(0, 50, (batch, count), generator=generator)
    spawners = TensorDict({"kind": kind, "x": x, "ring": ring, "base": base}, batch_size=[batch, count])
    for tick in [*range(0, 300), 2**31 - 3, 10**12 + 7]:
        now = torch.full((batch,), tick, dtype=torch.int64)
        schedule = spawn_schedule(spawners, now, frogs.SPAWN_COOLDOWN)
        q, r = tick // cooldown, tick % cooldown
        assert torch.equal(schedule["spawn"], r == 0), tick
        assert torch.equal(schedule["fresh"], r == 1), tick
        assert torch.equal(schedule["slot"], base + q % ring.clamp_min(1)), tick


@pytest.mark.parametrize("seed", range(40))
def test_level_logs_borrow_only_ring_slots_first_written_after_they_are_gone(seed):
    # Invariant 3, on random levels: every slot is used once, a borrowed ring slot j is first
    # written in tick j * cooldown >= x0 + 2, and the level's own slots come before the rings.
    rng = random.Random(seed)
    xs = tuple(rng.choice([-1, *range(0, 300, 10)]) for _ in range(rng.randint(0, 12)))
    cooldowns = tuple(rng.choice(frogs.SPAWN_COOLDOWN) for _ in range(rng.randint(0, 5)))
    rings = tuple(
        rng.choice([0, int(spawner_ring_size(torch.tensor(rng.randrange(0, 300, 10)), torch.tensor(c)))])
        for c in cooldowns
    )
    layout = log_layout(xs, rings, cooldowns)
    placed = [k for k, x in enumerate(xs) if x >= 0]
    slots = [layout.slots[k] for k in placed]
    assert len(set(slots)) == len(slots)
    assert layout.size == layout.bases[0] + sum(rings) if rings else layout.size == len(placed)
    for k in placed:
        slot = layout.slots[k]
        owner = [s for s, base in enumerate(layout.bases) if base <= slot < base + rings[s]]
        if owner:
            (spawner,) = owner
            j = slot - layout.bases[spawner]
            assert xs[k] + 2 <= j * cooldowns[spawner], f"log at x = {xs[k]} in ring slot {j}"
        else:
            assert slot < (layout.bases[0] if rings else layout.size)


def test_log_keys_are_near_exactly_when_sprites_on_rows_overlap():
    # Invariant 4: rows are 10 * 2^20 apart, so |key difference| < 10 only in one row, by x.
    x = torch.arange(-10, 300).repeat(11)
    y = torch.arange(0, 110, 10).repeat_interleave(310)
    for tick in (0, 1, 999, 2 * 10**9):
        for fx, fy in ((0, 0), (45, 50), (289, 100), (-1, 30)):
            near = (log_key(x, y, tick) - log_key(torch.tensor(fx), torch.tensor(fy), tick)).abs() < 10
            assert torch.equal(near, (y == fy) & ((x - fx).abs() < 10)), (tick, fx, fy)
        frog = log_key(x, y, tick)
        assert (frog.abs() >= 10).all()  # a dead slot (key 0) is never near a frog
        # Exact in int32: the key equals the int64 arithmetic.
        assert torch.equal(frog.long(), (y + 10) * frogs_logs.LOG_ROW_KEY + x + tick)


@pytest.mark.parametrize("velocity", frogs.TRUCK_VELOCITY)
def test_wrap_around_sends_trucks_off_their_edge_to_the_other_edge(velocity):
    # Invariant 5: the sign-bit masks equal the rule they stand for, for each env's own screen.
    last = torch.tensor([[90], [270], [0]], dtype=torch.int32)
    x = torch.arange(-300, 300, dtype=torch.int32).expand(3, -1).contiguous()
    x = torch.cat([x, torch.tensor([[-(2**30) + 1, 2**30 - 1]] * 3, dtype=torch.int32)], dim=1)
    if velocity > 0:
        expected = torch.where(x > last, 0, x)
    else:
        expected = torch.where(x < 0, last, x)
    assert torch.equal(wrap_around_(x.clone(), last, velocity), expected)
