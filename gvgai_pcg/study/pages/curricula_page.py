"""The curricula comparison's page: ``docs/results-curricula.md``'s block between
``<!-- curricula:start -->`` and ``<!-- curricula:end -->``, written from the published folder
(``results/curricula``) and the budget's fair folder beside it (``Budget.fair``,
``results/curricula-fair``): the runs, the headline table, the tables and the answer
(``gvgai_pcg.study.verdicts.comparison``, recomputed from the published records), the curves of d
over training and the levels each curriculum replays at the end, and what the levels it holds
contain beside the generator's and the human ones.

A game and curriculum with runs in the fair folder is judged on those; the published runs they
replace stay in a table of the reference setting, never judged. Each game's UED columns are the
budget's protocol (the tail protocol) where any of its judged runs has that record, else the first
protocol's, said so in the block: within a game a run without that record shows as such, never
read from the other protocol.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path

from gvgai_pcg.evaluation.checkpoints import find_runs, run_info
from gvgai_pcg.evaluation.protocol import Protocol
from gvgai_pcg.games.registry import get_game_spec
from gvgai_pcg.generators import get_generator
from gvgai_pcg.levels import human_levels
from gvgai_pcg.rundir.atomic_files import atomic_copy
from gvgai_pcg.study.pages.page import _runs_table, replace_block
from gvgai_pcg.study.pages.ued_by_difficulty import write_solved_by_difficulty
from gvgai_pcg.study.sweeps.borrowed_runs import borrowed_lines
from gvgai_pcg.study.sweeps.conditions import Budget
from gvgai_pcg.study.sweeps.curricula_runs import (
    REPLAY_PICTURE,
    REPLAY_STATS,
    level_count_summary,
    write_curves,
)
from gvgai_pcg.study.verdicts.comparison import (
    CurriculumRuns,
    _order,
    cell,
    collect_runs,
    comparison_markdown,
    tables_markdown,
    ued_record,
)

START, END = "<!-- curricula:start -->", "<!-- curricula:end -->"


# The generated levels the curricula's held levels are set beside: this many at d = 1 per game.
REFERENCE_LEVELS = 100
# The first UED protocol's settings beyond the budget's level count (2 seeds of one episode per
# level): the records of the runs the tail protocol has not evaluated yet.
FIRST_UED = {"seeds": 2}
# The headline UED measures: metric -> column title.
HEADLINE = {
    "solved": "UED solved rate",
    "wincvar10": "UED win-rate CVaR 10 %",
    "cvar10": "UED score CVaR 10 % (beside)",
    "human": "human levels 0-4",
}


def _summary_cells(summary: dict, names: list[str]) -> str:
    counts = summary.get("counts", {})
    cells = [
        f"{counts[name]['median']:g} ({counts[name]['p90']:g}, {counts[name]['max']})"
        if name in counts
        else "-"
        for name in names
    ]
    return " | ".join(cells)


def _reference_summaries(game: str) -> list[tuple[str, dict]]:
    """The human levels' and the generator's at d = 1 (seeds 0 to ``REFERENCE_LEVELS`` - 1)."""
    generate = get_generator(game)
    return [
        (
            f"generator, d = 1 ({REFERENCE_LEVELS} levels)",
            level_count_summary([generate(1.0, seed) for seed in range(REFERENCE_LEVELS)]),
        ),
        ("human levels", level_count_summary(human_levels(game))),
    ]


def _held_levels_tables(runs: list, notes: dict[Path, str] | None = None) -> list[str]:
    """Per game, what the levels each replaying curriculum holds at the end contain (its
    ``replay-levels.json``), beside the generator's at d = 1 and the human levels."""
    import json

    notes = notes or {}
    held: dict[str, list[tuple[str, dict]]] = {}
    for info in runs:
        path = info.path / REPLAY_STATS
        if path.is_file():
            summary = json.loads(path.read_text())
            held.setdefault(info.game, []).append(
                (
                    f"{info.label}{notes.get(info.path, '')} seed {info.seed}, {summary['levels']:,} held",
                    summary,
                )
            )
    lines = []
    for game, rows in sorted(held.items()):
        rows = [*rows, *_reference_summaries(game)]
        names = sorted({name for _, summary in rows for name in summary.get("counts", {})})
        lines += [
            "",
            f"{get_game_spec(game).title}: each count of the game's level checks (`GameSpec.counts`), "
            "median (90th percentile, most) over the levels.",
            "",
            "| levels | " + " | ".join(names) + " |",
            "|---|" + "---:|" * len(names),
            *[f"| {label} | {_summary_cells(summary, names)} |" for label, summary in rows],
        ]
    return lines


def _replay_section(runs: list, images: Path, prefix: str, notes: dict[Path, str]) -> list[str]:
    """The replay pictures of the published runs, copied into ``images``, one line each, then the
    tables of what the levels each curriculum holds contain (``notes``: a run's words after its
    curriculum, as the reference setting's)."""
    lines = []
    for info in runs:
        picture = info.path / REPLAY_PICTURE
        if picture.is_file():
            # a reference-setting run shares its folder name with the fair run that replaces it
            setting = "-reference" if notes.get(info.path) else ""
            name = f"replay-{info.path.name}{setting}.png"
            atomic_copy(picture, images / name)
            lines.append(
                f"- {info.game}, {info.label}{notes.get(info.path, '')} (seed {info.seed}): "
                f"![levels it replays]({prefix}/{name})"
            )
    if not lines:
        return ["No run's curriculum replays levels yet (PCG 1, PPCG and DR play a new level every episode)."]
    return lines + _held_levels_tables(runs, notes)


def _runs_of(folder: Path | None) -> list[Path]:
    runs_dir = folder / "runs" if folder is not None else None
    return find_runs([runs_dir]) if runs_dir and runs_dir.is_dir() and any(runs_dir.iterdir()) else []


def _ued_settings(budget: Budget, runs: list[Path]) -> tuple[dict, str]:
    """The UED protocol one game's runs are read on, and its name: the budget's where any run has
    its record, else the first protocol's."""
    if not budget.ued:
        return {}, "no UED protocol"
    if any(ued_record(run, budget.ued) for run in runs) or "rank_episodes" not in budget.ued:
        return budget.ued, "the tail protocol" if "rank_episodes" in budget.ued else "the UED protocol"
    return {"levels": budget.ued["levels"], **FIRST_UED}, "the first protocol"


def _collect(runs: list[Path], budget: Budget, settings: dict[str, dict]) -> dict:
    """``collect_runs`` per game, each on its own UED settings."""
    games: dict[str, dict[str, CurriculumRuns]] = {}
    for game, ued in settings.items():
        ours = [run for run in runs if run_info(run).game == game]
        games.update(collect_runs(ours, Protocol(**budget.protocol), ued))
    return games


def _protocol_text(budget: Budget, name: str) -> str:
    ued = budget.ued
    if name == "the tail protocol":
        return (
            f"the tail protocol ({ued['levels']:,} levels, {ued['rank_episodes']} episodes to rank and "
            f"{ued['score_episodes']} to score each)"
        )
    if name == "the first protocol":
        return (
            f"the first protocol ({ued['levels']:,} levels, {FIRST_UED['seeds']} seeds of one episode each)"
        )
    return name


def _headline(games: dict, protocols: dict[str, str], budget: Budget) -> list[str]:
    """Per game, the headline UED measures of each judged curriculum over seeds."""
    lines = [
        "Each cell: the mean over seeds with its 95 % Student t interval over seeds (not over levels) in "
        "brackets; `-`: no run of the row has the measure (the first protocol ranks levels by one "
        "episode, so its records carry no win-rate CVaR).",
    ]
    for game, curricula in sorted(games.items()):
        lines += [
            "",
            f"{game.capitalize()}, UED columns on {_protocol_text(budget, protocols[game])}:",
            "",
            "| curriculum | seeds | " + " | ".join(HEADLINE.values()) + " |",
            "|---|---:|" + "---:|" * len(HEADLINE),
        ]
        for runs in sorted(curricula.values(), key=_order):
            cells = " | ".join(cell(runs.values.get(metric)) for metric in HEADLINE)
            lines.append(f"| {runs.label} | {len(runs.frames)} | {cells} |")
    return lines


def _missing_lines(runs: list[Path], settings: dict[str, dict], protocols: dict[str, str]) -> list[str]:
    """The judged runs without their game's UED record, by name."""
    missing = [
        run
        for run in runs
        if settings.get(run_info(run).game) and ued_record(run, settings[run_info(run).game]) is None
    ]
    if not missing:
        return []
    return [
        "Runs without their game's UED record (their UED cells are left out, not read from another "
        "protocol): "
        + ", ".join(f"`{run.name}` ({protocols[run_info(run).game]})" for run in sorted(missing))
        + ".",
        "",
    ]


def curricula_block(published: Path, budget: Budget, images: Path, prefix: str, commit: str) -> str:
    """The page's block from ``published`` and the budget's fair folder beside it; figures go to
    ``images``, linked as ``prefix/<name>``."""
    fair_folder = published.parent / budget.fair if budget.fair else None
    fair = _runs_of(fair_folder)
    fair_keys = {(run_info(run).game, run_info(run).label) for run in fair}
    old = _runs_of(published)
    reference = [run for run in old if (run_info(run).game, run_info(run).label) in fair_keys]
    runs = sorted([run for run in old if run not in reference] + fair)
    infos = [run_info(run) for run in runs]
    images.mkdir(parents=True, exist_ok=True)
    stale_figures = ("curricula-curves-*.png", "replay-*.png", "ued-solved-by-d-*.png")
    for stale in [path for pattern in stale_figures for path in images.glob(pattern)]:
        stale.unlink()
    settings, protocols = {}, {}
    for game in sorted({info.game for info in infos}):
        settings[game], protocols[game] = _ued_settings(
            budget, [run for run in runs if run_info(run).game == game]
        )
    games = _collect(runs, budget, settings)
    reference_games = _collect(
        reference,
        budget,
        {
            game: _ued_settings(budget, [r for r in reference if run_info(r).game == game])[0]
            for game in {run_info(r).game for r in reference}
        },
    )
    reference_protocols = {
        game: _ued_settings(budget, [r for r in reference if run_info(r).game == game])[1]
        for game in reference_games
    }
    fair_regimens = {run_info(run).regimen["name"]: run_info(run).label for run in fair}
    awaiting = sorted(
        {
            (info.game, info.label)
            for info in map(run_info, old)
            if info.regimen["name"] in fair_regimens and (info.game, info.label) not in fair_keys
        }
    )
    borrowed = borrowed_lines(old)
    labelled = [(info.game, info.label, info.path) for info in infos]
    curves = write_curves(labelled, images)
    by_difficulty = [
        path
        for game, ued in settings.items()
        for path in write_solved_by_difficulty([row for row in labelled if row[0] == game], ued, images)
    ]
    machine = f"{platform.machine()} Linux, {os.cpu_count()} cores, torch CPU, one torch thread per run"
    ued = "; ".join(f"{game}: {name}'s UED records" for game, name in protocols.items()) or "no UED protocol"
    fair_text = (
        f" and its fair folder `{fair_folder}` (the budget's `fair`: its runs replace the published "
        "runs of the same game and curriculum in the answer)"
        if fair
        else ""
    )
    setting = []
    if reference_games:
        setting += [
            "#### The reference setting (shown, never judged)",
            "",
            "The published runs the fair folder's replace (the references' 4,000-level buffer, ACCEL's "
            "editor unbounded), UED columns on "
            + ", ".join(
                f"{game.capitalize()}: {_protocol_text(budget, name)}"
                for game, name in sorted(reference_protocols.items())
            )
            + ".",
            "",
            tables_markdown(reference_games),
        ]
    waiting = (
        [
            "Awaiting retraining at the fair setting (shown and judged here at the reference setting): "
            + ", ".join(f"{game.capitalize()} {label}" for game, label in awaiting)
            + ".",
            "",
        ]
        if awaiting
        else []
    )
    return "\n".join(
        [
            START,
            f"Data: `{published}`{fair_text}; budget `{budget.name}`; commit `{commit}` of the code that "
            f"evaluated it, and trained every run whose own record below names no other; {machine}; {ued}.",
            "",
            "### Runs",
            "",
            _runs_table(published, budget.frames_range[0]) if old else "No runs published yet.",
            "",
            *(
                [
                    f"Runs at the fair setting (`{fair_folder}`):",
                    "",
                    _runs_table(fair_folder, budget.frames_range[0]),
                    "",
                ]
                if fair
                else []
            ),
            *borrowed,
            *([""] if borrowed else []),
            "### The headline: the UED levels' tail",
            "",
            *(_headline(games, protocols, budget) if games else ["No run evaluated yet."]),
            "",
            *_missing_lines(runs, settings, protocols),
            *waiting,
            "### Scores and the answer",
            "",
            comparison_markdown(games) if games else "No run evaluated yet.",
            *setting,
            "### The UED levels solved, by difficulty",
            "",
            f"Each run's {budget.ued.get('levels', 0):,} UED levels binned by d, on its game's UED "
            "protocol (every evaluation seed or episode of a level counts): where each curriculum's "
            "tail lies."
            if by_difficulty
            else "No run has per-level UED records yet.",
            "",
            *[f"![{path.stem}]({prefix}/{path.name})" for path in by_difficulty],
            "",
            "### Curves over training",
            "",
            *(
                [f"![{path.stem}]({prefix}/{path.name})" for path in curves]
                or ["No curriculum logged d yet."]
            ),
            "",
            "### Levels each curriculum replays at the end",
            "",
            *_replay_section(
                sorted([*infos, *map(run_info, reference)], key=lambda info: info.path.name),
                images,
                prefix,
                {run_info(run).path: " (reference setting)" for run in reference},
            ),
            END,
        ]
    )


def write_curricula_page(page: Path, published: Path, budget: Budget, commit: str) -> Path:
    """Rewrite ``page``'s curricula block from ``published`` (figures in ``images/<page stem>``)."""
    images, prefix = page.parent / "images" / page.stem, f"images/{page.stem}"
    return replace_block(page, curricula_block(published, budget, images, prefix, commit), START, END)
