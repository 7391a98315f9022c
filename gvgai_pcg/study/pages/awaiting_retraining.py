"""The published runs whose models exist on no machine any more, and the command that trains each
again with the same config and seed: ``results/awaiting-retraining.json``, and the list on each
budget's page.

Their records still rebuild every published table; only replaying or evaluating them again needs
the model. A test holds the list to what ``results/`` holds: a listed run has no model, every
other run folder has one.

``python -m gvgai_pcg.study.pages.awaiting_retraining [RESULTS]`` writes the list again from ``RESULTS``
(default ``results``), and its block on each budget's page (``PAGES``).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import yaml

from gvgai_pcg.rundir.atomic_files import atomic_write_text
from gvgai_pcg.study.pages.page import replace_block

LIST_NAME = "awaiting-retraining.json"
MODEL = "model.pt"


def condition_of(config: dict) -> str:
    """The study's condition a run's config is (``zelda-pcg1`` for the tag ``pcg1.0``)."""
    return f"{config['game']['name']}-{config['regimen']['tag'].removesuffix('.0')}"


def retrain_command(run: Path) -> str:
    """The command that trains ``run`` (``results/<budget>/runs/<name>``) again as it trained: its
    budget's sweep for one condition and seed (a borrowed run: borrowed again from ``medium``), a
    pilot run with its own overrides."""
    config = yaml.safe_load((run / "config.yaml").read_text())
    budget, seed = run.parent.parent.name, int(config["seed"])
    if budget == "pilot":
        overrides = [
            f"condition={condition_of(config)}",
            f"env.num_envs={config['env']['num_envs']}",
            f"algo.lr={config['algo']['lr']}",
            f"seed={seed}",
            f"total_frames={config['total_frames']}",
            f"run_name={run.name}",
            "out_dir=reproduce/pilot/runs",
        ]
        return "gvgai-pcg train " + " ".join(overrides)
    command = f"gvgai-pcg reproduce --budget {budget} --conditions {condition_of(config)} --seeds {seed}"
    if (run / "borrowed.json").is_file():
        command += " --borrow-from reproduce/medium"
    return f"{command} --out reproduce/{budget}"


def awaiting(results: Path) -> dict[str, list[dict[str, str]]]:
    """Per budget, the run folders under ``results`` without a model, each with its command."""
    found: dict[str, list[dict[str, str]]] = {}
    for run in sorted(Path(results).glob("*/runs/*")):
        if run.is_dir() and not (run / MODEL).is_file():
            entry = {"run": run.name, "command": retrain_command(run)}
            found.setdefault(run.parent.parent.name, []).append(entry)
    return found


def read_list(results: Path) -> dict[str, list[dict[str, str]]]:
    path = Path(results) / LIST_NAME
    return json.loads(path.read_text()) if path.is_file() else {}


def page_lines(results: Path, budget: str) -> list[str]:
    """The markdown list of ``budget``'s runs awaiting retraining (none: an empty list)."""
    return [f"- `{entry['run']}`: `{entry['command']}`" for entry in read_list(results).get(budget, [])]


PAGES = {
    "small": "docs/results.md",
    "medium": "docs/results-medium.md",
    "curricula": "docs/results-curricula.md",
    "pilot": "docs/pilot.md",
}
START, END = "<!-- awaiting-retraining:start -->", "<!-- awaiting-retraining:end -->"


def page_block(results: Path, budget: str) -> str:
    """The page's block between ``START`` and ``END``: the list, or a line saying none waits."""
    lines = page_lines(results, budget) or ["None: every run of this page holds its model."]
    return "\n".join([START, *lines, END])


def write_page(page: Path, results: Path, budget: str) -> None:
    """Replace the block in ``page`` (appended, under its heading, where it has none)."""
    block = page_block(results, budget)
    if START in page.read_text():
        replace_block(page, block, START, END)
        return
    heading = (
        "\n\n## Runs awaiting retraining\n\n"
        "Their models exist on no machine any more: their records rebuild the tables above, and\n"
        "`replay`/`evaluate` refuse them in one line. Each trains again with the same config and\n"
        "seed (then publishes with the budget's sweep; `results/awaiting-retraining.json`):\n\n"
    )
    atomic_write_text(page, page.read_text().rstrip("\n") + heading + block + "\n")


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    results = Path(args[0]) if args else Path("results")
    (results / LIST_NAME).write_text(json.dumps(awaiting(results), indent=1) + "\n")
    for budget, page in PAGES.items():
        write_page(results.parent / page, results, budget)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
