"""What a learner declares without importing torch: its name, its config schema, its run-name tag
and where its ``Learner`` class lives.

A ``LearnerSpec`` is to a learner what a ``GameSpec`` is to a game: ``gvgai-pcg train`` checks the
``algo`` section against ``schema`` (rules of ``gvgai_pcg.config``) before any heavy import, and
only a run builds the class (``load_object("module:Class")``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class LearnerSpec:
    """A registered learner.

    Args:
        name: the ``algo.name`` that selects it (and its ``conf/algo/<name>.yaml``).
        learner: the ``Learner`` subclass, or its import path ``"package.module:Class"``.
        schema: the rules of its ``algo`` keys other than ``name`` (``gvgai_pcg.config`` rules).
        run_tag: what ``run_name`` adds for it: ``""`` for A2C (the study's learner: the published
            runs' names stay as they were), ``"-<name>"`` by default.
        description: one line for error messages and docs.
        config: the yaml of a learner from outside the package (its ``algo`` defaults), stored as
            the ``algo`` group's option ``name`` so that ``gvgai-pcg train algo=<name>`` finds it;
            ``None`` for ours (``conf/algo/<name>.yaml``).
        check: rules across keys, called with the checked ``algo`` section and the whole checked
            config before a run starts (PPO: no more minibatches than a batch has steps); it
            raises ``gvgai_pcg.config.ConfigError`` with a one-line message. ``None``: none.
    """

    name: str
    learner: str | type
    schema: Mapping[str, Any] = field(default_factory=dict)
    run_tag: str | None = None
    description: str = ""
    config: str | Path | None = None
    check: Callable[[Mapping[str, Any], Mapping[str, Any]], None] | None = None

    @property
    def tag(self) -> str:
        return f"-{self.name}" if self.run_tag is None else self.run_tag
