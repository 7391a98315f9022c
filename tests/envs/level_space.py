"""The space of levels a user can write, drawn from a game's level format alone, and a check that
the env plays them as the engine alone does.

Nothing here knows a game: the levels come from ``LevelFormat`` (its legend, avatar characters and
largest grid), so every registered game, and any game registered later, is covered as it is.

* :func:`random_level`: a seeded draw from the levels the format accepts: any size up to the
  largest, every character of the legend from absent to filling the grid, the border walled or
  not, the avatar anywhere.
* :func:`count_cases`: each character of the legend at its count 0, 1 and its largest (a grid
  of it around the avatar), made from a base level; an avatar character, exactly once.
* :func:`check_env_runs`: runs levels through ``GVGAIEnv`` (a batching, eager or compiled, with a
  partial reset halfway) and holds every env, every step, to the engine alone
  (``game.compile`` + ``game.tick`` on that level by itself, unpadded).
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass, field

import torch

from gvgai_pcg.envs import GVGAIEnv, LevelSource
from gvgai_pcg.games import get_game
from gvgai_pcg.games.base import Game
from gvgai_pcg.games.render import render_tiles
from gvgai_pcg.games.rng import mix64
from gvgai_pcg.levels import Level, LevelFormat, human_level, level_format

WALL = "w"  # GVGAI's wall in every game's legend; a format without it borders with its first char


def wall_char(fmt: LevelFormat) -> str:
    return WALL if WALL in fmt.chars else fmt.chars[0]


def sprite_chars(fmt: LevelFormat) -> str:
    """The legend without the avatar characters."""
    return "".join(ch for ch in fmt.chars if ch not in fmt.avatar_chars)


def _side(rng: random.Random, largest: int) -> int:
    """A height or width: often the largest or tiny, else anything between."""
    pick = rng.random()
    if pick < 0.3:
        return largest
    if pick < 0.45:
        return rng.randint(1, min(3, largest))
    return rng.randint(1, largest)


def random_level(fmt: LevelFormat, rng: random.Random, name: str | None = None) -> Level:
    """A level ``fmt`` accepts, drawn with ``rng``: any size, each sprite character absent
    (often), rare or common (a random weight), often one flooding the grid, a walled border
    or not, and one avatar anywhere (border included)."""
    height, width = _side(rng, fmt.height), _side(rng, fmt.width)
    chars = sprite_chars(fmt)
    weights = [0.0 if rng.random() < 0.4 else rng.expovariate(1.0) for _ in chars]
    if rng.random() < 0.3:
        weights[rng.randrange(len(chars))] += 50.0
    if not any(weights):
        weights[rng.randrange(len(chars))] = 1.0
    grid = [rng.choices(chars, weights, k=width) for _ in range(height)]
    if rng.random() < 0.5:
        for r in range(height):
            for c in range(width):
                if r in (0, height - 1) or c in (0, width - 1):
                    grid[r][c] = wall_char(fmt)
    grid[rng.randrange(height)][rng.randrange(width)] = rng.choice(fmt.avatar_chars)
    return Level(fmt.game, tuple("".join(row) for row in grid), name=name)


def base_level(game: str) -> Level:
    """A level to vary one sprite kind of: the game's first human level, or for a game that ships
    none a random full-size one (seeded)."""
    from gvgai_pcg.games.registry import get_game_spec

    if get_game_spec(game).human_levels:
        return human_level(game, 0)
    fmt = level_format(game)
    rng = random.Random(0)
    while True:
        level = random_level(fmt, rng, name=f"{game} base")
        if (level.height, level.width) == (fmt.height, fmt.width):
            return level


@dataclass(frozen=True)
class CountCases:
    """One sprite character of a level at counts 0, 1 and the largest the format allows."""

    char: str
    zero: Level
    one: Level
    largest: Level


def count_cases(base: Level) -> list[CountCases]:
    """For each sprite character: ``base`` with none of it (its cells given to the commonest other
    one), with one (its first kept, or one added) and a full grid of it around one avatar. Every
    one is a level the format accepts."""
    fmt = level_format(base.game)
    chars = sprite_chars(fmt)
    avatar = _avatar_cell(base)
    cases = []
    for ch in chars:
        filler = max((other for other in chars if other != ch), key=base.count)
        zero = [list(row.replace(ch, filler)) for row in base.rows]
        r, c = (base.find(ch) or [next(cell for cell in _cells(base) if cell != avatar)])[0]
        one = [list(row) for row in zero]
        one[r][c] = ch
        full = [[ch] * fmt.width for _ in range(fmt.height)]
        full[fmt.height // 2][fmt.width // 2] = fmt.avatar_chars[0]
        made = (
            _level(base.game, rows, f"{base.game} {ch!r} x {n}")
            for rows, n in ((zero, 0), (one, 1), (full, "max"))
        )
        cases.append(CountCases(ch, *made))
    return cases


def avatar_cases(base: Level) -> list[Level]:
    """``base`` with each of its format's avatar characters as its avatar (a level has exactly
    one), each avatar character alone on a one-cell level (every sprite kind at 0 at once), and a
    one-row level holding every sprite character once (every kind at 1 at once)."""
    fmt = level_format(base.game)
    r, c = _avatar_cell(base)
    cases = []
    for ch in fmt.avatar_chars:
        rows = [list(row) for row in base.rows]
        rows[r][c] = ch
        cases.append(_level(base.game, rows, f"{base.game} avatar {ch!r}"))
        cases.append(Level(base.game, (ch,), name=f"{base.game} avatar {ch!r} alone"))
    row = fmt.avatar_chars[0] + sprite_chars(fmt)
    if len(row) <= fmt.width:
        cases.append(Level(base.game, (row,), name=f"{base.game} every kind once"))
    return cases


def _level(game: str, rows: list[list[str]], name: str) -> Level:
    return Level(game, tuple(map("".join, rows)), name=name)


def _avatar_cell(level: Level) -> tuple[int, int]:
    avatars = level_format(level.game).avatar_chars
    (cell,) = [cell for cell in _cells(level) if level.rows[cell[0]][cell[1]] in avatars]
    return cell


def _cells(level: Level) -> list[tuple[int, int]]:
    return [(r, c) for r in range(level.height) for c in range(level.width)]


# --- the env against the engine alone ------------------------------------------------------------


def episode_actions(game: Game, seed: int, steps: int) -> list[int]:
    """The actions of an episode whose seed is ``seed``: random, the same in every batching."""
    generator = torch.Generator().manual_seed(seed & 0x7FFF_FFFF_FFFF_FFFF)
    return torch.randint(0, game.num_actions, (steps,), generator=generator).tolist()


@dataclass(frozen=True)
class Shown:
    """What an env shows after a tick: its score, whether it is won or lost, its tiles (``[C, h,
    w]``, its own screen) and, after the reset tick and the last step, its golden-trace snapshot
    (a snapshot costs more than a tick)."""

    score: int
    won: bool
    lost: bool
    tiles: torch.Tensor
    snapshot: dict | None


@dataclass
class EngineRuns:
    """Episodes of the engine alone, by (level, episode seed), made once: each level on its own
    (a batch of one, unpadded), ``game.compile`` then its reset tick (NIL) and a tick per step of
    ``steps``, the actions :func:`episode_actions` gives."""

    game: Game
    steps: int
    _runs: dict[tuple[Level, int], list[Shown]] = field(default_factory=dict)

    def shown(self, level: Level, seed: int, step: int) -> Shown:
        """What the engine shows after the reset tick (step 0) and after step ``step``."""
        key = (level, seed)
        if key not in self._runs:
            state = self.game.compile([level], torch.tensor([seed]), torch.device("cpu"))
            runs = self._runs[key] = []
            for at, action in enumerate([0, *episode_actions(self.game, seed, self.steps)]):  # NIL first
                self.game.tick(state, torch.tensor([action]))
                tiles = render_tiles(self.game, state)[0].clone()
                flags = (state.get(name)[0].item() for name in ("score", "won", "lost"))
                snapshot = self.game.snapshot(state, 0) if at in (0, self.steps) else None
                runs.append(Shown(*flags, tiles, snapshot))
        return self._runs[key][step]


class ScheduledLevels(LevelSource):
    """A level source that plays, in each episode, the level scheduled for its episode seed (known
    ahead: ``GVGAIEnv``'s episode seeds depend only on the env seed and the episode number), and
    env i's ``default[i]`` in an episode without one. A function of the episode seed only, so the
    env prepares its resets ahead, as it does for its own sources."""

    prepare_ahead = True

    def __init__(self, schedule: dict[int, Level], default: Sequence[Level]) -> None:
        self.game, self.schedule, self.default = default[0].game, schedule, list(default)

    def next_levels(
        self, env_indices: torch.Tensor, episode_seeds: torch.Tensor, difficulties: torch.Tensor
    ) -> list[Level]:
        return [
            self.schedule.get(seed, self.default[env])
            for env, seed in zip(env_indices.tolist(), episode_seeds.tolist(), strict=True)
        ]


def episode_seed(env_seed: int, episode: int) -> int:
    """The seed of episode ``episode`` of an env whose seed is ``env_seed`` (``GVGAIEnv``'s rule)."""
    return int(mix64(torch.tensor(env_seed) ^ mix64(torch.tensor(episode))))


def _check_envs(
    env: GVGAIEnv, engine: EngineRuns, observed: torch.Tensor, steps: dict[int, int], snapshot: bool = False
) -> None:
    """Each env ``i`` of ``steps`` is at step ``steps[i]`` of the engine's run of its level and
    episode seed: the same score and status, the same tiles on its own screen (``observed``: the
    env's) and none beyond it, and with ``snapshot`` the same golden-trace snapshot where the
    engine took one."""
    state = env.state
    seeds = state.get("seed").tolist()
    flags = [state.get(name).tolist() for name in ("score", "won", "lost")]
    for i, step in steps.items():
        level = env.current_levels[i]
        expected = engine.shown(level, seeds[i], step)
        where = f"env {i} of {env.num_envs} ({level.name}: {level.rows}) at step {step}"
        assert (flags[0][i], flags[1][i], flags[2][i]) == (expected.score, expected.won, expected.lost), where
        shown = observed[i]
        assert torch.equal(shown[:, : level.height, : level.width], expected.tiles), where
        assert not shown[:, level.height :].any() and not shown[:, :, level.width :].any(), where
        if snapshot and expected.snapshot is not None:
            assert env.game.snapshot(state, i) == expected.snapshot, where


def check_env_runs(
    game_name: str,
    levels: Sequence[Level],
    num_envs: int,
    compiled: bool,
    steps: int,
    engine: EngineRuns,
    reset_halfway: bool = True,
) -> None:
    """``levels`` played by envs of ``num_envs``, a batch at a time (env i of a batch its i-th
    level, the last batch filled up from the first levels), eager or ``compiled``, for ``steps``
    steps; with ``reset_halfway`` the odd envs then reset to the level of another env of their
    batch, so that fresh episodes merge into the running state. Level j of ``levels`` is played
    by an env of seed j in every batching (so its engine runs are shared). Every env at every step
    shows what ``engine``'s run of its level and episode seed shows, and their snapshots agree
    at the first and the last step."""
    game = get_game(game_name)
    for start in range(0, len(levels), num_envs):
        batch = list(levels[start : start + num_envs])
        env_seeds = list(range(start, start + len(batch)))
        batch += list(levels[: num_envs - len(batch)])  # the last batch filled up from the first
        env_seeds += list(range(num_envs - len(env_seeds)))
        second = {episode_seed(s, 1): batch[-1 - i] for i, s in enumerate(env_seeds)}
        env = GVGAIEnv(
            game_name,
            num_envs,
            ScheduledLevels(second, batch),
            seed=env_seeds,
            max_steps=10 * steps,
            compile_tick=compiled,
        )
        out = env.reset()
        _check_envs(env, engine, out.get("tiles"), dict.fromkeys(range(num_envs), 0), snapshot=True)
        at = [0] * num_envs  # each env's step in its episode
        actions = [episode_actions(game, s, steps) for s in env.state.get("seed").tolist()]
        reset = list(range(1, num_envs, 2)) if reset_halfway else []
        for step in range(1, steps + 1):
            if reset and step == steps // 2:
                mask = torch.zeros(num_envs, 1, dtype=torch.bool)
                mask[reset] = True
                out = env.reset(out.set("_reset", mask))
                seeds = env.state.get("seed").tolist()
                for i in reset:
                    at[i], actions[i] = 0, episode_actions(game, seeds[i], steps)
                _check_envs(env, engine, out.get("tiles"), dict.fromkeys(reset, 0))
            at = [a + 1 for a in at]
            action = torch.tensor([actions[i][at[i] - 1] for i in range(num_envs)])
            out = env.step(out.set("action", action)).get("next")
            _check_envs(env, engine, out.get("tiles"), dict(enumerate(at)), snapshot=step == steps)
