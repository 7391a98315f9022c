"""``gvgai-pcg evaluate``: play agents on levels and report per-level scores.

Two uses:

* the study's protocol (GENERATORS.md §4): ``gvgai-pcg evaluate RUN [RUN ...]`` evaluates the
  trained runs (a run directory, or a multirun directory holding many), and
  ``gvgai-pcg evaluate --agent random --game G --protocol`` the random baseline. Every frozen test
  level is played ``--test-episodes`` times and every human level ``--human-episodes`` times, all
  in one batched env; records go to ``<run>/eval/protocol-<key>.jsonl`` (random: the cache).
  ``--test-sets large`` plays the 100-level frozen sets instead of the study's 30-level ones; its
  records go to a file of their own (another key), beside the study-sized ones.
* the UED protocol (``gvgai_pcg.evaluation.ued``): ``gvgai-pcg evaluate RUN --ued`` (and
  ``--agent random --game G --ued``) plays ``--ued-levels`` newly generated levels over d in
  [0, 1], ``--ued-rank-episodes`` times to rank each and ``--ued-score-episodes`` other times to
  score it (the tail protocol, 1,000 levels x 10 + 10 by default; ``--ued-seeds N`` is the first
  protocol, the published curricula records'), and reports the solved rate, the mean score and the
  bias-corrected alpha-CVaRs of the score and the win rate (``--alphas``); per-level CSV in
  ``<run>/eval/ued-<key>.csv``.
* held-out scores over training: ``gvgai-pcg evaluate RUN --snapshots [--every FRAMES]`` plays
  each of the run's snapshots (on the 100-level sets unless ``--test-sets study``), prints a table
  and plots the held-out scores beside the training curve (``gvgai_pcg.evaluation.held_out``).
* ad-hoc levels: ``--levels human|NAMES|PATHS --episodes N`` plays each listed level N times and
  prints a table; ``--json PATH`` (``-`` for stdout) writes ``{"game", "levels": [...]}``.

The evaluation modules (torch) are imported inside the functions that play, so a bad option is
refused in one line before they are.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from gvgai_pcg.commands.folders import refuse_files_for_folders
from gvgai_pcg.games import get_game, registered_games
from gvgai_pcg.levels import Level, human_levels, resolve_level
from gvgai_pcg.rundir.atomic_files import atomic_write_text

if TYPE_CHECKING:
    from gvgai_pcg.evaluation.protocol import Protocol
    from gvgai_pcg.evaluation.ued import UEDProtocol

AGENTS = ("random", "trained")
# Settings of the study's protocol that the UED protocol has no use for (their defaults are None).
STUDY_ONLY = ("test_sets", "test_levels", "test_episodes", "human_episodes")


def add_protocol_arguments(parser: argparse.ArgumentParser) -> None:
    """The protocol's settings (shared with ``gvgai-pcg report``)."""
    group = parser.add_argument_group("protocol")
    group.add_argument(
        "--test-sets",
        choices=("study", "large"),
        default=None,
        help="the frozen generated sets: the study's 30 levels per difficulty (the default), or 100 "
        "(results kept apart; the default with --snapshots)",
    )
    group.add_argument(
        "--test-levels", type=int, default=None, help="levels used of each frozen test set (default: all)"
    )
    group.add_argument(
        "--test-episodes", type=int, default=None, help="episodes per generated test level (default 1)"
    )
    group.add_argument(
        "--human-episodes", type=int, default=None, help="episodes per human level (default 30)"
    )
    group.add_argument("--max-steps", type=int, default=2000, help="step limit per episode")
    group.add_argument("--greedy", action="store_true", help="argmax actions instead of sampling")
    group.add_argument("--seed", type=int, default=0)
    group.add_argument("--device", default="cpu")
    group.add_argument("--cache-dir", type=Path, help="where random-agent results are cached")
    group.add_argument("--force", action="store_true", help="evaluate again even if results exist")
    group.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def protocol_from(args: argparse.Namespace) -> Protocol:
    from gvgai_pcg.evaluation.protocol import TEST_SET_SIZES, Protocol

    test_sets = args.test_sets or ("large" if getattr(args, "snapshots", False) else "study")
    try:
        return Protocol(
            test_sets=test_sets,
            test_levels=TEST_SET_SIZES[test_sets] if args.test_levels is None else args.test_levels,
            test_episodes=1 if args.test_episodes is None else args.test_episodes,
            human_episodes=30 if args.human_episodes is None else args.human_episodes,
            max_steps=args.max_steps,
            greedy=args.greedy,
            seed=args.seed,
        )
    except ValueError as error:
        raise ValueError(f"invalid protocol setting: {error}") from None


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("runs", nargs="*", type=Path, help="run directories or multirun directories")
    parser.add_argument(
        "--checkpoint",
        "--model",
        type=Path,
        help="a chosen model or checkpoint file of the run (one run only; a published run's model.pt)",
    )
    parser.add_argument(
        "--snapshots",
        action="store_true",
        help="evaluate each run's snapshots (snapshots/model-*.pt), by default on the 100-level sets, "
        "and plot the held-out scores beside the training curve",
    )
    parser.add_argument(
        "--every",
        type=int,
        default=None,
        metavar="FRAMES",
        help="--snapshots: one snapshot per FRAMES frames (default: every snapshot)",
    )
    parser.add_argument(
        "--agent", choices=AGENTS, help="'random' or 'trained' (the default when RUNs are given, else random)"
    )
    parser.add_argument("--game", choices=registered_games(), help="the game (random agent)")
    parser.add_argument("--protocol", action="store_true", help="the study's protocol for the random agent")
    parser.add_argument(
        "--levels", help="ad-hoc levels instead of the protocol: 'human' or comma-separated names/paths"
    )
    parser.add_argument("--episodes", type=int, default=30, help="episodes per level (ad-hoc levels)")
    parser.add_argument(
        "--obs", choices=("tiles", "pixels"), default="tiles", help="observation (random agent)"
    )
    parser.add_argument(
        "--json", metavar="PATH", help="ad-hoc levels: write the results as JSON ('-': stdout)"
    )
    add_protocol_arguments(parser)
    add_ued_arguments(parser, "the UED protocol: many new generated levels, solved rate, CVaR")


def add_ued_arguments(parser: argparse.ArgumentParser, what: str, alphas: bool = True) -> None:
    """The UED protocol's settings (shared with ``gvgai-pcg report --ued``, whose table has the
    CVaR at the default fractions only: ``alphas=False``)."""
    group = parser.add_argument_group("UED protocol (--ued)")
    group.add_argument("--ued", action="store_true", help=what)
    group.add_argument(
        "--ued-levels", type=int, default=1000, help="generated levels, d evenly in [0, 1] (default 1000)"
    )
    group.add_argument(
        "--ued-rank-episodes",
        type=int,
        default=None,
        help="episodes per level that rank it for the CVaR (the tail protocol, default 10)",
    )
    group.add_argument(
        "--ued-score-episodes",
        type=int,
        default=None,
        help="other episodes per level that score it for the CVaR (the tail protocol, default 10)",
    )
    group.add_argument(
        "--ued-seeds",
        type=int,
        default=None,
        help="the first protocol instead (the published curricula records): this many episodes per level, "
        "ranked by one, ties by a fixed order",
    )
    if alphas:
        group.add_argument(
            "--alphas",
            default="0.01,0.1",
            help="CVaR fractions in (0, 1], comma-separated (default 0.01,0.1)",
        )
    else:
        parser.set_defaults(alphas="0.01,0.1")


def ued_protocol_from(args: argparse.Namespace) -> tuple[UEDProtocol, tuple[float, ...]]:
    """The UED protocol's settings and CVaR fractions, or one ValueError naming the bad one."""
    from gvgai_pcg.evaluation.ued import (
        TAIL_RANK_EPISODES,
        TAIL_SCORE_EPISODES,
        UEDProtocol,
        check_alphas,
    )

    try:
        alphas = tuple(float(part) for part in args.alphas.split(",") if part.strip())
    except ValueError:
        raise ValueError(f"--alphas {args.alphas!r}: expected comma-separated numbers in (0, 1]") from None
    common = {"max_steps": args.max_steps, "greedy": args.greedy, "seed": args.seed}
    if args.ued_seeds is not None:
        if args.ued_rank_episodes is not None or args.ued_score_episodes is not None:
            raise ValueError(
                "--ued-seeds is the first protocol: leave out --ued-rank-episodes and --ued-score-episodes"
            )
        settings = {"levels": args.ued_levels, "seeds": args.ued_seeds}
    else:
        settings = {
            "levels": args.ued_levels,
            "rank_episodes": TAIL_RANK_EPISODES if args.ued_rank_episodes is None else args.ued_rank_episodes,
            "score_episodes": TAIL_SCORE_EPISODES
            if args.ued_score_episodes is None
            else args.ued_score_episodes,
        }
    try:
        return UEDProtocol(**settings, **common), check_alphas(alphas)
    except ValueError as error:
        raise ValueError(f"invalid UED protocol setting: {error}") from None


def _levels(spec: str, game: str) -> list[Level]:
    """``human``, one level file (a comma in its name included), or comma-separated names/paths."""
    if spec == "human":
        return human_levels(game)
    if Path(spec).is_file():
        return [resolve_level(spec, game)]
    names = [part.strip() for part in spec.split(",") if part.strip()]
    if not names:
        raise ValueError(
            f"--levels {spec!r}: no level given; expected 'human' or comma-separated names/paths"
        )
    return [resolve_level(name, game) for name in names]


def run(args: argparse.Namespace) -> int:
    refuse_files_for_folders({"--cache-dir": args.cache_dir})
    agent = args.agent or ("trained" if args.runs else "random")
    if agent == "trained" and not args.runs:
        raise ValueError("--agent trained needs at least one RUN directory")
    if agent == "random" and args.runs:
        raise ValueError("RUN directories are for trained agents; leave out --agent random")
    if agent == "random" and not args.game:
        raise ValueError("--agent random needs --game")
    if args.checkpoint and len(args.runs) != 1:
        raise ValueError("--checkpoint picks the checkpoint of one run; give exactly one RUN")
    if args.snapshots and (agent != "trained" or args.levels or args.checkpoint or args.ued):
        raise ValueError(
            "--snapshots evaluates trained RUNs on the protocol; leave out --levels, --checkpoint and --ued"
        )
    if args.every is not None and not args.snapshots:
        raise ValueError("--every picks snapshots to evaluate; it needs --snapshots")
    if args.every is not None and args.every < 1:
        raise ValueError(f"--every {args.every}: expected a positive number of frames")
    if args.snapshots:
        return _run_snapshots(args)
    if args.ued and (args.levels or args.protocol):
        raise ValueError("--ued is a protocol of its own; leave out --levels and --protocol")
    ignored = [f"--{name.replace('_', '-')}" for name in STUDY_ONLY if getattr(args, name) is not None]
    if args.ued and ignored:
        raise ValueError(
            f"{', '.join(ignored)}: settings of the study's protocol, which --ued does not play (it plays "
            "--ued-levels new levels --ued-seeds times); leave them out"
        )
    if args.ued:
        return _run_ued(args, agent)
    if agent == "trained" and not args.levels:
        return _run_protocol_trained(args)
    if agent == "random" and args.protocol:
        return _run_protocol_random(args)
    return _run_levels(args, agent)


def _runs_of(args: argparse.Namespace) -> list:
    """The run directories under ``args.runs``; none found is a usage error naming the paths."""
    from gvgai_pcg.evaluation.checkpoints import find_runs

    runs = find_runs(args.runs)
    if not runs:
        raise ValueError(
            f"no run directories (with config.yaml and a model) in {', '.join(map(str, args.runs))}"
        )
    return runs


def _run_protocol_trained(args: argparse.Namespace) -> int:
    from gvgai_pcg.evaluation.checkpoints import run_info
    from gvgai_pcg.evaluation.evaluator import evaluate_run, run_results_path
    from gvgai_pcg.evaluation.summary import format_protocol_table

    protocol = protocol_from(args)
    runs = _runs_of(args)
    for path in runs:
        info = run_info(path, args.checkpoint)
        records = evaluate_run(info, protocol, args.device, not args.no_progress, args.force)
        print(format_protocol_table(f"{info.game}: {path} ({info.label}, {info.frames} frames)", records))
        print(f"  -> {run_results_path(path, protocol)}\n")
    return 0


def _run_snapshots(args: argparse.Namespace) -> int:
    from gvgai_pcg.evaluation.held_out import (
        evaluate_snapshots,
        format_held_out_table,
        held_out_plot_path,
        held_out_scores,
        plot_held_out,
    )

    protocol = protocol_from(args)
    runs = _runs_of(args)
    for path in runs:
        results = evaluate_snapshots(
            path, protocol, args.every or 0, args.device, not args.no_progress, args.force
        )
        curves = held_out_scores(results)
        print(format_held_out_table(f"{path}: held-out mean score per snapshot", curves))
        plot = plot_held_out(path / "log.csv", curves, held_out_plot_path(path, protocol), path.name)
        print(f"  -> {plot}\n")
    return 0


def _run_protocol_random(args: argparse.Namespace) -> int:
    from gvgai_pcg.evaluation.evaluator import evaluate_random, random_results_path
    from gvgai_pcg.evaluation.summary import format_protocol_table

    protocol = protocol_from(args)
    records = evaluate_random(
        args.game, protocol, args.cache_dir, args.device, not args.no_progress, args.force
    )
    print(format_protocol_table(f"{args.game}: random agent", records))
    print(f"  -> {random_results_path(args.game, protocol, args.cache_dir)}")
    return 0


def _run_ued(args: argparse.Namespace, agent: str) -> int:
    protocol, alphas = ued_protocol_from(args)
    from gvgai_pcg.evaluation.ued import evaluate_random_ued, evaluate_run_ued, format_ued_summary

    progress = not args.no_progress
    if agent == "random":
        summary, table = evaluate_random_ued(
            args.game, protocol, alphas, args.cache_dir, args.device, progress, args.force
        )
        print(format_ued_summary(f"{args.game}: random agent, UED protocol", summary))
        print(f"  -> {table}")
        return 0
    from gvgai_pcg.evaluation.checkpoints import run_info

    runs = _runs_of(args)
    for path in runs:
        info = run_info(path, args.checkpoint)
        summary, table = evaluate_run_ued(info, protocol, alphas, args.device, progress, args.force)
        print(format_ued_summary(f"{info.game}: {path} ({info.label}, {info.frames} frames), UED", summary))
        print(f"  -> {table}\n")
    return 0


def _run_levels(args: argparse.Namespace, agent: str) -> int:
    if args.episodes < 1:
        raise ValueError(f"--episodes must be at least 1, got {args.episodes}")
    if args.levels is not None and not args.levels.strip(" ,"):
        raise ValueError(
            f"--levels {args.levels!r}: no level given; expected 'human' or comma-separated names/paths"
        )
    from gvgai_pcg.evaluation import RandomAgent, evaluate_levels, format_table
    from gvgai_pcg.evaluation.checkpoints import run_info
    from gvgai_pcg.evaluation.policy import load_policy

    if agent == "trained":
        info = run_info(args.runs[0], args.checkpoint)
        game, obs = info.game, info.obs
        policy = load_policy(info, greedy=args.greedy, seed=args.seed, device=args.device)
    else:
        game, obs = args.game, args.obs
        policy = RandomAgent(get_game(game).num_actions, seed=args.seed, device=args.device)
    summaries = evaluate_levels(
        game,
        _levels("human" if args.levels is None else args.levels, game),
        policy,
        episodes=args.episodes,
        max_steps=args.max_steps,
        seed=args.seed,
        obs=obs,
        device=args.device,
        progress=not args.no_progress,
    )
    payload = {
        "game": game,
        "agent": agent if agent == "random" else str(args.runs[0]),
        "seed": args.seed,
        "max_steps": args.max_steps,
        "levels": [s.as_dict() for s in summaries],
    }
    table = format_table(game, summaries, payload["agent"])
    if args.json == "-":
        json.dump(payload, sys.stdout, indent=1)
        print(file=sys.stdout)
        print(table, file=sys.stderr)
        return 0
    if args.json:  # whole or not at all: a full disk leaves no empty or half file
        atomic_write_text(Path(args.json), json.dumps(payload, indent=1))
    print(table)
    return 0
