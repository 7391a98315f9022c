"""``gvgai-pcg vgdl``: GVGAI's VGDL games as this package reads them.

``list`` prints every VGDL game found (the corpus folder, see ``gvgai_pcg.vgdl.corpus``), one a
line, with the features the engine does not implement yet; ``inspect GAME`` prints the parsed
description in Java's orders and the plan compiled from it (``--level FILE`` gives each table's
slots for that level; ``--json`` for all of it as JSON; a game the engine cannot run yet shows
the one-line refusal in the plan's place). ``GAME`` is a name from ``list`` or a path to a .txt
file. A file Java would misread is refused as ``path:line: ...``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

from gvgai_pcg.vgdl import VGDLError, parse_file
from gvgai_pcg.vgdl.corpus import ENV_VAR, find_game, vgdl_games
from gvgai_pcg.vgdl.describe import describe, encode
from gvgai_pcg.vgdl.plan import Plan, compile_plan
from gvgai_pcg.vgdl.plan_text import describe_plan
from gvgai_pcg.vgdl.support import unsupported_features


def add_arguments(parser: argparse.ArgumentParser) -> None:
    actions = parser.add_subparsers(dest="action", required=True, metavar="ACTION")
    actions.add_parser("list", help="every VGDL game found, one a line, with what the engine lacks for it")
    inspect = actions.add_parser("inspect", help="a game's parsed structure in Java's orders")
    inspect.add_argument("game", metavar="GAME", help="a name from 'gvgai-pcg vgdl list' or a path to a .txt")
    inspect.add_argument(
        "--level", metavar="FILE", help="a level file: the plan gives each table's slots for it"
    )
    inspect.add_argument("--json", action="store_true", help="print the whole description and plan as JSON")


def run(args: argparse.Namespace) -> int:
    if args.action == "list":
        return list_games()
    game = parse_file(find_game(args.game))
    rows = _level_rows(args.level) if args.level else None
    try:
        plan: Plan | str = compile_plan(game, rows)
    except VGDLError as error:
        plan = str(error)  # a game the engine cannot run yet: its parse is still worth seeing
    if args.json:
        whole = dataclasses.asdict(game) | (
            {"plan": None, "plan_refused": plan}
            if isinstance(plan, str)
            else {"plan": dataclasses.asdict(plan)}
        )
        print(json.dumps(whole, default=encode, indent=1))
    else:
        print(describe(game))
        print(f"plan: refused: {plan}" if isinstance(plan, str) else describe_plan(plan))
    return 0


def _level_rows(path: str) -> list[str]:
    try:
        return Path(path).read_text(encoding="utf-8").splitlines()
    except OSError as error:
        raise ValueError(f"cannot read level {path}: {error.strerror}") from None


def list_games() -> int:
    games = vgdl_games()
    if not games:
        raise ValueError(f"no VGDL games: set {ENV_VAR} to a folder of GVGAI's VGDL files")
    for name, path in games.items():
        missing = [feature.name for feature in unsupported_features(parse_file(path))]
        print(f"{name}\t{'ready' if not missing else 'needs ' + ', '.join(missing)}")
    return 0
