"""Trained agents from run directories, as the evaluator and the replays need them.

A run directory (``gvgai_pcg.rl``) holds ``config.yaml`` (the resolved config), ``log.csv``,
``checkpoints/last.pt`` and, once finished, ``model.pt``. Both ``.pt`` files are dicts with the
network's ``model`` state dict, the resolved ``config`` and the ``frames`` trained. This module
only reads them and says which model a run's evaluation plays (``gvgai_pcg.evaluation.policy``
turns it into a policy).

Files are read as tensors and plain data only (``gvgai_pcg.rundir.checkpoint.read_file``), and a
model is refused, before anything is played or filed, when its weights are not finite (a diverged
run) or when it is not the run's model: another game, observation kind or architecture than the
run's ``config.yaml`` says (``evaluate RUN --checkpoint FILE``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from gvgai_pcg.curricula.registry import get_curriculum
from gvgai_pcg.evaluation.protocol import LARGE_PROTOCOL, TRAINING_SET, Protocol, protocol_test_sets
from gvgai_pcg.rl.environment import training_levels
from gvgai_pcg.rundir.checkpoint import check_finite, check_identity, identity, read_file
from gvgai_pcg.rundir.earlier_outputs import ASIDE_DIR

FINAL_MODEL = "model.pt"
LAST_CHECKPOINT = Path("checkpoints") / "last.pt"


@dataclass
class RunInfo:
    """What a run directory says about the agent in it."""

    path: Path
    config: dict = field(repr=False)
    checkpoint: Path  # the model its records name (a published run: its file in the run folder)
    frames: int
    published_copy: Path | None = None  # a published run's model, copied beside its records
    not_published: str | None = None  # why a published run holds no model

    @property
    def model_file(self) -> Path:
        """The file that holds the run's weights here. A published run without its model, whose
        record names a file of the machine that trained it or says it is not published, is one
        line saying so."""
        if self.published_copy is not None:
            return self.published_copy
        if self.not_published is not None:
            raise FileNotFoundError(
                f"{self.path}: its model is not published ({self.not_published}), so it cannot be "
                "played or evaluated here; its published records still rebuild the report"
            )
        if not self.checkpoint.is_file() and (self.path / PUBLISHED).is_file():
            raise FileNotFoundError(
                f"{self.path}: its model was not published with it ({PUBLISHED} names "
                f"{self.checkpoint}, a file of the machine that trained the run), so it cannot be "
                "played or evaluated here; its published records still rebuild the report"
            )
        return self.checkpoint

    @property
    def agent(self) -> str:
        """What its evaluation records name the agent: a published run by its folder's name, so that
        records made in ``results/`` name nothing outside the repository; any other by its path."""
        return self.path.name if (self.path / PUBLISHED).is_file() else str(self.path)

    @property
    def game(self) -> str:
        return self.config["game"]["name"]

    @property
    def regimen(self) -> dict:
        return self.config["regimen"]

    @property
    def seed(self) -> int:
        return int(self.config.get("seed", 0))

    @property
    def obs(self) -> str:
        return self.config["env"]["obs"]

    @property
    def curriculum(self):
        """The run's registered curriculum (``gvgai_pcg.curricula``); ``None`` when its plug-in is
        not installed here (the run is then labelled by its regimen's name and has no training
        set of its own)."""
        try:
            return get_curriculum(self.regimen["name"])
        except ValueError:
            return None

    @property
    def label(self) -> str:
        """The regimen as the study names it: ``Lv 0``, ``Lv 0-3``, ``PCG 1``, ``PPCG``; a finite
        generated set ``PCG 1, 100 levels``, a level set ``Levels mine``: the curriculum's
        ``row_label``."""
        curriculum = self.curriculum
        return self.regimen["name"] if curriculum is None else curriculum.row_label(self.regimen)

    @property
    def has_training_set(self) -> bool:
        """Whether the run trained on a set of levels of its own (a level set, a finite generated
        set): the evaluation plays it as the run's ``train`` test set."""
        curriculum = self.curriculum
        return curriculum is not None and curriculum.has_training_set(self.regimen)

    def training_levels(self, limit: int | None = None) -> list:
        """The first ``limit`` (default: all) levels of the run's own training set."""
        if not self.has_training_set:
            raise ValueError(f"{self.path}: regimen {self.regimen['name']!r} has no training set of its own")
        return training_levels(self.game, self.regimen, limit)

    @property
    def training_sets(self) -> tuple[str, ...]:
        """The test sets this run trained on: its own human levels, its ``train`` set, and any
        test set with a level that is also in a level set of its own (generated training levels
        are held out by their seeds)."""
        curriculum = self.curriculum
        human = () if curriculum is None else tuple(curriculum.human_levels_trained(self.regimen))
        if human:
            return human
        if not self.has_training_set:
            return ()
        if curriculum.generated:  # generated training levels are held out by their seeds
            return (TRAINING_SET,)
        own = set(self.training_levels())
        # Both frozen families (30 and 100 levels per d) share their set names: a set counts as
        # trained on where either one holds a training level.
        shared = {
            s.name
            for protocol in (Protocol(), LARGE_PROTOCOL)
            for s in protocol_test_sets(self.game, protocol)
            if own & set(s.levels)
        }
        return (TRAINING_SET, *sorted(shared))


# A published run (``gvgai_pcg.study.sweeps.publish.publish``) names its model here instead of holding
# it: its results and logs rebuild a report (``--no-evaluate``) without the model file.
PUBLISHED = "published.json"


def is_run_dir(path: Path) -> bool:
    return (path / "config.yaml").is_file() and any(
        (path / name).is_file() for name in (FINAL_MODEL, LAST_CHECKPOINT, PUBLISHED)
    )


def find_runs(paths: list[Path]) -> list[Path]:
    """Run directories among ``paths`` and below them (a Hydra multirun directory holds many)."""
    found: list[Path] = []
    for path in paths:
        if not path.exists():
            raise FileNotFoundError(f"{path}: no such run or multirun directory")
        candidates = [path] if is_run_dir(path) else sorted(p.parent for p in path.rglob("config.yaml"))
        # an earlier run that a fresh start moved aside is not a run of the sweep, nor is a hidden
        # folder (a run being published or borrowed, or one a publish is replacing)
        candidates = [
            p
            for p in candidates
            if ASIDE_DIR not in (parts := p.relative_to(path).parts)
            and not any(x.startswith(".") for x in parts)
        ]
        # Compared resolved: one run named twice (relative and absolute, via a link) counts once.
        found += [p for p in map(Path.resolve, candidates) if is_run_dir(p) and p not in found]
    return found


def load_state(path: Path) -> dict:
    """A model or checkpoint file, read safely; refused when its weights are not finite."""
    state = read_file(path)
    check_finite(state, path)
    return state


def read_run_config(run_dir: Path) -> dict | None:
    """The run's resolved ``config.yaml`` (``None`` when it has none); a file that is not a plain
    YAML mapping (malformed, or with a Python tag) is a ``ValueError`` naming it, in one line."""
    import yaml

    path = run_dir / "config.yaml"
    if not path.is_file():
        return None
    try:
        config = yaml.safe_load(path.read_text())
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f"line {mark.line + 1}, column {mark.column + 1}: " if mark is not None else ""
        problem = getattr(error, "problem", None) or str(error).splitlines()[0]
        raise ValueError(
            f"{path}: not a readable config ({where}{problem}); restore the run's config"
        ) from None
    if not isinstance(config, dict):
        raise ValueError(f"{path}: not a config (a YAML mapping); restore the run's config")
    return config


def check_model_of_run(state: dict, path: Path, run_dir: Path, config: dict) -> None:
    """Refuse a model that is not of the run's game, observation kind and architecture."""
    try:
        expected = identity(config)
    except (KeyError, TypeError) as error:
        raise ValueError(f"{run_dir / 'config.yaml'} does not say the run's {error} ") from None
    check_identity(state, path, expected, f"the run {run_dir}")


def run_info(run_dir: Path, checkpoint: Path | None = None) -> RunInfo:
    """The run in ``run_dir``, from ``checkpoint`` (default: whichever of ``model.pt`` and the last
    checkpoint has trained longer, ``model.pt`` on a tie: a resumed session that was killed leaves
    a newer checkpoint beside an older final model)."""
    run_dir = Path(run_dir).resolve()
    if checkpoint is None and (run_dir / PUBLISHED).is_file():
        return published_run_info(run_dir)  # its records name the model, a copy beside them or not
    if checkpoint is None:
        found = [run_dir / name for name in (FINAL_MODEL, LAST_CHECKPOINT) if (run_dir / name).is_file()]
        if not found:
            raise FileNotFoundError(
                f"{run_dir}: no model to evaluate (looked for {FINAL_MODEL} and {LAST_CHECKPOINT}); "
                "is it a training run directory, and has it written a checkpoint?"
            )
        states = {path: load_state(path) for path in found}
        checkpoint = max(found, key=lambda path: int(states[path].get("frames", 0)))  # first on a tie
        state = states[checkpoint]
    elif not Path(checkpoint).is_file():
        if Path(checkpoint).is_dir():
            raise IsADirectoryError(f"{checkpoint}: a folder, not a model or checkpoint file")
        if Path(checkpoint).exists():
            raise ValueError(f"{checkpoint}: not a regular file, so not a model or checkpoint file")
        raise FileNotFoundError(f"{checkpoint}: no such checkpoint")
    else:
        state = load_state(Path(checkpoint))
    checkpoint = Path(checkpoint).resolve()
    config = read_run_config(run_dir) or state["config"]
    check_model_of_run(state, checkpoint, run_dir, config)
    return RunInfo(run_dir, config, checkpoint, int(state.get("frames", 0)))


def published_run_info(run_dir: Path) -> RunInfo:
    """A published run: its config from ``config.yaml``, its model as ``published.json`` names it,
    and the copy of that model published beside it, where there is one. ``published.json`` names
    the model as a file of the run folder (``"model"``, ``null`` with ``not_published`` when there
    is none: ``gvgai_pcg.study.sweeps.portable``), or, in the older form, as the path it had on the
    machine that trained it (``"checkpoint"``, with ``"copied"`` where a copy is beside it)."""
    import json

    from omegaconf import OmegaConf

    path = run_dir / PUBLISHED
    try:
        model = json.loads(path.read_text())
        int(model["frames"])
        if "checkpoint" in model or "model" not in model:
            str(model["checkpoint"])
        elif model["model"] is None:
            str(model["not_published"])
        elif not isinstance(model["model"], str) or Path(model["model"]).is_absolute():
            raise ValueError(f"'model' is {model['model']!r}, not a file of the run folder")
    except (ValueError, KeyError, TypeError) as error:
        raise ValueError(
            f"{path}: not a published run's record ({type(error).__name__}: {error}); restore it, or "
            "remove that run's folder to publish the run again"
        ) from None
    read_run_config(run_dir)  # a file that is not a config: one line naming it
    config = OmegaConf.to_container(OmegaConf.load(run_dir / "config.yaml"), resolve=True)
    if "checkpoint" not in model:  # records name the model by its path inside the run folder
        name = model["model"] or model.get("evaluated", FINAL_MODEL)
        copy = run_dir / name if model["model"] and (run_dir / name).is_file() else None
        reason = model.get("not_published") if model["model"] is None else None
        if model["model"] is not None and copy is None:
            reason = f"{PUBLISHED} names {name}, which is not in the run folder"
        return RunInfo(run_dir, config, Path(name), int(model["frames"]), copy, reason)
    copy = run_dir / model["copied"] if model.get("copied") else None
    copy = copy if copy is not None and copy.is_file() else None
    return RunInfo(run_dir, config, Path(model["checkpoint"]), int(model["frames"]), copy)
