"""ACCEL without selection, a control: ``regimen=accel-noselect`` (``conf/regimen/accel-noselect.yaml``).

ACCEL (``gvgai_pcg.curricula.accel``) with every score-driven choice taken out, so that what its
buffer drifts to is what the game's editor alone does: every level offered is kept (a child or a
new generated level goes into a free slot, else in place of the level that arrived first), and a
replay is chosen by staleness only (``staleness_coef`` 1, the score never weighs in). The rest is
ACCEL's: the same editor, ``num_edits`` edits per child, children played before replays, the
same buffer size, ``replay_prob`` and ``rho``. Scores are still computed and stored (the logs
stay comparable); nothing reads them. Set beside ``accel`` in the curricula comparison, the
difference between the two buffers is what ACCEL's score selects.
"""

from __future__ import annotations

import torch

from gvgai_pcg.config_rules import ConfigError
from gvgai_pcg.curricula.accel import CHILD_SLOTS, Accel, EditedLevelBuffer, EditedLevels
from gvgai_pcg.curricula.plr import Episode

STALENESS_ONLY = 1.0  # the staleness coefficient that leaves the score no weight in replays


class ArrivalBuffer(EditedLevelBuffer):
    """ACCEL's buffer that keeps every level offered, replacing the oldest arrival when full, and
    replays by staleness only."""

    def __init__(self, capacity: int, height: int, width: int, children: int = CHILD_SLOTS) -> None:
        super().__init__(capacity, height, width, children)
        self.register_shared("arrived", torch.zeros(capacity, dtype=torch.int64))  # arrival number
        self.register_shared("arrivals", torch.zeros(1, dtype=torch.int64))

    def replay_probabilities(self, temperature: float, staleness_coef: float) -> torch.Tensor:
        return super().replay_probabilities(temperature, STALENESS_ONLY)

    def keep(
        self, seed: int, difficulty: float, score: float, episode_return: float, content: torch.Tensor
    ) -> int:
        """Add a level whatever its score: into a free slot, else the oldest arrival's."""
        free = (~self.valid).nonzero().flatten()
        index = int(free[0]) if len(free) > 0 else int(torch.argmin(self.arrived))
        self.arrived[index] = self.arrivals[0]
        self.arrivals.add_(1)
        return self.write(index, seed, difficulty, score, episode_return, content)


class UnselectedLevels(EditedLevels):
    """ACCEL's level source whose buffer keeps every level offered."""

    buffer: ArrivalBuffer

    def _offer(self, episode: Episode, score: float, episode_return: float) -> int:
        content = self.offered_content(episode)
        if content is None:
            return -1
        return self.buffer.keep(episode.seed, episode.difficulty, score, episode_return, content)


class AccelNoSelect(Accel):
    """ACCEL with every child kept and replays chosen by staleness: the editor's drift alone."""

    name, summary, label = (
        "accel-noselect",
        "ACCEL without selection: every child kept, replays by staleness (a control)",
        "ACCEL, no selection",
    )
    buffer_type = ArrivalBuffer
    levels_type = UnselectedLevels

    def check(self, section, config):
        super().check(section, config)
        if section["staleness_coef"] != STALENESS_ONLY:
            raise ConfigError(
                f"regimen.staleness_coef={section['staleness_coef']}: accel-noselect replays by "
                f"staleness only (the score must not choose), expected {STALENESS_ONLY}"
            )


CURRICULUM = AccelNoSelect()
