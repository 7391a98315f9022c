"""``gvgai-pcg replay RUN --level zelda_lvl0 --out replay.gif``: watch what a trained agent does.

Plays one episode of the run's agent (its final model, or ``--checkpoint``) on a level — a human
level name, a frozen test level (``zelda_pcg1_07``) or a level file — and writes it, rendered in
pixels, as an animated GIF.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gvgai_pcg.commands.folders import refuse_folders_for_files
from gvgai_pcg.levels import resolve_level
from gvgai_pcg.levels.test_sets import TEST_DIFFICULTIES, frozen_test_set


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("run", type=Path, help="a run directory")
    parser.add_argument("--level", required=True, help="e.g. zelda_lvl0, zelda_pcg1_07, or a level file")
    parser.add_argument("--out", type=Path, default=Path("replay.gif"))
    parser.add_argument("--checkpoint", type=Path, help="a chosen checkpoint file of the run")
    parser.add_argument("--greedy", action="store_true", help="argmax actions instead of sampling")
    parser.add_argument("--max-steps", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--fps", type=_positive(float), default=10.0)
    parser.add_argument("--scale", type=_positive(int), default=2, help="pixels per game pixel")
    parser.add_argument("--device", default="cpu")


def _positive(kind: type):
    """An argparse type: a number of ``kind`` above zero."""

    def parse(text: str):
        value = kind(text)
        if not value > 0:
            raise argparse.ArgumentTypeError(f"must be above 0, got {text}")
        return value

    return parse


def resolve_any_level(spec: str, game: str):
    """A human level name, a frozen test level name or a path."""
    for difficulty in TEST_DIFFICULTIES:
        for level in frozen_test_set(game, difficulty) if spec.startswith(f"{game}_pcg") else ():
            if level.name == spec:
                return level
    return resolve_level(spec, game)


def run(args: argparse.Namespace) -> int:
    from gvgai_pcg.evaluation.checkpoints import run_info
    from gvgai_pcg.evaluation.policy import load_policy
    from gvgai_pcg.evaluation.replay import record_episode, write_gif

    refuse_folders_for_files({"--out": args.out}, suffix=".gif")
    info = run_info(args.run, args.checkpoint)
    level = resolve_any_level(args.level, info.game)
    if level.game != info.game:
        raise ValueError(f"{args.level} is a {level.game} level, but {args.run} trained on {info.game}")
    policy = load_policy(info, greedy=args.greedy, seed=args.seed, device=args.device)
    episode = record_episode(level, policy, info.obs, args.max_steps, args.seed, args.device)
    write_gif(episode, args.out, fps=args.fps, scale=args.scale)
    outcome = "won" if episode.won else "did not win"
    print(f"{args.out}: {len(episode.frames)} frames, score {episode.scores[-1]:g}, {outcome}")
    return 0
