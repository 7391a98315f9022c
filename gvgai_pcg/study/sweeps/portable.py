"""A published run folder that names nothing outside itself.

A run trained elsewhere names that machine's paths: its config's ``out_dir``, its records'
``agent`` and ``checkpoint``, the model's own config, a borrowed run's source. Published into
``results/`` those would name files no reader has, so ``publish`` rewrites them: the agent is the
run's folder name, a model is named by its path inside the run folder, ``out_dir`` is the
package's default (``runs``), a borrowed run's source is ``<sweep>/runs/<run>``. The same rewrite
migrates a folder published in the older form (``make_portable``), changing no number.

``published.json`` then names the model as a file beside it (``{"model": "model.pt", "frames":
N}``), or says it is not published (``"model": null`` with a ``not_published`` reason, and
``evaluated``: the name its records give the model): such a run's records still rebuild its
report, and ``replay``/``evaluate`` refuse it in one line.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import PUBLISHED, load_state
from gvgai_pcg.rundir.atomic_files import atomic_write

DEFAULT_OUT_DIR = "runs"  # conf/config.yaml's out_dir
NOT_PUBLISHED = (
    "its model exists on no machine any more; the run awaits retraining with the same config and "
    "seed (results/awaiting-retraining.json)"
)
PATH_KEYS = ("agent", "checkpoint")  # the evaluation records' and UED summaries' paths
_OUT_DIR_LINE = re.compile(r"^out_dir: /.*$", re.MULTILINE)


def published_record(model: str | None, frames: int, reason: str = NOT_PUBLISHED) -> dict:
    """``published.json``'s content: the model's file inside the run folder, or why there is none."""
    if model is None:
        return {"model": None, "frames": int(frames), "not_published": reason}
    return {"model": model, "frames": int(frames)}


def inside_name(path: str, run_dir: str | None) -> str:
    """``path`` as a path inside its run folder ``run_dir`` (both as the training machine wrote
    them), or its file name when it is not inside; a relative path is kept."""
    if not path.startswith("/"):
        return path
    if run_dir is not None and path.startswith(run_dir.rstrip("/") + "/"):
        return path[len(run_dir.rstrip("/")) + 1 :]
    return Path(path).name


def portable_fields(record: dict, run_name: str, renamed: dict[str, str], run_dir: str | None) -> dict:
    """One evaluation record or UED summary with its paths made portable: the agent is the run's
    name (``random`` stays), a model named in ``renamed`` gets its new name, any other model its
    path inside the run folder."""
    record = dict(record)
    agent = record.get("agent")
    if isinstance(agent, str) and agent.startswith("/"):
        record["agent"] = run_name
    checkpoint = record.get("checkpoint")
    if isinstance(checkpoint, str):
        record["checkpoint"] = renamed.get(checkpoint, inside_name(checkpoint, run_dir))
    return record


def portable_config_text(text: str) -> str:
    """A ``config.yaml`` whose absolute ``out_dir`` is the default one, every other line as it was."""
    return _OUT_DIR_LINE.sub(f"out_dir: {DEFAULT_OUT_DIR}", text)


def portable_config(config: dict) -> dict:
    """A model file's config with an absolute ``out_dir`` made the default one."""
    config = dict(config)
    if str(config.get("out_dir", "")).startswith("/"):
        config["out_dir"] = DEFAULT_OUT_DIR
    return config


def write_portable_model(source: Path, target: Path) -> None:
    """``source``'s final model into ``target``: read as tensors and plain data only, written with
    the weights, config (made portable), frames, format and identity, and nothing else (a
    checkpoint's optimiser and random states stay behind)."""
    import torch

    state = load_state(source)
    kept = {key: state[key] for key in ("format", "identity", "model", "config", "frames") if key in state}
    kept["config"] = portable_config(state["config"])
    atomic_write(target, lambda handle: torch.save(kept, handle))


def _rewrite_lines(path: Path, change: Callable[[dict], dict]) -> None:
    lines = path.read_text().splitlines()
    path.write_text("".join(json.dumps(change(json.loads(line))) + "\n" for line in lines if line.strip()))


def make_portable(run: Path) -> None:
    """Rewrite the published run folder ``run`` in place so that it names nothing outside itself:
    ``published.json`` in the new form (read from either form), its records, UED summaries,
    ``config.yaml``, ``borrowed.json`` and model. No number changes."""
    record = json.loads((run / PUBLISHED).read_text())
    renamed: dict[str, str] = {}
    run_dir = None
    if "checkpoint" in record:  # the older form: the training machine's path of the model
        old = str(record["checkpoint"])
        copied = record.get("copied")
        has_model = bool(copied) and (run / copied).is_file()
        name = copied if has_model else Path(old).name
        renamed[old] = name
        run_dir = str(Path(old).parent)
        record = published_record(name if has_model else None, record["frames"])
        if not has_model:
            record["evaluated"] = name
        (run / PUBLISHED).write_text(json.dumps(record, indent=1) + "\n")
    change = lambda line: portable_fields(line, run.name, renamed, run_dir)  # noqa: E731
    for path in sorted((run / "eval").rglob("*.jsonl")) if (run / "eval").is_dir() else []:
        _rewrite_lines(path, change)
    for path in sorted((run / "eval").glob("ued-*.json")) if (run / "eval").is_dir() else []:
        path.write_text(json.dumps(change(json.loads(path.read_text())), indent=1) + "\n")
    config = run / "config.yaml"
    if config.is_file():
        config.write_text(portable_config_text(config.read_text()))
    borrowed = run / "borrowed.json"
    if borrowed.is_file():
        data = json.loads(borrowed.read_text())
        data["from"] = sweep_relative(data["from"])
        borrowed.write_text(json.dumps(data, indent=1) + "\n")
    if record.get("model"):
        model = run / record["model"]
        write_portable_model(model, model)


def sweep_relative(source: str) -> str:
    """A borrowed run's source as ``<sweep>/runs/<run>``: what a results page says of it."""
    return "/".join(Path(source).parts[-3:])
