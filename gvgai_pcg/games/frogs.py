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

Logs live in one entity table. Level logs take the first slots; each spawner owns a ring of
slots sized from its position and cooldown (a log lives a fixed number of ticks, so a ring of
``(x + 2) // cooldown + 1`` slots can never be full when the spawner fires), and a last "dump"
slot absorbs the writes of spawners that do not fire. Slot order is therefore not creation
order; no rule depends on it (see ``_apply_rules``, rule 2b).
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import cache

import torch
from tensordict import TensorDict

from gvgai_pcg.games import rng
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
    pad_level,
)
from gvgai_pcg.games.geometry import CELL, cell_mask, grid_count, grid_hits
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
LOG_SPEED = 1  # px per tick, to the left
STREAM_LOG_SPAWN = 1
SLOT_ROW_STRIDE = 1 << 16  # rng slot of a spawner: y * stride + x, independent of the grid size

NIL = 0
# Frog actions 1..4 are LEFT, RIGHT, DOWN, UP: unit moves indexed by the action.
ACTION_DX = (0, -1, 1, 0, 0)
ACTION_DY = (0, 0, 0, 1, -1)


@cache
def _constant(values: tuple, dtype: torch.dtype, device: torch.device) -> torch.Tensor:
    """A small lookup table (per-kind or per-action constants) on ``device``, made once."""
    return torch.tensor(values, dtype=dtype, device=device)


def spawner_ring_size(x: torch.Tensor, cooldown: torch.Tensor) -> torch.Tensor:
    """Slots a spawner at pixel column ``x`` needs so that its logs never outnumber them.

    A log spawned at tick t sits at x in ticks t and t+1, moves 1 px per tick from t+2, reaches
    x = −1 (EOS kill) in tick t + x + 2 and is removed at the end of that tick. Spawns happen
    only at multiples of ``cooldown``, so slot ``(t // cooldown) % size`` is free again when
    ``size * cooldown > x + 2``.
    """
    return (x + 2).div(cooldown, rounding_mode="floor") + 1


@register_game("frogs")
class Frogs(Game):
    actions = ("NIL", "LEFT", "RIGHT", "DOWN", "UP")
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
        """Levels of different sizes are padded to the largest with wall rows/columns (frogs lvl4)."""
        height, width = max(level.height for level in levels), max(level.width for level in levels)
        levels = [pad_level(level, height, width, self.pad_char) for level in levels]
        batch = len(levels)
        cpu = torch.device("cpu")

        spawners = char_entities(levels, SPAWNER_CHARS, cpu)
        kind, present = spawners.get("kind"), spawners.get("alive")
        cooldown = torch.tensor(SPAWN_COOLDOWN)[kind]
        ring = spawner_ring_size(spawners.get("x"), cooldown) * present
        level_logs = torch.tensor([sum(level.count(ch) for ch in LOG_CHARS) for level in levels])
        spawners.set("base", level_logs.unsqueeze(-1) + ring.cumsum(-1) - ring)
        capacity = int((level_logs + ring.sum(-1)).max()) + 1  # + the dump slot

        logs = char_entities(levels, dict.fromkeys(LOG_CHARS, 0), cpu, capacity=capacity)
        del logs["kind"]
        logs.set("fresh", logs.get("alive").clone())  # level logs skip their first update (tick 0)

        ax, ay = avatar_cell(levels, "AB")
        avatar = {"x": ax, "y": ay, "alive": torch.ones(batch, dtype=torch.bool)}
        state = {
            **common_state(seeds, device),
            "wall": char_grid(levels, WALL_CHARS, device),
            "water": char_grid(levels, WATER_CHARS, device),
            "goal": char_grid(levels, GOAL_CHARS, device),
            "grass": char_grid(levels, GRASS_CHARS, device),
            "highway": char_grid(levels, HIGHWAY_CHARS, device),
            "forestDense": char_grid(levels, DENSE_CHARS, device),
            "forestSparse": char_grid(levels, SPARSE_CHARS, device),
            "avatar": TensorDict(avatar, batch_size=[batch]).to(device),
            "logs": logs.to(device),
            **{
                name: char_entities(levels, {ch: 0}, device)
                for name, ch in zip(TRUCK_TYPES, TRUCK_CHARS, strict=True)
            },
            "spawners": spawners.to(device),
        }
        return TensorDict(state, batch_size=[batch], device=device)

    def tick(self, state: TensorDict, action: torch.Tensor) -> None:
        tick = state.get("tick") + 1
        state.set("tick", tick)
        avatar = state.get("avatar")
        alive, x, y = avatar.get("alive"), avatar.get("x"), avatar.get("y")
        pressed = alive & (action != NIL)
        lastx, lasty = x, y
        x, y = self._update_avatar(action, pressed, x, y)
        self._update_trucks(state, tick)
        moved = self._update_logs(state)
        self._update_spawners(state, tick)
        height, width = state.get("wall").shape[1:]
        x, y = self._apply_eos(state, x, y, lastx, lasty, height, width)
        self._apply_rules(state, alive, pressed, moved, x, y, lastx, lasty)
        state.get("logs").get("alive").copy_(self._logs_after_cleanup(state))
        self._check_termination(state)

    # --- step 2: the frog (MovingAvatar: every direction action moves 10 px at once) ---
    @staticmethod
    def _update_avatar(
        action: torch.Tensor, pressed: torch.Tensor, x: torch.Tensor, y: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor]:
        dx = _constant(ACTION_DX, x.dtype, x.device)[action]
        dy = _constant(ACTION_DY, y.dtype, y.device)[action]
        return x + pressed * CELL * dx, y + pressed * CELL * dy

    # --- step 3: trucks, logs (Missiles, first update skipped), then spawners ---
    @staticmethod
    def _update_trucks(state: TensorDict, tick: torch.Tensor) -> None:
        """Level trucks have their first update in tick 0 and drive from tick 1."""
        running = (tick >= 1).unsqueeze(-1)
        for name, velocity in zip(TRUCK_TYPES, TRUCK_VELOCITY, strict=True):
            trucks = state.get(name)
            trucks.get("x").add_(velocity * (running & trucks.get("alive")))

    @staticmethod
    def _update_logs(state: TensorDict) -> torch.Tensor:
        """Move every log past its first update 1 px left; returns which moved (``[B, K]``)."""
        logs = state.get("logs")
        fresh = logs.get("fresh")
        moved = logs.get("alive") & ~fresh
        logs.get("x").sub_(moved.to(torch.int64) * LOG_SPEED)
        fresh.zero_()
        return moved

    @staticmethod
    def _update_spawners(state: TensorDict, tick: torch.Tensor) -> None:
        """SpawnPoint: one uniform draw per spawner and tick; a log at ticks ≡ 0 mod cooldown with
        probability prob, written to the spawner's ring slot (never occupied, checked)."""
        spawners, logs = state.get("spawners"), state.get("logs")
        kind, sx, sy = spawners.get("kind"), spawners.get("x"), spawners.get("y")
        cooldown = _constant(SPAWN_COOLDOWN, torch.int64, kind.device)[kind]
        prob = _constant(SPAWN_PROB, torch.float64, kind.device)[kind]
        now = tick.unsqueeze(-1)
        draw = rng.uniform(state.get("seed"), tick, sy * SLOT_ROW_STRIDE + sx, STREAM_LOG_SPAWN)
        spawn = spawners.get("alive") & (now % cooldown == 0) & (draw < prob)
        ring_slot = spawners.get("base") + now.div(cooldown, rounding_mode="floor") % spawner_ring_size(
            sx, cooldown
        )
        dump = logs.batch_size[1] - 1
        slot = torch.where(spawn, ring_slot, dump)
        alive = logs.get("alive")
        torch._assert_async(
            ~(torch.gather(alive, 1, slot) & spawn).any(),
            "frogs: a spawned log found its ring slot occupied; the log table is smaller than the "
            "bound of spawner_ring_size",
        )
        logs.get("x").scatter_(1, slot, torch.where(spawn, sx, 0))
        logs.get("y").scatter_(1, slot, torch.where(spawn, sy, 0))
        alive.scatter_(1, slot, spawn)
        logs.get("fresh").scatter_(1, slot, spawn)

    # --- step 4b: EOS rules E1 (frog stepBack), E2 (log kill, at cleanup), E3 (truck wrap) ---
    @staticmethod
    def _apply_eos(
        state: TensorDict,
        x: torch.Tensor,
        y: torch.Tensor,
        lastx: torch.Tensor,
        lasty: torch.Tensor,
        height: int,
        width: int,
    ) -> tuple[torch.Tensor, torch.Tensor]:
        edge = (x < 0) | (y < 0) | (x + CELL > CELL * width) | (y + CELL > CELL * height)
        x, y = torch.where(edge, lastx, x), torch.where(edge, lasty, y)
        for name, velocity in zip(TRUCK_TYPES, TRUCK_VELOCITY, strict=True):
            tx = state.get(name).get("x")
            if velocity > 0:
                tx.masked_fill_(tx + CELL > CELL * width, 0)
            else:
                tx.masked_fill_(tx < 0, CELL * width - CELL)
        return x, y

    # --- step 4c: collision rules in declaration order ---
    @staticmethod
    def _apply_rules(
        state: TensorDict,
        alive: torch.Tensor,
        pressed: torch.Tensor,
        moved: torch.Tensor,
        x: torch.Tensor,
        y: torch.Tensor,
        lastx: torch.Tensor,
        lasty: torch.Tensor,
    ) -> None:
        goal, wall, water = state.get("goal"), state.get("wall"), state.get("water")
        logs = state.get("logs")

        # 1 goal × avatar: kill every goal the frog overlaps, +1 each.
        cells, hit = grid_hits(goal, x, y)
        hit &= alive.unsqueeze(-1)
        score = state.get("score") + hit.sum(-1)
        goal = goal & ~cell_mask(goal.shape, cells, hit)

        # 2a avatar × log: shield from water. A log killed by EOS this tick still counts.
        # 2b avatar × log: pullWithIt, once per tick, through the first overlapping log in creation
        # order. Logs that have not moved yet are exactly the youngest ones, so the first
        # overlapping log moved iff any overlapping log moved; a frog that moved itself is not pulled.
        on_log = (
            logs.get("alive")
            & (logs.get("y") == y.unsqueeze(-1))
            & ((logs.get("x") - x.unsqueeze(-1)).abs() < CELL)
        )
        shielded = alive & on_log.any(-1)
        pulled = alive & ~pressed & (on_log & moved).any(-1)
        x = x - pulled * LOG_SPEED

        # 3 avatar × wall: stepBack to the start-of-tick position.
        back = alive & (grid_count(wall, x, y) > 0)
        x, y = torch.where(back, lastx, x), torch.where(back, lasty, y)

        # 4 avatar × truck: kill the frog. 5 avatar × water: kill the frog unless shielded.
        hit_truck = torch.zeros_like(alive)
        for name in TRUCK_TYPES:
            trucks = state.get(name)
            near = ((trucks.get("y") - y.unsqueeze(-1)).abs() < CELL) & (
                (trucks.get("x") - x.unsqueeze(-1)).abs() < CELL
            )
            hit_truck |= (near & trucks.get("alive")).any(-1)
        drowned = ~shielded & (grid_count(water, x, y) > 0)
        killed = alive & (hit_truck | drowned)

        state.get("avatar").update({"x": x, "y": y, "alive": alive & ~killed})
        state.update({"score": score, "goal": goal})

    # --- step 5: cleanup (logs killed by EOS at x < 0 are removed) ---
    @staticmethod
    def _logs_after_cleanup(state: TensorDict) -> torch.Tensor:
        logs = state.get("logs")
        return logs.get("alive") & (logs.get("x") >= 0)

    # --- step 6: termination, in declaration order ---
    @staticmethod
    def _check_termination(state: TensorDict) -> None:
        won = ~state.get("goal").flatten(1).any(-1)
        lost = ~won & ~state.get(("avatar", "alive"))
        state.set("won", state.get("won") | won)
        state.set("lost", state.get("lost") | lost)

    def layers(self, state: TensorDict) -> list:
        avatar, logs = state.get("avatar"), state.get("logs")
        layers = [
            GridLayer(name, state.get(name))
            for name in ("grass", "highway", "forestDense", "forestSparse", "water", "goal")
        ]
        layers.append(SpriteLayer("log", logs.get("x"), logs.get("y"), logs.get("alive")))
        for name in ("fastRtruck", "slowRtruck", "fastLtruck", "slowLtruck"):
            trucks = state.get(name)
            layers.append(SpriteLayer(name, trucks.get("x"), trucks.get("y"), trucks.get("alive")))
        layers.append(GridLayer("wall", state.get("wall")))
        one = lambda t: t.unsqueeze(-1)  # noqa: E731 - [B] -> [B, 1]
        layers.append(
            SpriteLayer("avatar", one(avatar.get("x")), one(avatar.get("y")), one(avatar.get("alive")))
        )
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
