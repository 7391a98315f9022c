"""ACCEL (Parker-Holder, Jiang, Dennis, Samvelyan, Foerster, Grefenstette and Rocktäschel 2022,
"Evolving Curricula with Regret-Based Environment Design"), as a curriculum: ``regimen=accel``
(``conf/regimen/accel.yaml``; its parameters and their sources: docs/curricula.md).

PLR⊥ (``gvgai_pcg.curricula.plr``) whose replayed levels are edited: each time a replayed level's
episode is scored, with probability ``editor_prob`` a child is made from that very level (the
parent: the buffer entry the episode played) by ``num_edits`` edits of the game's editor
(``gvgai_pcg.games.registry.level_editor``), and queued. The next resetting env plays the oldest
queued child before any replay decision (dcd evaluates the edits in the rollout after the replay
that made them); its episode is scored like a new level's, and the child joins the buffer when it
scores at least as high as the buffer's lowest (or there is room). Children are evaluated, not
trained on (robust: they are not in the buffer while they play).

Levels are stored by content: the buffer keeps every level's characters (``content``, uint8
``[capacity, H, W]``, rows padded with 0), a child also its parent's d and a seed of its own
(``EDITED_SEED_BASE`` + the count of children made), which is its identity in the rollout's
``level_seed``.
"""

from __future__ import annotations

from collections.abc import Callable

import torch

from gvgai_pcg.config_rules import Integer, Number
from gvgai_pcg.curricula.level_buffer import EDITED_SEED_BASE, LevelBuffer
from gvgai_pcg.curricula.plr import (
    Episode,
    PrioritizedLevelReplay,
    PrioritizedLevels,
    ReplaySettings,
    seed_uniforms,
)
from gvgai_pcg.levels import Level
from gvgai_pcg.levels.formats import level_format
from gvgai_pcg.levels.seeds import TRAINING_SEED_SPACE

CHILD_SLOTS = 1024  # children queued or playing at once; the oldest slot is reused when full
_EDIT_STREAM = 0x4143434C  # "ACCL": the editor_prob draw of each child


def encode_level(level: Level, height: int, width: int) -> torch.Tensor:
    """``[height, width]`` uint8 character codes of ``level``'s rows (0 past its own size)."""
    if level.height > height or level.width > width:
        raise ValueError(f"a {level.height}x{level.width} level does not fit {height}x{width}")
    codes = torch.zeros(height, width, dtype=torch.uint8)
    for r, row in enumerate(level.rows):
        codes[r, : len(row)] = torch.frombuffer(bytearray(row.encode("ascii")), dtype=torch.uint8)
    return codes


def decode_level(game: str, codes: torch.Tensor, seed: int) -> Level:
    """The level whose characters are ``codes`` (``encode_level``), with ``seed`` as its identity."""
    rows = [bytes(row.tolist()).rstrip(b"\0").decode("ascii") for row in codes]
    return Level(game, tuple(row for row in rows if row), seed=seed)


def level_editor(game: str) -> Callable[[Level, int], Level]:
    """The game's editor: ``edit(level, seed)`` is a valid level one small edit away."""
    try:
        from gvgai_pcg.games.registry import level_editor as registered_editor
    except ImportError:
        raise ValueError(
            f"regimen accel needs a level editor for {game!r}, and this version of gvgai_pcg has no "
            "editors (gvgai_pcg.games.registry.level_editor)"
        ) from None
    return registered_editor(game)


class EditedLevelBuffer(LevelBuffer):
    """PLR's buffer with each level's content, and the queue of children (``child_*``) made by
    edits and not yet scored."""

    def __init__(self, capacity: int, height: int, width: int, children: int = CHILD_SLOTS) -> None:
        super().__init__(capacity, height, width)
        self.register_shared("child_seed", torch.full((children,), -1, dtype=torch.int64))
        self.register_shared("child_d", torch.zeros(children, dtype=torch.float64))
        self.register_shared("child_content", torch.zeros(children, height, width, dtype=torch.uint8))
        self.register_shared("child_waiting", torch.zeros(children, dtype=torch.bool))  # not handed out
        self.register_shared("children_made", torch.zeros(1, dtype=torch.int64))

    def queue_child(self, difficulty: float, content: torch.Tensor) -> int:
        """Queue a child; returns its seed."""
        count = int(self.children_made[0])
        slot = count % len(self.child_seed)
        self.child_seed[slot], self.child_d[slot] = EDITED_SEED_BASE + count, difficulty
        self.child_content[slot], self.child_waiting[slot] = content, True
        self.children_made.add_(1)
        return EDITED_SEED_BASE + count

    def take_child(self) -> int:
        """The slot of the oldest waiting child, now handed out; -1 where none waits."""
        waiting = self.child_waiting.nonzero().flatten()
        if len(waiting) == 0:
            return -1
        slot = int(waiting[torch.argmin(self.child_seed[waiting])])
        self.child_waiting[slot] = False
        return slot

    def child_slot(self, seed: int) -> int:
        """The slot of the child ``seed``; -1 where it is gone (its slot reused)."""
        found = (self.child_seed == seed).nonzero().flatten()
        return int(found[0]) if len(found) else -1


class EditedLevels(PrioritizedLevels):
    """ACCEL's level source: PLR⊥'s, with children of replayed levels played first and offered
    to the buffer by content."""

    buffer: EditedLevelBuffer

    def __init__(
        self,
        game: str,
        buffer: EditedLevelBuffer,
        settings: ReplaySettings,
        num_edits: int,
        editor_prob: float,
        generator: str | None = None,
    ) -> None:
        super().__init__(game, buffer, settings, generator)
        self.num_edits, self.editor_prob = int(num_edits), float(editor_prob)
        self._edit: Callable[[Level, int], Level] | None = None

    @property
    def edit(self) -> Callable[[Level, int], Level]:
        if self._edit is None:
            self._edit = level_editor(self.game)
        return self._edit

    def _special_level(self, env, episode_seed):
        slot = self.buffer.take_child()
        if slot < 0:
            return None, 0.0
        seed = int(self.buffer.child_seed[slot])
        return decode_level(self.game, self.buffer.child_content[slot], seed), float(
            self.buffer.child_d[slot]
        )

    def replayed_level(self, index):
        return decode_level(self.game, self.buffer.content[index], int(self.buffer.seed[index]))

    def child_of(self, parent: Level, child_seed: int) -> Level:
        """``num_edits`` edits of ``parent``, each chosen by a seed of the child's."""
        child = parent
        for j in range(self.num_edits):
            child = self.edit(child, (child_seed - EDITED_SEED_BASE) * max(self.num_edits, 1) + j)
        return child

    def _replayed(self, index: int, episode: Episode) -> None:
        count = int(self.buffer.children_made[0])
        draw = float(seed_uniforms(torch.tensor([count]), _EDIT_STREAM)[0])
        if draw >= self.editor_prob:
            return
        parent = self.replayed_level(index)
        child = self.child_of(parent, EDITED_SEED_BASE + count)
        height, width = self.buffer.content.shape[1:]
        self.buffer.queue_child(float(self.buffer.level_d[index]), encode_level(child, height, width))

    def _offer(self, episode: Episode, score: float, episode_return: float) -> int:
        if not self.buffer.admits(score):
            return -1
        content = self.offered_content(episode)
        if content is None:
            return -1
        return self.buffer.insert(episode.seed, episode.difficulty, score, episode_return, content)

    def offered_content(self, episode: Episode) -> torch.Tensor | None:
        """The characters of the level ``episode`` played, to store: a child's (its queue slot is
        freed) or a generated level's; ``None`` where it is neither (its slot already reused)."""
        height, width = self.buffer.content.shape[1:]
        if episode.seed >= EDITED_SEED_BASE:
            slot = self.buffer.child_slot(episode.seed)
            if slot < 0:
                return None
            content = self.buffer.child_content[slot].clone()
            self.buffer.child_seed[slot] = -1  # scored: its slot is free
            return content
        if 0 <= episode.seed < TRAINING_SEED_SPACE:
            return encode_level(self.generated_level(episode.difficulty, episode.seed), height, width)
        return None


class Accel(PrioritizedLevelReplay):
    """ACCEL: PLR⊥ whose replayed levels are edited, the children evaluated and kept by score."""

    name, summary, label = "accel", "ACCEL: PLR⊥ that edits the levels it replays", "ACCEL"
    schema = {
        **PrioritizedLevelReplay.schema,
        "num_edits": Integer(1, 1000),
        "editor_prob": Number(0.0, 1.0),
    }
    buffer_type: type[EditedLevelBuffer] = EditedLevelBuffer
    levels_type: type[EditedLevels] = EditedLevels

    def make_state(self, game, section):
        fmt = level_format(game)
        buffer = self.buffer_type(
            int(section.get("buffer_size", ReplaySettings.buffer_size)), fmt.height, fmt.width
        )
        buffer.game = game  # whose levels replay_levels rebuilds
        return buffer

    def make_source(self, game, section, state=None):
        buffer = state if state is not None else self.make_state(game, section)
        return self.levels_type(
            game,
            buffer,
            ReplaySettings.of(section),
            int(section.get("num_edits", 5)),
            float(section.get("editor_prob", 1.0)),
        )


CURRICULUM = Accel()
