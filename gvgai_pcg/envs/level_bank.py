"""The compiled initial states of recurring levels, stacked so that a reset gathers them.

Human levels and fixed level lists come back episode after episode; parsing and compiling them
again at every reset would cost more than the tick. The bank compiles each level once and keeps
all of them as the rows of one batched state, so the fresh states of any number of resets are
one gather per state entry.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch
from tensordict import TensorDict

from gvgai_pcg.engine.rows import select_rows
from gvgai_pcg.envs.states import concatenate_states
from gvgai_pcg.games.base import Game, pad_level
from gvgai_pcg.levels import Level


class CompiledLevelBank:
    """At most ``capacity`` compiled levels; the least recently used one goes first."""

    def __init__(self, game: Game, height: int, width: int, device: torch.device, capacity: int) -> None:
        self.game, self.height, self.width, self.device = game, height, width, device
        self.capacity = capacity
        self._rows: dict[Level, int] = {}
        self._last_used: dict[Level, int] = {}
        self._uses = 0
        self._bank: TensorDict | None = None

    def __len__(self) -> int:
        return len(self._rows)

    def __contains__(self, level: Level) -> bool:
        return level in self._rows

    def fresh_states(self, levels: Sequence[Level], seeds: torch.Tensor, recurring: bool) -> TensorDict:
        """The initial states of ``levels``. Levels that recur (human levels, a fixed list) come
        from the bank, so their resets cost a gather, not a parse; a batch of mostly unseen levels
        is compiled in one call, and so are the levels of a source whose levels do not recur
        (``recurring`` False: generated ones), which the bank would only churn through."""
        unseen = [level for level in set(levels) if level not in self]
        if not recurring or len(unseen) > max(1, len(levels) // 2):
            padded = [pad_level(lv, self.height, self.width) for lv in levels]
            return self.game.compile(padded, seeds, self.device)
        return self.initial_states(levels, seeds)

    def initial_states(self, levels: Sequence[Level], seeds: torch.Tensor) -> TensorDict:
        """The states of ``levels`` before their reset tick, with episode ``seeds``."""
        self._uses += 1
        distinct = dict.fromkeys(levels, self._uses)
        self._last_used.update(distinct)
        missing = [level for level in distinct if level not in self._rows]
        if missing:
            self._add(missing, keep=set(distinct))
        rows = torch.tensor(list(map(self._rows.__getitem__, levels)), device=self.device)
        states = select_rows(self._bank, rows)
        states.set("seed", seeds.to(self.device))
        return states

    def _add(self, levels: list[Level], keep: set[Level]) -> None:
        """Compile ``levels`` into the bank, then drop the least recently used levels not in
        ``keep`` beyond the capacity. The bank changes by one gather of the rows it keeps (where
        levels go) and one concatenation with the new rows: rebuilding it from every level's
        state took about 46 ms an added level at 64 levels, most of a PLR⊥ or ACCEL run's time,
        where most resets bring a level the bank has not seen (one-env resets; docs/history/
        benchmarks-notebook.md, "The level bank adds a level without rebuilding itself")."""
        zero = torch.zeros(1, dtype=torch.int64)
        new = [
            self.game.compile([pad_level(lv, self.height, self.width)], zero, self.device) for lv in levels
        ]
        order = list(self._rows)  # the bank's levels, in row order
        stale = sorted((lv for lv in order if lv not in keep), key=self._last_used.__getitem__)
        going = set(stale[: max(0, len(order) + len(levels) - self.capacity)])
        kept = [lv for lv in order if lv not in going]
        for level in going:
            del self._last_used[level]
        bank = self._bank
        if going and kept:
            bank = select_rows(bank, torch.tensor([self._rows[lv] for lv in kept], device=self.device))
        self._bank = concatenate_states([bank, *new] if kept else new)
        self._rows = {level: row for row, level in enumerate([*kept, *levels])}
