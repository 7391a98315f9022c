"""Where VGDL games are found: the package's own (``registry``), GVGAI's corpus read from a folder.

GVGAI's 104 grid-physics files are not in this repository. A folder of them is named by
``GVGAI_VGDL_DIR``; without it, ``../shared/vgdl/games/`` beside a source checkout is used
when present. A game is named by a registered name (the package's own description first), its
corpus file's stem (``zelda`` for ``zelda.txt``) or by a path.
"""

from __future__ import annotations

import os
from pathlib import Path

from gvgai_pcg.vgdl.registry import VGDL_GAMES

ENV_VAR = "GVGAI_VGDL_DIR"
_CHECKOUT_DEFAULT = Path(__file__).resolve().parents[2].parent / "shared" / "vgdl" / "games"


def corpus_dir() -> Path | None:
    """The folder of VGDL files in use, or None when there is none."""
    named = os.environ.get(ENV_VAR)
    if named:
        path = Path(named)
        if not path.is_dir():
            raise ValueError(f"{ENV_VAR}={named} is not a folder")
        return path
    return _CHECKOUT_DEFAULT if _CHECKOUT_DEFAULT.is_dir() else None


def vgdl_games() -> dict[str, Path]:
    """Game name -> its VGDL file, in name order (level files ``*_lvlN.txt`` left out)."""
    folder = corpus_dir()
    if folder is None:
        return {}
    files = (path for path in folder.glob("*.txt") if "_lvl" not in path.stem)
    return {path.stem: path for path in sorted(files, key=lambda path: path.stem.lower())}


def find_game(game: str) -> Path:
    """A game's VGDL file from its name or a path; one-line error listing what is known."""
    path = Path(game)
    if path.suffix == ".txt" or os.sep in game:
        if not path.is_file():
            raise ValueError(f"no VGDL file {game}")
        return path
    if game in VGDL_GAMES:
        return VGDL_GAMES[game].description
    games = vgdl_games()
    if game in games:
        return games[game]
    if not games:
        raise ValueError(
            f"unknown VGDL game {game!r}: no corpus folder (set {ENV_VAR} or give a path to a .txt)"
        )
    raise ValueError(f"unknown VGDL game {game!r}: 'gvgai-pcg vgdl list' names the {len(games)} known ones")
