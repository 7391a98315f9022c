"""``gvgai-pcg vgdl``: GVGAI's VGDL games as this package reads them.

``list`` prints every VGDL game found (the corpus folder, see ``gvgai_pcg.vgdl.corpus``), one a
line, with the features the engine does not implement yet; ``inspect GAME`` prints the parsed
description in Java's orders (``--json`` for all of it as JSON). ``GAME`` is a name from
``list`` or a path to a .txt file. A file Java would misread is refused as ``path:line: ...``.
"""

from __future__ import annotations

import argparse

from gvgai_pcg.vgdl import parse_file
from gvgai_pcg.vgdl.corpus import ENV_VAR, find_game, vgdl_games
from gvgai_pcg.vgdl.describe import describe, to_json
from gvgai_pcg.vgdl.support import unsupported_features


def add_arguments(parser: argparse.ArgumentParser) -> None:
    actions = parser.add_subparsers(dest="action", required=True, metavar="ACTION")
    actions.add_parser("list", help="every VGDL game found, one a line, with what the engine lacks for it")
    inspect = actions.add_parser("inspect", help="a game's parsed structure in Java's orders")
    inspect.add_argument("game", metavar="GAME", help="a name from 'gvgai-pcg vgdl list' or a path to a .txt")
    inspect.add_argument("--json", action="store_true", help="print the whole description as JSON")


def run(args: argparse.Namespace) -> int:
    if args.action == "list":
        return list_games()
    game = parse_file(find_game(args.game))
    print(to_json(game) if args.json else describe(game))
    return 0


def list_games() -> int:
    games = vgdl_games()
    if not games:
        raise ValueError(f"no VGDL games: set {ENV_VAR} to a folder of GVGAI's VGDL files")
    for name, path in games.items():
        missing = [feature.name for feature in unsupported_features(parse_file(path))]
        print(f"{name}\t{'ready' if not missing else 'needs ' + ', '.join(missing)}")
    return 0
