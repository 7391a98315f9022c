"""The study's conditions (Table 1's rows) and the budgets to run them at.

A condition is one ``conf/condition/<game>-<regimen>.yaml`` (a game and a regimen); a budget
says which conditions run, with how many seeds, frames and overrides, and with which evaluation
protocol. ``smoke`` tests the pipeline in minutes; ``small`` is what a 2-core machine does over
a few sittings; ``paper`` is the study's own setting, for a GPU or a cluster.

A user's own conditions join a budget's from two places: a curriculum plug-in (its condition
with each game, ``<game>-<name>``, ``gvgai_pcg.curricula.registry.plugin_conditions``) and a
config directory of their own, ``DIR/condition/<name>.yaml``, which Hydra searches after ours
where the runs' overrides say ``hydra.searchpath=[file://DIR]`` (``reproduce --config-dir DIR``
adds it; ``searchpath_dirs`` reads it back).

A budget also names what it compares: the study's claims (``comparison="study"``, the page
``docs/results.md``) or the curricula comparison (``"curricula"``: PCG 1, PPCG, DR, PLR⊥,
ACCEL and SFL against PPCG, with the UED protocol, ``docs/results-curricula.md``). A condition whose
curriculum is not registered (yet) is refused by name (``unregistered``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from gvgai_pcg.config import config_dir
from gvgai_pcg.curricula import registered_curricula
from gvgai_pcg.curricula.registry import plugin_conditions

GAMES = ("zelda", "solarfox", "frogs", "boulderdash")
# Table 1 of the study: every regimen on Zelda; PCG 1 and PPCG on the other games (the study
# skipped the rest for lack of compute).
STUDY_CONDITIONS = (
    "zelda-lv0",
    "zelda-lv4",
    "zelda-lv0-3",
    "zelda-pcg0.5",
    "zelda-pcg1",
    "zelda-ppcg",
    "solarfox-pcg1",
    "solarfox-ppcg",
    "frogs-pcg1",
    "frogs-ppcg",
    "boulderdash-pcg1",
    "boulderdash-ppcg",
)
# What the study did not run: the other regimens on Solarfox, Frogs and Boulderdash.
EXTRA_CONDITIONS = tuple(
    f"{game}-{regimen}" for game in GAMES[1:] for regimen in ("lv0", "lv4", "lv0-3", "pcg0.5")
)

# The curricula comparison: the curricula of the UED family beside the study's PCG 1 and PPCG, on
# Zelda and Frogs (the games whose generated-level agents failed the human levels), Solarfox and
# Boulderdash as extras. A condition whose curriculum is not registered is refused by name.
CURRICULA = ("pcg1", "ppcg", "dr", "plr", "accel", "sfl")
CURRICULA_BASELINE = "ppcg"
CURRICULA_CONDITIONS = tuple(f"{game}-{c}" for game in ("zelda", "frogs") for c in CURRICULA)
CURRICULA_EXTRA = tuple(f"{game}-{c}" for game in ("solarfox", "boulderdash") for c in CURRICULA)
# Controls: run only when named (--conditions), not in the comparison's tables. ACCEL without
# selection shows where ACCEL's editor alone takes the buffer (docs/curricula.md).
CURRICULA_CONTROLS = tuple(f"{game}-accel-noselect" for game in GAMES)


@dataclass(frozen=True)
class Budget:
    """How much of the study to run.

    Args:
        name: ``smoke``, ``small`` or ``paper``.
        conditions: the conditions (names of ``conf/condition`` files).
        seeds: the training seeds of every condition.
        frames: training frames per run (of every condition ``condition_frames`` leaves out).
        overrides: Hydra overrides for every run (a preset, the env batch, checkpoints).
        protocol: the evaluation protocol's settings (``gvgai_pcg.evaluation.Protocol``).
        condition_frames: frames of the conditions that train longer or shorter than ``frames``.
        condition_seeds: seeds of the conditions that need more or fewer than ``seeds``.
        condition_overrides: Hydra overrides of some conditions only, after ``overrides`` (a key
            that only their regimen has, as SFL's pool size in a smoke budget).
        extra: the conditions ``--extra`` adds (the study's: those it skipped).
        controls: conditions run only when ``--conditions`` names them (no table shows them).
        comparison: ``study`` (the study's claims) or ``curricula`` (``gvgai_pcg.study.verdicts.comparison``).
        page: the docs page whose results block ``--page`` writes by default.
        ued: the UED protocol's settings (``gvgai_pcg.evaluation.ued.UEDProtocol``) where the
            comparison evaluates with it too; empty: not.
        level_sampling: the claims' intervals include the generated test sets' level-sampling
            error (``gvgai_pcg.study.verdicts.intervals``); off for ``small``, whose page predates it.
        fair: the folder beside the published one (``results/<fair>``) holding the runs retrained at
            the fair setting (``FAIR_BUFFER_SIZE``, bounded editors): on the page they replace the
            published runs of the same game and curriculum, which stay shown, never judged, as the
            reference setting; empty: no such folder.
    """

    name: str
    conditions: tuple[str, ...]
    seeds: tuple[int, ...]
    frames: int
    overrides: tuple[str, ...] = ()
    protocol: dict = field(default_factory=dict)
    condition_frames: dict[str, int] = field(default_factory=dict)
    condition_seeds: dict[str, tuple[int, ...]] = field(default_factory=dict)
    condition_overrides: dict[str, tuple[str, ...]] = field(default_factory=dict)
    extra: tuple[str, ...] = EXTRA_CONDITIONS
    controls: tuple[str, ...] = ()
    comparison: str = "study"
    page: str = "docs/results.md"
    ued: dict = field(default_factory=dict)
    level_sampling: bool = False
    fair: str = ""

    def frames_of(self, condition: str) -> int:
        return int(self.condition_frames.get(condition, self.frames))

    def seeds_of(self, condition: str) -> tuple[int, ...]:
        return tuple(self.condition_seeds.get(condition, self.seeds))

    def overrides_of(self, condition: str) -> tuple[str, ...]:
        """Every Hydra override of ``condition``'s runs: the budget's, then its own."""
        return (*self.overrides, *self.condition_overrides.get(condition, ()))

    @property
    def all_seeds(self) -> tuple[int, ...]:
        """Every seed some condition trains, in order."""
        return tuple(sorted({s for c in self.conditions for s in self.seeds_of(c)} | set(self.seeds)))

    @property
    def runs(self) -> int:
        return sum(len(self.seeds_of(c)) for c in self.conditions)

    @property
    def frames_range(self) -> tuple[int, int]:
        frames = [self.frames_of(c) for c in self.conditions] or [self.frames]
        return min(frames), max(frames)


# The training setup of ``medium``, chosen by the pilot (docs/pilot.md): A2C at 64 envs x 5 steps
# with the learning rate at 2e-3 (the study's 7e-4 with 12 envs): on Zelda PCG 0.5 it reached the
# study's score in 5-7M frames, where 7e-4 was at half of it at 5M and 4e-3 had not left the
# uniform policy at 4.7M.
MEDIUM_SETUP: tuple[str, ...] = ("env.num_envs=64", "algo.lr=0.002")

BUDGETS = {
    "smoke": Budget(
        "smoke",
        STUDY_CONDITIONS,
        seeds=(0,),
        frames=1_600,
        overrides=(
            "env.num_envs=16",
            "env.max_steps=200",
            "checkpoint.every_frames=800",
            "log.every_episodes=4",
        ),
        protocol={"test_levels": 2, "human_episodes": 1, "max_steps": 100},
    ),
    "small": Budget("small", STUDY_CONDITIONS, seeds=(0, 1, 2), frames=5_000_000),
    # The study: pixels and the Nature CNN, 12 envs, 40M frames (GENERATORS.md §3), 4 seeds.
    # Enough training to settle the study's claims: frames per condition from the small
    # sweep's curves (Zelda's multi-level and generated conditions still rose at 5M: 20M), 4 seeds,
    # 5 where the power estimate asks for them (Zelda's PCG/PPCG contrasts); a model kept every 1M
    # frames for the test score over training; the setup the pilot chose (docs/results.md); the
    # 100-level test sets.
    "medium": Budget(
        "medium",
        STUDY_CONDITIONS,
        seeds=(0, 1, 2, 3),
        frames=10_000_000,
        overrides=MEDIUM_SETUP + ("checkpoint.keep_every_frames=1000000",),
        # The claims are judged on the 100-level frozen sets (at least 100 distinct levels per
        # difficulty), so that level sampling adds little to the intervals.
        protocol={"test_levels": 100, "test_sets": "large"},
        condition_frames={c: 20_000_000 for c in ("zelda-lv0-3", "zelda-pcg0.5", "zelda-pcg1", "zelda-ppcg")},
        condition_seeds={c: (0, 1, 2, 3, 4) for c in ("zelda-pcg0.5", "zelda-pcg1", "zelda-ppcg")},
        page="docs/results-medium.md",
        level_sampling=True,
    ),
    "paper": Budget(
        "paper", STUDY_CONDITIONS, seeds=(0, 1, 2, 3), frames=40_000_000, overrides=("preset=paper",)
    ),
}


# The comparison's learner: A2C with medium's setup, which the pilot tuned on these games
# (docs/pilot.md) and the study's medium runs use, so its PCG 1 and PPCG are the study's learner;
# PPO has only the UED libraries' defaults, untuned here. Same learner for all.
# PLR-robust's and ACCEL's buffer at 10M frames: the references' 4,000 levels at rho 0.5 take
# 17-18 % of Zelda's frames to fill (no gradient step before) and replay each slot 2-3 times; 300
# fills in about 1.3 % and replays a slot dozens of times, as dcd's, minimax's and jaxued's maze
# runs do (docs/curricula.md compares them).
FAIR_BUFFER_SIZE = 300

CURRICULA_BUDGETS = {
    "curricula-smoke": Budget(
        "curricula-smoke",
        CURRICULA_CONDITIONS,
        seeds=(0,),
        frames=800,
        overrides=(
            "env.num_envs=8",
            "env.max_steps=100",
            "checkpoint.every_frames=400",
            "log.every_episodes=4",
            "log.curve=false",
        ),
        protocol={"test_levels": 2, "human_episodes": 1, "max_steps": 50},
        # SFL's default pool (200 levels x 4 episodes of up to 1,000 steps) took 9 minutes of an
        # 800-frame run under load; a smoke run needs only that a refresh happens.
        condition_overrides={
            f"{game}-sfl": ("regimen.pool_size=8", "regimen.buffer_size=4", "regimen.rollout_steps=50")
            for game in GAMES
        },
        extra=CURRICULA_EXTRA,
        controls=CURRICULA_CONTROLS,
        comparison="curricula",
        page="docs/results-curricula.md",
        ued={"levels": 8, "seeds": 2, "max_steps": 50},
    ),
    "curricula": Budget(
        "curricula",
        CURRICULA_CONDITIONS,
        seeds=(0, 1, 2),
        frames=10_000_000,
        overrides=MEDIUM_SETUP,
        condition_overrides={
            f"{game}-{name}": (f"regimen.buffer_size={FAIR_BUFFER_SIZE}",)
            for game in GAMES
            for name in ("plr", "accel", "accel-noselect")
        },
        extra=CURRICULA_EXTRA,
        controls=CURRICULA_CONTROLS,
        comparison="curricula",
        page="docs/results-curricula.md",
        ued={"levels": 1000, "rank_episodes": 10, "score_episodes": 10},
        fair="curricula-fair",
    ),
}
BUDGETS.update(CURRICULA_BUDGETS)


def conditions_of(budget: Budget, extra: bool = False) -> tuple[str, ...]:
    """The budget's conditions, and its extra ones (the study's: those it skipped) if ``extra``."""
    return budget.conditions + (budget.extra if extra else ())


def known_conditions() -> tuple[str, ...]:
    """Every condition of the study there is a config for (``conf/condition/*.yaml``)."""
    return STUDY_CONDITIONS + EXTRA_CONDITIONS


def user_conditions(search: Sequence[Path] = ()) -> tuple[str, ...]:
    """The conditions of the user's config folders (``DIR/condition/*.yaml``) and of the
    curriculum plug-ins (``<game>-<name>``) that the study's do not name already."""
    ours = config_dir()
    found = [path.stem for folder in search for path in sorted(Path(folder).glob("condition/*.yaml"))]
    found += list(plugin_conditions(ours))
    return tuple(c for c in dict.fromkeys(found) if not (ours / "condition" / f"{c}.yaml").is_file())


def condition_regimen(condition: str, search: Sequence[Path] = ()) -> str:
    """The curriculum (``regimen``) a condition's config selects, read from its yaml without
    composing it (a curriculum not registered yet has no ``regimen`` option to compose): ours
    first, then the user's folders ``search`` (Hydra's order), then the curriculum plug-ins'."""
    from omegaconf import OmegaConf

    ours = config_dir()
    folders = [ours, *search]
    path = next(
        (
            f / "condition" / f"{condition}.yaml"
            for f in folders
            if (f / "condition" / f"{condition}.yaml").is_file()
        ),
        None,
    )
    if path is None:
        plugin = plugin_conditions(ours).get(condition)
        if plugin is not None:
            return plugin[1]
        places = " or ".join(str(f / "condition") for f in folders)
        raise ValueError(f"unknown condition {condition!r}: no {condition}.yaml in {places}, nor a plug-in's")
    for entry in OmegaConf.to_container(OmegaConf.load(path)).get("defaults", []):
        if isinstance(entry, dict) and "override /regimen" in entry:
            return str(entry["override /regimen"])
    raise ValueError(f"{path}: no 'override /regimen' in its defaults")


def unregistered(conditions: Sequence[str], search: Sequence[Path] = ()) -> dict[str, str]:
    """``condition -> one line`` for each condition whose curriculum is not registered
    (``search``: the user's config folders, ``searchpath_dirs``)."""
    names = registered_curricula()
    known = ", ".join(sorted(names))
    regimens = {c: condition_regimen(c, search) for c in conditions}
    return {
        c: f"{c}: the curriculum {regimens[c]!r} is not registered (registered: {known})"
        for c in conditions
        if regimens[c] not in names
    }
