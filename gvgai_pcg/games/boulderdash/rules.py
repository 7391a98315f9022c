"""Boulderdash (RULES.md §7): dig, collect diamonds, dodge boulders and monsters, open the exit.

The tick is RULES.md §1.3 with Boulderdash's classes and rules:

* step 2, the avatar (ShootAvatar): rotate in place or move 10 px; USE puts the pickaxe (``sword``,
  Flicker limit 1, singleton) in the faced cell;
* step 3 in update order butterfly, crab (RandomNPC, cons 1: still at tick 0, a new direction at
  ticks 1, 3, 5, …, one cell per tick), boulder (Missile: 2 px down per tick from tick 1), sword (age);
* step 4, the collision rules in declaration order:
  1 dirt × avatar kill dirt · 2 dirt × sword kill dirt · 3 diamond × avatar collectResource (+2, cap 10) ·
  4 moving × wall stepBack · 5 moving × boulder stepBack · 6 avatar × boulder killIfFromAbove (−1) ·
  7 avatar × butterfly kill (−1 each) · 8 avatar × crab kill (−1 each) · 9–11 boulder × dirt, wall,
  diamond stepBack · 12 boulder × boulder stepBack · 13–14 enemy × dirt, diamond stepBack ·
  15 crab × butterfly kill crab · 16 butterfly × crab transformTo diamond (+1) ·
  17 exitdoor × avatar killIfOtherHasMore(diamond, 9);
* step 5 cleanup: killed dirt, diamonds, monsters and the exit go only now, so a killed sprite still
  acts as second sprite in every later rule of its tick (dead dirt holds a boulder for that tick);
* step 6 termination: no avatar → LOSE, then no exitdoor → WIN.

Static tiles are ``[B, H, W]`` grids (``diamond`` holds a count, since two butterflies sharing a
cell leave two diamonds). Boulders are an entity table in level (row-major) order. They never
appear, disappear or move sideways, so each keeps its column and its neighbour below for the
whole episode (``below``, computed at compile time). That makes the sequential ``boulder ×
boulder`` stepBack a single gather, see :func:`boulder_stepback`. Done in list order as §1.3
says, that rule leaves every boulder above the second-lowest of a stopped stack resting 2 px inside
the one below it (RULES.md §7.7; the Java engine does the same: golden traces ``boulderdash_stack3_resting``,
``boulderdash_stack5_fall``, ``boulderdash_two_stacks_merge``, ``boulderdash_three_stack_fall``).
Cleanup edits the dirt, diamond and exitdoor grids in place.

Off the screen. boulderdash.txt has no EOS rule, so in a level without a full wall border the
avatar and the monsters can walk off the grid and boulders fall out of it, and the rules still
apply out there on pixel rectangles (RULES.md §1.1, §7.7; golden traces ``boulderdash_offgrid_*``).
The grids hold what is on each env's own screen, so a sprite off it is tested by rectangles
instead (``geometry.overlaps_any``): rule 5 against the boulders for the avatar and the monsters,
and rules 3, 11 and 14 against the diamonds that butterflies turned into off the screen (rule 16),
kept in ``gems`` (one slot per monster slot) since no cell can hold them. Everything else needs
nothing there: dirt, walls and the exit never leave the screen, and rules 6-8 and 15-16 compare
positions. Only a level whose border is not all wall (``open``) lets a sprite leave its screen,
so the tick does this work only in a batch that holds one.
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
    Layer,
    SpriteArt,
    SpriteLayer,
    avatar_cell,
    char_entities,
    char_grid,
    common_state,
    golden_record,
    open_border,
    single_sprite_layer,
)
from gvgai_pcg.games.geometry import (
    CELL,
    DIRECTION_NAMES,
    NONE,
    RIGHT,
    add_at_,
    any_last,
    clear_listed_cells_,
    count_last,
    direction_dx,
    direction_dy,
    overlaps_any,
    screen_cell,
    small_cell_of,
)
from gvgai_pcg.games.registry import register_game
from gvgai_pcg.levels import Level

BUTTERFLY, CRAB = 0, 1  # enemy kinds, in update order (RULES.md §7.2)
ENEMY_CHARS = {"b": BUTTERFLY, "c": CRAB}
DIAMOND_LIMIT = 10  # the avatar holds at most 10 diamonds
EXIT_DIAMONDS = 9  # killIfOtherHasMore limit of rule 17
DIAMOND_SCORE, BUTTERFLY_SCORE, DEATH_SCORE = 2, 1, -1
SWORD_LIMIT = 1
BOULDER_FALL = 2  # px per tick: speed 0.2 of a 10-px cell
STREAM_ENEMY_DIRECTION = 1
# A boulder's flat key is column * _COLUMN_KEY + y: one subtraction compares column and height.
_COLUMN_KEY = 1 << 20


def draw_enemy_directions(seed: torch.Tensor, draw_tick: torch.Tensor, slots: torch.Tensor) -> torch.Tensor:
    """The direction (``[B, E]``, LEFT..UP) that enemy ``slot`` draws at ``draw_tick`` (``[B]``)."""
    return rng.randint(seed, draw_tick, slots, STREAM_ENEMY_DIRECTION, 4)


def enemy_directions(seed: torch.Tensor, tick: torch.Tensor, slots: torch.Tensor) -> torch.Tensor:
    """RandomNPC with cons 1 (RULES.md §2) for sprites placed by the level, ``[B, E]``.

    The counter makes the schedule a function of the tick alone: NONE at tick 0, a fresh draw at
    every odd tick, and the previous tick's draw at every even tick. Drawing from the
    counter-based rng at the draw tick gives the same direction on both ticks, so no ``counter``
    or ``prev`` has to be stored. (Enemies are never spawned in Boulderdash.)
    """
    draw_tick = tick - (1 - tick % 2)
    drawn = draw_enemy_directions(seed, draw_tick, slots)
    return torch.where((tick > 0).unsqueeze(-1), drawn, torch.full_like(drawn, NONE))


def boulder_cells(y: torch.Tensor, column: torch.Tensor, height: int, width: int) -> torch.Tensor:
    """Flat indices ``[B, 2K]`` of the cells boulders at ``y`` (``[B, K]``) in ``column`` overlap:
    boulder k's top row at ``2k``, its bottom row at ``2k + 1`` (the same cell again when it is
    aligned). Rows below the grid map to row ``height``, which the caller's grids keep empty (a
    boulder falls out of a level that has no bottom wall)."""
    y = y.clamp(max=CELL * height)
    rows = small_cell_of(torch.stack([y, y + (CELL - 1)], dim=-1))
    return (rows * width + column.unsqueeze(-1)).view(y.shape[0], -1)


def boulder_stepback(y: torch.Tensor, below: torch.Tensor, has_below: torch.Tensor) -> torch.Tensor:
    """Rule 12, ``boulder × boulder → stepBack`` in list order: which boulders go back (``[B, K]``).

    ``y`` are the positions after rules 9–11. Boulders only share a column with boulders, and list
    order is top to bottom within a column. Boulder a, at its turn, sees the boulder below it
    (later in the list) where rules 9–11 left it, and the boulder above it at its final place.
    The one above never overlaps a: two boulders are never closer than 8 px (a pair can end a tick
    2 px into each other when the lower one is stepped back by rule 12 after the upper one fell),
    and an upper boulder that is closer than 10 px to the one below is always stepped back itself,
    since it overlaps that one's position of rule 9–11 whether it moved or not. So only the
    neighbour below matters, and the sequential rule is one comparison per boulder: a goes back iff
    it overlaps its lower neighbour's position after rules 9–11. Boulders that did not move go back
    to where they are, which changes nothing.
    """
    lower = torch.gather(y, 1, below)
    return has_below & (lower - y < CELL)


def below_neighbours(
    x: torch.Tensor, y: torch.Tensor, alive: torch.Tensor
) -> tuple[torch.Tensor, torch.Tensor]:
    """For each boulder slot (``[B, K]``, row-major level order) the slot of the nearest boulder
    below it in its column, and whether there is one."""
    k = x.shape[1]
    slots = torch.arange(k, device=x.device)
    same_column = (x.unsqueeze(-1) == x.unsqueeze(-2)) & alive.unsqueeze(-1) & alive.unsqueeze(-2)
    lower = same_column & (y.unsqueeze(-2) > y.unsqueeze(-1))
    candidate = torch.where(lower, slots.view(1, 1, k), torch.full_like(lower, k, dtype=torch.int64))
    nearest = candidate.min(-1).values
    has_below = nearest < k
    return torch.where(has_below, nearest, slots.expand_as(nearest)), has_below


def collect_gems(
    gx: torch.Tensor,
    gy: torch.Tensor,
    galive: torch.Tensor,
    ax: torch.Tensor,
    ay: torch.Tensor,
    off: torch.Tensor,
    held: torch.Tensor,
) -> tuple[torch.Tensor, torch.Tensor]:
    """Rule 3 off the screen: an avatar at ``ax, ay`` (``[B]``) where ``off`` collects the gems at
    its place (``gx, gy, galive`` ``[B, E]``, cell-aligned like it), one at a time while it holds
    fewer than 10. Returns which gems are taken (``[B, E]``, removed at cleanup) and how many."""
    here = galive & (gx == ax.unsqueeze(-1)) & (gy == ay.unsqueeze(-1)) & off.unsqueeze(-1)
    taken = torch.minimum(count_last(here).long(), DIAMOND_LIMIT - held)
    return here & (here.cumsum(-1) <= taken.unsqueeze(-1)), taken


@register_game("boulderdash")
class Boulderdash(Game):
    actions = SHOOT_ACTIONS
    tile_types = ("wall", "sword", "dirt", "exitdoor", "diamond", "boulder", "crab", "butterfly", "avatar")
    seed_free_reset_tick = True  # enemies move NONE at tick 0 (enemy_directions); nothing else draws
    art = {
        "background": SpriteArt((20, 20, 20)),
        "wall": SpriteArt((110, 80, 50)),
        "sword": SpriteArt((200, 200, 230), "bar"),
        "dirt": SpriteArt((150, 105, 55)),
        "exitdoor": SpriteArt((60, 170, 60), "frame"),
        "diamond": SpriteArt((80, 220, 250), "small"),
        "boulder": SpriteArt((150, 150, 150), "circle"),
        "crab": SpriteArt((220, 60, 60), "diamond"),
        "butterfly": SpriteArt((200, 120, 250), "diamond"),
        "avatar": SpriteArt((250, 250, 250), "circle", oriented=True),
    }

    def compile(self, levels: Sequence[Level], seeds: torch.Tensor, device: torch.device) -> TensorDict:
        batch = len(levels)
        if max(level.height for level in levels) * CELL + CELL > 1028:
            raise ValueError("boulderdash levels must have at most 101 rows (the range of small_cell_of)")
        ax, ay = avatar_cell(levels, "A")
        zeros = torch.zeros(batch, dtype=torch.int64)
        table = char_entities(levels, {"o": 0}, device, capacity=1)
        bx, by, balive = table.get("x"), table.get("y"), table.get("alive")
        below, has_below = below_neighbours(bx, by, balive)
        column = small_cell_of(bx)
        boulders = {  # int32: half the memory traffic of int64, and still valid gather indices
            "x": bx.int(),
            "y": by.int(),
            "alive": balive,
            "column": column.int(),
            "key": (column * _COLUMN_KEY).int(),
            "weight": balive.unsqueeze(-1).repeat(1, 1, 2).to(torch.uint8),
            "below": below.int(),
            "has_below": has_below,
        }
        enemies = char_entities(levels, ENEMY_CHARS, device)
        # Diamonds off the screen: the one each monster slot's butterfly may turn into out there.
        gems = TensorDict(
            {
                key: torch.zeros(enemies.batch_size, dtype=enemies.get(key).dtype)
                for key in ("x", "y", "alive")
            },
            batch_size=enemies.batch_size,
            device=enemies.device,
        )
        avatar = {
            "x": ax,
            "y": ay,
            "ori": torch.full((batch,), RIGHT, dtype=torch.int64),
            "diamonds": zeros.clone(),
            "alive": torch.ones(batch, dtype=torch.bool),
        }
        sword = {"x": zeros.clone(), "y": zeros.clone(), "age": zeros.clone(), "exists": zeros.bool()}
        common = common_state(levels, seeds, device)
        wall = char_grid(levels, "w", device)
        state = {
            **common,
            "wall": wall,
            "open": open_border(wall, common["height"], common["width"]),
            "dirt": char_grid(levels, ".", device),
            "diamond": char_grid(levels, "x", device).to(torch.uint8),
            "exitdoor": char_grid(levels, "e", device),
            "exits": torch.tensor([level.count("e") for level in levels], dtype=torch.int64, device=device),
            "avatar": TensorDict(avatar, batch_size=[batch]).to(device),
            "sword": TensorDict(sword, batch_size=[batch]).to(device),
            "boulders": TensorDict(boulders, batch_size=table.batch_size),
            "enemies": enemies,
            "gems": gems,
        }
        return TensorDict(state, batch_size=[batch], device=device)

    def host_arguments(self, state: TensorDict) -> dict[str, object]:
        """Whether a sprite may be off its screen in this batch (one check, see the module docstring)."""
        return {"leaving": bool(any_last(state.get("open")))}

    def tick(self, state: TensorDict, action: torch.Tensor, leaving: bool | None = None) -> None:
        """RULES.md §1.3: the avatar, then butterflies, crabs, boulders and the pickaxe, then the rules."""
        if leaving is None:
            leaving = self.host_arguments(state)["leaving"]
        tick = state.get("tick") + 1
        state.set("tick", tick)
        avatar, sword = state.get("avatar"), state.get("sword")
        enemies, boulders, gems = state.get("enemies"), state.get("boulders"), state.get("gems")

        # Step 2, the avatar (ShootAvatar): a new direction only turns it, the faced one moves it 10 px;
        # USE places the pickaxe in the faced cell unless one exists (singleton).
        alive, lastx, lasty = avatar.get("alive"), avatar.get("x"), avatar.get("y")
        exists = sword.get("exists")
        moved = shoot_avatar(action, alive, avatar.get("ori"), lastx, lasty, ~exists)
        ax, ay, ori, place = moved.x, moved.y, moved.ori, moved.place
        sx = torch.where(place, moved.place_x, sword.get("x"))
        sy = torch.where(place, moved.place_y, sword.get("y"))
        age = torch.where(place, torch.zeros_like(sword.get("age")), sword.get("age"))
        exists = exists | place

        # Step 3: butterflies and crabs (RandomNPC, one cell per tick), boulders (Missile, 2 px down
        # from their second update on), the pickaxe (Flicker: killed once older than its limit).
        elastx, elasty, present = enemies.get("x"), enemies.get("y"), enemies.get("alive")
        heading = enemy_directions(state.get("seed"), tick, torch.arange(elastx.shape[1], device=tick.device))
        ex, ey = elastx + CELL * direction_dx(heading), elasty + CELL * direction_dy(heading)
        blasty = boulders.get("y")
        by = blasty + (BOULDER_FALL * (tick > 0)).int().unsqueeze(-1)
        sword_killed = exists & (age > SWORD_LIMIT)
        age = age + exists.long()

        # Step 4, the collision rules in declaration order.
        wall, dirt, diamond, exitdoor = (state.get(k) for k in ("wall", "dirt", "diamond", "exitdoor"))
        batch, height, width = wall.shape
        cells = height * width
        # Each env's last on-screen position of a cell-aligned sprite (its own screen, not the grid's).
        last_x, last_y = CELL * (state.get("width") - 1), CELL * (state.get("height") - 1)
        last_ex, last_ey = last_x.unsqueeze(-1), last_y.unsqueeze(-1)
        wall_f, dirt_f = wall.view(batch, cells), dirt.view(batch, cells)
        diamond_f, exit_f = diamond.view(batch, cells), exitdoor.view(batch, cells)
        score = state.get("score")

        # 1 dirt × avatar, 2 dirt × sword: the dirt is killed (it stays, as second sprite, until cleanup).
        a_cell, a_on = screen_cell(ax, ay, last_x, last_y, width)
        a_here = alive & a_on
        s_cell, s_on = screen_cell(sx, sy, last_x, last_y, width)
        dig_cells = torch.stack([a_cell, s_cell], dim=-1)
        dig = torch.stack([a_here, exists & s_on], dim=-1)

        # 3 diamond × avatar: collectResource, one diamond at a time while the avatar holds < 10 (+2 each).
        held = avatar.get("diamonds")
        collected = torch.minimum(
            diamond_f.gather(1, a_cell.unsqueeze(-1)).squeeze(-1).long(), DIAMOND_LIMIT - held
        )
        collected = collected * a_here
        held = held + collected
        score = score + DIAMOND_SCORE * collected
        if leaving:  # off the screen, the diamonds butterflies left there
            gx, gy, galive = gems.get("x"), gems.get("y"), gems.get("alive")
            gems_taken, from_gems = collect_gems(gx, gy, galive, ax, ay, alive & ~a_on, held)
            held = held + from_gems
            score = score + DIAMOND_SCORE * from_gems

        # 4 moving × wall, 5 moving × boulder: stepBack, against the boulders where step 3 moved them.
        padded = cells + width  # one empty row under the grid for boulders that fell out of it
        b_cells = boulder_cells(by, boulders.get("column"), height, width)
        covered = torch.zeros(batch, padded, dtype=torch.uint8, device=tick.device)
        add_at_(covered, b_cells, boulders.get("weight").view(batch, -1))
        # Off the screen (no wall is there): against the boulders' rectangles.
        a_index = a_cell.unsqueeze(-1)
        blocked = wall_f.gather(1, a_index) | (covered.gather(1, a_index) > 0)
        back = a_here & blocked.squeeze(-1)
        bx, balive = boulders.get("x"), boulders.get("alive")
        if leaving:
            back |= overlaps_any(ax, ay, alive & ~a_on, bx, by, balive)
        ax, ay = torch.where(back, lastx, ax), torch.where(back, lasty, ay)
        e_cell, e_on = screen_cell(ex, ey, last_ex, last_ey, width)
        back = present & e_on & (wall_f.gather(1, e_cell) | (covered.gather(1, e_cell) > 0))
        if leaving:
            back |= overlaps_any(ex, ey, present & ~e_on, bx, by, balive)
        ex, ey = torch.where(back, elastx, ex), torch.where(back, elasty, ey)

        # 6 avatar × boulder: killIfFromAbove, −1 if a boulder that was > 5 px higher moved down onto it.
        # An avatar that moved and stayed overlaps no boulder (rule 5), so only one at its start-of-tick
        # place can die. Every boulder moved 2 px in step 3 (from tick 1), so "was > 5 px higher and
        # overlaps now" is: same column and by − ay in (−10, 2 − 5).
        # Off the screen the avatar's column is clamped to one beside the grid, where no boulder is.
        still = alive & (ax == lastx) & (ay == lasty) & (tick > 0)
        column = small_cell_of(ax.clamp(-CELL, CELL * width) if leaving else ax)
        offset = boulders.get("key") + by - (column * _COLUMN_KEY + ay).int().unsqueeze(-1)
        from_above = (offset > -CELL) & (offset < BOULDER_FALL - 5) & balive
        crushed = still & any_last(from_above)
        score = score + DEATH_SCORE * crushed.long()
        # 7 avatar × butterfly, 8 avatar × crab: kill, −1 per monster (everything here is cell-aligned;
        # a disabled avatar still collides for the rest of the tick).
        touching = present & (ex == ax.unsqueeze(-1)) & (ey == ay.unsqueeze(-1)) & alive.unsqueeze(-1)
        score = score + DEATH_SCORE * touching.sum(-1)
        disabled = crushed | any_last(touching)

        # 9-11 boulder × dirt, wall, diamond: stepBack (dead dirt and collected diamonds still count;
        # a boulder reaching off the screen meets only the diamonds there).
        below_grid = torch.zeros(batch, width, dtype=torch.bool, device=tick.device)
        solid = torch.cat([dirt_f | wall_f | diamond_f.bool(), below_grid], dim=1)
        hit = solid.gather(1, b_cells).view(batch, -1, 2)
        hit = hit[..., 0] | hit[..., 1]
        if leaving:
            off = balive & (by > last_ey) & any_last(galive).unsqueeze(-1)
            hit |= overlaps_any(bx, by, off, gx, gy, galive)
        by = torch.where(hit, blasty, by)
        # 12 boulder × boulder: stepBack, in list order (see boulder_stepback).
        by = torch.where(boulder_stepback(by, boulders.get("below"), boulders.get("has_below")), blasty, by)

        # 13-14 enemy × dirt, diamond: stepBack (an enemy is never inside a wall by now; off the
        # screen only diamonds are there).
        e_cell, e_on = screen_cell(ex, ey, last_ex, last_ey, width)
        back = present & e_on & solid.gather(1, e_cell)
        if leaving:
            back |= overlaps_any(ex, ey, present & ~e_on, gx, gy, galive)
        ex, ey = torch.where(back, elastx, ex), torch.where(back, elasty, ey)

        # 15 crab × butterfly: kill the crab. 16 butterfly × crab: transformTo diamond, +1 per butterfly
        # (a crab killed by rule 15 still counts as second sprite).
        kind = enemies.get("kind")
        crab, butterfly = present & (kind == CRAB), present & (kind == BUTTERFLY)
        meet = (ex.unsqueeze(-1) == ex.unsqueeze(-2)) & (ey.unsqueeze(-1) == ey.unsqueeze(-2))
        crab_dies = crab & any_last(meet & butterfly.unsqueeze(-2))
        turns = butterfly & any_last(meet & crab.unsqueeze(-2))
        score = score + BUTTERFLY_SCORE * turns.sum(-1)

        # 17 exitdoor × avatar: killIfOtherHasMore, the exit goes if the avatar holds >= 9 diamonds.
        a_cell, a_on = screen_cell(ax, ay, last_x, last_y, width)
        exit_here = exit_f.gather(1, a_cell.unsqueeze(-1)).squeeze(-1)
        opens = alive & a_on & exit_here & (held >= EXIT_DIAMONDS)

        # Step 5, cleanup: killed sprites go now; the new diamonds stay (off the screen, as gems).
        clear_listed_cells_(dirt_f, dig_cells, dig)
        add_at_(diamond_f, dig_cells[:, :1], (-collected).to(torch.uint8).unsqueeze(-1))
        e_cell, e_on = screen_cell(ex, ey, last_ex, last_ey, width)
        add_at_(diamond_f, e_cell, (turns & e_on).to(torch.uint8))
        if leaving:
            made = turns & ~e_on
            gems.update(
                {
                    "x": torch.where(made, ex, gx),
                    "y": torch.where(made, ey, gy),
                    "alive": galive & ~gems_taken | made,
                }
            )
        exit_f.scatter_(1, a_cell.unsqueeze(-1), (exit_here & ~opens).unsqueeze(-1))
        exits = state.get("exits") - opens.long()
        alive = alive & ~disabled
        avatar.update({"x": ax, "y": ay, "ori": ori, "alive": alive, "diamonds": held})
        sword.update({"x": sx, "y": sy, "age": age, "exists": exists & ~sword_killed})
        enemies.update({"x": ex, "y": ey, "alive": present & ~crab_dies & ~turns})
        boulders.set("y", by)
        # Step 6, termination in declaration order: no avatar → LOSE, then no exitdoor → WIN.
        lost = ~alive
        won = ~lost & (exits == 0)
        state.update(
            {"exits": exits, "score": score, "won": state.get("won") | won, "lost": state.get("lost") | lost}
        )

    def layers(self, state: TensorDict) -> list[Layer]:
        avatar, sword = state.get("avatar"), state.get("sword")
        boulders, enemies = state.get("boulders"), state.get("enemies")
        wall = state.get("wall")
        ex, ey, present, kind = enemies.get("x"), enemies.get("y"), enemies.get("alive"), enemies.get("kind")
        return [
            GridLayer("background", ~wall),
            GridLayer("wall", wall),
            single_sprite_layer("sword", sword, "exists"),
            GridLayer("dirt", state.get("dirt")),
            GridLayer("exitdoor", state.get("exitdoor")),
            GridLayer("diamond", state.get("diamond").bool()),
            SpriteLayer("boulder", boulders.get("x"), boulders.get("y"), boulders.get("alive")),
            SpriteLayer("crab", ex, ey, present & (kind == CRAB)),
            SpriteLayer("butterfly", ex, ey, present & (kind == BUTTERFLY)),
            single_sprite_layer("avatar", avatar, oriented=True),
        ]

    def snapshot(self, state: TensorDict, index: int) -> dict:
        s = state[index]
        avatar = None
        if s.get(("avatar", "alive")).item():
            held = s.get(("avatar", "diamonds")).item()
            avatar = {
                "type": "avatar",
                "x": s.get(("avatar", "x")).item(),
                "y": s.get(("avatar", "y")).item(),
                "orientation": DIRECTION_NAMES[s.get(("avatar", "ori")).item()],
                "resources": {"diamond": held} if held else {},
            }
        sprites = []
        for name in ("dirt", "exitdoor"):
            sprites += [[name, CELL * c, CELL * r] for r, c in s.get(name).nonzero().tolist()]
        diamond = s.get("diamond")
        for r, c in diamond.nonzero().tolist():
            sprites += [["diamond", CELL * c, CELL * r]] * int(diamond[r, c])
        gems = s.get("gems")
        for k in gems.get("alive").nonzero().flatten().tolist():
            sprites.append(["diamond", gems.get("x")[k].item(), gems.get("y")[k].item()])
        if s.get(("sword", "exists")).item():
            sprites.append(["sword", s.get(("sword", "x")).item(), s.get(("sword", "y")).item()])
        boulders = s.get("boulders")
        for k in boulders.get("alive").nonzero().flatten().tolist():
            sprites.append(["boulder", boulders.get("x")[k].item(), boulders.get("y")[k].item()])
        enemies = s.get("enemies")
        for k in enemies.get("alive").nonzero().flatten().tolist():
            name = "crab" if enemies.get("kind")[k].item() == CRAB else "butterfly"
            sprites.append([name, enemies.get("x")[k].item(), enemies.get("y")[k].item()])
        return golden_record(s, avatar, sprites)

    def max_score(self, level: Level) -> int:
        """+2 per diamond collected, at most 10 ever (the count never drops), from the level's diamonds
        and the one each butterfly leaves when a crab meets it (+1 each; needs a crab). Opening the
        exit scores 0, and a level without an exit is won at the reset tick (score 0)."""
        if level.count("e") == 0:
            return 0
        butterflies = level.count("b") if level.count("c") > 0 else 0
        diamonds = min(DIAMOND_LIMIT, level.count("x") + butterflies)
        return DIAMOND_SCORE * diamonds + BUTTERFLY_SCORE * butterflies
