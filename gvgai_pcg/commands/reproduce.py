"""``gvgai-pcg reproduce``: the study from sweep to Table 1 in one command.

``gvgai-pcg reproduce --budget smoke|small|medium|paper`` trains every condition and seed of the budget
(a Hydra multirun of ``gvgai-pcg train``; resumable), evaluates every run with the study's
protocol, writes the report (tables and curves) into ``--out`` and, with ``--publish DIR``,
copies what rebuilds the report into DIR. Running it again continues where it stopped. Extra
arguments are Hydra overrides for every run (e.g. ``hydra.launcher.partition=gpu``).

``--budget curricula`` (and ``curricula-smoke``) runs the curricula comparison the same way:
a condition whose curriculum is not registered yet is refused with one line and the rest run; the
UED protocol evaluates each run where this checkout has it; ``--page docs/results-curricula.md``
writes the comparison's page from the published data. ``--borrow-from SWEEP`` takes the runs that
another sweep trained exactly as this one would (``gvgai_pcg.study.sweeps.borrowed_runs``).

``--conditions`` also takes a user's own conditions: a curriculum plug-in's with each game
(``zelda-<name>``), and those of ``--config-dir DIR`` (``DIR/condition/<name>.yaml``, searched by
every run after the package's configs), so a new curriculum joins the comparison in one command.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

from gvgai_pcg.commands.folders import refuse_files_for_folders
from gvgai_pcg.config_rules import searchpath_dirs, searchpath_override
from gvgai_pcg.study.sweeps.conditions import (
    BUDGETS,
    conditions_of,
    known_conditions,
    unregistered,
    user_conditions,
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--budget", choices=sorted(BUDGETS), default="smoke", help="how much of the study")
    parser.add_argument("--out", type=Path, help="where runs, results and the report go (reproduce/BUDGET)")
    parser.add_argument("--jobs", type=int, default=1, help="runs side by side (basic launcher)")
    parser.add_argument("--launcher", help="a Hydra launcher for the sweep (ray, ray_local, slurm, local)")
    parser.add_argument(
        "--conditions",
        help="comma-separated conditions instead of the budget's: the study's, a curriculum plug-in's "
        "(<game>-<name>) or --config-dir's",
    )
    parser.add_argument(
        "--config-dir",
        type=Path,
        metavar="DIR",
        help="a config folder of your own whose condition/<name>.yaml --conditions may name",
    )
    parser.add_argument("--extra", action="store_true", help="also the conditions the study skipped")
    parser.add_argument("--no-train", action="store_true", help="evaluate and report the runs there are")
    parser.add_argument(
        "--finished-only",
        action="store_true",
        help="report only runs at the budget's frames (a report taken while the sweep trains)",
    )
    parser.add_argument("--publish", type=Path, help="copy configs, logs, results and report here")
    parser.add_argument(
        "--page", type=Path, help="with --publish: rewrite the results block of this page (docs/results.md)"
    )
    parser.add_argument(
        "--budget-page",
        action="store_true",
        help="with --publish: rewrite the budget's own page (docs/results.md, docs/results-curricula.md)",
    )
    parser.add_argument(
        "--trained-at",
        metavar="COMMIT",
        help="with --page: the commit that trained and evaluated the runs, when not this checkout's "
        "(runs trained from a worktree at a fixed commit)",
    )
    parser.add_argument(
        "--borrow-from",
        type=Path,
        metavar="SWEEP",
        help="take runs that train exactly as another sweep's (its --out folder) did, at this budget's "
        "frames, instead of training them (the curricula comparison's PCG 1 and PPCG from medium's)",
    )
    parser.add_argument(
        "--seeds",
        type=_seed_list,
        metavar="S,S,...",
        help="the seeds of every condition run (instead of the budget's): more seeds of some "
        "conditions in the same sweep folder, e.g. --conditions solarfox-pcg1 --seeds 0,1,2,3,4,5",
    )
    parser.add_argument(
        "--status",
        action="store_true",
        help="show each planned run's frames and state and the run-hours left, and train nothing",
    )
    parser.add_argument("--no-progress", action="store_true", help="hide progress bars")
    parser.add_argument("overrides", nargs="*", help="Hydra overrides for every run")


def _seed_list(text: str) -> tuple[int, ...]:
    """An argparse type: comma-separated seeds, each a whole number >= 0, none twice."""
    try:
        seeds = tuple(int(part) for part in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated whole numbers, got {text!r}") from None
    if any(seed < 0 for seed in seeds) or len(set(seeds)) != len(seeds):
        raise argparse.ArgumentTypeError(f"expected distinct seeds >= 0, got {text!r}")
    return seeds


def run(args: argparse.Namespace) -> int:
    from gvgai_pcg.study.pipeline import reproduce

    budget = BUDGETS[args.budget]
    conditions = conditions_of(budget, args.extra)
    if args.config_dir is not None:
        if not (args.config_dir / "condition").is_dir():
            raise ValueError(
                f"--config-dir {args.config_dir}: no condition/ folder in it (expected "
                f"{args.config_dir / 'condition' / '<name>.yaml'})"
            )
        args.overrides = [searchpath_override(args.config_dir), *args.overrides]
    search = searchpath_dirs(args.overrides)
    if args.conditions:
        conditions = tuple(c.strip() for c in args.conditions.split(",") if c.strip())
        valid = dict.fromkeys(
            (
                *known_conditions(),
                *budget.conditions,
                *budget.extra,
                *budget.controls,
                *user_conditions(search),
            )
        )
        unknown = sorted(set(conditions) - set(valid))
        if unknown:
            raise ValueError(
                f"unknown condition(s) {', '.join(unknown)}; valid conditions are: " + ", ".join(valid)
            )
    refused = unregistered(conditions, search)
    for line in refused.values():  # a curriculum not merged yet: the rest of the comparison runs
        print(f"refused: {line}")
    conditions = tuple(c for c in conditions if c not in refused)
    if not conditions:
        raise ValueError("no condition left to run: every one's curriculum is not registered")
    if args.jobs < 1:
        raise ValueError(f"--jobs must be at least 1, got {args.jobs}")
    if args.seeds is not None:  # finished runs are kept as they are: only the new seeds train
        budget = replace(
            budget, condition_seeds={**budget.condition_seeds, **dict.fromkeys(conditions, args.seeds)}
        )
    out = args.out or Path("reproduce") / budget.name
    refuse_files_for_folders({"--out": out, "--publish": args.publish, "--borrow-from": args.borrow_from})
    if args.status:
        from gvgai_pcg.study.sweep_status import status_text, sweep_status

        published = Path(args.publish) if args.publish else None
        borrow = Path(args.borrow_from) if args.borrow_from else None
        print(f"reproduce --status: budget {budget.name}, {len(conditions)} conditions, into {out}")
        print(
            status_text(
                sweep_status(budget, conditions, Path(out), args.overrides, published, borrow), args.jobs
            )
        )
        return 0
    low, high = budget.frames_range
    frames = f"{low:,} frames each" if low == high else f"{low:,}-{high:,} frames each"
    runs = sum(len(budget.seeds_of(c)) for c in conditions)
    print(f"reproduce: budget {budget.name}, {len(conditions)} conditions, {runs} runs, {frames}, into {out}")
    outcome = reproduce(
        budget,
        conditions,
        out,
        jobs=args.jobs,
        launcher=args.launcher,
        overrides=args.overrides,
        train=not args.no_train,
        publish_to=args.publish,
        progress=not args.no_progress,
        finished_only=args.finished_only,
        borrow_from=args.borrow_from,
    )
    print(f"runs:   {outcome.runs}")
    print(f"report: {outcome.report / 'results.md'}")
    if outcome.published is not None:
        print(f"published: {outcome.published}")
    if args.budget_page and args.page is None:
        args.page = Path(budget.page)
    if args.page is not None:
        if outcome.published is None:
            raise ValueError("--page needs --publish (the page is written from the published data)")
        from gvgai_pcg.rundir.provenance import code_commit
        from gvgai_pcg.study.pages.curricula_page import write_curricula_page
        from gvgai_pcg.study.pages.page import page_images, write_results_page

        commit = args.trained_at or code_commit()
        if budget.comparison == "curricula":
            write_curricula_page(args.page, outcome.published, budget, commit)
        else:
            images, prefix = page_images(args.page)
            write_results_page(args.page, outcome.published, images, prefix, budget.frames_range[0], commit)
        print(f"page: {args.page}")
    return 0
