"""The speed targets beside the figures of the same ``make bench`` run: met or missed.

Figures on these shared 2-core machines move by a quarter between runs, so a target is a ratio of
two figures taken in the same run (ours against a peer, a job against its eager twin), or a wall
time, never a figure against one remembered from another day, except the one target set that
way (every game at 64 envs against its baseline figure: the speed-up asked for is over that
commit). Each measuring section hands back its :class:`Check` values with its text; the command
gathers them into one table at the end.
"""

from __future__ import annotations

from dataclasses import dataclass, field

# Tiles steps/s at B = 64 of main @ 29e65d2 (quiet machine, 2 torch threads), the `make bench`
# whose table docs/history/benchmarks-notebook.md keeps ("A graph of its own for large batches"):
# the target is 1.5x each.
BASELINE_AT_64 = {"zelda": 114_667, "solarfox": 80_291, "boulderdash": 90_635, "frogs": 39_077}
SPEEDUP_OVER_BASELINE = 1.5
DOORKEY_BARE_AT_64 = 1.0  # Zelda tiles at 64 envs against XLand-MiniGrid's DoorKey-8x8 bare step
GRIDDLY_AT_4096 = 10.0  # Zelda tiles at 4,096 envs against Griddly's one Zelda env
VGDLX_AT = {64: 3.0, 4096: 20.0}  # every game against VGDLx at the same batch size
PROTOCOL_SECONDS = 30.0  # the study's protocol on one run, wall seconds on 2 cores
TRAINING_OVER_EAGER = 1.3  # a 20k-frame training job (warm inductor cache) against compiling off


@dataclass(frozen=True)
class Check:
    """One target: ``measured`` against ``goal`` (at least, or ``at_most``); ``None`` when the
    run did not measure it (a peer not installed, a section left out)."""

    what: str
    goal: float
    measured: float | None
    unit: str = "x"  # "x": a ratio; "s": seconds
    at_most: bool = False

    @property
    def met(self) -> bool | None:
        if self.measured is None:
            return None
        return self.measured <= self.goal if self.at_most else self.measured >= self.goal

    def row(self) -> str:
        bound = "at most" if self.at_most else "at least"
        verdict = {True: "met", False: "missed", None: "not measured"}[self.met]
        measured = "-" if self.measured is None else _figure(self.measured, self.unit)
        return f"| {self.what} | {bound} {_figure(self.goal, self.unit)} | {measured} | {verdict} |"


def _figure(value: float, unit: str) -> str:
    return f"{value:.2f}x" if unit == "x" else f"{value:,.1f} s"


@dataclass
class Section:
    """A measured part of the bench: its Markdown and the targets it measured."""

    text: str = ""
    checks: list[Check] = field(default_factory=list)

    def __add__(self, other: Section) -> Section:
        return Section(self.text + other.text, self.checks + other.checks)


def ratio(ours: float, peer: float) -> float | None:
    return ours / peer if peer > 0 else None


def env_checks(tiles_at_64: dict[str, float]) -> list[Check]:
    """Every game's tiles steps/s at B = 64 of this run against its baseline figure."""
    return [
        Check(
            f"{game} tiles at B = 64 / its figure at 29e65d2 ({BASELINE_AT_64[game]:,})",
            SPEEDUP_OVER_BASELINE,
            ratio(rate, BASELINE_AT_64[game]),
        )
        for game, rate in tiles_at_64.items()
        if game in BASELINE_AT_64
    ]


def target_lines(checks: list[Check]) -> list[str]:
    """The Markdown table of every target the run measured (or skipped), in the order given."""
    if not checks:
        return []
    met = sum(check.met is True for check in checks)
    return [
        "",
        "### Speed targets (ratios from this run)",
        "",
        f"{met} of {len(checks)} met.",
        "",
        "| target | goal | measured | |",
        "|---|---:|---:|:-:|",
        *(check.row() for check in checks),
    ]
