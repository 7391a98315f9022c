"""``gvgai-pcg report RUNS...``: the results table and training curves of trained runs.

RUNS are run directories or a Hydra multirun directory. Runs without results for the protocol
are evaluated first (``--no-evaluate`` only reads existing results), the random agent comes from
its cache, and the report is written to ``--out`` (default: ``<first RUNS>/report``, or beside the
run when the first of RUNS is a single run directory): a table per
game as ``results.md``, ``results.csv`` and ``results.html``, and ``curves-<game>.png/.svg``.

``--ued`` adds ``ued.md``: the UED protocol on every run (``--ued-levels``, ``--ued-seeds``), and
per game each curriculum's solved rate, mean score and score CVaR over seeds, with the intervals,
Welch comparisons against ``--baseline`` (PPCG) and Holm correction of the curricula page
(``gvgai_pcg.study.pages.ued_table``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gvgai_pcg.commands.evaluate import (
    add_protocol_arguments,
    add_ued_arguments,
    protocol_from,
    ued_protocol_from,
)
from gvgai_pcg.commands.folders import refuse_files_for_folders
from gvgai_pcg.evaluation.checkpoints import is_run_dir
from gvgai_pcg.report import build_report
from gvgai_pcg.report.render import markdown_table
from gvgai_pcg.study.pages.ued_table import write_ued_table
from gvgai_pcg.study.verdicts.table1 import STUDY_REACHED


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("runs", nargs="+", type=Path, help="run directories or multirun directories")
    parser.add_argument(
        "--out", type=Path, help="report directory (default: <first RUNS>/report, beside it for a single run)"
    )
    parser.add_argument("--no-evaluate", action="store_true", help="use existing results only")
    add_protocol_arguments(parser)
    add_ued_arguments(
        parser, "also the UED protocol's table (ued.md), judged as the curricula page", alphas=False
    )
    parser.add_argument(
        "--baseline",
        default="PPCG",
        metavar="LABEL",
        help="with --ued: the row every curriculum is compared with (default PPCG)",
    )


def run(args: argparse.Namespace) -> int:
    first = args.runs[0]
    out = args.out or (first.parent if is_run_dir(first) else first) / "report"
    refuse_files_for_folders({"--out": out, "--cache-dir": args.cache_dir})
    protocol = protocol_from(args)
    ued = None
    if args.ued:
        ued, _ = ued_protocol_from(args)  # a bad setting is refused before anything is evaluated
    report = build_report(
        args.runs,
        out,
        protocol,
        cache_dir=args.cache_dir,
        evaluate=not args.no_evaluate,
        device=args.device,
        progress=not args.no_progress,
        force=args.force,
        reached_by_game=STUDY_REACHED,
    )
    for table in report.tables:
        print(f"{table.game}\n{markdown_table(table)}\n")
    print(f"report: {report.markdown}, {report.csv}, {report.html}")
    for paths in report.figures.values():
        print("curves: " + ", ".join(map(str, paths)))
    if ued is not None:
        table = write_ued_table(
            args.runs,
            out,
            protocol,
            ued,
            args.baseline,
            evaluate=not args.no_evaluate,
            device=args.device,
            progress=not args.no_progress,
            force=args.force,
        )
        print(f"\n{table.read_text()}\nUED table: {table}")
    return 0
