"""When an env's partial reset takes episodes prepared ahead, and when they are prepared.

``ReadyEpisodes`` keeps the prepared episodes; this decides how the env uses them: which resets
take prepared rows (partial ones of at most ``PREPARED_RESETS_MAX`` envs), when the missing ones
are prepared in one bulk (where the difficulty holds), and how large a bulk of generated levels
may grow. The env itself only asks for a reset's envs and falls back to its own reset tick.
"""

from __future__ import annotations

from collections.abc import Callable

import torch
from tensordict import TensorDict

from gvgai_pcg.envs.level_sources import LevelSource
from gvgai_pcg.envs.ready_episodes import ReadyEpisodes
from gvgai_pcg.levels import Level

# Partial resets of up to this many envs take prepared episodes (see ReadyEpisodes). A larger one
# runs its own reset tick: that batch is already large, and a prepared row costs an extra copy.
PREPARED_RESETS_MAX = 256
# Prepared episodes keep their first observations where all of them take at most this much.
# Episodes are prepared this many envs' worth at a time (up to READY_DEPTH_MAX ahead per env, at
# least one). 64 Frogs envs under random play end about 10 episodes a step; over 800 steps they
# prepared episodes 654 times one episode ahead, 92 times four ahead and 35 times eight ahead,
# and a step went from 3.6 to 1.9 ms (human levels; docs/history/benchmarks-notebook.md, "The
# small-batch step").
READY_ROWS = 512
READY_DEPTH_MAX = 8
READY_OBSERVATIONS_MAX_BYTES = 32 << 20

Episodes = tuple[TensorDict, list[Level], torch.Tensor | None]
# ``prepare(envs, observe, episodes)``: those episodes' states after the reset tick, their levels
# and (if ``observe``) their observations (``GVGAIEnv._prepare``).
Prepare = Callable[[torch.Tensor, bool, torch.Tensor], Episodes]


class PreparedResets:
    """The prepared episodes of ``num_envs`` envs and the rules for using them. ``by_difficulty``:
    the source's levels depend on the difficulty (generated ones), so episodes are prepared at it
    and count only at it; ``round_up`` is ``merge_states``'s (the env compiles its tick)."""

    def __init__(self, num_envs: int, observation_bytes: int, by_difficulty: bool, round_up: bool) -> None:
        depth = max(1, min(READY_DEPTH_MAX, READY_ROWS // num_envs))
        keeps = depth * observation_bytes <= READY_OBSERVATIONS_MAX_BYTES
        self.episodes = ReadyEpisodes(num_envs, keeps, depth)
        self.by_difficulty, self.round_up = by_difficulty, round_up
        self.last_difficulties: torch.Tensor | None = None  # every env's at the last reset

    @classmethod
    def for_source(
        cls, source: LevelSource, num_envs: int, observation_bytes: int, round_up: bool
    ) -> PreparedResets | None:
        """Prepared resets for ``source``, or None where its next levels are not known in advance
        (``prepare_ahead``)."""
        if not source.prepare_ahead:
            return None
        return cls(num_envs, observation_bytes, source.depends_on_difficulty, round_up)

    def take(
        self,
        state: TensorDict | None,
        index: torch.Tensor,
        next_episodes: torch.Tensor,
        difficulty: torch.Tensor,
        prepare: Prepare,
    ) -> Episodes | None:
        """The next episodes of envs ``index`` (CPU, sorted) merged into the running ``state``, their
        levels and observations (None where not kept), or None where this reset must tick its own
        envs: a whole-batch reset, a large one, or episodes not ready at a difficulty on the move.
        ``next_episodes`` and ``difficulty`` are every env's; called at every reset, as it
        remembers the difficulties."""
        difficulties = difficulty.to("cpu", copy=True) if self.by_difficulty else None
        taken = (
            state is not None
            and len(index) < self.episodes.num_envs
            and len(index) <= PREPARED_RESETS_MAX
            and self._episodes_ready(index, next_episodes, difficulties, prepare)
        )
        self.last_difficulties = difficulties
        if not taken:
            return None
        return self.episodes.take_into(state, index, next_episodes[index], self.round_up)

    def clear(self) -> None:
        """Forget every prepared episode (the env seeds changed)."""
        self.episodes.clear()

    def _episodes_ready(
        self,
        index: torch.Tensor,
        next_episodes: torch.Tensor,
        difficulties: torch.Tensor | None,
        prepare: Prepare,
    ) -> bool:
        """Whether the next episodes of envs ``index`` are prepared (at ``difficulties``, where
        the levels depend on them), after preparing every missing one in one batch where the
        difficulty holds (``_difficulty_holds``)."""
        if self.episodes.ready(index, next_episodes[index], difficulties):
            return True
        if not self._difficulty_holds(difficulties):
            return False
        envs, ahead = self.episodes.missing(next_episodes, difficulties)
        if difficulties is not None:
            envs, ahead = self.bounded_bulk(index, next_episodes, envs, ahead)
        states, levels, observed = prepare(envs, self.episodes.keeps_observations, ahead)
        prepared_at = None if difficulties is None else difficulties[envs]
        self.episodes.store(
            envs, ahead, states, levels, observed, round_up=self.round_up, difficulties=prepared_at
        )
        return True

    def bounded_bulk(
        self, index: torch.Tensor, next_episodes: torch.Tensor, envs: torch.Tensor, episodes: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """The missing episodes ``envs, episodes`` to prepare in one bulk of generated levels: the
        resetting envs' own and at most ``READY_ROWS`` others. Each costs a generated level (up to
        about 1 ms in Boulderdash), and the whole bulk is lost when the difficulty moves before
        it is used: unbounded, 4,096 envs would prepare 4,096 levels at once."""
        own = torch.isin(envs, index) & (episodes == next_episodes[envs])
        others = (~own).nonzero().flatten()[:READY_ROWS]
        keep = own.clone()
        keep[others] = True
        return envs[keep], episodes[keep]

    def _difficulty_holds(self, difficulties: torch.Tensor | None) -> bool:
        """Whether episodes prepared ahead at these difficulties (every env's, or None where the
        levels do not depend on them) are likely to be played: every env is at one difficulty,
        the same as at the last reset. So PCG X and the stretches where PPCG's difficulty stays
        put (at 0 or 1) prepare ahead, while a difficulty on the move (each env's changes at its
        next reset) prepares only each reset's own envs, as a bulk would be thrown away."""
        if difficulties is None:
            return True
        last = self.last_difficulties
        return (
            bool((difficulties == difficulties[0]).all())
            and last is not None
            and torch.equal(difficulties, last)
        )
