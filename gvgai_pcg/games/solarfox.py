"""Solarfox (RULES.md §5): fly the ship over every blib and powerblib, never touching a wall,
the enemy lanes, the two enemies or their shots.

The ship (OngoingAvatar) moves 1 px per tick, so its position is usually not cell-aligned; every
other sprite is. Static and cell-aligned sprites are ``[B, H, W]`` grids (walls, enemyground,
blibs, powerblibs with their "res" counter, powerblibturning flickers by their creation tick); the
enemies (by cell) and their shots are entity tables. One tick is RULES.md §1.3 in this order:

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
each enemy owns ``SHOTS_PER_ENEMY`` slots of the shot table.
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
)
from gvgai_pcg.games.geometry import CELL, DIRECTION_NAMES, DOWN, LEFT, NONE, RIGHT, UP, overlaps
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
RES_LIMIT = 4  # the powerblib's "res" counter capacity
BLIB_AT_RES = 2  # spawnIfHasMore limit of rule 6a
DEATH_SCORE = -10
NO_TURNING = -(1 << 20)  # turning_born of a cell without a powerblibturning
STREAM_SHOT = 1

# Gym action index -> heading (0 NIL keeps the heading).
ACTION_DIRECTION = (NONE, LEFT, RIGHT, DOWN, UP)
_DX = (-1, 1, 0, 0, 0)
_DY = (0, 0, 1, -1, 0)


@cache
def _constants(device: str) -> dict[str, torch.Tensor]:
    """Small lookup tables, made once per device."""
    return {
        "action_direction": torch.tensor(ACTION_DIRECTION, device=device),
        "dx": torch.tensor(_DX, device=device),
        "dy": torch.tensor(_DY, device=device),
    }


def _cell_span(pos: torch.Tensor, count: int) -> torch.Tensor:
    """``[B, count]`` bool: the cells along one axis that a 10-px span starting at ``pos`` (``[B]``)
    overlaps (strictly, RULES.md §1.1)."""
    start = torch.arange(0, CELL * count, CELL, device=pos.device, dtype=pos.dtype)
    pos = pos.unsqueeze(-1)
    return (start < pos + CELL) & (pos < start + CELL)


@register_game("solarfox")
class Solarfox(Game):
    actions = ("NIL", "LEFT", "RIGHT", "DOWN", "UP")
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
        enemies = char_entities(levels, ENEMY_CHARS, device, capacity=1)
        kind = enemies.get("kind")
        enemies.update(
            {
                "col": enemies.get("x") // CELL,
                "row": enemies.get("y") // CELL,
                "dx": torch.tensor(ENEMY_START_DX, device=device)[kind],
            }
        )
        del enemies["x"], enemies["y"]
        slots = SHOTS_PER_ENEMY * kind.shape[1]
        shots = {
            "x": torch.zeros(batch, slots, dtype=torch.int64),
            "y": torch.zeros(batch, slots, dtype=torch.int64),
            # The owner's shot direction: -1 for the upshots of btm, +1 for the downshots of top.
            "dy": torch.tensor(SHOT_DY)[kind.cpu()].repeat_interleave(SHOTS_PER_ENEMY, dim=1),
            "alive": torch.zeros(batch, slots, dtype=torch.bool),
            "fresh": torch.zeros(batch, slots, dtype=torch.bool),  # created this tick: no move next update
        }
        avatar = {
            "x": ax,
            "y": ay,
            "ori": torch.full((batch,), RIGHT, dtype=torch.int64),
            "alive": torch.ones(batch, dtype=torch.bool),
        }
        wall = char_grid(levels, "w", device)
        ground = char_grid(levels, ".12", device)
        state = {
            **common_state(seeds, device),
            "wall": wall,
            "enemyground": ground,
            "deadly": wall | ground,  # a cell holds a wall or an enemyground, never both
            "floor": char_grid(levels, "+bpA12", device),
            "blib": char_grid(levels, "b", device),
            "powerblib": char_grid(levels, "p", device),
            "res": torch.zeros(wall.shape, dtype=torch.int8, device=device),
            "turning_born": torch.full(wall.shape, NO_TURNING, dtype=torch.int32, device=device),
            "avatar": TensorDict(avatar, batch_size=[batch]).to(device),
            "enemies": enemies,
            "shots": TensorDict(shots, batch_size=[batch, slots]).to(device),
        }
        return TensorDict(state, batch_size=[batch], device=device)

    def tick(self, state: TensorDict, action: torch.Tensor) -> None:
        tick = state.get("tick") + 1
        state.set("tick", tick)
        self._update_avatar(state, action, tick)
        self._update_shots(state)
        self._update_enemies(state, tick)
        # powerblibturning (Flicker) needs no update: its age is tick - turning_born.
        self._apply_rules(state, tick)
        self._cleanup(state)
        self._check_termination(state)

    # --- step 2: the ship (OngoingAvatar) ---
    def _update_avatar(self, state: TensorDict, action: torch.Tensor, tick: torch.Tensor) -> None:
        avatar = state.get("avatar")
        const = _constants(str(action.device))
        alive = avatar.get("alive")
        direction = const["action_direction"][action]
        ori = torch.where(alive & (direction != NONE), direction, avatar.get("ori"))
        # Passive move along the heading, skipped on the first update (tick 0).
        step = alive & (tick >= 1)
        avatar.update(
            {
                "ori": ori,
                "x": avatar.get("x") + step * const["dx"][ori],
                "y": avatar.get("y") + step * const["dy"][ori],
            }
        )

    # --- step 3: shots, enemies (powerblibturning: see tick) ---
    def _update_shots(self, state: TensorDict) -> None:
        """Missiles at 1 px per tick, from their second update on."""
        shots = state.get("shots")
        fresh = shots.get("fresh")
        moving = shots.get("alive") & ~fresh
        shots.update({"y": shots.get("y") + moving * shots.get("dy"), "fresh": torch.zeros_like(fresh)})

    def _update_enemies(self, state: TensorDict, tick: torch.Tensor) -> None:
        """Missiles, 10 px per move, cooldown 3. Enemies are level sprites that are never created or
        removed, so with the first-update skip at tick 0 they move exactly at ticks 2, 5, 8, …"""
        enemies = state.get("enemies")
        move = (tick % ENEMY_COOLDOWN == ENEMY_COOLDOWN - 1).unsqueeze(-1) & enemies.get("alive")
        enemies.set("col", enemies.get("col") + move * enemies.get("dx"))

    # --- step 4: collision rules in declaration order ---
    def _apply_rules(self, state: TensorDict, tick: torch.Tensor) -> None:
        avatar, enemies, shots = state.get("avatar"), state.get("enemies"), state.get("shots")
        wall = state.get("wall")
        blib, powerblib, res, born = (
            state.get("blib"),
            state.get("powerblib"),
            state.get("res"),
            state.get("turning_born"),
        )
        alive, ax, ay = avatar.get("alive"), avatar.get("x"), avatar.get("y")
        col, row, e_alive = enemies.get("col"), enemies.get("row"), enemies.get("alive")
        batch, height, width = wall.shape
        grid_tick = tick.to(born.dtype).view(-1, 1, 1)
        # The cells the ship overlaps (a ship disabled in an earlier tick collides with nothing).
        under = _cell_span(ay, height).unsqueeze(-1) & (
            _cell_span(ax, width) & alive.unsqueeze(-1)
        ).unsqueeze(-2)
        ship_x, ship_y = ax.unsqueeze(-1), ay.unsqueeze(-1)

        # 1-4 avatar × wall, enemy, enemyground, shot: kill (disable) the ship, -10 per sprite overlapped.
        lethal = (under & state.get("deadly")).flatten(1).sum(-1)
        enemy_hit = e_alive & overlaps(ship_x, ship_y, CELL * col, CELL * row)
        shot_hit = shots.get("alive") & overlaps(ship_x, ship_y, shots.get("x"), shots.get("y"))
        lethal = lethal + alive * (enemy_hit.sum(-1) + shot_hit.sum(-1))
        # 5 blib × avatar: collect, +1 each (the ship still collects in the tick it dies).
        taken = blib & under
        # 6a powerblib × powerblibturning: a blib on the powerblib once its counter is ≥ 2 (for all
        # pairs before 6b); 6b: the counter grows by 1 up to its limit. A turning is cell-aligned on
        # its powerblib's cell, and one killed by its Flicker update this tick still counts.
        paired = powerblib & (born >= grid_tick - TURNING_LIFE)
        spawned = paired & (res >= BLIB_AT_RES)
        res = res + (paired & (res < RES_LIMIT)).to(res.dtype)
        # 7 powerblibturning × avatar: kill the turnings the ship overlaps.
        # 8 powerblib × blib: the new blib kills its powerblib, +1 (a level blib never shares a cell
        # with a powerblib, so only the blibs of 6a can).
        powerblib = powerblib & ~spawned
        # 9 powerblib × avatar: a new turning on every powerblib the ship overlaps; under the ship,
        # rule 7 has killed the old one.
        born = torch.where(under, torch.where(powerblib, grid_tick, NO_TURNING), born)
        gained = taken.flatten(1).sum(-1) + spawned.flatten(1).sum(-1)
        state.update(
            {
                "score": state.get("score") + DEATH_SCORE * lethal + gained,
                "blib": (blib & ~taken) | spawned,
                "powerblib": powerblib,
                "res": res,
                "turning_born": born,
            }
        )
        avatar.set("alive", alive & (lethal == 0))

        # 10 enemy × wall: reverse (every tick of overlap, no stepBack). 11 btm × enemyground,
        # 12 top × enemyground: with probability 0.02 a shot at the enemy's cell.
        on_grid = e_alive & (col >= 0) & (col < width) & (row >= 0) & (row < height)
        cell = (row.clamp(0, height - 1) * width + col.clamp(0, width - 1)).view(batch, -1)
        on_wall = on_grid & torch.gather(wall.view(batch, -1), 1, cell)
        enemies.set("dx", torch.where(on_wall, -enemies.get("dx"), enemies.get("dx")))
        slots = torch.arange(col.shape[1], device=col.device)
        draw = rng.uniform(state.get("seed"), tick, slots, STREAM_SHOT)
        on_ground = on_grid & torch.gather(state.get("enemyground").view(batch, -1), 1, cell)
        self._spawn_shots(shots, on_ground & (draw < SHOT_PROBABILITY), enemies)

    @staticmethod
    def _spawn_shots(shots: TensorDict, fire: torch.Tensor, enemies: TensorDict) -> None:
        """A firing enemy (``fire`` ``[B, E]``) puts a shot into the first free slot of its own block."""
        batch, count = fire.shape
        block = (batch, count, SHOTS_PER_ENEMY)
        alive = shots.get("alive").view(block)
        free = ~alive
        place = free & (free.cumsum(-1) == 1) & fire.unsqueeze(-1)
        x = torch.where(place, CELL * enemies.get("col").unsqueeze(-1), shots.get("x").view(block))
        y = torch.where(place, CELL * enemies.get("row").unsqueeze(-1), shots.get("y").view(block))
        shots.update(
            {
                "x": x.view(batch, -1),
                "y": y.view(batch, -1),
                "alive": (alive | place).view(batch, -1),
                "fresh": place.view(batch, -1),
            }
        )

    # --- step 5: cleanup ---
    def _cleanup(self, state: TensorDict) -> None:
        """Killed sprites are already gone from the grids. Shots: GVGAI keeps them forever; here a
        shot is dropped once it has left the screen and is at least 10 px beyond the ship along its
        flight. Both move at most 1 px per tick, so such a shot can never overlap the ship again,
        and off screen it is neither drawn nor in ``tiles``."""
        shots, avatar = state.get("shots"), state.get("avatar")
        screen_h = CELL * state.get("wall").shape[1]
        y, dy = shots.get("y"), shots.get("dy")
        ship_y, ship_alive = avatar.get("y").unsqueeze(-1), avatar.get("alive").unsqueeze(-1)
        gone_up = (dy < 0) & (y + CELL <= 0) & (~ship_alive | (y + CELL <= ship_y))
        gone_down = (dy > 0) & (y >= screen_h) & (~ship_alive | (y >= ship_y + CELL))
        shots.set("alive", shots.get("alive") & ~(gone_up | gone_down))

    # --- step 6: termination, in declaration order ---
    def _check_termination(self, state: TensorDict) -> None:
        lost = ~state.get(("avatar", "alive"))
        won = ~lost & ~(state.get("blib") | state.get("powerblib")).flatten(1).any(-1)
        state.update({"won": state.get("won") | won, "lost": state.get("lost") | lost})

    def layers(self, state: TensorDict) -> list:
        avatar, enemies, shots = state.get("avatar"), state.get("enemies"), state.get("shots")
        one = lambda t: t.unsqueeze(-1)  # noqa: E731 - [B] -> [B, 1]
        ex, ey = CELL * enemies.get("col"), CELL * enemies.get("row")
        e_alive, e_kind = enemies.get("alive"), enemies.get("kind")
        sx, sy, s_alive, up = shots.get("x"), shots.get("y"), shots.get("alive"), shots.get("dy") < 0
        return [
            GridLayer("floor", state.get("floor")),
            GridLayer("enemyground", state.get("enemyground")),
            GridLayer("powerblib", state.get("powerblib")),
            GridLayer("powerblibturning", turning_grid(state)),
            GridLayer("blib", state.get("blib")),
            SpriteLayer("top", ex, ey, e_alive & (e_kind == TOP)),
            SpriteLayer("btm", ex, ey, e_alive & (e_kind == BTM)),
            SpriteLayer("upshot", sx, sy, s_alive & up),
            SpriteLayer("downshot", sx, sy, s_alive & ~up),
            GridLayer("wall", state.get("wall")),
            SpriteLayer(
                "avatar",
                one(avatar.get("x")),
                one(avatar.get("y")),
                one(avatar.get("alive")),
                one(avatar.get("ori")),
            ),
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
            ("powerblibturning", turning_grid(s)),
        )
        sprites = [[name, CELL * c, CELL * r] for name, grid in grids for r, c in grid[0].nonzero().tolist()]
        enemies = s.get("enemies")[0]
        for k in enemies.get("alive").nonzero().flatten().tolist():
            x, y = CELL * enemies.get("col")[k].item(), CELL * enemies.get("row")[k].item()
            sprites.append([ENEMY_TYPES[enemies.get("kind")[k].item()], x, y])
        shots = s.get("shots")[0]
        for k in shots.get("alive").nonzero().flatten().tolist():
            name = "upshot" if shots.get("dy")[k].item() < 0 else "downshot"
            sprites.append([name, shots.get("x")[k].item(), shots.get("y")[k].item()])
        return golden_record(s, avatar, sprites)

    def max_score(self, level: Level) -> int:
        """+1 per blib and +2 per powerblib (its blib is worth 1 and eating its powerblib 1, §5.6),
        collected without dying."""
        return level.count("b") + 2 * level.count("p")


def turning_grid(state: TensorDict) -> torch.Tensor:
    """``[B, H, W]`` bool: the powerblibturning sprites after the last tick. One created in tick
    ``born`` is killed by its Flicker update (limit 8) in tick ``born + 10``, so it is shown after
    ticks born … born + 9."""
    born = state.get("turning_born")
    return born >= (state.get("tick").to(born.dtype) - (TURNING_LIFE - 1)).view(-1, 1, 1)
