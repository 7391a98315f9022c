"""The study's Table 1 as data (Justesen et al., 2018), and cells normalised between its own
Random and Max rows.

Source: ``shared/study/TABLE1.md`` (the paper's Table 1 as printed): mean score over 120 test
episodes per cell (4 models x 30 episodes; Solarfox PPCG 3 models, PCG 1 one). The paper gives no
per-seed values, so a cell is a point estimate. One correction: the paper's Boulderdash Max row
is wrong in all seven columns, and is the package's Max formula here (``Game.max_score``: 2 per
diamond, at most 10, plus a butterfly's): 22 on every human level (the paper prints 48-58), and
on the generated sets the formula's mean over 10,000 levels of the generator at d = 0.5 and d = 1
(seeds 0-9999; a set of 30 levels moves it by about 0.2 at d = 0.5 and 0.3 at d = 1), 21.51 and
25.73, where the paper prints 31.50 and 29.80: no level at d = 0.5 allows more than 24, and the
printed row has d = 0.5 above d = 1, where the generator puts more butterflies. The printed
values are kept in ``BOULDERDASH_PRINTED_MAX``.
"""

from __future__ import annotations

from collections.abc import Mapping

TEST_SETS = ("pcg0.5", "pcg1", "lv0", "lv1", "lv2", "lv3", "lv4")
GENERATED_SETS = TEST_SETS[:2]
HUMAN_SETS = TEST_SETS[2:]
BOULDERDASH_HUMAN_MAX = 22.0
# the Max formula's mean over 10,000 generated levels at d = 0.5 and d = 1 (module docstring)
BOULDERDASH_GENERATED_MAX = (21.51, 25.73)
BOULDERDASH_PRINTED_MAX = (31.50, 29.80, 48.00, 52.00, 58.00, 48.00, 44.00)


def _row(*cells: float) -> dict[str, float]:
    return dict(zip(TEST_SETS, cells, strict=True))


# game -> row label -> test set -> mean score, in the paper's order. Condition labels are the
# report's (``Lv 0``, ``PCG 1``, ...); Zelda's longer runs carry their frames (``PCG 1 (100M)``).
TABLE1: dict[str, dict[str, dict[str, float]]] = {
    "zelda": {
        "Max": _row(4.40, 6.87, 8.00, 8.00, 8.00, 10.00, 8.00),
        "Random": _row(0.38, 0.22, 0.26, 0.17, -0.11, -0.07, 0.18),
        "Lv 0": _row(0.28, 0.51, 6.97, -0.45, -0.53, 0.07, -0.58),
        "Lv 4": _row(0.56, 0.07, -0.51, 0.99, 0.04, -0.35, 5.93),
        "Lv 0-3": _row(1.98, 2.37, 6.95, 7.17, 7.20, 8.17, 1.91),
        "PCG 0.5": _row(3.45, 4.00, 2.21, 2.28, 0.92, 2.27, 0.15),
        "PCG 1": _row(0.27, 3.56, 2.40, 1.37, 1.49, 2.88, -0.62),
        "PPCG": _row(3.44, 4.28, 2.67, 3.35, 2.43, 1.89, 0.96),
        "PCG 1 (100M)": _row(3.05, 4.38, 2.49, 1.54, 1.18, 2.04, -0.29),
        "PPCG (100M)": _row(3.82, 4.51, 2.71, 3.74, 2.84, 1.90, 0.88),
    },
    "solarfox": {
        "Max": _row(30.83, 51.83, 32.00, 32.00, 34.00, 70.00, 62.00),
        "Random": _row(-3.68, -4.55, -5.49, -4.80, -5.41, 2.03, 1.13),
        "PCG 1": _row(20.70, 32.43, 22.00, 21.83, 26.00, 43.96, 28.16),
        "PPCG": _row(16.08, 21.40, 16.87, 10.26, 12.02, 27.37, 20.00),
    },
    "frogs": {
        "Max": _row(1.00, 1.00, 1.00, 1.00, 1.00, 1.00, 1.00),
        "Random": _row(0.01, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00),
        "PCG 1": _row(0.01, 0.00, 0.00, 0.00, 0.00, 0.00, 0.00),
        "PPCG": _row(0.81, 0.57, 0.00, 0.00, 0.00, 0.00, 0.00),
    },
    "boulderdash": {
        "Max": _row(*BOULDERDASH_GENERATED_MAX, *(BOULDERDASH_HUMAN_MAX,) * 5),
        "Random": _row(6.29, 3.71, 0.85, 2.58, 3.5, 0.65, 2.66),
        "PCG 1": _row(14.63, 8.32, 5.39, 10.28, 5.85, 5.08, 8.27),
        "PPCG": _row(11.78, 4.86, 3.44, 0.98, 0.68, 0.41, 3.32),
    },
}
# Training frames of the study's rows ("steps" in the paper, no frame skip).
STUDY_FRAMES = {"zelda": 60_000_000, "solarfox": 40_000_000, "frogs": 40_000_000, "boulderdash": 60_000_000}
# Episodes behind every cell of the study (4 models x 30).
STUDY_EPISODES = 120
# What the study's Figure 2 and text say of PPCG's difficulty in training: the highest d reached.
# Zelda and Frogs reach d = 1; Boulderdash "stops near d = 0.2"; Solarfox never reaches the
# hardest levels (its highest d is not stated: below 1 is all the rules use).
STUDY_REACHED = {"zelda": 1.0, "frogs": 1.0, "boulderdash": 0.2, "solarfox": None}

NORMALISATION_ROWS = ("Max", "Random")


def normalise(rows: Mapping[str, Mapping[str, float]]) -> dict[str, dict[str, float]]:
    """Every condition row of ``rows`` (one game's table: ``Max``, ``Random`` and conditions)
    as ``(score - random) / (max - random)`` per test set, with the table's own Max and Random
    rows: 0 is the random agent, 1 the maximum. A set whose gap is not positive is left out."""
    maximum, random = rows["Max"], rows["Random"]
    normalised: dict[str, dict[str, float]] = {}
    for label, cells in rows.items():
        if label in NORMALISATION_ROWS:
            continue
        normalised[label] = {
            test_set: (score - random[test_set]) / (maximum[test_set] - random[test_set])
            for test_set, score in cells.items()
            if test_set in maximum and test_set in random and maximum[test_set] > random[test_set]
        }
    return normalised


def study_normalised(game: str) -> dict[str, dict[str, float]]:
    """The study's condition rows of ``game``, normalised with its own Max and Random rows."""
    if game not in TABLE1:
        raise ValueError(f"no study table for game {game!r}; the study's games are {', '.join(TABLE1)}")
    return normalise(TABLE1[game])


LATE_FRAMES = 500_000  # PPCG's difficulty "at the end" of a run: its mean over the last 0.5M frames
