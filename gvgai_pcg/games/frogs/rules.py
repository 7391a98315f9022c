"""Frogs (RULES.md §6): cross the road (trucks) and the river (riding logs) to the goal.

Frogs is the game of many small moving sprites: logs drift left 1 px per tick and are spawned
by forest spawners, trucks drive 1 or 2 px per tick and wrap around, and the frog rides a log
by being pulled along. The tick below is RULES.md §1.3 with Frogs' rules in declaration order:

step 2 the frog (MovingAvatar: 10 px per direction action) · step 3 trucks, then logs, then the
spawners (sparse before dense), so a log spawned in tick t first moves in t+2 ·
EOS: E1 frog stepBack · E2 log killed at x = −1 · E3 truck wrapAround ·
collisions: 1 goal × frog kill goal (+1) · 2a frog × log shield from water · 2b frog × log
pullWithIt (1 px, only if the frog did not move) · 3 frog × wall stepBack · 4 frog × truck kill ·
5 frog × water kill (unless shielded).
Termination: no goal → WIN, then no frog → LOSE.

Logs live in one entity table whose slots are laid out, scheduled and keyed by
:mod:`gvgai_pcg.games.frogs.logs` (the machinery and the invariants it keeps); slot order is not
creation order, and no rule depends on it (see ``_apply_rules``, rule 2b). The tick touches the
whole log table only to move all x at once, to find the logs near the frog and to remove those at
x = −1. Every step has fixed shapes and no host sync, so the tick compiles as one graph
(``compiles``, gvgai_pcg.engine.compiled).
"""

from __future__ import annotations

from collections.abc import Sequence

import torch
from tensordict import TensorDict

from gvgai_pcg._private_apis import assert_async
from gvgai_pcg.games import rng
from gvgai_pcg.games.actions import MOVE_ACTIONS, NIL, move_displacement
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
from gvgai_pcg.games.frogs.logs import (
    LOG_SPEED,
    log_key,
    log_tables,
    spawn_schedule,
    wrap_around_,
)
from gvgai_pcg.games.geometry import (
    CELL,
    clear_listed_cells_,
    gather_cells,
    off_screen,
    row_cells,
    write_rows_,
)
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.games.registry import register_game
from gvgai_pcg.levels import Level

# Level legend (RULES.md §6.1): which characters put which static sprite on their tile.
WALL_CHARS = "w"
GRASS_CHARS = "w+.g0A"
HIGHWAY_CHARS = ".-x_l"
GOAL_CHARS = "g"
WATER_CHARS = "0=13B"
LOG_CHARS = "=24B"
DENSE_CHARS = "12"
SPARSE_CHARS = "34"

# Trucks in update order (slowL, fastL, slowR, fastR): level char and signed speed in px per tick.
# Each type is its own entity table, so that each is drawn and moved without masks.
TRUCK_TYPES = ("slowLtruck", "fastLtruck", "slowRtruck", "fastRtruck")
TRUCK_CHARS = "_l-x"
TRUCK_VELOCITY = (-1, -2, 1, 2)

# Spawners in update order: forestSparse (kind 0) before forestDense (kind 1).
SPAWNER_TYPES = ("forestSparse", "forestDense")
SPAWNER_CHARS = {"3": 0, "4": 0, "1": 1, "2": 1}
SPAWN_COOLDOWN = (5, 10)
SPAWN_PROB = (0.1, 0.4)
STREAM_LOG_SPAWN = 1
SLOT_ROW_STRIDE = 1 << 16  # rng slot of a spawner: y * stride + x, independent of the grid size


@register_game("frogs")
class Frogs(Game):
    actions = MOVE_ACTIONS
    tile_types = ("wall", "water", "forestDense", "forestSparse", "goal", "log", *TRUCK_TYPES, "avatar")
    art = {
        "grass": SpriteArt((40, 110, 40)),
        "highway": SpriteArt((70, 70, 70)),
        "forestDense": SpriteArt((20, 90, 60), "frame"),
        "forestSparse": SpriteArt((60, 130, 90), "frame"),
        "water": SpriteArt((30, 60, 170)),
        "goal": SpriteArt((250, 210, 0), "frame"),
        "log": SpriteArt((130, 80, 30), "bar"),
        "fastRtruck": SpriteArt((220, 40, 40), "diamond"),
        "slowRtruck": SpriteArt((240, 140, 40), "diamond"),
        "fastLtruck": SpriteArt((200, 40, 200), "diamond"),
        "slowLtruck": SpriteArt((150, 100, 240), "diamond"),
        "wall": SpriteArt((20, 60, 20), "cross"),
        "avatar": SpriteArt((250, 250, 250), "circle"),
    }

    def compile(self, levels: Sequence[Level], seeds: torch.Tensor, device: torch.device) -> TensorDict:
        """Positions are int32 (half the memory traffic of int64 in the tick and the renderer)."""
        batch = len(levels)
        cpu = torch.device("cpu")

        spawners = char_entities(levels, SPAWNER_CHARS, cpu)
        placed = char_entities(levels, dict.fromkeys(LOG_CHARS, 0), cpu)
        logs = log_tables(spawners, placed, SPAWN_COOLDOWN)
        spawners.set("row", (spawners.get("y") // CELL).to(torch.int32))

        ax, ay = avatar_cell(levels, "AB")
        avatar = {
            "x": ax.to(torch.int32),
            "y": ay.to(torch.int32),
            "alive": torch.ones(batch, dtype=torch.bool),
        }
        trucks = {}
        for name, ch in zip(TRUCK_TYPES, TRUCK_CHARS, strict=True):
            placed = char_entities(levels, {ch: 0}, cpu)
            alive, x, y = (
                placed.get("alive"),
                placed.get("x").to(torch.int32),
                placed.get("y").to(torch.int32),
            )
            table = {
                "x": x,
                "y": y,
                "alive": alive,
                "lane": torch.where(alive, y + CELL, 0),
                "row": y // CELL,
            }
            trucks[name] = on_device(device, table, placed.batch_size)
        state = {
            **common_state(levels, seeds, device),
            "wall": char_grid(levels, WALL_CHARS, device),
            "water": char_grid(levels, WATER_CHARS, device),
            "goal": char_grid(levels, GOAL_CHARS, device),
            # Goals left: rule 1 is the only one that removes goals, and it counts them (termination).
            "goals": torch.tensor(
                [sum(level.count(ch) for ch in GOAL_CHARS) for level in levels], device=device
            ),
            "grass": char_grid(levels, GRASS_CHARS, device),
            "highway": char_grid(levels, HIGHWAY_CHARS, device),
            "forestDense": char_grid(levels, DENSE_CHARS, device),
            "forestSparse": char_grid(levels, SPARSE_CHARS, device),
            "avatar": on_device(device, avatar, [batch]),
            "logs": on_device(device, dict(logs.items()), logs.batch_size),
            **trucks,
            "spawners": on_device(device, dict(spawners.items()), spawners.batch_size),
        }
        return on_device(device, state, [batch])

    def tick(self, state: TensorDict, action: torch.Tensor) -> None:
        tick = state.get("tick") + 1
        state.set("tick", tick)
        avatar = state.get("avatar")
        alive, x, y = avatar.get("alive"), avatar.get("x"), avatar.get("y")
        pressed = alive & (action != NIL)
        lastx, lasty = x, y
        x, y = self._update_avatar(action, pressed, x, y)
        # Each env's own screen in px (a level padded to the batch's grid keeps its edges).
        screen_w, screen_h = CELL * state.get("width"), CELL * state.get("height")
        self._update_trucks(state, tick, screen_w)
        schedule = spawn_schedule(state.get("spawners"), tick, SPAWN_COOLDOWN)
        fresh = self._update_logs(state, tick, schedule)
        spawned = self._update_spawners(state, tick, schedule)
        x, y = self._apply_eos(x, y, lastx, lasty, screen_h, screen_w)
        unmoved = fresh | spawned
        self._apply_rules(state, tick, alive, pressed, schedule, unmoved, x, y, lastx, lasty)
        self._cleanup_logs(state)
        self._check_termination(state)

    def reset_tick(self, state: TensorDict) -> None:
        """Tick 0 with NIL does only this: nothing moves yet (trucks and logs start moving in tick
        1), every spawner is at a spawn tick, no log is old enough to leave, and the frog starts
        on a tile of its own (never a goal, wall, truck or bare water: 'B' is a log on water), so
        no collision rule changes anything. Left are the spawns and the termination check (a
        level without a goal is won at once). A third of the ops of ``tick``: Frogs envs reset
        often under random play (a sixth of its episodes last one step)."""
        tick = state.get("tick") + 1
        state.set("tick", tick)
        self._update_spawners(state, tick, spawn_schedule(state.get("spawners"), tick, SPAWN_COOLDOWN))
        self._check_termination(state)

    # --- step 2: the frog (MovingAvatar: every direction action moves 10 px at once) ---
    @staticmethod
    def _update_avatar(
        action: torch.Tensor, pressed: torch.Tensor, x: torch.Tensor, y: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor]:
        dx, dy = move_displacement(torch.where(pressed, action, NIL), CELL, x.dtype)
        return x + dx, y + dy

    # --- step 3: trucks, logs (Missiles, first update skipped), then spawners ---
    @staticmethod
    def _update_trucks(state: TensorDict, tick: torch.Tensor, screen_w: torch.Tensor) -> None:
        """Level trucks have their first update in tick 0 and drive from tick 1; EOS rule E3
        (wrapAround, at each env's own screen width ``screen_w`` ``[B]`` px) is applied right away,
        as nothing in between reads the trucks.

        Padding slots drive and wrap too; they are never drawn nor hit (``alive``, ``lane``).
        """
        running = (tick >= 1).to(torch.int32).unsqueeze(-1)
        # The last x at which a truck is fully on the screen, ``[B, 1]``.
        last = (screen_w - CELL).to(torch.int32).unsqueeze(-1)
        for name, velocity in zip(TRUCK_TYPES, TRUCK_VELOCITY, strict=True):
            tx = state.get(name).get("x")
            wrap_around_(tx.add_(running * velocity), last, velocity)

    @staticmethod
    def _update_logs(state: TensorDict, tick: torch.Tensor, schedule: dict) -> torch.Tensor:
        """Move every log 1 px left from tick 1 on, except those spawned in the previous tick (their
        first update): these are moved back and their key advanced. Returns which spawners' ring
        slot holds such a log (``[B, S]``).

        Dead slots move too (their x means nothing); their key stays 0.
        """
        logs, spawners = state.get("logs"), state.get("spawners")
        running = (tick >= 1).to(torch.int32).unsqueeze(-1)
        logs.get("x").sub_(running * LOG_SPEED)
        slot = schedule["slot"]
        fresh = spawners.get("alive") & schedule["fresh"] & torch.gather(logs.get("alive"), 1, slot)
        back = fresh.to(torch.int32) * LOG_SPEED
        write_rows_(logs.get("x"), slot, back, accumulate=True)
        write_rows_(logs.get("key"), slot, back, accumulate=True)
        return fresh

    @staticmethod
    def _update_spawners(state: TensorDict, tick: torch.Tensor, schedule: dict) -> torch.Tensor:
        """SpawnPoint: one uniform draw per spawner and tick; a log at ticks ≡ 0 mod cooldown with
        probability prob, written to the spawner's ring slot (never occupied, checked). Returns
        which spawners spawned (``[B, S]``).

        Every spawner draws (a draw is a pure function of the seed, tick and spawner, so those not
        at a spawn tick draw in vain and change nothing) and every spawner writes: one that does
        not fire writes the dump slot (the last, never a log) with what it holds. Fixed shapes and
        no host sync, so that the tick compiles as one graph; eager, this is fewer ops than
        picking out the few spawners that fire (at B <= 64 a tick costs its ops, not its work).
        """
        spawners, logs = state.get("spawners"), state.get("logs")
        sx, sy = spawners.get("x"), spawners.get("y")
        draw = rng.uniform(state.get("seed"), tick, sy * SLOT_ROW_STRIDE + sx, STREAM_LOG_SPAWN)
        fires = spawners.get("alive") & schedule["spawn"]
        fires &= draw < lookup(SPAWN_PROB, spawners.get("kind"), torch.float64)
        slot = torch.where(fires, schedule["slot"], logs.batch_size[1] - 1)
        alive = logs.get("alive")
        assert_async(  # the dump slot never holds a log
            ~alive.gather(1, slot).any(),
            "frogs: a spawned log found its ring slot occupied; the log table is smaller than the "
            "bound of frogs.logs.spawner_ring_size",
        )
        x32, y32 = sx.to(torch.int32), sy.to(torch.int32)
        spawned = {
            "x": x32,
            "y": y32,
            "row": spawners.get("row"),
            "key": log_key(x32, y32, tick.unsqueeze(-1)),
            "alive": fires,
        }
        for name, value in spawned.items():
            column = logs.get(name)
            write_rows_(column, slot, torch.where(fires, value, column[:, -1:]))
        return fires

    # --- step 4b: EOS rules E1 (frog stepBack), E2 (log kill, at cleanup), E3 (truck wrap, above) ---
    @staticmethod
    def _apply_eos(
        x: torch.Tensor,
        y: torch.Tensor,
        lastx: torch.Tensor,
        lasty: torch.Tensor,
        screen_h: torch.Tensor,
        screen_w: torch.Tensor,
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """E1: a frog not entirely inside its env's screen (``screen_h``, ``screen_w`` ``[B]`` px)
        goes back to where it started the tick (RULES.md §1.1)."""
        edge = off_screen(x, y, screen_h, screen_w)
        return torch.where(edge, lastx, x), torch.where(edge, lasty, y)

    # --- step 4c: collision rules in declaration order ---
    @staticmethod
    def _apply_rules(
        state: TensorDict,
        tick: torch.Tensor,
        alive: torch.Tensor,
        pressed: torch.Tensor,
        schedule: dict,
        unmoved: torch.Tensor,
        x: torch.Tensor,
        y: torch.Tensor,
        lastx: torch.Tensor,
        lasty: torch.Tensor,
    ) -> None:
        goal, wall, water = state.get("goal"), state.get("wall"), state.get("water")
        logs = state.get("logs")

        # The frog is tested against the grids at three positions at most: where EOS left it, 1 px
        # to the left (pulled by a log) and where it started the tick (stepped back by a wall).
        # Their cells are found at once; the log rules (2a, 2b) do not read the grids.
        px = torch.stack([x, x - LOG_SPEED, lastx], dim=-1)
        cells, valid = row_cells(px, torch.stack([y, y, lasty], dim=-1), *goal.shape[1:])

        # 1 goal × avatar: kill every goal the frog overlaps, +1 each (in place).
        hit = gather_cells(goal, cells[:, 0], valid[:, 0]) & alive.unsqueeze(-1)
        state.set("score", state.get("score") + hit.sum(-1))
        state.set("goals", state.get("goals") - hit.sum(-1))
        clear_listed_cells_(goal.view(goal.shape[0], -1), cells[:, 0], hit)

        # 2a avatar × log: shield from water. A log killed by EOS this tick still counts.
        # 2b avatar × log: pullWithIt, once per tick, through the first overlapping log in creation
        # order. Logs that have not moved yet are exactly the youngest ones, so the first
        # overlapping log moved iff any overlapping log moved; a frog that moved itself is not pulled.
        # The logs that have not moved this tick are those spawned in this tick or the previous one
        # (each in its spawner's current ring slot), and in tick 0 all of them.
        # The unmoved logs' slots are distinct (one per spawner), so the frog is on a moved log iff
        # it is on more logs than unmoved ones (counts: no copy of the table to mask them out).
        near = (logs.get("key") - log_key(x, y, tick).unsqueeze(-1)).abs_() < CELL
        near_unmoved = torch.gather(near, 1, schedule["slot"]) & unmoved
        on_unmoved = near_unmoved.any(-1)
        on_moved = near.sum(-1, dtype=torch.int32) > near_unmoved.sum(-1, dtype=torch.int32)
        shielded = alive & (on_moved | on_unmoved)
        pulled = alive & ~pressed & on_moved & (tick >= 1)
        x = torch.where(pulled, px[:, 1], x)

        # 3 avatar × wall: stepBack to the start-of-tick position.
        on_wall = gather_cells(wall, cells[:, :2], valid[:, :2]).any(-1)
        back = alive & torch.where(pulled, on_wall[:, 1], on_wall[:, 0])
        x, y = torch.where(back, lastx, x), torch.where(back, lasty, y)

        # 4 avatar × truck: kill the frog. 5 avatar × water: kill the frog unless shielded.
        # Trucks and the frog are cell-aligned in y, so they overlap iff the L1 distance of their
        # positions is below 10; ``lane`` is y + 10 for a truck and 0 (never near) for padding.
        lane, fx = (y + CELL).unsqueeze(-1), x.unsqueeze(-1)
        nearest = torch.stack(
            [
                ((trucks.get("x") - fx).abs_() + (trucks.get("lane") - lane).abs_()).amin(-1)
                for trucks in (state.get(name) for name in TRUCK_TYPES)
                if trucks.batch_size[1]
            ]
            or [torch.full_like(x, CELL)]
        )
        hit_truck = (nearest < CELL).any(0)
        in_water = gather_cells(water, cells, valid).any(-1)
        in_water = torch.where(back, in_water[:, 2], torch.where(pulled, in_water[:, 1], in_water[:, 0]))
        drowned = ~shielded & in_water
        killed = alive & (hit_truck | drowned)

        state.get("avatar").update({"x": x, "y": y, "alive": alive & ~killed})

    # --- step 5: cleanup (logs killed by EOS at x = −1 are removed) ---
    @staticmethod
    def _cleanup_logs(state: TensorDict) -> None:
        """E2: a log dies when it reaches x = −1 (a log is spawned at x >= 0 and loses 1 px a
        tick, so it is at x = −1 once, in the tick it leaves); its slot gets ``alive`` false and
        key 0. Dead slots (x moves on, alive already false, key already 0) are left as they are."""
        logs = state.get("logs")
        alive = logs.get("alive").logical_and_(logs.get("x") >= 0)
        logs.get("key").mul_(alive)

    # --- step 6: termination, in declaration order ---
    @staticmethod
    def _check_termination(state: TensorDict) -> None:
        won = state.get("goals") == 0
        lost = ~won & ~state.get(("avatar", "alive"))
        state.set("won", state.get("won") | won)
        state.set("lost", state.get("lost") | lost)

    def layers(self, state: TensorDict) -> list:
        avatar, logs = state.get("avatar"), state.get("logs")
        layers = [
            GridLayer(name, state.get(name))
            for name in ("grass", "highway", "forestDense", "forestSparse", "water", "goal")
        ]
        layers.append(
            SpriteLayer("log", logs.get("x"), logs.get("y"), logs.get("alive"), row=logs.get("row"))
        )
        for name in ("fastRtruck", "slowRtruck", "fastLtruck", "slowLtruck"):
            trucks = state.get(name)
            layers.append(
                SpriteLayer(
                    name, trucks.get("x"), trucks.get("y"), trucks.get("alive"), row=trucks.get("row")
                )
            )
        layers.append(GridLayer("wall", state.get("wall")))
        layers.append(single_sprite_layer("avatar", avatar))
        return layers

    def snapshot(self, state: TensorDict, index: int) -> dict:
        s = state[index]
        avatar = None
        if s.get(("avatar", "alive")).item():
            x, y = s.get(("avatar", "x")).item(), s.get(("avatar", "y")).item()
            avatar = {"type": "avatar", "x": x, "y": y, "orientation": None, "resources": {}}
        sprites = [
            [name, CELL * c, CELL * r]
            for name in ("goal", "forestDense", "forestSparse")
            for r, c in s.get(name).nonzero().tolist()
        ]
        for name, key in (("log", "logs"), *((truck, truck) for truck in TRUCK_TYPES)):
            table = s.get(key)
            for k in table.get("alive").nonzero().flatten().tolist():
                sprites.append([name, table.get("x")[k].item(), table.get("y")[k].item()])
        return golden_record(s, avatar, sprites)

    def max_score(self, level: Level) -> int:
        """+1 per goal (rule 1 is the only score change); the game is won when none is left."""
        return level.count("g")
