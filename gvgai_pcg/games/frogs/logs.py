"""How Frogs' many small moving sprites are kept cheap: the log table's slots, the spawn schedule,
the collision key of logs, and the trucks' wrap-around. None of this is a rule of the game; the
rules, in the order they apply, are in :mod:`gvgai_pcg.games.frogs`, which calls these.

Logs live in one entity table. Each spawner owns a ring of slots sized from its position and
cooldown; level logs borrow ring slots that are first written after they are gone, or get slots
of their own before the rings; a last "dump" slot absorbs the writes of spawners that do not
fire. Slot order is therefore not creation order (no rule depends on it). Since every log moves
1 px per tick, a log's first update and its spawn happen at ticks known in advance and are
written into the few slots they concern (:func:`spawn_schedule`), its removal is where its x is
−1, and the frog finds the logs near it by a key that a moving log keeps (:func:`log_key`).

What this relies on and keeps true (tests/games/test_frogs_logs.py checks each):

1. Logs move :data:`LOG_SPEED` = 1 px per tick to the left, from their second update on (RULES.md
   §6.2). This is not a parameter: the key of a moving log stays the same only because x falls
   by 1 exactly as the tick grows by 1, a log's lifetime in ticks (ring sizes, the ring slots
   level logs borrow) is its distance in px plus 2, and a log is at x = −1 in one tick only, the
   tick it is removed in (the cleanup finds it there).
2. A log spawned in tick t sits at its spawner's x in ticks t and t + 1, reaches x = −1 (EOS
   kill) in tick t + x + 2 and is removed at the end of that tick. A spawner fires only at
   multiples of its cooldown, so with :func:`spawner_ring_size` slots its ring slot
   ``(t // cooldown) % size`` is always free when it fires (checked in the tick too).
3. A level log at x0 is gone after tick x0 + 1, so it may take ring slot j of a spawner when
   ``x0 + 2 <= j * cooldown``, the tick that slot is first written (:func:`log_layout`).
4. Keys are ``(y + 10) * 2^20 + x + tick`` in int32: for sprites on rows (y a multiple of 10),
   ``|key − frog key| < 10`` exactly when they overlap; a dead slot's key 0 is never near. Exact
   while the key fits in int32: up to 11 rows for 2e9 ticks.
5. The spawn schedule divides whole float64 numbers (exact below 2^53; integer division is
   slower on the CPU), and the trucks wrap by sign-bit masks in int32 (exact for |x| < 2^30).
"""

from __future__ import annotations

import bisect
from functools import lru_cache
from typing import NamedTuple

import torch
from tensordict import TensorDict

from gvgai_pcg.games.geometry import CELL
from gvgai_pcg.games.lookup import lookup

LOG_SPEED = 1  # px per tick, to the left: fixed, see invariant 1 of the module docstring
LOG_ROW_KEY = 1 << 20  # rows of log keys are 10 * 2^20 apart (see log_key)


def spawner_ring_size(x: torch.Tensor, cooldown: torch.Tensor) -> torch.Tensor:
    """Slots a spawner at pixel column ``x`` needs so that its logs never outnumber them
    (invariant 2): slot ``(t // cooldown) % size`` is free again when ``size * cooldown > x + 2``."""
    return (x + 2).div(cooldown, rounding_mode="floor") + 1


def log_key(x: torch.Tensor, y: torch.Tensor, tick: torch.Tensor | int) -> torch.Tensor:
    """The int32 collision key of a log (or the frog) at ``x, y`` in tick ``tick`` (invariant 4).

    A moving log keeps its key, so keys change only when a log is spawned, makes its first
    (non-moving) update, or dies (key 0).
    """
    return ((y + CELL) * LOG_ROW_KEY + x + tick).to(torch.int32)


class LogLayout(NamedTuple):
    """Where one level's logs live in the log table (see :func:`log_layout`)."""

    slots: tuple[int, ...]  # the slot of each level log (of the level's placed logs, in order)
    bases: tuple[int, ...]  # the first slot of each spawner's ring
    size: int  # slots used, the dump slot not counted


@lru_cache(maxsize=4096)  # per distinct level; generated levels are many
def log_layout(xs: tuple[int, ...], rings: tuple[int, ...], cooldowns: tuple[int, ...]) -> LogLayout:
    """Log slots of one level: level logs at pixel columns ``xs`` (−1: no log, padding) and
    spawner rings of ``rings`` slots (0: no spawner).

    A level log borrows a ring slot it may take (invariant 3): fewest slots, most constrained
    logs first, each taking the earliest ring slot it may; the others get slots of their own
    before the rings. A borrowed slot is free again before its ring first writes it, so the
    guarantee of the rings holds as is.
    """
    free = sorted(
        (j * cooldown, spawner, j)
        for spawner, (ring, cooldown) in enumerate(zip(rings, cooldowns, strict=True))
        for j in range(ring)
    )
    borrowed, own = {}, []
    for log in sorted((k for k, x in enumerate(xs) if x >= 0), key=lambda k: -xs[k]):
        k = bisect.bisect_left(free, (xs[log] + 2,))
        if k < len(free):
            borrowed[log] = free.pop(k)[1:]
        else:
            own.append(log)
    bases = [len(own) + sum(rings[:spawner]) for spawner in range(len(rings))]
    slots = [0] * len(xs)
    for n, log in enumerate(own):
        slots[log] = n
    for log, (spawner, j) in borrowed.items():
        slots[log] = bases[spawner] + j
    return LogLayout(tuple(slots), tuple(bases), len(own) + sum(rings))


def log_tables(spawners: TensorDict, placed: TensorDict, cooldowns: tuple[int, ...]) -> TensorDict:
    """The log table of a batch (``[B, L]``: x, y, row, key, alive, positions int32) from the
    spawners (``[B, S]``, given ``ring`` and ``base`` here) and the logs placed by the levels
    (``[B, P]``), on the CPU."""
    batch = spawners.batch_size[0]
    cooldown = lookup(cooldowns, spawners.get("kind"))
    ring = spawner_ring_size(spawners.get("x"), cooldown) * spawners.get("alive")
    layouts = [
        log_layout(tuple(xs), tuple(rs), tuple(cs))
        for xs, rs, cs in zip(
            torch.where(placed.get("alive"), placed.get("x"), -1).tolist(),
            ring.tolist(),
            cooldown.tolist(),
            strict=True,
        )
    ]
    spawners.set("base", torch.tensor([layout.bases for layout in layouts], dtype=torch.int64).view_as(ring))
    spawners.set("ring", ring)
    capacity = max(layout.size for layout in layouts) + 1  # + the dump slot

    count = placed.batch_size[1]
    slot = torch.tensor([layout.slots for layout in layouts], dtype=torch.int64).view(batch, count)
    slot = torch.where(placed.get("alive"), slot, capacity - 1)
    alive = torch.zeros(batch, capacity, dtype=torch.bool).scatter_(1, slot, placed.get("alive"))
    x = torch.zeros(batch, capacity, dtype=torch.int32).scatter_(1, slot, placed.get("x").to(torch.int32))
    y = torch.zeros(batch, capacity, dtype=torch.int32).scatter_(1, slot, placed.get("y").to(torch.int32))
    key = torch.where(alive, log_key(x, y, 0), 0)
    # ``row`` (y // 10, a lane never changes) spares the tiles renderer working it out from y.
    return TensorDict(
        {"x": x, "y": y, "row": y // CELL, "key": key, "alive": alive}, batch_size=[batch, capacity]
    )


def _floor_mod(a: torch.Tensor, n: torch.Tensor) -> torch.Tensor:
    """``a mod n`` (floor) of whole float64 numbers, by float division (invariant 5)."""
    return a - (a / n).floor_() * n


def spawn_schedule(
    spawners: TensorDict, tick: torch.Tensor, cooldowns: tuple[int, ...]
) -> dict[str, torch.Tensor]:
    """Which spawners (``[B, S]``, of cooldown ``cooldowns[kind]``) are at a spawn tick or at the
    tick after one, and the ring slot these concern (all ``[B, S]``).

    With q = tick // cooldown and r = tick % cooldown: a spawn tick has r = 0 and uses ring slot
    q % ring; the tick after it has r = 1 and the same slot.
    """
    cooldown = lookup(cooldowns, spawners.get("kind"), torch.float64)
    ring = spawners.get("ring").clamp_min(1).to(torch.float64)
    now = tick.to(torch.float64).unsqueeze(-1)
    q = (now / cooldown).floor_()
    r = now - q * cooldown
    return {
        "spawn": r == 0,
        "fresh": r == 1,
        "slot": spawners.get("base") + _floor_mod(q, ring).to(torch.int64),
    }


def wrap_around_(x: torch.Tensor, last: torch.Tensor, velocity: int) -> torch.Tensor:
    """Wrap trucks that just moved ``velocity`` px (int32 ``x`` ``[B, K]``, in place) around each
    env's screen (``last`` ``[B, 1]``: the last x at which a truck is fully on it): one moving
    right and off the right edge (x > last) to 0, one moving left and off the left edge (x < 0)
    to ``last``. Sign-bit masks instead of ``torch.where`` (invariant 5)."""
    if velocity > 0:  # keep x only where x - last - 1 < 0
        return x.bitwise_and_(torch.sub(x, last + 1).bitwise_right_shift_(31))
    # x ^= (x ^ last) where x < 0
    return x.bitwise_xor_(torch.bitwise_xor(x, last).bitwise_and_(x >> 31))
