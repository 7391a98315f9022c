"""``gvgai-pcg generate``: levels from the constructive generators, printed or written as files.

``--difficulty`` takes one value or a sweep ``start:stop:step`` (stop included); for each
difficulty, ``--count`` levels with seeds ``seed .. seed+count-1``. With ``--out`` the levels are
written as text files, and with ``--png`` also as pictures drawn with the game's tile art.
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

from gvgai_pcg.generators import check_difficulty, generate_level, registered_generators
from gvgai_pcg.levels.level import Level

MAX_SWEEP = 10_001  # difficulties in one sweep (0:1:0.0001)


def difficulties(spec: str) -> list[float]:
    """``"0.5"`` -> [0.5]; ``"0:1:0.25"`` -> [0, 0.25, 0.5, 0.75, 1] (stop included)."""
    parts = spec.split(":")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"difficulty must be a number or start:stop:step, got {spec!r}"
        ) from None
    if not all(math.isfinite(value) for value in values):
        raise argparse.ArgumentTypeError(
            f"difficulty must be a finite number or start:stop:step of finite numbers, got {spec!r}"
        )
    if len(values) == 1:
        sweep = values
    elif len(values) == 3 and values[2] > 0 and values[0] <= values[1]:
        start, stop, step = values
        try:
            check_difficulty(start), check_difficulty(stop)
        except ValueError as error:
            raise argparse.ArgumentTypeError(str(error)) from None
        steps = int((stop - start) / step + 1e-9)
        if steps >= MAX_SWEEP:
            raise argparse.ArgumentTypeError(
                f"a difficulty sweep has at most {MAX_SWEEP:,} values, got {steps + 1:,} from {spec!r}"
            )
        sweep = [round(start + i * step, 10) for i in range(steps + 1)]
    else:
        raise argparse.ArgumentTypeError(
            f"a difficulty sweep is start:stop:step with start <= stop and step > 0, got {spec!r}"
        )
    try:
        return [check_difficulty(d) for d in sweep]
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--game", required=True, choices=registered_generators())
    parser.add_argument(
        "--difficulty",
        type=difficulties,
        default=[1.0],
        help="d in [0, 1], or a sweep start:stop:step with stop included (default 1)",
    )
    parser.add_argument("--count", type=int, default=1, help="levels per difficulty (default 1)")
    parser.add_argument("--seed", type=int, default=0, help="first seed; level i uses seed+i (default 0)")
    parser.add_argument("--out", type=Path, help="write <name>.txt files here instead of printing")
    parser.add_argument("--png", action="store_true", help="with --out, also write <name>.png pictures")


def write_level(level: Level, out: Path) -> Path:
    """Write ``level`` as ``<out>/<name>.txt`` whole or not at all (a full disk leaves no empty or
    cut file behind); returns the path. ``OSError`` naming the file when it cannot be written."""
    path = out / f"{level.name}.txt"
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        tmp.write_text(str(level))
        os.replace(tmp, path)
    except OSError as error:
        tmp.unlink(missing_ok=True)
        raise OSError(error.errno, f"{path} could not be written ({error.strerror or error})") from error
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


def run(args: argparse.Namespace) -> int:
    if args.count < 1 or args.seed < 0:
        raise ValueError(f"--count must be >= 1 and --seed >= 0, got --count {args.count} --seed {args.seed}")
    if args.png and args.out is None:
        raise ValueError("--png needs --out DIR")
    if args.out is not None:
        if args.out.exists() and not args.out.is_dir():
            raise ValueError(f"--out {args.out}: a file; expected a folder for the level files")
        args.out.mkdir(parents=True, exist_ok=True)
    for difficulty in args.difficulty:
        for seed in range(args.seed, args.seed + args.count):
            level = generate_level(args.game, difficulty, seed)
            if args.out is None:
                print(f"# game={args.game} d={difficulty:g} seed={seed}")
                print(level, end="")
            else:
                print(write_level(level, args.out))
                if args.png:
                    from gvgai_pcg.generators.pictures import write_png

                    print(write_png(level, args.out / f"{level.name}.png"))
    return 0
