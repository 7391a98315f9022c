"""Zelda (RULES.md §4): take the key, reach the door, kill monsters with the sword.

Everything here is cell-aligned (all moves are 10 px), but positions are pixels like in every
game. The tick below is RULES.md §1.3 with Zelda's rules in declaration order:

1 movable × wall stepBack · 2 nokey × goal stepBack · 3 goal × withkey kill goal (+1) ·
4 enemy × sword kill enemy (+2) · 5 enemy × enemy stepBack · 6 avatar × enemy kill avatar (−1 each) ·
7 nokey × key transformTo withkey (+1, facing RIGHT; score even when the avatar is disabled).
Termination: no goal → WIN, then no avatar → LOSE.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch
from tensordict import TensorDict

from gvgai_pcg.games import rng
from gvgai_pcg.games.actions import SHOOT_ACTIONS, shoot_avatar
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
    single_sprite_layer,
)
from gvgai_pcg.games.geometry import (
    CELL,
    DIRECTION_NAMES,
    NONE,
    RIGHT,
    any_last,
    clear_cells_,
    direction_dx,
    direction_dy,
    grid_count,
    grid_hits,
    overlaps,
    overlaps_aligned,
)
from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.games.registry import register_game
from gvgai_pcg.games.rules import step_back_in_order
from gvgai_pcg.levels import Level

# Monster kinds in processing order of the enemy group (quick, normal, slow), RULES.md §4.7.
MONSTER_TYPES = ("monsterQuick", "monsterNormal", "monsterSlow")
MONSTER_CHARS = {"1": 0, "2": 1, "3": 2}
MONSTER_COOLDOWN = (2, 4, 8)
MONSTER_CONS = (6, 8, 12)
SWORD_LIMIT = 5
STREAM_MONSTER_DIRECTION = 1
# Every Zelda sprite moves by whole cells and starts on one, so each covers exactly one cell.
ALIGNED = True
# The widest monster table that ticks compiled. Compiled, the ordered stepBack runs all its rounds
# (one per slot: no early exit in a graph), so its cost grows as slots cubed; eagerly it stops when
# nothing changes (about 4 rounds). At 64 envs, env steps per CPU second with tables of 16, 32 and
# 64 slots, compiled: 31-48k, 11.2k, 2.4k; with a wider table eager: 17.7k (32), 11.9k (64);
# eager at 16: 22k (docs/experiments/crowded_zelda.py; docs/history/benchmarks-notebook.md,
# "Crowded Zelda levels").
# Human and generated levels have at most 4 monsters; ACCEL's edited levels reach 50.
COMPILED_MONSTER_SLOTS = 16
sprites_overlap = overlaps_aligned if ALIGNED else overlaps


def random_npc_directions(
    state: TensorDict, table: str, cons: torch.Tensor, stream: int
) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """RandomNPC direction schedule (RULES.md §2): hold ``prev`` for ``cons`` updates, then draw.

    Returns (direction, new counter), both ``[B, K]``; the direction is also the new ``prev``.
    """
    monsters = state.get(table)
    counter, prev = monsters.get("counter"), monsters.get("prev")
    slots = torch.arange(counter.shape[1], device=counter.device)
    drawn = rng.randint(state.get("seed"), state.get("tick"), slots, stream, 4)
    draw = counter >= cons
    prev = torch.where(draw, drawn, prev)
    counter = torch.where(draw, torch.zeros_like(counter), counter + 1)
    return prev, counter


@register_game("zelda")
class Zelda(Game):
    actions = SHOOT_ACTIONS
    tile_types = ("wall", "goal", "key", "sword", "nokey", "withkey", *MONSTER_TYPES)
    # A monster first draws a direction once its counter (0 in every compiled level) reaches its
    # cons (6 or more), so tick 0 draws nothing.
    seed_free_reset_tick = True
    art = {
        "floor": SpriteArt((40, 40, 40)),
        "wall": SpriteArt((110, 90, 70)),
        "goal": SpriteArt((140, 80, 20), "frame"),
        "key": SpriteArt((250, 210, 0), "cross"),
        "sword": SpriteArt((200, 200, 230), "bar"),
        "nokey": SpriteArt((250, 250, 250), "circle", oriented=True),
        "withkey": SpriteArt((250, 160, 0), "circle", oriented=True),
        "monsterQuick": SpriteArt((120, 60, 200), "diamond"),
        "monsterNormal": SpriteArt((200, 40, 40), "diamond"),
        "monsterSlow": SpriteArt((40, 160, 60), "diamond"),
    }

    def compile(self, levels: Sequence[Level], seeds: torch.Tensor, device: torch.device) -> TensorDict:
        batch = len(levels)
        ax, ay = avatar_cell(levels, "A")
        zeros = torch.zeros(batch, dtype=torch.int64)
        monsters = char_entities(levels, MONSTER_CHARS, device)
        k = monsters.batch_size[1]
        monsters.update(
            {
                "lastx": monsters.get("x").clone(),
                "lasty": monsters.get("y").clone(),
                "lastmove": torch.zeros(batch, k, dtype=torch.int64, device=device),
                "counter": torch.zeros(batch, k, dtype=torch.int64, device=device),
                "prev": torch.full((batch, k), NONE, dtype=torch.int64, device=device),
                "killed": torch.zeros(batch, k, dtype=torch.bool, device=device),
            }
        )
        avatar = {
            "x": ax,
            "y": ay,
            "lastx": ax.clone(),
            "lasty": ay.clone(),
            "ori": torch.full((batch,), RIGHT, dtype=torch.int64),
            "has_key": torch.zeros(batch, dtype=torch.bool),
            "alive": torch.ones(batch, dtype=torch.bool),
        }
        sword = {
            "x": zeros,
            "y": zeros.clone(),
            "ori": zeros.clone(),
            "age": zeros.clone(),
            "exists": zeros.bool(),
            "killed": zeros.bool(),
        }
        state = {
            **common_state(levels, seeds, device),
            "wall": char_grid(levels, "w", device),
            "goal": char_grid(levels, "g", device),
            "key": char_grid(levels, "+", device),
            "avatar": TensorDict(avatar, batch_size=[batch]).to(device),
            "sword": TensorDict(sword, batch_size=[batch]).to(device),
            "monsters": monsters,
        }
        return TensorDict(state, batch_size=[batch], device=device)

    def host_arguments(self, state: TensorDict) -> dict[str, object]:
        """Whether the monster table is wider than ``COMPILED_MONSTER_SLOTS`` (its shape, no sync)."""
        return {"crowded": state.get("monsters").batch_size[1] > COMPILED_MONSTER_SLOTS}

    def tick(self, state: TensorDict, action: torch.Tensor, crowded: bool | None = None) -> None:
        """RULES.md §4; ``crowded`` only chooses how the engine runs it (``StepFacts.eager_when``)."""
        state.set("tick", state.get("tick") + 1)
        self._update_avatar(state, action)
        self._update_monsters(state)
        self._update_sword(state)
        self._apply_rules(state)
        self._cleanup(state)
        self._check_termination(state)

    # --- step 2: the avatar (ShootAvatar: rotate in place, move, or place the sword) ---
    def _update_avatar(self, state: TensorDict, action: torch.Tensor) -> None:
        avatar, sword = state.get("avatar"), state.get("sword")
        x, y = avatar.get("x"), avatar.get("y")
        avatar.set("lastx", x)
        avatar.set("lasty", y)
        moved = shoot_avatar(action, avatar.get("alive"), avatar.get("ori"), x, y, ~sword.get("exists"))
        avatar.update({"x": moved.x, "y": moved.y, "ori": moved.ori})
        place = moved.place
        sword.set("x", torch.where(place, moved.place_x, sword.get("x")))
        sword.set("y", torch.where(place, moved.place_y, sword.get("y")))
        sword.set("ori", torch.where(place, moved.ori, sword.get("ori")))
        sword.set("age", torch.where(place, torch.zeros_like(sword.get("age")), sword.get("age")))
        sword.set("exists", sword.get("exists") | place)

    # --- step 3: monsters (RandomNPC, cooldown-gated) and the sword (Flicker) ---
    def _update_monsters(self, state: TensorDict) -> None:
        monsters = state.get("monsters")
        kind, alive = monsters.get("kind"), monsters.get("alive")
        cons, cooldown = lookup(MONSTER_CONS, kind), lookup(MONSTER_COOLDOWN, kind)
        direction, counter = random_npc_directions(state, "monsters", cons, STREAM_MONSTER_DIRECTION)
        lastmove = monsters.get("lastmove") + 1
        move = alive & (direction != NONE) & (lastmove >= cooldown)
        x, y = monsters.get("x"), monsters.get("y")
        monsters.update(
            {
                "lastx": x,
                "lasty": y,
                "x": x + move * CELL * direction_dx(direction),
                "y": y + move * CELL * direction_dy(direction),
                "lastmove": torch.where(move, torch.zeros_like(lastmove), lastmove),
                "counter": torch.where(alive, counter, monsters.get("counter")),
                "prev": torch.where(alive, direction, monsters.get("prev")),
            }
        )

    def _update_sword(self, state: TensorDict) -> None:
        sword = state.get("sword")
        exists, age = sword.get("exists"), sword.get("age")
        sword.set("killed", exists & (age > SWORD_LIMIT))
        sword.set("age", age + exists)

    # --- step 4: collision rules in declaration order ---
    def _apply_rules(self, state: TensorDict) -> None:
        avatar, sword, monsters = state.get("avatar"), state.get("sword"), state.get("monsters")
        wall, goal, key = state.get("wall"), state.get("goal"), state.get("key")
        alive, has_key = avatar.get("alive"), avatar.get("has_key")
        ax, ay, lastx, lasty = avatar.get("x"), avatar.get("y"), avatar.get("lastx"), avatar.get("lasty")
        mx, my = monsters.get("x"), monsters.get("y")
        present = monsters.get("alive")
        score = state.get("score")

        # 1 movable × wall: stepBack.
        back = alive & (grid_count(wall, ax, ay, ALIGNED) > 0)
        ax, ay = torch.where(back, lastx, ax), torch.where(back, lasty, ay)
        back = present & (grid_count(wall, mx, my, ALIGNED) > 0)
        mx, my = torch.where(back, monsters.get("lastx"), mx), torch.where(back, monsters.get("lasty"), my)
        # 2 nokey × goal: stepBack.
        back = alive & ~has_key & (grid_count(goal, ax, ay, ALIGNED) > 0)
        ax, ay = torch.where(back, lastx, ax), torch.where(back, lasty, ay)
        # 3 goal × withkey: kill the goal, +1 each.
        cells, hit = grid_hits(goal, ax, ay, ALIGNED)
        hit &= (alive & has_key).unsqueeze(-1)
        score = score + hit.sum(-1)
        clear_cells_(goal, cells, hit)
        # 4 enemy × sword: kill the monster, +2 each (a sword killed this tick still acts as second).
        sword_here = sword.get("exists").unsqueeze(-1)
        killed = (
            present
            & sword_here
            & sprites_overlap(mx, my, sword.get("x").unsqueeze(-1), sword.get("y").unsqueeze(-1))
        )
        score = score + 2 * killed.sum(-1)
        # 5 enemy × enemy: stepBack, the first in processing order goes back.
        mx, my = step_back_in_order(
            mx, my, monsters.get("lastx"), monsters.get("lasty"), present & ~killed, present, ALIGNED
        )
        # 6 avatar × enemy: kill (disable) the avatar, −1 per monster overlapped.
        meets = sprites_overlap(ax.unsqueeze(-1), ay.unsqueeze(-1), mx, my)
        touching = alive.unsqueeze(-1) & present & meets
        score = score - touching.sum(-1)
        disabled = any_last(touching)
        # 7 nokey × key: transformTo withkey (facing RIGHT), killing the key, +1; a disabled avatar
        # still scores but is not transformed.
        cells, hit = grid_hits(key, ax, ay, ALIGNED)
        hit &= (alive & ~has_key).unsqueeze(-1)
        take = any_last(hit)
        score = score + torch.where(disabled, hit.sum(-1), take.long())
        transform = take & ~disabled
        first_hit = hit & (hit.cumsum(-1) == 1) & transform.unsqueeze(-1)
        clear_cells_(key, cells, first_hit)

        avatar.update(
            {
                "x": ax,
                "y": ay,
                "alive": alive & ~disabled,
                "has_key": has_key | transform,
                "ori": torch.where(transform, torch.full_like(avatar.get("ori"), RIGHT), avatar.get("ori")),
            }
        )
        monsters.update({"x": mx, "y": my, "killed": killed})
        state.set("score", score)  # goal and key were cleared in place

    # --- step 5: cleanup ---
    def _cleanup(self, state: TensorDict) -> None:
        monsters, sword = state.get("monsters"), state.get("sword")
        monsters.set("alive", monsters.get("alive") & ~monsters.get("killed"))
        sword.set("exists", sword.get("exists") & ~sword.get("killed"))

    # --- step 6: termination, in declaration order ---
    def _check_termination(self, state: TensorDict) -> None:
        won = ~any_last(state.get("goal").flatten(1))
        lost = ~won & ~state.get(("avatar", "alive"))
        state.set("won", state.get("won") | won)
        state.set("lost", state.get("lost") | lost)

    def layers(self, state: TensorDict) -> list:
        avatar, sword, monsters = state.get("avatar"), state.get("sword"), state.get("monsters")
        wall = state.get("wall")
        alive, has_key = avatar.get("alive"), avatar.get("has_key")
        layers = [
            GridLayer("floor", ~wall),
            GridLayer("goal", state.get("goal")),
            GridLayer("key", state.get("key")),
            single_sprite_layer("sword", sword, "exists"),
        ]
        kind, present = monsters.get("kind"), monsters.get("alive")
        for code, name in enumerate(MONSTER_TYPES):
            layers.append(SpriteLayer(name, monsters.get("x"), monsters.get("y"), present & (kind == code)))
        layers.append(GridLayer("wall", wall))
        for name, mask in (("nokey", alive & ~has_key), ("withkey", alive & has_key)):
            layers.append(single_sprite_layer(name, avatar, mask, oriented=True))
        return layers

    def snapshot(self, state: TensorDict, index: int) -> dict:
        s = state[index]
        avatar = None
        if s.get(("avatar", "alive")).item():
            avatar = {
                "type": "withkey" if s.get(("avatar", "has_key")).item() else "nokey",
                "x": s.get(("avatar", "x")).item(),
                "y": s.get(("avatar", "y")).item(),
                "orientation": DIRECTION_NAMES[s.get(("avatar", "ori")).item()],
                "resources": {},
            }
        sprites = [["goal", 10 * c, 10 * r] for r, c in s.get("goal").nonzero().tolist()]
        sprites += [["key", 10 * c, 10 * r] for r, c in s.get("key").nonzero().tolist()]
        if s.get(("sword", "exists")).item():
            sprites.append(["sword", s.get(("sword", "x")).item(), s.get(("sword", "y")).item()])
        monsters = s.get("monsters")
        for k in monsters.get("alive").nonzero().flatten().tolist():
            name = MONSTER_TYPES[monsters.get("kind")[k].item()]
            sprites.append([name, monsters.get("x")[k].item(), monsters.get("y")[k].item()])
        return golden_record(s, avatar, sprites)

    def max_score(self, level: Level) -> int:
        monsters = sum(level.count(ch) for ch in MONSTER_CHARS)
        return 2 * monsters + 2
