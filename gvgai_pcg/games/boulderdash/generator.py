"""Boulderdash generator (GENERATORS.md §1.5, v3): a cellular-automaton cave with gems, boulders that
never cut off a gem or the exit, and enemies in dug pockets; grows with d and is centred in a
`w` frame of 26x13.

d grows the cave (``W = floor(14d + 2r) + 10``, ``H = floor(d + 2r) + 10``), its wall density and
roughness, the boulder and enemy counts, and lowers the extra gems. Quirks of the original kept
because they shape the distribution:

* the boulder count ``B = floor((0.7 + 0.3r) d 2 (10 + g))`` uses the raw extra-gem fraction g,
  not the extra-gem count E; the gem target is 10 + E;
* every tentative boulder is kept only if every gem and the exit stay reachable from the start
  through dirt and gems;
* caves are connected by an L corridor for every ordered pair of regions, a region with itself
  included, so corridors also cut through walls inside one region;
* start and exit are still dirt while enemies are placed: pockets may run through them (they
  are marked last), and an enemy may land on a pocket dug by an earlier enemy.

Noisy sort: boulder candidates are ordered by distance to the nearest gem with +-0.1 comparator
noise, which only breaks ties between equal integer distances. We use the key form: sort by
distance, ties in uniformly random order.

Reachability is checked exactly but cheaply: a boulder on a tile whose open 4-neighbours are
joined around it (through its 8-neighbour ring) cannot disconnect anything, so only the other
tiles need a search from the start.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from scipy import ndimage

from gvgai_pcg.games.boulderdash import LEVEL_FORMAT as FULL
from gvgai_pcg.generators._common import UniformStream, frame, generated_level
from gvgai_pcg.levels.level import Level

DIRT, WALL, GEM, BOULDER, BUTTERFLY, CRAB, EMPTY, AVATAR, EXIT = range(9)
CHARS = ".wxobc-Ae"
BASE_GEMS = 10
MIN_EXIT_DISTANCE = 4
BOULDER_CLEARANCE = 4  # boulders go strictly further than this from start and exit
ENEMY_START_CLEARANCE, ENEMY_EXIT_CLEARANCE = 5, 2
_TO_CHARS = bytes.maketrans(bytes(range(len(CHARS))), CHARS.encode())
_FOUR_CONNECTED = ndimage.generate_binary_structure(2, 1)


def parameters(difficulty: float, r: UniformStream) -> tuple[int, int, float, int, int, int, int]:
    """(W, H, wall probability s, CA sweeps T, enemies N, boulders B, extra gems E)."""
    d = difficulty
    width = math.floor((FULL.width - 12) * d + 2 * r()) + 10
    height = math.floor((FULL.height - 12) * d + 2 * r()) + 10
    solid = 0.6 * d + 0.2 + 0.2 * r()
    smoothness = 0.5 * (1 - d) + 0.3 + 0.2 * r()
    enemies = (0.7 + 0.3 * r()) * d
    boulders = (0.7 + 0.3 * r()) * d
    extra_gems = 0.7 * (1 - d) + 0.1 + 0.2 * r()
    return (
        max(width, 10),
        max(height, 10),
        solid * 0.5,
        math.floor(smoothness * 10 + 1),
        math.floor(enemies * 0.05 * width * height),
        math.floor(boulders * 2 * (10 + extra_gems)),
        math.floor(extra_gems * 0.05 * width * height),
    )


def cave(
    width: int, height: int, wall_probability: float, sweeps: int, rng: np.random.Generator
) -> np.ndarray:
    """[H, W] int8 grid, 1 = wall: random walls smoothed by ``sweeps`` synchronous CA sweeps.

    The rules (open -> wall with more than 5 wall neighbours, wall -> open with more than 4 open
    ones) are both "3x3 wall count plus the tile itself >= 6", which needs one box sum per sweep.
    """
    grid = (rng.random((height, width)) < wall_probability).astype(np.int8)
    grid[0, :] = grid[-1, :] = grid[:, 0] = grid[:, -1] = 1
    for _ in range(sweeps):
        rows = grid[:, :-2] + grid[:, 1:-1] + grid[:, 2:]
        box = rows[:-2] + rows[1:-1] + rows[2:]
        grid[1:-1, 1:-1] = box + grid[1:-1, 1:-1] >= 6
    return grid


def connect_regions(grid: np.ndarray, r: UniformStream) -> None:
    """Dig an L corridor (along the row, then the column) between random tiles of every ordered
    pair of open regions, a region with itself included."""
    labels, count = ndimage.label(grid == 0, structure=_FOUR_CONNECTED)
    flat = labels.ravel()
    by_region = np.argsort(flat, kind="stable")
    ends = np.searchsorted(flat[by_region], np.arange(count + 2)).tolist()
    by_region = by_region.tolist()
    regions = [(ends[k], ends[k + 1] - ends[k]) for k in range(1, count + 1)]  # (offset, size)
    width = grid.shape[1]
    for first, first_size in regions:
        for second, second_size in regions:
            y1, x1 = divmod(by_region[first + math.floor(r() * first_size)], width)
            y2, x2 = divmod(by_region[second + math.floor(r() * second_size)], width)
            if x1 < x2:
                grid[y1, x1:x2] = 0
            elif x1 > x2:
                grid[y1, x2 + 1 : x1 + 1] = 0
            if y1 < y2:
                grid[y1:y2, x2] = 0
            elif y1 > y2:
                grid[y2 + 1 : y1 + 1, x2] = 0


def _reaches_all(passable: int, width: int, start: int, targets: int) -> bool:
    """Whether every bit of ``targets`` is 4-connected to bit ``start`` within ``passable``.

    Grids are bitsets (bit y*W + x); the border is wall, so shifts never wrap into a row. Each
    round grows the reached set by one step in every direction, and along rows towards higher x
    in a single carry (adding the seeds to the passable bits ripples through each run).
    """
    reach = 1 << start
    while True:
        grown = (reach | reach << 1 | reach >> 1 | reach << width | reach >> width) & passable
        grown |= ((passable + grown) ^ passable) & passable
        if grown & targets == targets:
            return True
        if grown == reach:
            return False
        reach = grown


def _separating_patterns() -> bytes:
    """For each 3x3 pattern of open tiles (bit 3*row + col, centre bit 4 ignored): 1 if blocking
    the centre could disconnect its open 4-neighbours, i.e. they do not all lie in one run of
    open tiles around the 8-neighbour ring (consecutive ring tiles are 4-adjacent)."""
    ring_bits = (1, 2, 5, 8, 7, 6, 3, 0)  # N, NE, E, SE, S, SW, W, NW
    table = bytearray(512)
    for pattern in range(512):
        ring = [bool(pattern >> b & 1) for b in ring_bits]
        if all(ring):
            continue
        first_closed = ring.index(False)
        runs_touching, in_run, touches = 0, False, False
        for step in range(1, 9):
            k = (first_closed + step) % 8
            if ring[k]:
                if not in_run:
                    in_run, touches = True, False
                touches = touches or k % 2 == 0
            elif in_run:
                runs_touching += touches
                in_run = False
        table[pattern] = runs_touching > 1
    return bytes(table)


_SEPARATING = _separating_patterns()


def _may_disconnect(passable: int, width: int, i: int) -> bool:
    """Whether blocking tile ``i`` might split the open tiles (if not, no search is needed)."""
    pattern = (
        (passable >> (i - width - 1) & 7)
        | (passable >> (i - 1) & 7) << 3
        | (passable >> (i + width - 1) & 7) << 6
    )
    return bool(_SEPARATING[pattern])


def _bitset(mask: np.ndarray) -> int:
    """A flat boolean array as an int with bit i = mask[i]."""
    return int.from_bytes(np.packbits(mask, bitorder="little").tobytes(), "little")


def place_boulders(
    grid: np.ndarray, count: int, gems: np.ndarray, start: int, exit_: int, rng: np.random.Generator
) -> None:
    """Boulders on dirt nearest the gems (ties random), each kept only if it leaves every gem and
    the exit reachable from the start."""
    if count <= 0:
        return
    width = grid.shape[1]
    dirt = np.flatnonzero(grid.ravel() == DIRT)
    ys, xs = np.divmod(dirt, width)
    gy, gx = np.divmod(gems, width)
    if len(gems):
        to_gems = (np.abs(ys[:, None] - gy[None, :]) + np.abs(xs[:, None] - gx[None, :])).min(axis=1)
    else:
        to_gems = np.full(len(dirt), -1)
    sy, sx = divmod(start, width)
    ey, ex = divmod(exit_, width)
    clear = (np.abs(ys - sy) + np.abs(xs - sx) > BOULDER_CLEARANCE) & (
        np.abs(ys - ey) + np.abs(xs - ex) > BOULDER_CLEARANCE
    )
    order = np.lexsort((rng.random(len(dirt)), to_gems))
    candidates = dirt[order[clear[order]]].tolist()
    flat = grid.ravel()
    passable = _bitset((flat == DIRT) | (flat == GEM))
    targets = 1 << exit_
    for gem in gems.tolist():
        targets |= 1 << gem
    placed = []
    for i in candidates:
        if len(placed) == count:
            break
        without = passable & ~(1 << i)
        if not _may_disconnect(passable, width, i) or _reaches_all(without, width, start, targets):
            passable = without
            placed.append(i)
    flat[placed] = BOULDER


def place_enemies(
    grid: np.ndarray, count: int, start: int, exit_: int, r: UniformStream, rng: np.random.Generator
) -> None:
    """Butterflies and crabs on shuffled dirt away from start and exit, each digging a pocket."""
    if count <= 0:
        return
    width = grid.shape[1]
    flat = grid.ravel()
    dirt = np.flatnonzero(flat == DIRT)
    sy, sx = divmod(start, width)
    ey, ex = divmod(exit_, width)
    for i in dirt[rng.permutation(len(dirt))].tolist():
        y, x = divmod(i, width)
        if abs(y - sy) + abs(x - sx) <= ENEMY_START_CLEARANCE:
            continue
        if abs(y - ey) + abs(x - ex) <= ENEMY_EXIT_CLEARANCE:
            continue
        flat[i] = BUTTERFLY + round_half_up(r())
        length = math.floor(5 * r())
        horizontal = round_half_up(r())
        along_x, along_y = 2 * round_half_up(r()) - 1, 2 * round_half_up(r()) - 1
        step = along_x if horizontal else along_y * width
        j = i + step
        for _ in range(length):
            if flat[j] != DIRT:
                break
            flat[j] = EMPTY
            j += step
        count -= 1
        if count == 0:
            break


def round_half_up(value: float) -> int:
    """JavaScript's Math.round for values in [0, 1)."""
    return 1 if value >= 0.5 else 0


def _start_and_exit(open_tiles: list[int], width: int, r: UniformStream) -> tuple[int, int] | None:
    """A uniform open start, and a uniform open exit at distance >= 4 (None if there is none).

    Rejection sampling as in the original; after many misses we check that an exit exists.
    """
    if not open_tiles:
        return None
    start = open_tiles[math.floor(r() * len(open_tiles))]
    sy, sx = divmod(start, width)
    far = None
    for attempt in itertools.count():
        if attempt == 64:
            far = [i for i in open_tiles if _distance(i, start, width) >= MIN_EXIT_DISTANCE]
            if not far:
                return None
        candidates = far or open_tiles
        exit_ = candidates[math.floor(r() * len(candidates))]
        ey, ex = divmod(exit_, width)
        if abs(ey - sy) + abs(ex - sx) >= MIN_EXIT_DISTANCE:
            return start, exit_


def _distance(i: int, j: int, width: int) -> int:
    (iy, ix), (jy, jx) = divmod(i, width), divmod(j, width)
    return abs(iy - jy) + abs(ix - jx)


def generate(difficulty: float, seed: int) -> Level:
    """A Boulderdash level at ``difficulty``, framed to 26x13; the same seed gives the same level."""
    rng = np.random.default_rng(seed)
    r = UniformStream(rng)
    while True:  # the original would hang on a cave without two tiles 4 apart; we draw again
        width, height, solid, sweeps, enemies, boulders, extra_gems = parameters(difficulty, r)
        grid = cave(width, height, solid, sweeps, rng)
        connect_regions(grid, r)
        open_tiles = np.flatnonzero(grid.ravel() == DIRT)
        ends = _start_and_exit(open_tiles.tolist(), width, r)
        if ends is not None:
            break
    start, exit_ = ends
    shuffled = open_tiles[rng.permutation(len(open_tiles))]
    gems = shuffled[(shuffled != start) & (shuffled != exit_)][: BASE_GEMS + extra_gems]
    grid.ravel()[gems] = GEM
    place_boulders(grid, boulders, gems, start, exit_, rng)
    place_enemies(grid, enemies, start, exit_, r, rng)
    grid.ravel()[start] = AVATAR
    grid.ravel()[exit_] = EXIT
    text = grid.astype(np.uint8).tobytes().translate(_TO_CHARS).decode()
    rows = [text[y * width : (y + 1) * width] for y in range(height)]
    return generated_level("boulderdash", frame(rows, "boulderdash"), difficulty, seed)
