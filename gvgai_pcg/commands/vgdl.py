"""``gvgai-pcg vgdl``: GVGAI's VGDL games as this package reads them.

``list`` prints every registered VGDL game (the package's own descriptions that run through the
generic step, ``gvgai_pcg.vgdl.registry``), one a line, then the GVGAI corpus games registered
from the corpus folder (``gvgai_pcg.vgdl.corpus_games``) with their file, and those it holds but
the engine refuses, with the refusal; ``list --corpus`` every
game of the corpus folder (``gvgai_pcg.vgdl.corpus``) with the features the engine does not
implement yet.
``games --out FILE`` writes ``docs/games.md`` (``gvgai_pcg.vgdl.games_page``).
``inspect GAME`` prints the parsed description in Java's orders and the plan compiled from it
(``--level FILE`` gives each table's slots for that level; ``--json`` for all of it as JSON; a
game the engine cannot run yet shows the one-line refusal in the plan's place). ``GAME`` is a
registered name, a corpus name or a path to a .txt file. ``trace GAME LEVEL --actions ...
--json OUT`` plays a level through the generic step and writes the golden traces' format
(``gvgai_pcg.vgdl.engine.trace``); there ``GAME`` is a registered name or a path. A file Java
would misread is refused as ``path:line: ...``; any bad input in one line, exit 2, nothing
written.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
from pathlib import Path

from gvgai_pcg.games import registered_games as registered_game_names
from gvgai_pcg.rundir.atomic_files import atomic_write_text
from gvgai_pcg.vgdl import VGDLError, corpus_games, parse_file
from gvgai_pcg.vgdl.corpus import ENV_VAR, corpus_dir, find_game, vgdl_games
from gvgai_pcg.vgdl.describe import describe, encode
from gvgai_pcg.vgdl.games_page import game_rows, games_markdown
from gvgai_pcg.vgdl.plan import Plan, compile_plan
from gvgai_pcg.vgdl.plan_text import describe_plan
from gvgai_pcg.vgdl.registry import registered_game, registered_games
from gvgai_pcg.vgdl.support import unsupported_features


def add_arguments(parser: argparse.ArgumentParser) -> None:
    actions = parser.add_subparsers(dest="action", required=True, metavar="ACTION")
    listing = actions.add_parser("list", help="every registered VGDL game, one a line")
    listing.add_argument(
        "--corpus", action="store_true", help="the corpus folder's games instead, with what the engine lacks"
    )
    games = actions.add_parser(
        "games", help="write the page of every corpus game: plays or not, what it lacks"
    )
    games.add_argument(
        "--out", required=True, metavar="FILE", help="the Markdown page to write (docs/games.md)"
    )
    games.add_argument(
        "--traces",
        default="tests/data/vgdl_corpus_traces",
        metavar="DIR",
        help="the folder of recorded Java traces (<game>_*.json) the page counts",
    )
    inspect = actions.add_parser("inspect", help="a game's parsed structure in Java's orders")
    inspect.add_argument("game", metavar="GAME", help="a name from 'gvgai-pcg vgdl list' or a path to a .txt")
    inspect.add_argument(
        "--level", metavar="FILE", help="a level file: the plan gives each table's slots for it"
    )
    inspect.add_argument("--json", action="store_true", help="print the whole description and plan as JSON")
    trace = actions.add_parser("trace", help="play a level through the generic step, write a golden trace")
    trace.add_argument("game", metavar="GAME", help="a name from 'gvgai-pcg vgdl list' or a path to a .txt")
    trace.add_argument("level", metavar="LEVEL_FILE", help="the level file to play")
    trace.add_argument(
        "--actions", required=True, help="comma-separated action names (NIL, USE, LEFT ...), tick 1 on"
    )
    trace.add_argument("--exclude", default="", help="comma-separated sprite types left out of the sprites")
    trace.add_argument("--seed", type=int, default=0, help="the env's seed (random draws)")
    trace.add_argument("--json", required=True, metavar="OUT", help="the trace file to write")


def run(args: argparse.Namespace) -> int:
    if args.action == "list":
        return list_corpus() if args.corpus else list_registered()
    if args.action == "trace":
        return write_trace(args)
    if args.action == "games":
        return write_games_page(Path(args.out), Path(args.traces))
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


def list_registered() -> int:
    for name in registered_games():
        print(name)
    games = registered_game_names()
    for name in games:
        path = corpus_games.corpus_file(name)
        if path is not None:
            print(f"{name}\tcorpus: {path}")
    folder = corpus_dir()
    for stem in corpus_games.CORPUS_GAMES:
        name = corpus_games.game_name(stem)
        if folder is not None and (folder / f"{stem}.txt").is_file() and name not in games:
            print(f"{name}\tcorpus, refused: {corpus_games.refusal(name)}")
    return 0


def write_trace(args: argparse.Namespace) -> int:
    """``vgdl trace``: every input checked before the play, the file written whole or not at all."""
    from gvgai_pcg.vgdl.engine import VGDLGame
    from gvgai_pcg.vgdl.engine.trace import play_trace, read_level

    if args.game.endswith(".txt") or os.sep in args.game:
        if not Path(args.game).is_file():
            raise ValueError(f"no VGDL file {args.game}")
        game, level_game = VGDLGame.from_file(args.game), Path(args.game).stem
    else:
        entry = registered_game(args.game)  # an unknown name is refused in one line
        game, level_game = (
            VGDLGame.from_file(entry.description, name=f"vgdl:{entry.name}", draw_order=entry.draw_order),
            entry.levels,
        )
    level = read_level(args.level, level_game)
    actions = [name for name in args.actions.split(",") if name]
    exclude = [name for name in args.exclude.split(",") if name]
    ticks = play_trace(game, level, actions, args.seed, exclude)
    trace = {
        "game": args.game,
        "name": Path(args.level).stem,
        "level": list(level.rows),
        "actions": actions,
        "seed": args.seed,
        "excluded": exclude,
        "ticks": ticks,
    }
    out = Path(args.json)
    try:
        atomic_write_text(out, json.dumps(trace) + "\n")
    except OSError as error:
        raise ValueError(f"cannot write {out}: {error.strerror}") from None
    print(f"{len(ticks)} ticks ({ticks[-1]['status']}, score {ticks[-1]['score']}) written to {out}")
    return 0


def write_games_page(out: Path, traces: Path) -> int:
    folder = corpus_dir()
    if folder is None:
        raise ValueError(f"no VGDL games: set {ENV_VAR} to a folder of GVGAI's VGDL files")
    if not traces.is_dir():
        raise ValueError(f"no traces folder {traces}")
    rows = game_rows(folder, traces)
    try:
        atomic_write_text(out, games_markdown(rows))
    except OSError as error:
        raise ValueError(f"cannot write {out}: {error.strerror}") from None
    print(f"{sum(row.registered for row in rows)} of {len(rows)} games play; written to {out}")
    return 0


def list_corpus() -> int:
    games = vgdl_games()
    if not games:
        raise ValueError(f"no VGDL games: set {ENV_VAR} to a folder of GVGAI's VGDL files")
    for name, path in games.items():
        missing = [feature.name for feature in unsupported_features(parse_file(path))]
        print(f"{name}\t{'ready' if not missing else 'needs ' + ', '.join(missing)}")
    return 0
