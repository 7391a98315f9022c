"""One tick's working view of the state: the sprites a rule names, where each is, and this tick's
kill marks.

Java kills a sprite during the event phase by putting it on a kill list: it stays a second of
later rules until cleanup, and is skipped as a first. A killed avatar is only disabled: it stays
a first too (and keeps scoring) until cleanup. The marks live here, not in the state, and
``cleanup`` applies them. A rule's types are split by where they live (``Side``): one entry per
record, table group or grid, in the rule's ``iSubTypes`` order.

**Narrowed tables.** A table is as wide as its capacity, but its sprites sit in its first slots
(a level's in slot order, a created one in the first free slot). Eagerly on the CPU
(``reads_back``), the frame hands the kernels only a table's occupied prefix (``narrow``: the
slots up to the last one alive in any env, rounded up to a power of two) and puts the untouched
rest back when it writes the state; a creation that needs more free slots than the prefix holds
widens it first (``make_room``). No kernel reads a free slot past the prefix (they mask by
``alive``, and a creation resets every column of the slot it takes), so the tick is the same;
compiled (or on a GPU), the tables keep their width.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from functools import cache

import torch
from tensordict import TensorDict

from gvgai_pcg._private_apis import entries, write_entries
from gvgai_pcg.games.geometry import covered_cells, overlaps, overlaps_aligned
from gvgai_pcg.vgdl.engine.cells import aligned_cell
from gvgai_pcg.vgdl.engine.layout import Layout
from gvgai_pcg.vgdl.engine.off_grid import off_key, off_overlaps
from gvgai_pcg.vgdl.layout import GRID, RECORD

# Aligned firsts x seconds of at least this many pairs are counted by sorting, not pairwise
# (Solarfox's 64 powerblibs x 8 turnings: 0.08 -> 0.11 of the hand-written at 1,024 envs, even at 64).
SORT_PAIRS = 256
POSITION_KEY = 1 << 32  # x * POSITION_KEY + y: one int64 per position
# Tables narrower than this are used whole; a narrowed one keeps at least half of it.
NARROW_FROM = 16
# The entries every state has that a tick reads or writes.
COMMON = ("seed", "tick", "score", "won", "lost", "height", "width")


@dataclass(frozen=True)
class Side:
    """The sprites of some of a rule's types that live in one state entry ``key``; ``kinds`` are
    the kind codes it selects of a table group."""

    representation: str
    key: str
    kinds: tuple[int, ...]
    aligned: bool


def sides(layout: Layout, leaves: tuple[str, ...]) -> list[Side]:
    """``leaves`` grouped by the entry that holds them, in order of first appearance."""
    found: dict[str, list[str]] = {}
    for name in leaves:
        if name not in layout.places:  # a type that never has sprites
            continue
        found.setdefault(layout.places[name].key, []).append(name)
    result = []
    for key, names in found.items():
        place = layout.places[names[0]]
        aligned = all(layout.plan.types[name].aligned for name in names)
        kinds = tuple(layout.places[name].kind for name in names)
        result.append(Side(place.representation, key, kinds, aligned))
    return result


class Entry:
    """A record's or a table's fields for one tick, as plain tensors: a ``TensorDict``'s ``get``
    and ``set`` cost more than most of the tick's ops, so the frame reads each field once and
    writes back only what changed (``Frame.write``)."""

    def __init__(self, values: dict[str, torch.Tensor]) -> None:
        self.values = dict(values)
        self.changed: dict[str, torch.Tensor] = {}

    def get(self, field: str) -> torch.Tensor:
        return self.values[field]

    def set(self, field: str, value: torch.Tensor) -> None:
        self.values[field] = self.changed[field] = value

    def update(self, values: dict[str, torch.Tensor]) -> None:
        for field, value in values.items():
            self.set(field, value)


class Frame:
    """The state of one tick and its kill marks (see the module docstring)."""

    def __init__(self, layout: Layout, state: TensorDict) -> None:
        self.layout, self.state = layout, state
        top = entries(state)
        spills = (off_key(name) for name in layout.spills)
        keys = (*layout.records, *(group.key for group in layout.tables), *spills)
        self.entries = {key: Entry(entries(top[key])) for key in keys}
        self.values = {key: top[key] for key in (*COMMON, *layout.grids)}
        self.changed: dict[str, torch.Tensor] = {}
        self.killed: dict[str, torch.Tensor] = {}  # per entry: [B] / [B, K] bool, grids [B, H, W] uint8
        self.disabled: dict[str, torch.Tensor] = {}  # per avatar record, [B] bool
        # shieldFrom's shields, per (first leaf, stype, effect name): [B] bool (``shield``)
        self.shields: dict[tuple[str, str, str], torch.Tensor] = {}
        self.skip: torch.Tensor | None = None  # [B]: envs where the rule being applied is shielded
        self._cells: dict[tuple, tuple] = {}  # ``cells``' results this tick
        self._record_xy: dict[str, tuple] = {}  # ``xy`` of the records
        self.draws: dict[str, tuple] = {}  # a spawning table's draws this tick (``spawn_effects``)
        # narrowed tables (see the module docstring): their columns at full width
        self.full: dict[str, dict[str, torch.Tensor]] = {}
        if reads_back(self.values["score"]):
            sources = set(layout.spills.values())  # their spills share their slots: kept whole
            for group in layout.tables:
                # a table nothing creates into holds its level's sprites: it seldom narrows
                made = any(layout.plan.types[name].created_by for name in group.kinds)
                if made and group.key not in sources:
                    self.narrow(group.key)

    def value(self, key: str) -> torch.Tensor:
        """A top-level entry: a common one (``tick``, ``score``...) or a grid."""
        return self.values[key]

    def put(self, key: str, value: torch.Tensor) -> None:
        self.values[key] = self.changed[key] = value

    def narrow(self, key: str) -> None:
        """Hand the kernels only table ``key``'s occupied prefix (eager only: it reads one
        number back from the tensors)."""
        entry = self.entries[key]
        alive = entry.get("alive")
        width = alive.shape[-1]
        if width < NARROW_FROM:
            return
        used = int(
            (alive.any(0) * _ranks(width, alive.device)).max()
        )  # one past the last slot alive in any env
        slots = max(NARROW_FROM // 2, 1 << used.bit_length())  # at least one free slot more
        if slots >= width:
            return
        self.full[key] = entry.values
        entry.values = {column: value[:, :slots] for column, value in entry.values.items()}

    def widen(self, key: str, in_place: bool = False) -> None:
        """Give table ``key`` back its full width: its prefix as the kernels left it, then the
        untouched rest. ``in_place`` (the tick's end) writes a changed prefix into the state's
        own column, where no other column shares that column's memory."""
        full = self.full.pop(key, None)
        if full is None:
            return
        entry = self.entries[key]
        slots = entry.get("alive").shape[-1]
        shared = Counter(_memory(value) for value in full.values())
        values, copies = dict(full), {}
        for column, value in entry.changed.items():
            target = full[column]
            if in_place and shared[_memory(target)] == 1 and target.is_contiguous():
                # a value read from the state (``lastx := x``) is copied before any column is written
                copies[column] = value.clone() if _memory(value) in shared else value
            else:
                values[column] = torch.cat([value, target[:, slots:]], 1)
        for column, value in copies.items():
            full[column][:, :slots].copy_(value)
        entry.values = values
        entry.changed = {column: values[column] for column in entry.changed}
        mask = self.killed.get(key)
        if mask is not None:
            rest = torch.zeros_like(full["alive"][:, slots:])
            self.killed[key] = torch.cat([mask, rest], 1)

    def make_room(self, key: str, count: torch.Tensor) -> None:
        """Widen narrowed table ``key`` where some env makes more sprites (``count``, ``[B, N]``)
        than its prefix has free slots."""
        if key in self.full and bool((count.sum(-1) > (~self.entries[key].get("alive")).sum(-1)).any()):
            self.widen(key)

    def write(self) -> None:
        """Write what changed back into the state, unchecked: every kernel keeps a field's shape
        and dtype."""
        for key in list(self.full):
            self.widen(key, in_place=True)
        write_entries(self.state, self.changed)
        top = entries(self.state)
        for key, entry in self.entries.items():
            if entry.changed:
                write_entries(top[key], entry.changed)

    # --- positions and presence, records seen as tables of one slot ([B, 1]) ---
    def entry(self, key: str) -> Entry:
        return self.entries[key]

    def xy(self, side: Side) -> tuple[torch.Tensor, torch.Tensor]:
        """Positions ``[B, N]``; a record's the same tensors while it stays put (``cells``)."""
        entry = self.entry(side.key)
        x, y = entry.get("x"), entry.get("y")
        if side.representation != RECORD:
            return x, y
        if torch.compiler.is_compiling():
            return x.unsqueeze(-1), y.unsqueeze(-1)
        known = self._record_xy.get(side.key)
        if known is None or known[0] is not x or known[1] is not y:
            known = self._record_xy[side.key] = (x, y, x.unsqueeze(-1), y.unsqueeze(-1))
        return known[2], known[3]

    def present(self, side: Side) -> torch.Tensor:
        """Sprites of ``side`` that exist this tick (killed ones included: they are still seconds)."""
        entry = self.entry(side.key)
        if side.representation == RECORD:
            return entry.get("alive").unsqueeze(-1)
        alive = entry.get("alive")
        group = self.layout.group(side.key)
        if len(side.kinds) == len(group.kinds):
            return alive
        kind = entry.get("kind")
        chosen = kind == side.kinds[0]
        for code in side.kinds[1:]:
            chosen = chosen | (kind == code)
        return alive & chosen

    def killed_mask(self, side: Side) -> torch.Tensor:
        """This tick's kill marks of ``side``'s entry, shaped like ``present``."""
        mask = self.killed.get(side.key)
        if mask is None:
            return torch.zeros_like(self.present(side))
        return mask.unsqueeze(-1) if side.representation == RECORD else mask

    def eligible(self, side: Side) -> torch.Tensor:
        """Sprites that may still be a rule's first: present and not killed (a disabled avatar is),
        in an env where the rule is not shielded."""
        eligible = self.present(side)
        if side.key in self.killed:
            eligible = eligible & ~self.killed_mask(side)
        if self.skip is not None:
            eligible = eligible & ~self.skip.unsqueeze(-1)
        return eligible

    def kill(self, side: Side, mask: torch.Tensor) -> None:
        """Mark ``mask`` (shaped like ``present``) killed; an avatar record is disabled instead."""
        if side.representation == RECORD:
            mask = mask.squeeze(-1)
            if side.key in self.layout.avatars:
                self.disabled[side.key] = self.disabled.get(side.key, torch.zeros_like(mask)) | mask
                return
        self.mark_killed(side.key, mask)

    def mark_killed(self, key: str, mask: torch.Tensor) -> None:
        """Put ``mask`` on the kill list of entry ``key`` (Java's kill list: also for an avatar
        that is transformed)."""
        previous = self.killed.get(key)
        self.killed[key] = mask if previous is None else previous | mask

    def is_disabled(self, key: str) -> torch.Tensor | None:
        return self.disabled.get(key)

    def disabled_mask(self, side: Side) -> torch.Tensor:
        """Sprites of ``side`` that Java skips as a transform's first (a disabled avatar), shaped
        like ``present``."""
        disabled = self.disabled.get(side.key) if side.representation == RECORD else None
        return torch.zeros_like(self.present(side)) if disabled is None else disabled.unsqueeze(-1)

    def add_score(self, delta: torch.Tensor) -> None:
        self.put("score", self.value("score") + delta)

    # --- grids ---
    def grid(self, key: str) -> torch.Tensor:
        return self.values[key]

    def grid_killed(self, key: str) -> torch.Tensor:
        killed = self.killed.get(key)
        return torch.zeros_like(self.grid(key)) if killed is None else killed

    def cell_counts(
        self, key: str, x: torch.Tensor, y: torch.Tensor, aligned: bool
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """Sprites of grid ``key`` in the cells rectangles at ``x, y`` (``[B, N]``) cover: the flat
        cells ``[B, N, c]`` and their counts ``[B, N, c]`` (zero for cells off the grid; one cell
        for aligned rectangles, else up to four, row-major)."""
        grid = self.grid(key)
        batch, height, width = grid.shape
        index, valid = self.cells(x, y, aligned, height, width)
        counts = torch.gather(grid.reshape(batch, -1), 1, index.reshape(batch, -1)).view(index.shape)
        return index, counts * valid

    def cells(
        self, x: torch.Tensor, y: torch.Tensor, aligned: bool, height: int, width: int
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """``aligned_cell`` or ``covered_cells`` of ``x, y``, once a tick for the same position
        tensors (the avatar against several grids, rule after rule: about 30 ops each time)."""
        if torch.compiler.is_compiling():  # a graph computes it once anyway (common subexpressions)
            return (aligned_cell if aligned else covered_cells)(x, y, height, width)
        key = (id(x), id(y), aligned, height, width)
        known = self._cells.get(key)
        if known is None or known[0] is not x or known[1] is not y:
            cover = aligned_cell if aligned else covered_cells
            known = self._cells[key] = (x, y, cover(x, y, height, width))  # holds x, y: ids stay theirs
        return known[2]

    # --- overlaps of firsts with a side of seconds ---
    def overlap_matrix(
        self, x: torch.Tensor, y: torch.Tensor, aligned: bool, first: Side, second: Side
    ) -> torch.Tensor:
        """``[B, N, K]`` bool: first sprite n (at ``x, y``, ``[B, N]``) overlaps present second k of
        ``second`` (a record or table; a sprite never overlaps itself)."""
        sx, sy = self.xy(second)
        test = overlaps_aligned if aligned and second.aligned else overlaps
        meets = test(x.unsqueeze(-1), y.unsqueeze(-1), sx.unsqueeze(-2), sy.unsqueeze(-2))
        meets = meets & self.present(second).unsqueeze(-2)
        if first.key == second.key:
            size = meets.shape[-1]
            meets = meets & ~torch.eye(size, dtype=torch.bool, device=meets.device)
        return meets

    def overlap_count(
        self, x: torch.Tensor, y: torch.Tensor, aligned: bool, first: Side, seconds: list[Side]
    ) -> torch.Tensor:
        """``[B, N]`` int64: how many present seconds each first sprite at ``x, y`` overlaps."""
        terms = []
        for second in seconds:
            if second.representation == GRID:
                terms.append(self.cell_counts(second.key, x, y, aligned)[1].sum(-1))
                if second.key in self.layout.spills:  # its sprites off the array
                    off = self.entry(off_key(second.key)).values
                    terms.append(off_overlaps(off, None, x, y, aligned).sum(-1))
            elif aligned and second.aligned and first.key != second.key and self._wide(x, second):
                terms.append(self.same_cell_count(x, y, second))
            else:
                terms.append(self.overlap_matrix(x, y, aligned, first, second).sum(-1))
        if not terms:
            return torch.zeros_like(x, dtype=torch.int64)
        total = terms[0]
        for term in terms[1:]:
            total = total + term
        return total

    def _wide(self, x: torch.Tensor, second: Side) -> bool:
        """Whether firsts ``x`` against ``second`` make a pairwise matrix worth sorting instead."""
        return x.shape[-1] * self.xy(second)[0].shape[-1] >= SORT_PAIRS

    def same_cell_count(self, x: torch.Tensor, y: torch.Tensor, second: Side) -> torch.Tensor:
        """``[B, N]``: present seconds at each aligned first's own position (two cell-aligned
        sprites overlap where they are at the same place), by sorting the seconds' positions."""
        sx, sy = self.xy(second)
        keys = torch.where(self.present(second), sx * POSITION_KEY + sy, torch.iinfo(torch.int64).max)
        keys = keys.sort(-1).values
        wanted = x * POSITION_KEY + y
        return torch.searchsorted(keys, wanted, right=True) - torch.searchsorted(keys, wanted)

    # --- cleanup ---
    def cleanup(self) -> None:
        """Remove the killed sprites and the disabled avatars."""
        for key, mask in self.killed.items():
            if self.layout.representation(key) == GRID:
                self.put(key, self.grid(key) - mask)
            else:
                entry = self.entry(key)
                entry.set("alive", entry.get("alive") & ~mask)
        for key, mask in self.disabled.items():
            entry = self.entry(key)
            entry.set("alive", entry.get("alive") & ~mask)


@cache
def _ranks(width: int, device: torch.device) -> torch.Tensor:
    """1, 2, ... ``width``, made once: never write to it."""
    return torch.arange(1, width + 1, device=device)


def reads_back(tensor: torch.Tensor) -> bool:
    """Whether the tick may read a number back from ``tensor`` to shrink its work: eagerly on
    the CPU, where that costs about a microsecond (a graph cannot; on a GPU it would wait for the
    device, and that has not been measured)."""
    return tensor.device.type == "cpu" and not torch.compiler.is_compiling()


def _memory(tensor: torch.Tensor) -> int:
    """Where ``tensor``'s storage starts: two tensors that share memory give the same number."""
    return tensor.untyped_storage().data_ptr()
