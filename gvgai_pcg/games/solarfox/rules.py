"""Solarfox (RULES.md §5): fly the ship over every blib and powerblib, never touching a wall,
the enemy lanes, the two enemies or their shots.

The ship (OngoingAvatar) moves 1 px per tick, so its position is usually not cell-aligned; every
other sprite is. Static and cell-aligned sprites are ``[B, H, W]`` grids (walls, enemyground,
blibs, powerblibs with their "res" counter, powerblibturning flickers by their creation tick, and
the turnings shown); the enemies (by cell), with their shots, are an entity table. Rules 1-9 only
touch cells near the ship, so the tick gathers those from the grids and scatters them back, and
keeps the count of blibs and powerblibs left for the WIN check. One tick is RULES.md §1.3 in
this order:

* step 2, the ship: a direction sets the heading at once, then it moves 1 px (not at tick 0);
* step 3, shots (move 1 px per tick from their second update), enemies (10 px every 3 ticks),
  powerblibturning (Flicker, limit 8: its age is implicit in its creation tick);
* step 4, the collision rules in declaration order: 1 avatar × wall, 2 avatar × enemy,
  3 avatar × enemyground, 4 avatar × shot (kill the ship, −10 per sprite overlapped; the disabled
  ship keeps colliding for the rest of the tick, so they stack) · 5 blib × avatar (collect, +1) ·
  6a powerblib × powerblibturning spawn a blib if res ≥ 2, then 6b res += 1 (≤ 4) · 7 powerblibturning
  × avatar (kill) · 8 powerblib × blib (kill the powerblib, +1) · 9 powerblib × avatar (create a
  powerblibturning) · 10 enemy × wall (reverse) · 11 btm × enemyground, 12 top × enemyground
  (create an upshot / a downshot with probability 0.02);
* step 5, cleanup; step 6, termination: no ship → LOSE, then no blib and no powerblib → WIN.

Shots are never removed in GVGAI. Here a shot is dropped once it is off screen and behind the
ship's reach (see :func:`Solarfox._cleanup`), which changes nothing an agent can observe, and
each enemy owns ``SHOTS_PER_ENEMY`` slots for its shots: a table nested in its slot of the enemy
table (``("enemies", "shots")``, leaves ``[B, E, SHOTS_PER_ENEMY]``), so that whatever grows the
enemy table (padding, merging, the power-of-two widths of a compiled tick) grows the shots with it.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import torch
from tensordict import TensorDict

from gvgai_pcg.games import rng
from gvgai_pcg.games.actions import MOVE_ACTIONS, move_direction
from gvgai_pcg.games.base import (
    Game,
    GridLayer,
    SpriteArt,
    SpriteLayer,
    avatar_cell,
    char_entities,
    char_grid,
    common_state,
    golden_record,
    on_device,
    single_sprite_layer,
)
from gvgai_pcg.games.geometry import (
    CELL,
    DIRECTION_NAMES,
    NONE,
    RIGHT,
    any_last,
    cell_of,
    count_last,
    direction_dx,
    direction_dy,
    flat_cell,
    overlaps,
    write_rows_,
)
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.games.registry import register_game
from gvgai_pcg.levels import Level

# Enemy kinds in update order (btm before top, RULES.md §5.2).
BTM, TOP = 0, 1
ENEMY_TYPES = ("btm", "top")
ENEMY_CHARS = {"1": BTM, "2": TOP}
ENEMY_START_DX = (-1, 1)  # btm faces LEFT, top faces RIGHT
ENEMY_COOLDOWN = 3
SHOT_PROBABILITY = 0.02
SHOT_DY = (-1, 1)  # btm fires upshots, top fires downshots, 1 px per tick
# Shot slots owned by each enemy. A shot is on screen for 112 ticks (spawn tick, first-update skip,
# 110 px), so an enemy needs more than 16 with probability ~1e-10 per tick (Binomial(112, 0.02)); a
# shot that finds no free slot of its enemy is not created.
SHOTS_PER_ENEMY = 16
TURNING_LIFE = 10  # powerblibturning (Flicker, limit 8) is killed at the update of tick born + 10
# Cells per axis of the window around the ship that holds every live powerblibturning (_pair_turnings).
WINDOW = 4
RES_LIMIT = 4  # the powerblib's "res" counter capacity
BLIB_AT_RES = 2  # spawnIfHasMore limit of rule 6a
DEATH_SCORE = -10
NO_TURNING = -(1 << 20)  # turning_born of a cell without a powerblibturning
STREAM_SHOT = 1


def _window_span(pos: torch.Tensor, count: int) -> tuple[torch.Tensor, torch.Tensor]:
    """Along one axis of ``count`` cells: the ``min(4, count)`` consecutive cells from one before
    the cell holding ``pos`` (``[N]``), shifted to lie inside the grid (``[N, n]`` int64), and which
    of them a 10-px span starting at ``pos`` overlaps (strictly, RULES.md §1.1)."""
    n = min(WINDOW, count)
    first = (cell_of(pos) - 1).clamp(0, count - n)
    cells = first.unsqueeze(-1) + torch.arange(n, device=pos.device)
    start, pos = CELL * cells, pos.unsqueeze(-1)
    return cells, (start < pos + CELL) & (pos < start + CELL)


@cache
def _ship_tables(height: int, width: int, device: str) -> dict[str, torch.Tensor]:
    """Cell look-ups for every ship position, made once per grid size. Row ``(y + 2 CELL) X + x +
    2 CELL`` (``X = CELL * width + 3 CELL + 1`` positions per row) is for a ship at (x, y) clamped
    to ``[-2 CELL, CELL * size + CELL]`` (:func:`_window_rows`); beyond that nothing changes.

    * ``window`` ``[P, K]``: flat indices of the window (see :meth:`Solarfox._pair_turnings`);
    * ``under`` ``[P, 4]``: flat indices of the cells of the grid the ship overlaps, each once and
      first; the other entries repeat the first, so a scatter of values that depend only on the
      cell writes exactly the overlapped cells (if the ship overlaps none, all are one arbitrary
      cell, where the callers write back its old value);
    * ``counted`` ``[P, 4]``: which entries of ``under`` are those distinct overlapped cells;
    * ``covered`` ``[P, K]``: which cells of ``window`` the ship overlaps (for a compiled tick).
    """
    xs = torch.arange(-2 * CELL, CELL * width + CELL + 1)
    ys = torch.arange(-2 * CELL, CELL * height + CELL + 1)
    cols, over_x = _window_span(xs, width)
    rows, over_y = _window_span(ys, height)
    window = (width * rows[:, None, :, None] + cols[None, :, None, :]).flatten(2).flatten(0, 1)
    covered = (over_y[:, None, :, None] & over_x[None, :, None, :]).flatten(2).flatten(0, 1)
    first = torch.sort((~covered).to(torch.uint8), dim=-1, stable=True).indices[:, :4]
    counted = covered.gather(1, first)
    under = torch.where(counted, window.gather(1, first), window.gather(1, first[:, :1]))
    tables = {"window": window, "under": under, "counted": counted, "covered": covered}
    # Whole tensors, not views: a compiled tick guards on the base of a view it takes.
    return {key: value.to(device).clone() for key, value in tables.items()}


def _window_rows(x: torch.Tensor, y: torch.Tensor, height: int, width: int) -> torch.Tensor:
    """Rows of :func:`_ship_tables` for ships at ``x, y`` (``[B]``)."""
    x = x.clamp(-2 * CELL, CELL * width + CELL) + 2 * CELL
    y = y.clamp(-2 * CELL, CELL * height + CELL) + 2 * CELL
    return y * (CELL * width + 3 * CELL + 1) + x


@register_game("solarfox")
class Solarfox(Game):
    actions = MOVE_ACTIONS
    tile_types = (
        "wall",
        "enemyground",
        "powerblib",
        "powerblibturning",
        "blib",
        "top",
        "btm",
        "upshot",
        "downshot",
        "avatar",
    )
    art = {
        "floor": SpriteArt((40, 40, 40)),
        "enemyground": SpriteArt((30, 60, 160)),
        "powerblib": SpriteArt((0, 200, 0), "diamond"),
        "powerblibturning": SpriteArt((200, 255, 200), "cross"),
        "blib": SpriteArt((0, 220, 220), "dot"),
        "top": SpriteArt((200, 40, 200), "circle"),
        "btm": SpriteArt((200, 40, 120), "circle"),
        "upshot": SpriteArt((250, 120, 0), "small"),
        "downshot": SpriteArt((250, 60, 0), "small"),
        "wall": SpriteArt((110, 90, 70)),
        "avatar": SpriteArt((250, 250, 0), "circle", oriented=True),
    }

    def compile(self, levels: Sequence[Level], seeds: torch.Tensor, device: torch.device) -> TensorDict:
        batch = len(levels)
        ax, ay = avatar_cell(levels, "A")
        # Enemies are always cell-aligned (they start on a cell and move 10 px), so the table holds
        # their cell (col, row); x = 10 col, y = 10 row.
        placed = char_entities(levels, ENEMY_CHARS, device, capacity=1)
        kind = placed.get("kind")
        enemies = {
            "kind": kind,
            "alive": placed.get("alive"),
            "col": (placed.get("x") // CELL).to(torch.int32),
            "row": (placed.get("y") // CELL).to(torch.int32),
            "dx": lookup(ENEMY_START_DX, kind, torch.int32).clone(),  # not a view (see _ship_tables)
        }
        # Each enemy's shots, in its own slot's block of SHOTS_PER_ENEMY (a table nested in the
        # enemy table: it grows with it). Positions are int32 here and in the ship and enemy
        # tables: the shot table is the widest.
        slots = (batch, kind.shape[1], SHOTS_PER_ENEMY)
        shots = {
            "x": torch.zeros(slots, dtype=torch.int32),
            "y": torch.zeros(slots, dtype=torch.int32),
            # The owner's shot direction: -1 for the upshots of btm, +1 for the downshots of top.
            "dy": lookup(SHOT_DY, kind.cpu(), torch.int32).unsqueeze(-1).expand(slots).clone(),
            "alive": torch.zeros(slots, dtype=torch.bool),
            "fresh": torch.zeros(slots, dtype=torch.bool),  # created this tick: no move next update
        }
        enemies["shots"] = on_device(device, shots, placed.batch_size)
        avatar = {
            "x": ax.to(torch.int32),
            "y": ay.to(torch.int32),
            "ori": torch.full((batch,), RIGHT, dtype=torch.int64),
            "alive": torch.ones(batch, dtype=torch.bool),
        }
        wall = char_grid(levels, "w", device)
        ground = char_grid(levels, ".12", device)
        blib, powerblib = char_grid(levels, "b", device), char_grid(levels, "p", device)
        state = {
            **common_state(levels, seeds, device),
            "wall": wall,
            "enemyground": ground,
            "deadly": wall | ground,  # a cell holds a wall or an enemyground, never both
            "floor": char_grid(levels, "+bpA12", device),
            "blib": blib,
            "powerblib": powerblib,
            # Blibs + powerblibs on the grid (never on the same cell), for the WIN check.
            "pickups": (blib | powerblib).flatten(1).sum(-1, dtype=torch.int32),
            "res": torch.zeros(wall.shape, dtype=torch.int8, device=device),
            "turning_born": torch.full(wall.shape, NO_TURNING, dtype=torch.int32, device=device),
            # The turnings shown after the last tick: one created in tick born is killed by its
            # Flicker update (limit 8) in tick born + 10, so it is shown after ticks born … born + 9.
            "turning": torch.zeros(wall.shape, dtype=torch.bool, device=device),
            # The last tick in which a turning was created (rule 9): 6a/6b run where it is recent.
            "turning_last": torch.full((batch,), NO_TURNING, dtype=torch.int32, device=device),
            "avatar": on_device(device, avatar, [batch]),
            "enemies": on_device(device, enemies, placed.batch_size),
        }
        return on_device(device, state, [batch])

    def host_arguments(self, state: TensorDict) -> dict[str, object]:
        """The ship's cell look-ups for this batch's grid size (:func:`_ship_tables`, cached): inputs
        of a compiled tick, which with dynamic shapes would rebuild them in every call."""
        wall = state.get("wall")
        return dict(_ship_tables(wall.shape[1], wall.shape[2], str(wall.device)))

    def tick(self, state: TensorDict, action: torch.Tensor, **tables: torch.Tensor) -> None:
        """RULES.md §1.3; ``tables`` are :meth:`host_arguments` (worked out here when not given)."""
        if not tables:
            tables = self.host_arguments(state)
        tick = state.get("tick") + 1
        state.set("tick", tick)
        self._update_avatar(state, action, tick)
        self._update_shots(state)
        self._update_enemies(state, tick)
        # powerblibturning (Flicker) needs no update: its age is tick - turning_born.
        self._apply_rules(state, tick, tables)
        self._cleanup(state)
        self._check_termination(state)

    # --- step 2: the ship (OngoingAvatar) ---
    def _update_avatar(self, state: TensorDict, action: torch.Tensor, tick: torch.Tensor) -> None:
        avatar = state.get("avatar")
        alive = avatar.get("alive")
        direction = move_direction(action)  # NIL keeps the heading
        ori = torch.where(alive & (direction != NONE), direction, avatar.get("ori"))
        # Passive move along the heading, skipped on the first update (tick 0).
        step = alive & (tick >= 1)
        avatar.update(
            {
                "ori": ori,
                "x": (avatar.get("x") + direction_dx(ori, torch.int32) * step).to(torch.int32),
                "y": (avatar.get("y") + direction_dy(ori, torch.int32) * step).to(torch.int32),
            }
        )

    # --- step 3: shots, enemies (powerblibturning: see tick) ---
    def _update_shots(self, state: TensorDict) -> None:
        """Missiles at 1 px per tick, from their second update on (``fresh`` is rewritten by
        :meth:`_spawn_shots` later in the tick)."""
        shots = state.get(("enemies", "shots"))
        moving = shots.get("alive") & ~shots.get("fresh")
        shots.set("y", shots.get("y") + shots.get("dy") * moving)

    def _update_enemies(self, state: TensorDict, tick: torch.Tensor) -> None:
        """Missiles, 10 px per move, cooldown 3. Enemies are level sprites that are never created or
        removed, so with the first-update skip at tick 0 they move exactly at ticks 2, 5, 8, …"""
        enemies = state.get("enemies")
        move = (tick % ENEMY_COOLDOWN == ENEMY_COOLDOWN - 1).unsqueeze(-1) & enemies.get("alive")
        enemies.set("col", enemies.get("col") + enemies.get("dx") * move)

    # --- step 4: collision rules in declaration order ---
    def _apply_rules(self, state: TensorDict, tick: torch.Tensor, tables: dict[str, torch.Tensor]) -> None:
        """Rules 1-9 touch only cells near the ship, so they gather those cells from the grids and
        scatter them back: the (up to 2x2) cells the ship overlaps, and for 6a/6b, in the envs where
        a powerblibturning may live, the window of :meth:`_pair_turnings`."""
        avatar, enemies = state.get("avatar"), state.get("enemies")
        shots = enemies.get("shots")
        wall = state.get("wall")
        alive, ax, ay = avatar.get("alive"), avatar.get("x"), avatar.get("y")
        col, row, e_alive = enemies.get("col"), enemies.get("row"), enemies.get("alive")
        batch, height, width = wall.shape
        keys = ("blib", "powerblib", "res", "turning_born", "turning")
        flat = {key: state.get(key).view(batch, -1) for key in keys}
        position = _window_rows(ax, ay, height, width)
        cells = tables["under"].index_select(0, position)
        # The cells the ship overlaps, each once (a ship disabled in an earlier tick collides with
        # nothing); when there is one, every entry of ``cells`` is one.
        hits = tables["counted"].index_select(0, position) & alive.unsqueeze(-1)
        under = hits[:, :1]

        # 1-4 avatar × wall, enemy, enemyground, shot: kill (disable) the ship, -10 per sprite overlapped.
        lethal = hits & torch.gather(state.get("deadly").view(batch, -1), 1, cells)
        ship_x, ship_y = ax.unsqueeze(-1), ay.unsqueeze(-1)
        enemy_hit = e_alive & overlaps(ship_x, ship_y, CELL * col, CELL * row)
        shot_x, shot_y = shots.get("x").flatten(1), shots.get("y").flatten(1)
        shot_hit = shots.get("alive").flatten(1) & overlaps(ship_x, ship_y, shot_x, shot_y)
        lethal = count_last(lethal) + alive * (count_last(enemy_hit) + count_last(shot_hit))
        if torch.compiler.is_compiling():  # every env's window, masked: no data-dependent shapes
            window = tables["window"].index_select(0, position)
            over = tables["covered"].index_select(0, position) & alive.unsqueeze(-1)
            live = state.get("turning_last") >= tick - TURNING_LIFE
            taken, gained, made = self._window_rules_dense(flat, window, over, tick, live)
        else:
            # 5 blib × avatar: collect, +1 each (the ship still collects in the tick it dies).
            blib = torch.gather(flat["blib"], 1, cells)
            taken = count_last(hits & blib)
            write_rows_(flat["blib"], cells, blib & ~under)
            # 6a, 6b, 8 (and the turnings' expiry), only where a turning created in the last 10 ticks
            # may still pair with its powerblib.
            gained = taken
            live = (state.get("turning_last") >= tick - TURNING_LIFE).nonzero().squeeze(-1)
            if len(live) > 0:
                at, spawned = self._pair_turnings(
                    flat, tables["window"].index_select(0, position[live]), tick[live], live
                )
                gained = gained.index_add(0, at, spawned.to(gained.dtype))
            # 7 powerblibturning × avatar: kill the turnings the ship overlaps. 9 powerblib × avatar: a
            # new turning on every powerblib the ship overlaps (after rule 8's kills).
            powerblib = under & torch.gather(flat["powerblib"], 1, cells)
            born = torch.gather(flat["turning_born"], 1, cells)
            born = torch.where(
                powerblib, tick.to(born.dtype).unsqueeze(-1), torch.where(under, NO_TURNING, born)
            )
            write_rows_(flat["turning_born"], cells, born)
            write_rows_(
                flat["turning"],
                cells,
                powerblib | (~under & torch.gather(flat["turning"], 1, cells)),
            )
            made = any_last(powerblib)
        # A blib of 6a replaces its powerblib (8), so only rule 5 changes the pickups left.
        state.update(
            {
                "score": state.get("score") + DEATH_SCORE * lethal + gained,
                "pickups": state.get("pickups") - taken,
                "turning_last": torch.where(made, tick.to(torch.int32), state.get("turning_last")),
            }
        )
        avatar.set("alive", alive & (lethal == 0))

        # 10 enemy × wall: reverse (every tick of overlap, no stepBack). 11 btm × enemyground,
        # 12 top × enemyground: with probability 0.02 a shot at the enemy's cell.
        cell, on_grid = flat_cell(col, row, height, width)
        on_grid &= e_alive
        cell = cell.long()
        on_wall = on_grid & torch.gather(wall.view(batch, -1), 1, cell)
        enemies.set("dx", torch.where(on_wall, -enemies.get("dx"), enemies.get("dx")))
        slots = torch.arange(col.shape[1], device=col.device)
        draw = rng.uniform(state.get("seed"), tick, slots, STREAM_SHOT)
        on_ground = on_grid & torch.gather(state.get("enemyground").view(batch, -1), 1, cell)
        self._spawn_shots(on_ground & (draw < SHOT_PROBABILITY), enemies)

    @staticmethod
    def _pair_turnings(
        flat: dict[str, torch.Tensor], window: torch.Tensor, tick: torch.Tensor, envs: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """Rules 6a, 6b and 8 in envs ``envs``, in their window ``[N, K]`` (flat cell indices): the
        (up to) 4x4 cells from one cell before the ship's to two after along each axis. It holds
        every turning created in the last 10 ticks: each sits on a cell the ship overlapped then,
        and the ship moves at most 1 px per tick. Only those few cells are read further and
        written, which also refreshes the shown turnings (rule 9 then adds this tick's). Returns
        the env of each such cell and whether a blib was created there (+1, rule 8)."""
        grid = {key: value.view(-1) for key, value in flat.items()}
        cells = window + (envs * flat["blib"].shape[1]).unsqueeze(-1)
        born = grid["turning_born"].index_select(0, cells.view(-1)).view(cells.shape)
        row, column = (born >= tick.to(born.dtype).unsqueeze(-1) - TURNING_LIFE).nonzero(as_tuple=True)
        cells, born, tick = cells[row, column], born[row, column], tick[row].to(born.dtype)
        powerblib, res = grid["powerblib"].index_select(0, cells), grid["res"].index_select(0, cells)
        # 6a powerblib × powerblibturning: a blib on the powerblib once its counter is ≥ 2 (for all
        # pairs before 6b); 6b: the counter grows by 1 up to its limit. A turning is cell-aligned on
        # its powerblib's cell, and one killed by its Flicker update this tick still counts.
        spawned = powerblib & (res >= BLIB_AT_RES)
        grid["res"].scatter_(0, cells, res + (powerblib & (res < RES_LIMIT)).to(res.dtype))
        # 8 powerblib × blib: the new blib kills its powerblib, +1 (a level blib never shares a cell
        # with a powerblib, so only the blibs of 6a can).
        grid["powerblib"].scatter_(0, cells, powerblib & ~spawned)
        grid["blib"].scatter_(0, cells, grid["blib"].index_select(0, cells) | spawned)
        # Shown after this tick: a turning created in tick born is killed by its Flicker update
        # (limit 8) in tick born + 10.
        grid["turning"].scatter_(0, cells, born >= tick - (TURNING_LIFE - 1))
        return envs[row], spawned

    @staticmethod
    def _window_rules_dense(
        flat: dict[str, torch.Tensor],
        window: torch.Tensor,
        over: torch.Tensor,
        tick: torch.Tensor,
        live: torch.Tensor,
    ) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """Rules 5-9 as the eager tick runs them (:meth:`_apply_rules`, :meth:`_pair_turnings`),
        for a compiled tick: in every env's window ``[B, K]`` (``over``: the cells of it that the
        live ship overlaps; ``live`` ``[B]``: envs where a turning may live), masked instead of
        selected, so that the graph has no data-dependent shapes, and each grid written once (a
        second write costs inductor a copy of the grid). Returns the blibs taken (rule 5), the
        score gained (5 and 8) and whether a turning was created (9), each ``[B]``."""
        now = tick.to(torch.int32).unsqueeze(-1)
        # 5 blib × avatar: collect, +1 each.
        blib = torch.gather(flat["blib"], 1, window)
        taken = count_last(over & blib)
        # 6a, 6b, 8 where a turning created in the last 10 ticks pairs with its powerblib.
        born = torch.gather(flat["turning_born"], 1, window)
        pick = live.unsqueeze(-1) & (born >= now - TURNING_LIFE)
        powerblib, res = torch.gather(flat["powerblib"], 1, window), torch.gather(flat["res"], 1, window)
        spawned = pick & powerblib & (res >= BLIB_AT_RES)
        grown = res + (powerblib & (res < RES_LIMIT)).to(res.dtype)
        write_rows_(flat["res"], window, torch.where(pick, grown, res))
        powerblib = powerblib & ~spawned
        write_rows_(flat["powerblib"], window, powerblib)
        write_rows_(flat["blib"], window, (blib & ~over) | spawned)
        turning = torch.where(
            pick, born >= now - (TURNING_LIFE - 1), torch.gather(flat["turning"], 1, window)
        )
        # 7 powerblibturning × avatar: kill the turnings the ship overlaps. 9 powerblib × avatar: a
        # new turning on every powerblib it overlaps (after rule 8's kills).
        made = over & powerblib
        write_rows_(flat["turning_born"], window, torch.where(made, now, torch.where(over, NO_TURNING, born)))
        write_rows_(flat["turning"], window, made | (~over & turning))
        return taken, taken + count_last(spawned), any_last(made)

    @staticmethod
    def _spawn_shots(fire: torch.Tensor, enemies: TensorDict) -> None:
        """A firing enemy (``fire`` ``[B, E]``) puts a shot into the first free slot of its own block.
        Few enemies fire in a tick, so only their blocks of the shot table are touched."""
        count = fire.shape[1]
        shots = enemies.get("shots")
        alive = shots.get("alive")
        if torch.compiler.is_compiling():  # every block, masked: no data-dependent shapes
            # The first free slot of each block (none: SHOTS_PER_ENEMY), a reduction inductor fuses.
            slots = torch.arange(SHOTS_PER_ENEMY, device=alive.device)
            first = torch.where(~alive, slots, SHOTS_PER_ENEMY).amin(-1, keepdim=True)
            fresh = (slots == first) & fire.unsqueeze(-1)
            for key, at in (("x", "col"), ("y", "row")):
                table = shots.get(key)
                position = (CELL * enemies.get(at)).to(table.dtype).unsqueeze(-1)
                table.copy_(torch.where(fresh, position, table))
            alive.logical_or_(fresh)
            shots.set("fresh", fresh)
            return
        fresh = torch.zeros_like(alive)
        env, enemy = fire.nonzero(as_tuple=True)
        if len(env) > 0:
            block = env * count + enemy
            free = ~alive.view(-1, SHOTS_PER_ENEMY).index_select(0, block)
            # argmax returns the first maximal index, i.e. the first free slot.
            slot = block * SHOTS_PER_ENEMY + free.to(torch.uint8).argmax(-1)
            room = any_last(free)
            slot, env, enemy = slot[room], env[room], enemy[room]
            for key, at in (("x", "col"), ("y", "row")):
                position = CELL * enemies.get(at)[env, enemy]
                shots.get(key).view(-1).scatter_(0, slot, position.to(shots.get(key).dtype))
            alive.view(-1).scatter_(0, slot, True)
            fresh.view(-1).scatter_(0, slot, True)
        shots.set("fresh", fresh)

    # --- step 5: cleanup ---
    def _cleanup(self, state: TensorDict) -> None:
        """Killed sprites are already gone from the grids. Shots: GVGAI keeps them forever; here a
        shot is dropped once it has left the screen and is at least 10 px beyond the ship along its
        flight. Both move at most 1 px per tick, so such a shot can never overlap the ship again,
        and off screen it is neither drawn nor in ``tiles``."""
        avatar, enemies = state.get("avatar"), state.get("enemies")
        shots = enemies.get("shots")
        screen_h = (CELL * state.get("height")).to(torch.int32).unsqueeze(-1)  # each env's own screen
        # Along the flight (y dy, y grows downward) an upshot is gone from -y = 10 - min(0, ship_y)
        # on, a downshot from y = max(screen_h, ship_y + 10) on; the ship's bound only while alive
        # (a ship y of 0 leaves both at the screen's).
        ship_y = (avatar.get("y") * avatar.get("alive")).unsqueeze(-1)
        up, down = CELL - ship_y.clamp(max=0), torch.maximum(ship_y + CELL, screen_h)
        bound = torch.where(enemies.get("kind") == BTM, up, down)
        alive = shots.get("alive")
        alive &= shots.get("y") * shots.get("dy") < bound.unsqueeze(-1)

    # --- step 6: termination, in declaration order ---
    def _check_termination(self, state: TensorDict) -> None:
        lost = ~state.get(("avatar", "alive"))
        won = ~lost & (state.get("pickups") == 0)
        state.update({"won": state.get("won") | won, "lost": state.get("lost") | lost})

    def layers(self, state: TensorDict) -> list:
        avatar, enemies = state.get("avatar"), state.get("enemies")
        shots = {key: value.flatten(1) for key, value in enemies.get("shots").items()}  # [B, E x 16]
        ex, ey = CELL * enemies.get("col"), CELL * enemies.get("row")
        e_alive, e_kind = enemies.get("alive"), enemies.get("kind")
        sx, sy, s_alive, up = shots["x"], shots["y"], shots["alive"], shots["dy"] < 0
        return [
            GridLayer("floor", state.get("floor")),
            GridLayer("enemyground", state.get("enemyground")),
            GridLayer("powerblib", state.get("powerblib")),
            GridLayer("powerblibturning", state.get("turning")),
            GridLayer("blib", state.get("blib")),
            SpriteLayer("top", ex, ey, e_alive & (e_kind == TOP)),
            SpriteLayer("btm", ex, ey, e_alive & (e_kind == BTM)),
            SpriteLayer("upshot", sx, sy, s_alive & up),
            SpriteLayer("downshot", sx, sy, s_alive & ~up),
            GridLayer("wall", state.get("wall")),
            single_sprite_layer("avatar", avatar, oriented=True),
        ]

    def snapshot(self, state: TensorDict, index: int) -> dict:
        s = state[index : index + 1]
        avatar = None
        if s.get(("avatar", "alive")).item():
            avatar = {
                "type": "avatar",
                "x": s.get(("avatar", "x")).item(),
                "y": s.get(("avatar", "y")).item(),
                "orientation": DIRECTION_NAMES[s.get(("avatar", "ori")).item()],
                "resources": {},
            }
        grids = (
            ("blib", s.get("blib")),
            ("powerblib", s.get("powerblib")),
            ("powerblibturning", s.get("turning")),
        )
        sprites = [[name, CELL * c, CELL * r] for name, grid in grids for r, c in grid[0].nonzero().tolist()]
        enemies = s.get("enemies")[0]
        for k in enemies.get("alive").nonzero().flatten().tolist():
            x, y = CELL * enemies.get("col")[k].item(), CELL * enemies.get("row")[k].item()
            sprites.append([ENEMY_TYPES[enemies.get("kind")[k].item()], x, y])
        shots = {key: value[0].flatten() for key, value in s.get(("enemies", "shots")).items()}
        for k in shots["alive"].nonzero().flatten().tolist():
            name = "upshot" if shots["dy"][k].item() < 0 else "downshot"
            sprites.append([name, shots["x"][k].item(), shots["y"][k].item()])
        return golden_record(s, avatar, sprites)

    def max_score(self, level: Level) -> int:
        """+1 per blib and +2 per powerblib (its blib is worth 1 and eating its powerblib 1, §5.6),
        collected without dying."""
        return level.count("b") + 2 * level.count("p")
