"""The compiled states of recurring levels, stacked so that a reset gathers them.

Human levels, fixed level lists and a curriculum's replayed levels come back episode after
episode; parsing and compiling them again at every reset would cost more than the tick. The bank
compiles each level once and keeps all of them as the rows of one batched state, so the fresh
states of any number of resets are one gather per state entry.

Where the game's reset tick draws nothing from the RNG (``Game.seed_free_reset_tick``), the
state after it does not depend on the episode seed: the bank then keeps each level started (after
its reset tick, run once when the level comes in) with its first observation, and a reset of a
banked level is a gather with the episode's seed written in, with no tick and no drawing.

A source that mixes new levels with replays (PLR⊥) says how many it may replay
(``LevelSource.replayed_levels``): the bank then has room for them too, and keeps a level only
once it comes back. A new level is compiled directly and remembered (its hash), since most never
come back and would push the replayed ones out: at 64 kept levels and a 300-level buffer, 32 % of
replays found their level gone, and 29 % with room for 364.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import torch
from tensordict import TensorDict

from gvgai_pcg.engine.rows import select_rows
from gvgai_pcg.envs.states import concatenate_states
from gvgai_pcg.games.base import Game, pad_level
from gvgai_pcg.levels import Level

# ``start(compiled)``: compiled envs after their reset tick, and their observations.
Start = Callable[[TensorDict], tuple[TensorDict, torch.Tensor]]
# Levels met once that a bank keeping replays remembers, per level it may keep.
MET_PER_LEVEL = 16
# Started levels keep their first observations where all of them would take at most this much
# (a level's Zelda tiles take 1,053 B, its pixels 35,100 B); else a reset draws them.
OBSERVATIONS_MAX_BYTES = 32 << 20


class CompiledLevelBank:
    """At most ``capacity`` compiled levels (and ``replayed`` more); the least recently used one
    goes first. With ``start`` (for a game whose reset tick is seed-free), each level is kept
    after its reset tick with its observation; with ``replayed``, only once it comes back."""

    def __init__(
        self,
        game: Game,
        height: int,
        width: int,
        device: torch.device,
        capacity: int,
        start: Start | None = None,
        replayed: int = 0,
    ) -> None:
        self.game, self.height, self.width, self.device = game, height, width, device
        self.capacity, self.start = capacity + replayed, start
        # hashes of the levels met once, oldest first, where only levels that come back are kept
        self._met: dict[int, None] | None = {} if replayed > 0 else None
        self._rows: dict[Level, int] = {}
        self._last_used: dict[Level, int] = {}
        self._uses = 0
        self._bank: TensorDict | None = None
        self._observations: torch.Tensor | None = None  # [rows, ...], where the levels are started

    def __len__(self) -> int:
        return len(self._rows)

    def __contains__(self, level: Level) -> bool:
        return level in self._rows

    def fresh_states(
        self, levels: Sequence[Level], seeds: torch.Tensor, recurring: bool
    ) -> tuple[TensorDict, bool, torch.Tensor | None]:
        """The states of ``levels`` with episode ``seeds``, whether they are started (after their
        reset tick; else the caller runs it) and their observations where the bank keeps them
        (started levels whose observations are small enough), else None. Levels that
        recur (human levels, a fixed list, replays) come from the bank, so their resets cost a
        gather, not a parse; a batch of mostly unseen levels is compiled in one call, and so are
        the levels of a source whose levels do not recur (``recurring`` False: generated ones),
        which the bank would only churn through."""
        unseen = [level for level in set(levels) if level not in self]
        if not recurring or len(unseen) > max(1, len(levels) // 2) or self._met_first(unseen):
            padded = [pad_level(lv, self.height, self.width) for lv in levels]
            return self.game.compile(padded, seeds, self.device), False, None
        states, observed = self._gather(levels, seeds)
        return states, self.start is not None, observed

    def initial_states(self, levels: Sequence[Level], seeds: torch.Tensor) -> TensorDict:
        """The banked states of ``levels`` with episode ``seeds`` (before their reset tick, or
        after it where the bank starts its levels)."""
        return self._gather(levels, seeds)[0]

    def _met_first(self, unseen: list[Level]) -> bool:
        """Whether some of ``unseen`` is met for the first time (and remembered now), where the
        bank keeps only levels that come back; such a reset compiles its levels directly."""
        if self._met is None:
            return False
        first = [key for key in map(hash, unseen) if key not in self._met]
        self._met.update(dict.fromkeys(first))
        while len(self._met) > MET_PER_LEVEL * self.capacity:
            del self._met[next(iter(self._met))]  # the oldest
        return bool(first)

    def _gather(self, levels: Sequence[Level], seeds: torch.Tensor) -> tuple[TensorDict, torch.Tensor | None]:
        """The rows of ``levels`` (added first where missing) with episode ``seeds``, and their
        observations where the bank keeps them."""
        self._uses += 1
        distinct = dict.fromkeys(levels, self._uses)
        self._last_used.update(distinct)
        missing = [level for level in distinct if level not in self._rows]
        if missing:
            self._add(missing, keep=set(distinct))
        rows = torch.tensor(list(map(self._rows.__getitem__, levels)), device=self.device)
        states = select_rows(self._bank, rows)
        states.set("seed", seeds.to(self.device))
        observed = None if self._observations is None else self._observations.index_select(0, rows)
        return states, observed

    def _add(self, levels: list[Level], keep: set[Level]) -> None:
        """Compile ``levels`` (and start them, with ``start``) into the bank, then drop the least
        recently used levels not in ``keep`` beyond the capacity. The bank changes by one gather
        of the rows it keeps (where levels go) and one concatenation with the new rows:
        rebuilding it from every level's state took about 46 ms an added level at 64 levels,
        most of a PLR⊥ or ACCEL run's time, where most resets bring a level the bank has not
        seen (one-env resets; docs/history/benchmarks-notebook.md, "The level bank adds a level
        without rebuilding itself")."""
        zero = torch.zeros(1, dtype=torch.int64)
        new = [
            self.game.compile([pad_level(lv, self.height, self.width)], zero, self.device) for lv in levels
        ]
        observed = None
        if self.start is not None:
            started, observed = self.start(new[0] if len(new) == 1 else concatenate_states(new))
            new = [started]
            if observed[0].numel() * observed.element_size() * self.capacity > OBSERVATIONS_MAX_BYTES:
                observed = None
        order = list(self._rows)  # the bank's levels, in row order
        stale = sorted((lv for lv in order if lv not in keep), key=self._last_used.__getitem__)
        going = set(stale[: max(0, len(order) + len(levels) - self.capacity)])
        kept = [lv for lv in order if lv not in going]
        for level in going:
            del self._last_used[level]
        bank, observations = self._bank, self._observations
        if going and kept:
            rows = torch.tensor([self._rows[lv] for lv in kept], device=self.device)
            bank = select_rows(bank, rows)
            observations = observations.index_select(0, rows) if observations is not None else None
        self._bank = concatenate_states([bank, *new] if kept else new)
        if observed is not None:
            self._observations = torch.cat([observations, observed] if kept else [observed])
        self._rows = {level: row for row, level in enumerate([*kept, *levels])}
