"""``gvgai-pcg bench``: measure throughput and write it into docs/benchmarks.md."""

from __future__ import annotations

import argparse
from pathlib import Path

import torch

from gvgai_pcg.bench.generic import generic_section
from gvgai_pcg.bench.jobs import jobs_section
from gvgai_pcg.bench.peers import peers_report
from gvgai_pcg.bench.targets import Section, target_lines
from gvgai_pcg.bench.throughput import BATCH_SIZES, LEVEL_SETS, OBSERVATIONS, run_benchmarks, write_section
from gvgai_pcg.bench.vgdlx import GAMES, vgdlx_section
from gvgai_pcg.commands.folders import refuse_folders_for_files


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--output", type=Path, help="Markdown file to update (default: print only)")
    parser.add_argument("--device", default=None, help="cpu, cuda, or both when left out and CUDA exists")
    parser.add_argument("--games", help="comma-separated games (default: all registered)")
    parser.add_argument("--batch-sizes", default=",".join(map(str, BATCH_SIZES)))
    parser.add_argument("--obs", default=",".join(OBSERVATIONS))
    parser.add_argument(
        "--levels",
        choices=tuple(LEVEL_SETS),
        default="human",
        help="the env tables' levels: the human ones, or a new generated level every episode at d = 0 "
        "(as PPCG training starts, where resets cost the most)",
    )
    parser.add_argument("--seconds", type=float, default=2.0, help="minimum timed seconds per configuration")
    parser.add_argument("--threads", type=int, default=None, help="torch CPU threads (default: torch's)")
    parser.add_argument(
        "--no-peers", action="store_true", help="leave out the peers (gvgai_pcg.bench.peers, .vgdlx)"
    )
    parser.add_argument(
        "--no-generic",
        action="store_true",
        help="leave out the generic VGDL step beside the hand-written engines (gvgai_pcg.bench.generic)",
    )
    parser.add_argument(
        "--no-jobs",
        action="store_true",
        help="leave out the whole jobs (gvgai_pcg.bench.jobs: the evaluation protocol, a 20k-frame training)",
    )


def check_arguments(args: argparse.Namespace) -> None:
    """Bad options in one line, before any measurement (and not as a torch traceback)."""
    refuse_folders_for_files({"--output": args.output})
    if not args.seconds > 0 or args.seconds == float("inf"):
        raise ValueError(f"--seconds must be a finite number > 0, got {args.seconds}")
    if args.threads is not None and args.threads < 1:
        raise ValueError(f"--threads must be at least 1, got {args.threads}")
    if args.device is not None:
        kind = args.device.split(":")[0]
        if kind not in ("cpu", "cuda"):
            raise ValueError(f"--device {args.device!r}: expected cpu, cuda or cuda:N")
        if kind == "cuda" and not torch.cuda.is_available():
            raise ValueError(f"--device {args.device!r}: CUDA is not available on this machine")
    try:
        sizes = [int(b) for b in args.batch_sizes.split(",")]
    except ValueError:
        sizes = []
    if not sizes or min(sizes) < 1:
        raise ValueError(f"--batch-sizes must be comma-separated integers >= 1, got {args.batch_sizes!r}")


def run(args: argparse.Namespace) -> int:
    check_arguments(args)
    if args.threads:
        torch.set_num_threads(args.threads)
    devices = [args.device] if args.device else ["cpu"] + (["cuda"] if torch.cuda.is_available() else [])
    for device in devices:
        section = run_benchmarks(
            device=device,
            games=args.games.split(",") if args.games else None,
            batch_sizes=tuple(int(b) for b in args.batch_sizes.split(",")),
            observations=tuple(args.obs.split(",")),
            min_seconds=args.seconds,
            levels=args.levels,
        )
        section += _peers(args, device) + _generic(args, device) + _jobs(args, device)
        body = section.text + "".join(line + "\n" for line in target_lines(section.checks))
        print(body)
        if args.output:
            write_section(args.output, torch.device(device).type, body)
            print(f"updated {args.output}")
    return 0


def _peers(args: argparse.Namespace, device: str) -> Section:
    """The peers on the CPU (the extra is CPU JAX): XLand-MiniGrid and Griddly beside Zelda tiles,
    VGDLx beside each game it plays."""
    if args.no_peers or torch.device(device).type != "cpu" or "tiles" not in args.obs.split(","):
        return Section()
    games = tuple(args.games.split(",")) if args.games else GAMES
    sizes = tuple(int(b) for b in args.batch_sizes.split(","))
    section = peers_report(sizes, args.seconds) if "zelda" in games else Section()
    return section + vgdlx_section(games, sizes, args.seconds)


def _generic(args: argparse.Namespace, device: str) -> Section:
    """The generic VGDL step beside each hand-written engine, on the CPU (where its tick compiles)."""
    if args.no_generic or torch.device(device).type != "cpu":
        return Section()
    games = args.games.split(",") if args.games else None
    sizes = tuple(int(b) for b in args.batch_sizes.split(","))
    return generic_section(games, sizes, args.seconds)


def _jobs(args: argparse.Namespace, device: str) -> Section:
    """The evaluation protocol and the short training job, on the CPU."""
    if args.no_jobs or torch.device(device).type != "cpu":
        return Section()
    return jobs_section()
