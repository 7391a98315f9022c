"""What the learner tells a curriculum after each batch: what happened on each level.

``LevelSignals`` cuts a batch's rollout (``[..., T]``, TorchRL's layout, with the env's
``("next", "level_seed")`` and ``("next", "level_difficulty")``) into level segments: the steps
one env played on one level within the batch. The training loop gives the result to the
curriculum's run (``CurriculumRun.observe``) where its source learns (``feedback_for(run)`` does
both). ``signals`` is a TensorDict of batch ``[S]`` (one row per segment, by env then time) with these
keys:

========================  =========  =====================================================
key                       dtype      meaning
========================  =========  =====================================================
``env``                   int64      the env's row in the batch (workers' envs one after another)
``level_seed``            int64      the generator seed of the level (-1: a given level)
``level_difficulty``      float64    the d the level was generated at
``steps``                 int64      steps of this segment in the batch
``finished``              bool       the level's episode ended in this batch
``won``                   bool       it ended in a win (false while it runs)
``return``                float32    the episode's return so far (the whole return once finished)
``length``                int64      the episode's length so far (the whole length once finished)
========================  =========  =====================================================

Where the learner provides them, per-step learning signals are averaged over the segment's steps
(a PLR score needs them; keys present only when given):

========================  =========  =====================================================
``advantage``             float32    mean GAE (or n-step) advantage
``advantage_abs``         float32    mean absolute advantage (PLR's L1 value loss)
``advantage_positive``    float32    mean of max(advantage, 0) (PLR⊥'s positive value loss)
``state_value``           float32    mean value estimate V(s)
``value_loss``            float32    mean squared error of V(s) against the value target
========================  =========  =====================================================

A level is identified by (the curriculum's generator, ``level_difficulty``, ``level_seed``):
regenerating it from them gives the same level. Episodes run across batches: ``LevelSignals``
carries each env's running return and length from one batch to the next.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch
from tensordict import TensorDict, TensorDictBase

if TYPE_CHECKING:
    from gvgai_pcg.curricula.base import CurriculumRun

LEVEL_KEYS = ("level_seed", "level_difficulty")
LEARNING_KEYS = ("advantage", "advantage_abs", "advantage_positive", "state_value", "value_loss")


class LevelSignals:
    """Per-level signals of successive batches of one training run (one instance per run)."""

    def __init__(self) -> None:
        self._return: torch.Tensor | None = None  # [E] running return of each env's episode
        self._length: torch.Tensor | None = None  # [E] running length

    def __call__(
        self,
        rollout: TensorDictBase,
        advantage: torch.Tensor | None = None,
        state_value: torch.Tensor | None = None,
        value_target: torch.Tensor | None = None,
    ) -> TensorDict:
        """The signals of ``rollout`` (``[..., T]``); ``advantage``, ``state_value`` and
        ``value_target`` are per step, of the rollout's shape (a trailing 1 allowed)."""
        steps = rollout.batch_size[-1]
        nxt = rollout.get("next")

        def flat(value: torch.Tensor) -> torch.Tensor:
            return value.reshape(-1, steps, *value.shape[len(rollout.batch_size) :]).reshape(-1, steps)

        done, won = flat(nxt.get("done")).cpu(), flat(nxt.get("won")).cpu()
        reward = flat(nxt.get("reward")).cpu().to(torch.float32)
        seeds, difficulty = flat(nxt.get("level_seed")).cpu(), flat(nxt.get("level_difficulty")).cpu()
        envs = done.shape[0]
        if self._return is None or self._return.shape[0] != envs:
            self._return = torch.zeros(envs, dtype=torch.float32)
            self._length = torch.zeros(envs, dtype=torch.int64)
        # segment k of env e: the steps after its k-th done of the batch
        before = torch.cumsum(done.to(torch.int64), 1) - done.to(torch.int64)
        ids = torch.arange(envs).unsqueeze(1) * (steps + 1) + before
        segments, inverse = torch.unique(ids.flatten(), return_inverse=True)
        count = len(segments)
        position = torch.arange(envs * steps)
        first = torch.full((count,), envs * steps, dtype=torch.int64).scatter_reduce(
            0, inverse, position, "amin"
        )
        last = torch.zeros(count, dtype=torch.int64).scatter_reduce(0, inverse, position, "amax")
        env = segments // (steps + 1)
        opens_batch = segments % (steps + 1) == 0  # the segment continues the previous batch's episode
        seg_steps = torch.bincount(inverse, minlength=count)
        seg_return = torch.zeros(count).index_add_(0, inverse, reward.flatten())
        carried_return = torch.where(opens_batch, self._return[env], 0.0)
        carried_length = torch.where(opens_batch, self._length[env], 0)
        finished = done.flatten()[last]
        signals = {
            "env": env,
            "level_seed": seeds.flatten()[first].to(torch.int64),
            "level_difficulty": difficulty.flatten()[first].to(torch.float64),
            "steps": seg_steps,
            "finished": finished,
            "won": finished & won.flatten()[last].to(torch.bool),
            "return": carried_return + seg_return,
            "length": carried_length + seg_steps,
        }
        # what runs on into the next batch: each env's last segment, unless it finished
        ends = torch.zeros(envs, dtype=torch.int64).scatter_reduce(0, env, torch.arange(count), "amax")
        self._return = torch.where(finished[ends], 0.0, signals["return"][ends])
        self._length = torch.where(finished[ends], 0, signals["length"][ends])
        if advantage is not None:
            adv = flat(advantage.detach()).cpu().to(torch.float32).flatten()
            signals["advantage"] = _mean(adv, inverse, seg_steps)
            signals["advantage_abs"] = _mean(adv.abs(), inverse, seg_steps)
            signals["advantage_positive"] = _mean(adv.clamp(min=0.0), inverse, seg_steps)
        if state_value is not None:
            value = flat(state_value.detach()).cpu().to(torch.float32).flatten()
            signals["state_value"] = _mean(value, inverse, seg_steps)
            if value_target is not None:
                target = flat(value_target.detach()).cpu().to(torch.float32).flatten()
                signals["value_loss"] = _mean((target - value) ** 2, inverse, seg_steps)
        return TensorDict(signals, batch_size=[count])


def _mean(values: torch.Tensor, inverse: torch.Tensor, counts: torch.Tensor) -> torch.Tensor:
    return torch.zeros(len(counts)).index_add_(0, inverse, values) / counts


class EpisodeOutcomes:
    """The rows of finished episodes, step by step, for a caller without a learner (the Gymnasium
    API): after each step, one row per episode that ended at it, with the keys above other than
    the learning ones, ``steps`` and ``length`` both its whole length, ``finished`` true."""

    def __init__(self, num_envs: int) -> None:
        self._return = torch.zeros(num_envs, dtype=torch.float32)
        self._length = torch.zeros(num_envs, dtype=torch.int64)

    def restart(self, mask: torch.Tensor) -> None:
        """The envs in ``mask`` (``[B]`` bool) start a new episode (a reset)."""
        mask = mask.cpu()
        self._return[mask], self._length[mask] = 0.0, 0

    def __call__(self, next_td: TensorDictBase, stepped: torch.Tensor) -> TensorDict | None:
        """Count the step of the envs in ``stepped`` (``[B]`` bool: those that played it, not those
        restarting); the rows of the episodes that ended at it, ``None`` where none did."""

        def column(key: str) -> torch.Tensor:
            return next_td.get(key).reshape(-1).cpu()

        stepped = stepped.reshape(-1).cpu()
        self._return += torch.where(stepped, column("reward").to(torch.float32), 0.0)
        self._length += stepped.to(torch.int64)
        ended = stepped & column("done").to(torch.bool)
        if not bool(ended.any()):
            return None
        envs = ended.nonzero().flatten()
        rows = TensorDict(
            {
                "env": envs,
                "level_seed": column("level_seed")[envs].to(torch.int64),
                "level_difficulty": column("level_difficulty")[envs].to(torch.float64),
                "steps": self._length[envs].clone(),
                "finished": torch.ones(len(envs), dtype=torch.bool),
                "won": column("won")[envs].to(torch.bool),
                "return": self._return[envs].clone(),
                "length": self._length[envs].clone(),
            },
            batch_size=[len(envs)],
        )
        self.restart(ended)
        return rows


TRAIN_MASK = "train_mask"  # [B, T] bool in a rollout: the steps a learner takes gradients from


class Feedback:
    """The learner's side of the run's feedback route: ``feedback(rollout, advantage=...,
    state_value=..., value_target=...)`` after each batch gives the batch's signals to
    ``run.observe``; ``mark_trained_steps(rollout)`` before the update writes ``run.trains_on``
    (where it names steps) as the rollout's ``train_mask``, which every learner honours."""

    def __init__(self, run: CurriculumRun) -> None:
        self.run, self.signals = run, LevelSignals()

    def mark_trained_steps(self, rollout: TensorDictBase) -> None:
        mask = self.run.trains_on(rollout)
        if mask is not None:
            rollout.set(TRAIN_MASK, mask.reshape(rollout.batch_size).to(torch.bool))

    def __call__(self, rollout: TensorDictBase, **learning: torch.Tensor | None) -> TensorDict:
        signals = self.signals(rollout, **learning)
        self.run.observe(signals)
        return signals


def feedback_for(run: CurriculumRun) -> Feedback | None:
    """A ``Feedback`` to ``run`` where its curriculum learns (``run.learns``), else ``None``: the
    loop then skips the signals altogether."""
    return Feedback(run) if run.learns else None
