"""``gvgai-pcg analyze``: where the human levels fall among generated ones (PCA + DBSCAN).

Generates ``--count`` levels per difficulty (seeds ``seed .. seed+count-1``) or reads a folder of
level files, adds the game's five human levels, and writes to ``--out``: the PCA scatter
(``<game>_pca.png``, coloured by cluster, or by difficulty when several are given), the cluster
representatives and human levels drawn (``<game>_levels.png``), a JSON summary
(``<game>_pca.json``) and a Markdown summary (``<game>_pca.md``).

The analysis, generators and plotting are imported inside ``run``: ``gvgai-pcg`` builds every
command's parser on each call, and scikit-learn, SciPy and matplotlib take seconds to import.
"""

from __future__ import annotations

import argparse
import json
import re
import time
from pathlib import Path

from gvgai_pcg.commands.folders import refuse_files_for_folders
from gvgai_pcg.generators import check_difficulty, generate_level
from gvgai_pcg.levels import LEVEL_FORMATS, Level, human_levels
from gvgai_pcg.levels.human import check_named_game

DIFFICULTY_IN_NAME = re.compile(r"_d(?:if)?(\d+(?:\.\d+)?)(?:_|$)")


def difficulty_list(spec: str) -> list[float]:
    """``"1"`` -> [1.0]; ``"0,0.5,1"`` -> [0.0, 0.5, 1.0]; each value must be in [0, 1]."""
    try:
        return [check_difficulty(float(part)) for part in spec.split(",") if part.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"difficulty must be a number in [0, 1] or a comma-separated list of them, got {spec!r}"
        ) from None


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--game", required=True, choices=sorted(LEVEL_FORMATS))
    parser.add_argument(
        "--count", type=int, default=1000, help="generated levels per difficulty (default 1000)"
    )
    parser.add_argument(
        "--difficulty",
        type=difficulty_list,
        default=[1.0],
        help="d in [0, 1] or a comma-separated list; a list colours the scatter by difficulty (default 1)",
    )
    parser.add_argument("--seed", type=int, default=0, help="first level seed, also the PCA solver's seed")
    parser.add_argument(
        "--levels", type=Path, help="read the generated levels from this folder of .txt files"
    )
    parser.add_argument("--eps", type=float, default=0.5, help="DBSCAN eps on the PCA plane (default 0.5)")
    parser.add_argument("--min-samples", type=int, default=10, help="DBSCAN min_samples (default 10)")
    parser.add_argument(
        "--encoding",
        choices=("study", "complete"),
        default="study",
        help="the study's tilesets, or every sprite type of the legend except floor",
    )
    parser.add_argument("--out", type=Path, default=Path("runs/analysis"), help="output folder")


def level_files(folder: Path) -> list[Path]:
    """The ``.txt`` files of ``--levels``; ``ValueError`` (one line) for a missing path, a file, or
    a folder without any."""
    if not folder.exists():
        raise ValueError(f"--levels {folder}: no such folder")
    if not folder.is_dir():
        raise ValueError(f"--levels {folder}: a file; expected a folder of .txt level files")
    paths = sorted(folder.glob("*.txt"))
    if not paths:
        raise ValueError(f"--levels {folder}: no .txt level files in this folder")
    return paths


def check_arguments(args: argparse.Namespace) -> None:
    """What can be refused before the analysis imports (seconds of scikit-learn and matplotlib)."""
    if args.levels is not None:
        level_files(args.levels)
    elif args.count < 2:
        raise ValueError(f"--count must be at least 2, got {args.count}")
    if args.min_samples < 1:
        raise ValueError(f"--min-samples must be at least 1, got {args.min_samples}")
    refuse_files_for_folders({"--out": args.out})


def generated_levels(args: argparse.Namespace) -> tuple[list[Level], list[float | None]]:
    """The levels to analyse against the human ones, with each one's difficulty if known."""
    if args.levels is not None:
        paths = level_files(args.levels)
        for path in paths:
            check_named_game(path.stem, args.game)
        levels = [Level.load(path, args.game) for path in paths]
        return levels, [_difficulty_in_name(path.stem) for path in paths]
    check_arguments(args)
    pairs = [(d, seed) for d in args.difficulty for seed in range(args.seed, args.seed + args.count)]
    return [generate_level(args.game, d, seed) for d, seed in pairs], [d for d, _ in pairs]


def _difficulty_in_name(stem: str) -> float | None:
    match = DIFFICULTY_IN_NAME.search(stem)
    return float(match.group(1)) if match else None


def run(args: argparse.Namespace) -> int:
    check_arguments(args)
    from gvgai_pcg.analysis import analyze_levels
    from gvgai_pcg.analysis.figures import representatives_figure, scatter_figure
    from gvgai_pcg.analysis.summary import human_status, markdown_summary

    started = time.perf_counter()
    levels, difficulties = generated_levels(args)
    loaded = time.perf_counter()
    analysis = analyze_levels(
        levels,
        human_levels(args.game),
        difficulties,
        eps=args.eps,
        min_samples=args.min_samples,
        complete=args.encoding == "complete",
        seed=args.seed,
    )
    analysed = time.perf_counter()
    by = "difficulty" if len({d for d in difficulties if d is not None}) > 1 else "cluster"
    scatter = scatter_figure(analysis, args.out / f"{args.game}_pca.png", by=by)
    drawn = representatives_figure(analysis, args.out / f"{args.game}_levels.png")
    finished = time.perf_counter()
    summary = analysis.as_dict()
    summary["seconds"] = {
        "levels": round(loaded - started, 2),
        "analysis": round(analysed - loaded, 2),
        "figures": round(finished - analysed, 2),
        "total": round(finished - started, 2),
    }
    (args.out / f"{args.game}_pca.json").write_text(json.dumps(summary, indent=1) + "\n")
    (args.out / f"{args.game}_pca.md").write_text(
        markdown_summary(analysis, [scatter.name, drawn.name]) + "\n"
    )
    print(
        f"{args.game}: {len(analysis.clusters)} cluster(s), {analysis.noise_count} noise; human levels "
        f"{human_status(analysis)}; distance percentiles "
        f"{', '.join(f'{h.index}: {h.percentile:.1f}' for h in analysis.humans)}; "
        f"{finished - started:.1f} s; written to {args.out}"
    )
    return 0
