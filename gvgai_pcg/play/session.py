"""``PlaySession``: one human-played episode at a time, free of any terminal code.

The curses front end (``gvgai_pcg.play.terminal``) only maps keys to action names and draws
what the session says, so the session can be driven and tested without a terminal.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch
from tensordict import TensorDict

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.levels import Level
from gvgai_pcg.play.glyphs import text_rows


class PlaySession:
    """A batch-of-one ``GVGAIEnv`` on ``level``, stepped by action name."""

    def __init__(self, level: Level, seed: int = 0, max_steps: int = 2000) -> None:
        self.level = level
        self.env = GVGAIEnv(level.game, 1, level, obs="tiles", max_steps=max_steps, seed=seed)
        self.actions: tuple[str, ...] = self.env.game.actions
        self.restart()

    def restart(self) -> None:
        """Start the level again (a new episode seed, so random monsters move differently)."""
        self._out = self.env.reset()

    def act(self, action: str) -> None:
        """One tick with ``action`` (a name in ``self.actions``); ignored once the episode is over."""
        if action not in self.actions:
            raise ValueError(f"{self.level.game} has no action {action!r}; its actions are: {self.actions}")
        if self.over:
            return
        step = TensorDict({"action": torch.tensor([self.actions.index(action)])}, batch_size=[1])
        self._out = self.env.step(step)["next"]

    @property
    def tick(self) -> int:
        return int(self.env.state["tick"][0])

    @property
    def score(self) -> float:
        return float(self._out["score"][0, 0])

    @property
    def won(self) -> bool:
        return bool(self._out["won"][0, 0])

    @property
    def over(self) -> bool:
        return bool(self._out["done"][0, 0])

    @property
    def outcome(self) -> str:
        """``playing``, ``won``, ``lost`` or ``out of time``."""
        if not self.over:
            return "playing"
        if self.won:
            return "won"
        return "out of time" if bool(self._out["truncated"][0, 0]) else "lost"

    def rows(self) -> list[str]:
        """The current frame as text, one string per grid row."""
        return text_rows(self.env.game.tile_types, self._out["tiles"][0].numpy())

    def frame(self) -> np.ndarray:
        """The current frame as pixels, ``[10H, 10W, 3]`` uint8."""
        return self.env.render(0, "rgb_array")

    def save_png(self, path: Path) -> None:
        from matplotlib.image import imsave

        imsave(path, self.frame())

    def summary(self) -> str:
        name = self.level.name or "level"
        return f"{self.level.game} {name}: {self.outcome}, score {self.score:g}, tick {self.tick}"
