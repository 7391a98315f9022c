"""Checkpoints and final models of a training run: written so that a kill loses nothing, read so
that a file can neither run code nor be used where it does not belong.

A checkpoint (``checkpoints/last.pt``) holds everything needed to continue a run as if it had
not stopped: the model, the optimizer, the curriculum's shared state (``CurriculumRun.state_dict``:
PPCG's d, PLR's buffer; under ``curriculum``, or ``difficulty`` in checkpoints written before),
the frame and episode counters, the number of log rows written before it, the RNG states and the
resolved config. A final model (``model.pt``) holds the weights, the config and the frames. Both
carry the format version and their identity (game, observation kind, model and width), and
hold tensors and plain data only (no NumPy arrays, no classes), so they load with
``torch.load(weights_only=True)``: a crafted file is refused, never run.

Writing keeps the previous checkpoint as ``prev.pt`` and replaces ``last.pt`` atomically, so a
kill at any moment leaves a whole ``last.pt`` (or, in the moment between the two renames, a whole
``prev.pt``). Reading refuses, with an error that says what is wrong: a file that cannot be read
or is not ours, a file of a newer format, non-finite weights (a diverged run), a checkpoint whose
config differs in anything that shapes the training or whose level files changed since, and a
model of another game, observation kind or architecture than the run or command it is used for.
Files of format 1 (before the identity fields; their RNG state held NumPy arrays, which the
loader allows) still load.
"""

from __future__ import annotations

import os
import pickle
import random
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import torch

from gvgai_pcg.rundir.atomic_files import atomic_write, fsync_directory, temporary_path

FORMAT_VERSION = 2
# How torch's weights-only unpickler names a global it refused to construct.
UNSAFE_GLOBAL = re.compile(r"GLOBAL (?P<name>[\w.]+)")
CHECKPOINT_NAME = "last.pt"
PREVIOUS_NAME = "prev.pt"
# Config sections that may change between a run and its resumption (budget, bookkeeping). Not
# ``collector``: its workers multiply the batch of an update and the pace of the difficulty, as
# ``env.num_envs`` does.
# The curriculum's shared state: its key, and the key it had before (PPCG's d was all it held).
CURRICULUM_KEY, LEGACY_CURRICULUM_KEY = "curriculum", "difficulty"
MAY_CHANGE = ("total_frames", "device", "threads", "rollout", "checkpoint", "log", "out_dir", "run_name")


def nonfinite_names(tensors: dict[str, torch.Tensor]) -> list[str]:
    """The names of the floating-point tensors in ``tensors`` holding NaN or inf."""
    return [
        name
        for name, value in tensors.items()
        if isinstance(value, torch.Tensor) and value.is_floating_point() and not bool(value.isfinite().all())
    ]


class CheckpointError(ValueError):
    """A checkpoint or model cannot be used for what it was asked for."""


class UnusableCheckpointError(CheckpointError):
    """The file cannot be used at all: unreadable, not ours, unsafe, too new, or diverged."""


class UnsafeCheckpointError(UnusableCheckpointError):
    """The file holds Python objects that loading would have to construct (it could run code)."""


class NonFiniteModelError(UnusableCheckpointError):
    """The model's weights hold NaN or inf: its run diverged."""


def _numpy_globals() -> list[Any]:
    """What a NumPy array in a format-1 checkpoint (the legacy RNG state) needs to load."""
    try:
        from numpy._core.multiarray import _reconstruct
    except ImportError:  # NumPy 1.x
        from numpy.core.multiarray import _reconstruct
    return [_reconstruct, np.ndarray, np.dtype, type(np.dtype(np.uint32))]


def rng_states() -> dict[str, Any]:
    numpy_state = np.random.get_state(legacy=False)
    return {
        "torch": torch.get_rng_state(),
        "numpy": {
            "bit_generator": numpy_state["bit_generator"],
            "key": torch.from_numpy(numpy_state["state"]["key"].astype(np.int64)),
            "pos": int(numpy_state["state"]["pos"]),
            "has_gauss": int(numpy_state["has_gauss"]),
            "gauss": float(numpy_state["gauss"]),
        },
        "python": random.getstate(),
    }


def set_rng_states(states: dict[str, Any]) -> None:
    torch.set_rng_state(states["torch"])
    numpy_state = states["numpy"]
    if isinstance(numpy_state, dict):
        key = numpy_state["key"].numpy().astype(np.uint32)
        numpy_state = {
            "bit_generator": numpy_state["bit_generator"],
            "state": {"key": key, "pos": numpy_state["pos"]},
            "has_gauss": numpy_state["has_gauss"],
            "gauss": numpy_state["gauss"],
        }
    np.random.set_state(numpy_state)  # format 1: NumPy's legacy tuple
    python_state = states["python"]
    random.setstate((python_state[0], tuple(python_state[1]), python_state[2]))


def identity(config: dict[str, Any]) -> dict[str, Any]:
    """What a model is: the game, the observation kind, the architecture and its width."""
    return {
        "game": config["game"]["name"],
        "obs": config["env"]["obs"],
        "model": config["model"]["name"],
        "hidden": int(config["model"]["hidden"]),
    }


def describe(found: dict[str, Any]) -> str:
    return f"{found['game']} model ({found['obs']}, {found['model']} hidden={found['hidden']})"


def _plain(value: Any) -> Any:
    """``value`` with every tensor a plain CPU ``torch.Tensor`` (no memory-mapped subclass)."""
    if isinstance(value, torch.Tensor):
        return value.detach().cpu().as_subclass(torch.Tensor).clone()
    if isinstance(value, dict):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return type(value)(_plain(item) for item in value)
    return value


def save_checkpoint(path: Path, state: dict[str, Any]) -> None:
    """Write ``state`` (plus format, identity and RNG states) to ``path`` atomically; the checkpoint
    it replaces becomes ``prev.pt`` beside it."""
    data = {"format": FORMAT_VERSION, "identity": identity(state["config"]), "rng": rng_states()}
    data.update(_plain(state))
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = temporary_path(path)
    try:
        with open(tmp, "wb") as handle:
            torch.save(data, handle)
            handle.flush()
            os.fsync(handle.fileno())
        if path.exists():
            _keep_as_previous(path)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    fsync_directory(path.parent)


def _keep_as_previous(path: Path) -> None:
    """``prev.pt`` := ``path``, with ``path`` in place all along (a hard link, renamed)."""
    previous = path.with_name(PREVIOUS_NAME)
    link = temporary_path(previous)
    link.unlink(missing_ok=True)
    try:
        os.link(path, link)
        os.replace(link, previous)
    except OSError:  # no hard links on this filesystem: a moment with prev.pt only
        os.replace(path, previous)


def save_model(path: Path, model: dict[str, torch.Tensor], config: dict[str, Any], frames: int) -> None:
    """The final model (weights, config, frames, format and identity), written atomically."""
    data = {"format": FORMAT_VERSION, "identity": identity(config), "model": _plain(model)}
    data.update(config=config, frames=int(frames))
    atomic_write(path, lambda handle: torch.save(data, handle))


def read_file(path: Path) -> dict[str, Any]:
    """A checkpoint or model file, loaded as tensors and plain data only."""
    path = Path(path)
    try:
        with torch.serialization.safe_globals(_numpy_globals()):
            state = torch.load(path, map_location="cpu", weights_only=True)
    except pickle.UnpicklingError as error:
        unsafe = UNSAFE_GLOBAL.search(str(error))
        if unsafe is None:
            raise _unreadable(path, error) from error
        raise UnsafeCheckpointError(
            f"{path}: refused to load: it holds a Python object ({unsafe.group('name')}) where a "
            "gvgai-pcg checkpoint holds only tensors and plain data, and loading it could run code; "
            "it was crafted or written by another program"
        ) from None
    except FileNotFoundError:
        raise
    except Exception as error:
        raise _unreadable(path, error) from error
    if not isinstance(state, dict) or not isinstance(state.get("model"), dict) or "config" not in state:
        raise UnusableCheckpointError(
            f"{path}: not a gvgai-pcg model or checkpoint (it needs 'model' and 'config' entries)"
        )
    version = state.get("format", 1)
    if not isinstance(version, int) or version > FORMAT_VERSION:
        raise UnusableCheckpointError(
            f"{path} has format {version!r}, written by a newer gvgai-pcg; this one reads formats up to "
            f"{FORMAT_VERSION}: upgrade gvgai-pcg to use it"
        )
    frames = state.get("frames", 0)
    if isinstance(frames, bool) or not isinstance(frames, int) or frames < 0:
        raise UnusableCheckpointError(
            f"{path}: its 'frames' entry is {frames!r}, not a count of frames; it was not written by "
            "gvgai-pcg train (or was edited)"
        )
    _check_stored_whole(state, path)
    return state


def _tensors(value: Any, name: str = "") -> Iterator[tuple[str, torch.Tensor]]:
    """Every tensor in ``value`` (nested dicts, lists and tuples), with its dotted name."""
    if isinstance(value, torch.Tensor):
        yield name, value
    elif isinstance(value, dict):
        for key, item in value.items():
            yield from _tensors(item, f"{name}.{key}" if name else str(key))
    elif isinstance(value, list | tuple):
        for index, item in enumerate(value):
            yield from _tensors(item, f"{name}[{index}]")


def _check_stored_whole(state: dict[str, Any], path: Path) -> None:
    """Refuse a tensor that shows more values than its file stores (a stride-0 or overlapping
    view): checking or copying it would materialise all of them, gigabytes from a small file.
    gvgai-pcg saves every tensor whole, so such a file was crafted or written by another program."""
    for name, value in _tensors(state):
        stored = value.untyped_storage().nbytes() // max(value.element_size(), 1)
        if value.numel() > stored:
            raise UnusableCheckpointError(
                f"{path}: refused: its tensor {name} shows {value.numel()} values of {tuple(value.shape)} "
                f"but stores {stored}; gvgai-pcg saves every tensor whole, so the file was crafted or "
                "written by another program"
            )


def _unreadable(path: Path, error: BaseException) -> UnusableCheckpointError:
    text = str(error)
    if "WeightsUnpickler error:" in text:  # torch's advice around the reason is not for us
        text = text.split("WeightsUnpickler error:", 1)[1]
    reason = text.strip().splitlines()[0] if text.strip() else ""
    return UnusableCheckpointError(
        f"{path} cannot be read ({type(error).__name__}: {reason}); it is corrupt or truncated"
    )


def identity_of(state: dict[str, Any], path: Path) -> dict[str, Any]:
    """The identity a file carries (format 2), or that its config implies (format 1)."""
    if isinstance(state.get("identity"), dict):
        return state["identity"]
    try:
        return identity(state["config"])
    except (KeyError, TypeError, ValueError):
        raise UnusableCheckpointError(
            f"{path} says neither its game, observation kind and model, nor has a config that does; "
            "it was not written by gvgai-pcg train"
        ) from None


def check_identity(state: dict[str, Any], path: Path, expected: dict[str, Any], where: str) -> None:
    """Refuse ``state`` unless it is the model ``expected`` (the identity of ``where``)."""
    found = identity_of(state, path)
    differs = [key for key in ("game", "obs", "model", "hidden") if found.get(key) != expected.get(key)]
    if differs:
        raise CheckpointError(
            f"{path} is a {describe(found)}, but {where} needs a {describe(expected)} (they differ in "
            f"{', '.join(differs)}); give a checkpoint of this run"
        )


def check_finite(state: dict[str, Any], path: Path) -> None:
    """Refuse NaN or inf weights; reads only what the file stores (``read_file`` refused views
    larger than their storage)."""
    bad = nonfinite_names(state["model"])
    if bad:
        more = f" and {len(bad) - 1} more" if len(bad) > 1 else ""
        raise NonFiniteModelError(
            f"{path}: the model's weights are not finite (NaN or inf in {bad[0]}{more}): its run "
            "diverged, so it is refused"
        )


# Keys added to the config after runs were started, with the value that keeps the old behaviour: a
# checkpoint without the key is the same run as a config that has this value.
ADDED_KEYS: dict[str, Any] = {"regimen.num_levels": 0, "regimen.start_seed": 0}


def config_differences(saved: dict[str, Any], current: dict[str, Any], prefix: str = "") -> list[str]:
    """The dotted keys whose values differ between two resolved configs (ignoring ``MAY_CHANGE``,
    and keys of ``ADDED_KEYS`` that the saved config lacks while the current one has their old
    behaviour's value)."""
    diffs = []
    for key in sorted(set(saved) | set(current)):
        name = f"{prefix}{key}"
        if not prefix and key in MAY_CHANGE:
            continue
        a, b = saved.get(key, "<missing>"), current.get(key, "<missing>")
        if key not in saved and name in ADDED_KEYS and b == ADDED_KEYS[name]:
            continue
        if isinstance(a, dict) and isinstance(b, dict):
            diffs += config_differences(a, b, prefix=f"{name}.")
        elif a != b:
            diffs.append(f"{name}: {a!r} in the checkpoint, {b!r} now")
    return diffs


def load_checkpoint(path: Path, config: dict[str, Any], level_set: str | None = None) -> dict[str, Any]:
    """Read the checkpoint at ``path`` and check that it belongs to a run with ``config`` and, when
    both say one, the level set whose fingerprint is ``level_set`` (the files of ``regimen.path``)."""
    state = read_file(path)
    if "optimizer" not in state or "frames" not in state:
        raise UnusableCheckpointError(f"{path} is a final model, not a training checkpoint (no optimizer)")
    check_finite(state, path)
    diffs = config_differences(state["config"], config)
    if diffs:
        raise CheckpointError(
            f"the run directory {path.parent.parent} holds a checkpoint of a run with a different "
            f"config ({'; '.join(diffs)}); start with the same settings to resume it, or choose "
            "another out_dir/run_name"
        )
    saved_set = state.get("level_set")
    if level_set is not None and saved_set is not None and saved_set != level_set:
        where = config.get("regimen", {}).get("path")
        raise CheckpointError(
            f"the run directory {path.parent.parent} holds a checkpoint of a run on other level files: "
            f"regimen.path={where!r} changed since it was saved (sha256 {saved_set[:12]} then, "
            f"{level_set[:12]} now); restore those files to resume it, or choose another "
            "out_dir/run_name to train on the new ones"
        )
    return state


def curriculum_state(state: dict[str, Any]) -> dict[str, Any] | None:
    """The curriculum's shared state a checkpoint holds (``None``: none), under its key or, in a
    checkpoint written before the key was named for what it holds, under ``difficulty``."""
    if CURRICULUM_KEY in state:
        return state[CURRICULUM_KEY]
    return state.get(LEGACY_CURRICULUM_KEY)


def restore(state: dict[str, Any], model: torch.nn.Module, optimizer: torch.optim.Optimizer, run) -> None:
    """Load the saved model, optimizer, curriculum (``run``: a ``CurriculumRun``) and RNG states
    into the live objects."""
    try:
        model.load_state_dict(state["model"])
        optimizer.load_state_dict(state["optimizer"])
        run.load_state_dict(curriculum_state(state))
    except (RuntimeError, KeyError, ValueError) as error:
        raise CheckpointError(f"the checkpoint does not fit this run's model/optimizer: {error}") from error
    set_rng_states(state["rng"])
