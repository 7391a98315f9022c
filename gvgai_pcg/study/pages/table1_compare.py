"""The study's Table 1 beside ours, normalised with each side's own Random and Max rows, and
PPCG's difficulty in training beside what the study's Figure 2 says of it.

Generated into the results page (``gvgai_pcg.study.pages.page``) from the published runs, so the
comparison always says what the data say.
"""

from __future__ import annotations

from collections.abc import Mapping

from gvgai_pcg.study.verdicts.table1 import (
    BOULDERDASH_GENERATED_MAX,
    BOULDERDASH_HUMAN_MAX,
    BOULDERDASH_PRINTED_MAX,
    LATE_FRAMES,
    STUDY_FRAMES,
    STUDY_REACHED,
    TABLE1,
    TEST_SETS,
    study_normalised,
)

AT_RANDOM = 0.05  # a normalised score within 0.05 of 0 counts as "at the random agent"
COLUMNS = {s: s.replace("pcg", "PCG ").replace("lv", "Lv ") for s in TEST_SETS}


def direction(value: float) -> int:
    """+1 above the random agent, -1 below it, 0 at it (within ``AT_RANDOM``)."""
    return 0 if abs(value) <= AT_RANDOM else 1 if value > 0 else -1


def side_by_side(study: Mapping[str, Mapping[str, float]], ours: Mapping[str, Mapping[str, float]]):
    """Per condition both sides have, per test set: (study, ours, directions agree)."""
    rows = {}
    for label, cells in study.items():
        if label not in ours:
            continue
        rows[label] = {
            s: (cells[s], ours[label][s], direction(cells[s]) == direction(ours[label][s]))
            for s in TEST_SETS
            if s in cells and s in ours[label]
        }
    return rows


def _our_normalised(game) -> dict[str, dict[str, float]]:
    return {
        label: {s: game.normalised(label, s) for s in sets if s in game.random and s in game.maximum}
        for label, sets in game.conditions.items()
    }


def side_by_side_markdown(games: Mapping) -> str:
    """For every game both sides have, the normalised cells "study / ours", a cell whose
    direction from the random agent differs marked ✗, and the count of cells that agree."""
    parts = [
        "### The study's Table 1 beside ours",
        "",
        "Each cell is `study / ours`, normalised per test set with each side's own rows: "
        "(score - random) / (max - random), so 0 is the random agent and 1 the maximum (the study's "
        "Boulderdash Max is the package's formula in all seven columns, not the paper's misprinted row: "
        f"{BOULDERDASH_GENERATED_MAX[0]:.2f} / {BOULDERDASH_GENERATED_MAX[1]:.2f} on the generated sets "
        "(its mean over 10,000 generated levels; the paper prints "
        f"{BOULDERDASH_PRINTED_MAX[0]:.2f} / {BOULDERDASH_PRINTED_MAX[1]:.2f}, and no level at d = 0.5 "
        f"allows more than 24) and the rules' cap of {BOULDERDASH_HUMAN_MAX:g} on every human level). ✗: the "
        f"two sides lie on different sides of the random agent (above, below, or within {AT_RANDOM} of "
        "it). The study's rows trained "
        f"{', '.join(f'{game} {frames / 1e6:g}M' for game, frames in STUDY_FRAMES.items())} frames; ours the "
        "frames in the runs table. Our cells are means over seeds.",
    ]
    for name, game in games.items():
        if name not in TABLE1:
            continue
        rows = side_by_side(study_normalised(name), _our_normalised(game))
        if not rows:
            continue
        header = ["condition", *(COLUMNS[s] for s in TEST_SETS)]
        lines = [f"#### {name}", "", "| " + " | ".join(header) + " |", "|---|" + "---:|" * len(TEST_SETS)]
        agree = total = 0
        for label, cells in rows.items():
            texts = []
            for s in TEST_SETS:
                if s not in cells:
                    texts.append("–")
                    continue
                theirs, ours, same = cells[s]
                agree, total = agree + same, total + 1
                texts.append(f"{theirs:.2f} / {ours:.2f}" + ("" if same else " ✗"))
            lines.append(f"| {label} | " + " | ".join(texts) + " |")
        lines += ["", f"Direction from the random agent agrees on {agree} of {total} cells." + _ratios(rows)]
        parts += ["", *lines]
    return "\n".join(parts)


def _ratios(rows) -> str:
    """Ours as a share of the study's normalised score, over the cells where the study is above
    the random agent (a share of a cell near 0 says nothing)."""
    ratios = sorted(
        ours / theirs
        for cells in rows.values()
        for theirs, ours, _ in cells.values()
        if direction(theirs) > 0
    )
    if not ratios:
        return ""
    median = (ratios[(len(ratios) - 1) // 2] + ratios[len(ratios) // 2]) / 2
    return (
        f" Where the study is above it ({len(ratios)} cells), ours reach {median:.2f} of its normalised "
        f"score at the median (from {ratios[0]:.2f} to {ratios[-1]:.2f})."
    )


def _frames(value: float | None) -> str:
    return "never" if value is None else f"{value / 1e6:.2f}M"


def difficulty_markdown(games: Mapping) -> str:
    """PPCG's difficulty per run, from its log up to the evaluated model: the highest d, when it
    first reached d = 0.5 and d = 1, and its mean over the last 0.5M frames; beside what the study
    reports of its own PPCG runs."""

    lines = [
        "### PPCG's difficulty in training",
        "",
        f"From each PPCG run's `log.csv` up to its evaluated model; 'late d' is the mean over its last "
        f"{LATE_FRAMES / 1e6:g}M frames. The study (Figure 2, text): Zelda and Frogs reach d = 1, Solarfox "
        f"never reaches it, Boulderdash stops near d = {STUDY_REACHED['boulderdash']}.",
        "",
        "| game | run | highest d | reached at | first d >= 0.5 | first d = 1 | late d |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    found = False
    for name, game in games.items():
        for i, log in enumerate(game.difficulty.get("PPCG", [])):
            found = True
            lines.append(
                f"| {name} | {i} | {log.highest:.2f} | {_frames(log.first_at(log.highest))} "
                f"| {_frames(log.first_at(0.5))} "
                f"| {_frames(log.first_at(1.0))} | {log.late():.2f} |"
            )
    return "\n".join(lines) if found else ""
