"""``Curriculum``: what a training regimen is, as one registered object; ``CurriculumRun``: one
run of it, the one object that owns the level choice while the run lasts.

A curriculum decides which level each resetting env plays next. The registry
(``gvgai_pcg.curricula.registry``) holds one ``Curriculum`` per name; the name is the
``regimen`` config group's option (``conf/regimen/<name>.yaml``, or the yaml a plug-in names).
Everything that differs between regimens is an attribute or method here, so the trainer, the
config checks and the Gymnasium API ask the object instead of testing names:

* ``schema``: the keys of its config section and their rules (``gvgai_pcg.config``'s rules);
  ``check`` adds the rules across keys;
* ``make_state``: the state every collector worker shares (PPCG's difficulty, PLR's buffer), or
  ``None``;
* ``make_source``: the ``LevelSource`` the env calls at reset (a subclass of
  ``gvgai_pcg.envs.LevelSource``: ``next_levels``, and the facts it declares with their defaults,
  such as ``prepare_ahead``); a source that learns from training defines ``observe(signals)``,
  one that keeps steps out of the gradient ``trains_on(rollout)``, one that plays the learner's
  policy ``between_updates(policy, frames)``;
* ``wrap``: the env the learner trains on (PCG X and PPCG add their ``DifficultyTransform``,
  which moves PPCG's d at every finished episode inside the step);
* ``episodes_ended``: that same move for a caller that steps the env unwrapped (the Gymnasium API);
* ``training_levels``: the finite set a regimen trains on (evaluated as its training set);
* ``replay_levels``: a few of the levels a curriculum that replays levels would replay next, from
  its shared state (the curricula comparison pictures them); none by default.

``Curriculum.start(game, section)`` returns the run object, ``CurriculumRun``: it holds the
shared state (``state_dict`` for checkpoints, ``share_through`` for collector workers), hands each
env its source (``source``), wraps the env (``wrap``) and takes every signal (``observe``,
``trains_on``, ``between_updates``, ``episodes_ended``). The trainer and the Gymnasium env both go
through it, so each kind of curriculum has one feedback route.

State that ``observe`` changes must live in the shared state (memory shared across processes,
``share_through(directory)`` for collector workers, ``state_dict`` for checkpoints), as
``DifficultyTransform`` keeps PPCG's d: each worker builds its own source around the same state.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import torch
    from tensordict import TensorDictBase
    from torchrl.envs import EnvBase

    from gvgai_pcg.envs.level_sources import LevelSource
    from gvgai_pcg.levels import Level


@dataclass(frozen=True)
class ActingPolicy:
    """The learner's policy as a curriculum that plays it is given it between updates: ``act``
    maps a tensordict holding the observation ``obs`` to ``[B]`` sampled actions, on ``device``."""

    act: Callable[[TensorDictBase], torch.Tensor]
    obs: str
    device: str = "cpu"


class Curriculum:
    """One training regimen. Subclass it, set the class attributes, override what differs, and
    register an instance (``register_curriculum`` or the ``gvgai_pcg.curricula`` entry point).

    Attributes:
        name: the regimen's name (``regimen=<name>``).
        summary: one line for listings and errors.
        schema: the rule of each key of its config section, ``name`` and ``tag`` included (a
            ``tag`` names the run: ``run_name`` is ``<game>-<tag>-...``).
        generated: whether it plays generated levels (a difficulty applies).
        label: the report's row name (``row_label`` where it depends on the section).
        config: the yaml of a curriculum from outside the package (its defaults), stored as the
            ``regimen`` group's option ``name``; ``None`` for ours (``conf/regimen/<name>.yaml``).
        optional: keys of ``schema`` a section may leave out.
        learner_needs: what its source needs from the learner beyond the outcome of episodes (level,
            return, win, length), in words; ``""``: nothing. The Gymnasium API, which has no
            learner, refuses a curriculum that needs one (PLR⊥, ACCEL: value estimates; SFL: the
            policy) and feeds the others' ``observe`` one row per finished episode.
    """

    name: str = ""
    summary: str = ""
    schema: Mapping[str, Any] = {}
    generated: bool = False
    label: str = ""
    config: str | Path | None = None
    optional: frozenset[str] = frozenset({"win_rule"})
    learner_needs: str = ""

    def check(self, section: Mapping[str, Any], config: Mapping[str, Any]) -> None:
        """Rules across keys of the checked ``section`` (``config``: the whole checked config);
        raise ``gvgai_pcg.config.ConfigError`` with a one-line message."""

    def make_state(self, game: str, section: Mapping[str, Any]) -> Any:
        """The state shared by every env and collector worker of a run (``None``: none)."""
        return None

    def make_source(self, game: str, section: Mapping[str, Any], state: Any = None) -> LevelSource:
        """The level source of one env, around the shared ``state``."""
        raise NotImplementedError(f"the curriculum {self.name!r} does not say where its levels come from")

    def wrap(self, env: EnvBase, state: Any = None) -> EnvBase:
        """The env the learner trains on (by default ``env`` itself)."""
        return env

    def episodes_ended(self, state: Any, next_tensordict: TensorDictBase, finished: torch.Tensor) -> None:
        """What ``wrap`` does at the end of the episodes in ``finished`` (``[B]`` bool), for a
        caller that steps the env unwrapped (the Gymnasium API); nothing by default."""

    def settable_difficulty(self, state: Any) -> Any | None:
        """The part of ``state`` whose ``shared_difficulty`` a caller may set by hand (the
        Gymnasium env's ``set_difficulty``), ``None`` where the curriculum chooses its levels'
        difficulty itself or plays no generated levels."""
        return None

    def start(self, game: str, section: Mapping[str, Any]) -> CurriculumRun:
        """A run of this curriculum on ``game`` with the config ``section``: its shared state
        made now (``make_state``)."""
        return CurriculumRun(self, game, section)

    def training_levels(
        self, game: str, section: Mapping[str, Any], limit: int | None = None
    ) -> list[Level] | None:
        """The finite set of levels it trains on (at most the first ``limit``), ``None`` where
        there is none (a new level every episode)."""
        return None

    def replay_levels(self, state: Any, k: int) -> list[Level]:
        """Up to ``k`` of the levels it would replay next from ``state`` (its ``make_state``, as a
        checkpoint restores it), most likely first; none where it does not replay levels."""
        return []

    def human_levels_trained(self, section: Mapping[str, Any]) -> tuple[str, ...]:
        """The human levels it trains on (``("lv0", "lv1")``), for the evaluation's tables."""
        return ()

    def has_training_set(self, section: Mapping[str, Any]) -> bool:
        """Whether it trains on a set of levels of its own (evaluated as the run's ``train`` set)."""
        return False

    def row_label(self, section: Mapping[str, Any]) -> str:
        """The report's row name of a run of this curriculum (the study's: ``Lv 0``, ``PPCG``)."""
        return self.label or self.name

    def __repr__(self) -> str:
        return f"<curriculum {self.name!r}: {self.summary}>"


class CurriculumRun:
    """One run's level choice: the curriculum, its config section and its shared state.

    The trainer and the Gymnasium env hold one each. It hands every env (and every collector
    worker's env) a level source around the one ``state`` (``source``), wraps the env where the
    curriculum needs to (``wrap``), and takes the signals of the run: ``observe`` (the learner's
    per-level report after each batch, or the Gymnasium env's finished episodes), ``trains_on``
    (before each update), ``between_updates`` (after it, with the acting policy) and
    ``episodes_ended`` (each step of an unwrapped env). A signal its source does not take is
    refused nowhere: ``learns`` and ``plays_policy`` say whether there is any to give.

    Those signals go to one source of this process (``learner_source``), kept for the run's
    length: PLR⊥'s running episodes live there. A pickled run (a collector worker's copy) leaves
    it behind.
    """

    def __init__(self, curriculum: Curriculum, game: str, section: Mapping[str, Any]) -> None:
        self.curriculum, self.game, self.section = curriculum, game, section
        self.state: Any = curriculum.make_state(game, section)
        self._learner_source: LevelSource | None = None

    @property
    def name(self) -> str:
        return self.curriculum.name

    # --- the envs' side ---
    def source(self) -> LevelSource:
        """A new level source for one env, around the shared state."""
        return self.curriculum.make_source(self.game, self.section, self.state)

    def wrap(self, env: EnvBase) -> EnvBase:
        """The env the learner trains on: ``env`` as the curriculum wraps it."""
        return self.curriculum.wrap(env, self.state)

    def spare(self) -> CurriculumRun:
        """A run of the same curriculum with a state of its own, for an env that only shows its
        specs (a transform has one parent: the run's own state stays free for the real envs)."""
        return type(self)(self.curriculum, self.game, self.section)

    # --- the learner's side ---
    @property
    def learner_source(self) -> LevelSource:
        """The source that the signals of this process go to (made on first use)."""
        if self._learner_source is None:
            self._learner_source = self.source()
        return self._learner_source

    @property
    def learns(self) -> bool:
        """Whether its source learns from what happened on its levels (``observe``)."""
        return self.learner_source.observe is not None

    @property
    def plays_policy(self) -> bool:
        """Whether its source plays the learner's policy between updates (SFL)."""
        return self.learner_source.between_updates is not None

    def observe(self, signals: TensorDictBase) -> None:
        """Give the source the rows of ``signals`` (``gvgai_pcg.curricula.signals``): a training
        batch's level segments, or a Gymnasium step's finished episodes. Nothing where the source
        does not learn."""
        hook = self.learner_source.observe
        if hook is not None:
            hook(signals)

    def trains_on(self, rollout: TensorDictBase) -> torch.Tensor | None:
        """``[B, T]`` bool of the steps the learner may take gradients from, ``None``: all."""
        hook = self.learner_source.trains_on
        return hook(rollout) if hook is not None else None

    def between_updates(self, policy: ActingPolicy, frames: int) -> bool:
        """After an update, with the acting policy; whether the source did anything with it."""
        hook = self.learner_source.between_updates
        return bool(hook(policy, frames)) if hook is not None else False

    def episodes_ended(self, next_tensordict: TensorDictBase, finished: torch.Tensor) -> None:
        """The episodes ``finished`` (``[B]`` bool) ended at this step of an unwrapped env: what
        the wrapped env does inside its step (PPCG moves its d, once per episode, in env order)."""
        self.curriculum.episodes_ended(self.state, next_tensordict, finished)

    # --- the state: checkpoints, workers, logs ---
    @property
    def difficulty(self) -> float:
        """The difficulty a training log shows for the run (NaN: none)."""
        return float(self.state.difficulty) if self.state is not None else math.nan

    @property
    def settable_difficulty(self) -> Any | None:
        """The curriculum's ``settable_difficulty`` of this run's state."""
        return self.curriculum.settable_difficulty(self.state)

    def share_through(self, directory: Path) -> None:
        """Back the shared state by files in ``directory`` for collector worker processes."""
        if self.state is not None:
            self.state.share_through(directory)

    def state_dict(self) -> dict[str, Any] | None:
        """The shared state for a checkpoint (``None``: there is none)."""
        return self.state.state_dict() if self.state is not None else None

    def load_state_dict(self, saved: Mapping[str, Any] | None) -> None:
        """Restore the shared state from a checkpoint's ``state_dict``."""
        if self.state is not None:
            if saved is None:
                raise KeyError(f"the checkpoint holds no state of the curriculum {self.name!r}")
            self.state.load_state_dict(saved)

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_learner_source": None}  # a worker's copy feeds no learner

    def __repr__(self) -> str:
        return f"<run of {self.name!r} on {self.game!r}: {self.state!r}>"
