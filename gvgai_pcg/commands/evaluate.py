"""``gvgai-pcg evaluate``: play an agent on levels and report per-level scores.

``--agent random`` is the study's uniformly random baseline. Results go to a table on stdout
and, with ``--json PATH`` (``-`` for stdout), to a JSON file.
"""

from __future__ import annotations

import argparse
import json
import sys

from gvgai_pcg.evaluation import RandomAgent, evaluate_levels, format_table
from gvgai_pcg.games import get_game, registered_games
from gvgai_pcg.levels import Level, human_levels, resolve_level

AGENTS = ("random",)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--agent", choices=AGENTS, default="random", help="which agent plays")
    parser.add_argument("--game", required=True, choices=registered_games())
    parser.add_argument(
        "--levels", default="human", help="'human' (the five human levels) or comma-separated names/paths"
    )
    parser.add_argument("--episodes", type=int, default=30, help="episodes per level")
    parser.add_argument("--max-steps", type=int, default=2000, help="step limit per episode")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--obs", choices=("tiles", "pixels"), default="tiles")
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--json", metavar="PATH", help="write the results as JSON ('-' for stdout)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def _levels(spec: str, game: str) -> list[Level]:
    if spec == "human":
        return human_levels(game)
    return [resolve_level(part.strip(), game) for part in spec.split(",") if part.strip()]


def run(args: argparse.Namespace) -> int:
    if args.episodes < 1:
        raise SystemExit(f"--episodes must be at least 1, got {args.episodes}")
    game = get_game(args.game)
    policy = RandomAgent(game.num_actions, seed=args.seed, device=args.device)
    summaries = evaluate_levels(
        args.game,
        _levels(args.levels, args.game),
        policy,
        episodes=args.episodes,
        max_steps=args.max_steps,
        seed=args.seed,
        obs=args.obs,
        device=args.device,
        progress=not args.no_progress,
    )
    payload = {
        "game": args.game,
        "agent": args.agent,
        "seed": args.seed,
        "max_steps": args.max_steps,
        "levels": [s.as_dict() for s in summaries],
    }
    table = format_table(args.game, summaries, args.agent)
    if args.json == "-":
        json.dump(payload, sys.stdout, indent=1)
        print(file=sys.stdout)
        print(table, file=sys.stderr)
        return 0
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(payload, handle, indent=1)
    print(table)
    return 0
