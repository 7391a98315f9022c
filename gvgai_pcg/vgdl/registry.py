"""The VGDL games the package ships: each name with its own description and the levels it plays.

A registered game is one whose description (``descriptions/<name>.txt``, inside the package)
runs through the generic step (``gvgai_pcg.vgdl.engine``). Its levels are those of the
hand-written game of the same rules (``levels``: a registered game of ``gvgai_pcg.games``), so
that both engines play the same level files. GVGAI's own files (``corpus``) are not registered:
they are found in a folder the user names.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

DESCRIPTIONS = Path(__file__).resolve().parent / "descriptions"


@dataclass(frozen=True)
class VGDLEntry:
    """A registered VGDL game: its name, description file and the game whose levels it plays."""

    name: str
    description: Path
    levels: str
    # the order a drawing table's kinds take their random draws, where the hand-written engine keys
    # them otherwise than by subtype order (``VGDLGame.from_text``'s ``draw_order``)
    draw_order: tuple[str, ...] = ()


VGDL_GAMES: dict[str, VGDLEntry] = {
    entry.name: entry
    for entry in (
        VGDLEntry("zelda", DESCRIPTIONS / "zelda.txt", levels="zelda"),
        VGDLEntry("frogs", DESCRIPTIONS / "frogs.txt", levels="frogs"),
        VGDLEntry(
            "boulderdash",
            DESCRIPTIONS / "boulderdash.txt",
            levels="boulderdash",
            draw_order=("butterfly", "crab"),
        ),
        VGDLEntry("solarfox", DESCRIPTIONS / "solarfox.txt", levels="solarfox"),
    )
}


def registered_games() -> dict[str, VGDLEntry]:
    """Every registered VGDL game, by name in name order."""
    return dict(sorted(VGDL_GAMES.items()))


def registered_game(name: str) -> VGDLEntry:
    """The entry of ``name``; a one-line error naming the registered games otherwise."""
    if name not in VGDL_GAMES:
        known = ", ".join(registered_games())
        raise ValueError(f"unknown VGDL game {name!r}: the registered ones are {known}")
    return VGDL_GAMES[name]
