"""Replays: one episode of an agent on one level, rendered in pixels as an animated GIF.

Frame 0 is the level after the reset tick, then one frame per step, so an episode of length L
gives L + 1 frames. A caption strip (step, score) above the game makes every frame differ from
the previous one: GIF writers merge identical consecutive frames, which would hide the time an
agent spends standing still.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.evaluation.runner import Policy
from gvgai_pcg.levels import Level

CAPTION_HEIGHT = 12


@dataclass
class Episode:
    """The rendered frames (``[H, W, 3]`` uint8 each) and the score after each of them."""

    frames: list[np.ndarray]
    scores: list[float]
    won: bool

    @property
    def length(self) -> int:
        return len(self.frames) - 1


@torch.no_grad()
def record_episode(
    level: Level,
    policy: Policy,
    obs: str = "tiles",
    max_steps: int = 2000,
    seed: int = 0,
    device: str = "cpu",
) -> Episode:
    """Play ``policy`` on ``level`` until the episode ends (or ``max_steps``), rendering every step."""
    env = GVGAIEnv(level.game, 1, level, obs=obs, max_steps=max_steps, device=device, seed=seed)
    td = env.reset()
    frames, scores, won = [env.render(0)], [0.0], False
    for _ in range(max_steps):
        td.set("action", policy(td))
        td = env.step(td).get("next")
        frames.append(env.render(0))
        scores.append(float(td.get("score")[0, 0]))
        if bool(td.get("done")[0, 0]):
            won = bool(td.get("won")[0, 0])
            break
    return Episode(frames, scores, won)


def captioned(frame: np.ndarray, text: str, scale: int) -> np.ndarray:
    """``frame`` scaled up by ``scale`` (nearest), under a black strip with ``text``."""
    from PIL import Image, ImageDraw

    big = np.repeat(np.repeat(frame, scale, axis=0), scale, axis=1)
    canvas = Image.new("RGB", (big.shape[1], big.shape[0] + CAPTION_HEIGHT), (0, 0, 0))
    canvas.paste(Image.fromarray(big), (0, CAPTION_HEIGHT))
    ImageDraw.Draw(canvas).text((2, 0), text, fill=(255, 255, 255))
    return np.asarray(canvas)


def write_gif(episode: Episode, path: Path, fps: float = 10.0, scale: int = 2) -> Path:
    """Write ``episode`` as a looping GIF at ``fps`` frames per second."""
    from PIL import Image

    images = [
        Image.fromarray(captioned(frame, f"step {t}  score {score:g}", scale))
        for t, (frame, score) in enumerate(zip(episode.frames, episode.scores, strict=True))
    ]
    path.parent.mkdir(parents=True, exist_ok=True)
    images[0].save(path, save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0)
    return path
