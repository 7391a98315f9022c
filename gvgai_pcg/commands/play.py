"""``gvgai-pcg play``: play a level yourself in the terminal, to feel a level before training on it.

``--level`` takes a human level name or a level file; ``--difficulty D --seed S`` generates the
level that ``generate_level(game, D, S)`` makes (the same one a training run at that seed sees).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from gvgai_pcg.games import get_game_spec, registered_games
from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels import Level, human_level, resolve_level

RENDERS = ("text", "pixels")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--game",
        required=True,
        type=game_argument,
        help=f"one of {', '.join(registered_games())} (GVGAI corpus games need GVGAI_VGDL_DIR)",
    )
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--level", help="a level name (zelda_lvl0) or a level file; default: human level 0")
    source.add_argument(
        "--difficulty", type=float, help="play a generated level at this difficulty in [0, 1]"
    )
    parser.add_argument(
        "--seed", type=int, default=0, help="generator seed (with --difficulty) and episode seed"
    )
    parser.add_argument("--max-steps", type=int, default=2000, help="step limit per episode")
    parser.add_argument(
        "--render",
        choices=RENDERS,
        default="text",
        help="text: the terminal only; pixels: also write the frame to --png on every key press",
    )
    parser.add_argument(
        "--png", type=Path, default=Path("gvgai-play.png"), help="where --render pixels writes"
    )
    parser.add_argument("--fps", type=float, default=0.0, help="ticks per second; 0: one tick per key press")


def game_argument(name: str) -> str:
    """A registered game's name; otherwise the registry's one line (the valid names, or what to
    set for a GVGAI corpus game) as the argument's error."""
    try:
        get_game_spec(name)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    return name


def choose_level(args: argparse.Namespace) -> Level:
    if args.difficulty is not None:
        if not 0.0 <= args.difficulty <= 1.0:
            raise ValueError(f"--difficulty must be in [0, 1], got {args.difficulty}")
        return generate_level(args.game, args.difficulty, args.seed)
    if args.level is None:
        return human_level(args.game, 0)
    return resolve_level(args.level, args.game)


def check_terminal() -> None:
    """``play`` reads keys from a terminal and draws on it: refuse a pipe or a file in one line."""
    for name, stream in (("stdin", sys.stdin), ("stdout", sys.stdout)):
        try:
            interactive = stream.isatty()
        except (AttributeError, ValueError):
            interactive = False
        if not interactive:
            raise ValueError(
                f"play needs a terminal, and its {name} is not one; run it in a terminal (for a level as "
                "text, use gvgai-pcg generate, or Level.load in Python)"
            )


def run(args: argparse.Namespace) -> int:
    level = choose_level(args)
    check_terminal()
    from gvgai_pcg.play.session import PlaySession
    from gvgai_pcg.play.terminal import play

    session = PlaySession(level, seed=args.seed, max_steps=args.max_steps)
    play(session, args.png if args.render == "pixels" else None, fps=args.fps)
    print(session.summary())
    return 0
