"""``Curriculum``: what a training regimen is, as one registered object.

A curriculum decides which level each resetting env plays next. The registry
(``gvgai_pcg.curricula.registry``) holds one ``Curriculum`` per name; the name is the
``regimen`` config group's option (``conf/regimen/<name>.yaml``, or the yaml a plug-in names).
Everything that differs between regimens is an attribute or method here, so the trainer, the
config checks and the Gymnasium API ask the object instead of testing names:

* ``schema``: the keys of its config section and their rules (``gvgai_pcg.config``'s rules);
  ``check`` adds the rules across keys;
* ``make_state``: the state every collector worker shares (PPCG's difficulty), or ``None``;
* ``make_source``: the ``LevelSource`` the env calls at reset (a subclass of
  ``gvgai_pcg.envs.LevelSource``: ``next_levels``, and the facts it declares with their defaults,
  such as ``prepare_ahead``); a source that learns from training defines ``observe(signals)``,
  which the training loop calls with a ``gvgai_pcg.curricula.signals`` TensorDict after each batch;
* ``between_updates(policy, frames)``, on a source that defines it: the training loop calls it
  after each update with the acting policy (``ActingPolicy``), for a curriculum that plays the
  learner's policy itself (SFL scores its pool so);
* ``wrap``: the env the learner trains on (PCG X and PPCG add their ``DifficultyTransform``);
* ``training_levels``: the finite set a regimen trains on (evaluated as its training set);
* ``replay_levels``: a few of the levels a curriculum that replays levels would replay next, from
  its shared state (the curricula comparison pictures them); none by default.

State that ``observe`` changes must live in the shared state (memory shared across processes,
``share_through(directory)`` for collector workers, ``state_dict`` for checkpoints), as
``DifficultyTransform`` keeps PPCG's d: each worker builds its own source around the same state.
"""

from __future__ import annotations

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
