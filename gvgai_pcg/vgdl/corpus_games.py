"""GVGAI corpus games played as registered games: ``GVGAIEnv("painter")``, their Gymnasium ids,
``gvgai-pcg play --game painter``.

GVGAI's own VGDL files are not in this repository, so a corpus game is registered only while the
corpus folder (``GVGAI_VGDL_DIR``, ``gvgai_pcg.vgdl.corpus``) holds its file, and only if the
generic step runs it: a registered game is one every env, test and tool can play. Its human
levels are that folder's ``<file>_lvl0..4.txt``, its level legend the file's LevelMapping, its
rules the generic step on the file. Asking for one that is not registered is refused in one line
(``refusal``): what to set without the folder, else why the file cannot be played (the feature
it needs, naming the file and the line). Finding them parses the files and imports no torch.
"""

from __future__ import annotations

from pathlib import Path

from gvgai_pcg.games.spec import GameSpec, LevelFormat
from gvgai_pcg.vgdl.corpus import ENV_VAR, corpus_dir
from gvgai_pcg.vgdl.errors import VGDLError
from gvgai_pcg.vgdl.layout import is_avatar
from gvgai_pcg.vgdl.parser import parse_file
from gvgai_pcg.vgdl.support import check_supported

# Corpus games the generic step plays as Java does (each held to Java traces,
# tests/data/vgdl_corpus_traces): those that need no VGDL feature the four study games lack
# (CORPUS.md, "Staging"), then labyrinth and labyrinthdual, which need only Timeout, and those
# that bounceForward, killBoth and undoAll complete (the Sokoban family, colourescape with its
# avatar's transforms; escape with Timeout); the file stems, as GVGAI spells them. A game's
# registered name is its stem in lower case.
CORPUS_GAMES = (
    "camelRace",
    "infection",
    "painter",
    "racebet",
    "racebet2",
    "zenpuzzle",
    "labyrinth",
    "labyrinthdual",
    "bait",
    "colourescape",
    "escape",
    "realsokoban",
    "sokoban",
    "thesnowman",
    "watergame",
)
HUMAN_LEVELS = 5

_FILES: dict[str, Path] = {}  # registered name -> its VGDL file, for the rules' import path


def game_name(stem: str) -> str:
    """The registered name of corpus file ``stem`` (``camelRace`` -> ``camelrace``)."""
    return stem.lower()


def game_title(stem: str) -> str:
    """Its title, the Gymnasium id's name (``camelRace`` -> ``CamelRace``: gvgai_pcg/CamelRace-v0)."""
    return stem[0].upper() + stem[1:]


def corpus_spec(path: Path) -> GameSpec:
    """The spec of the corpus game in ``path``, whose ``<stem>_lvl0..4.txt`` lie beside it."""
    description = parse_file(path)
    stem, name = path.stem, game_name(path.stem)
    levels = [path.with_name(f"{stem}_lvl{index}.txt") for index in range(HUMAN_LEVELS)]
    missing = [level.name for level in levels if not level.is_file()]
    if missing:
        raise ValueError(f"{path.parent}: {stem}'s human levels {', '.join(missing)} are missing")
    sizes = [_size(level) for level in levels]
    mapping = description.level_mapping
    avatars = {type_name for type_name, sprite in description.types.items() if is_avatar(sprite)}
    level_format = LevelFormat(
        name,
        "".join(mapping),
        "".join(char for char, types in mapping.items() if avatars.intersection(types)),
        height=max(height for height, _ in sizes),
        width=max(width for _, width in sizes),
    )
    _FILES[name] = path
    return GameSpec(
        name=name,
        title=game_title(stem),
        level_format=level_format,
        rules=f"{__name__}:{name}",
        human_levels=HUMAN_LEVELS,
        human_level_files=str(path.with_name(f"{stem}_lvl{{index}}.txt")),
    )


def _size(level: Path) -> tuple[int, int]:
    rows = level.read_text(encoding="utf-8").replace("\r\n", "\n").rstrip("\n").split("\n")
    return len(rows), max(map(len, rows))


def playable_spec(path: Path) -> GameSpec:
    """``corpus_spec`` of a file whose every feature the generic step implements
    (``gvgai_pcg.vgdl.support``, pure Python: listing the games imports no torch); the refusal
    (``VGDLError``) naming the first missing one otherwise. What only the engine's own checks
    find is refused, in one line, where the game's rules are first asked for (``get_game``)."""
    spec = corpus_spec(path)
    try:
        check_supported(parse_file(path))
    except VGDLError:
        del _FILES[spec.name]
        raise
    return spec


def SPECS() -> list[GameSpec]:  # noqa: N802 (the registry's name for a provider's specs)
    """The specs of the corpus games of the folder that the generic step runs; none without a
    folder, or when the folder is unusable (``refusal`` says why when such a game is asked for)."""
    try:
        folder = corpus_dir()
    except ValueError:
        return []
    if folder is None:
        return []
    specs = []
    for stem in CORPUS_GAMES:
        try:
            specs.append(playable_spec(folder / f"{stem}.txt"))
        except (OSError, ValueError, VGDLError):
            continue
    return specs


def corpus_file(name: str) -> Path | None:
    """The VGDL file of registered corpus game ``name``; None for any other game."""
    return _FILES.get(name)


def refusal(name: str) -> str | None:
    """Why corpus game ``name`` is not registered, in one line; None for another name. A game of
    the folder that is not among ``CORPUS_GAMES`` is refused with the first feature the engine
    lacks, or, where it has them all, as not yet verified against Java."""
    stem = next((stem for stem in CORPUS_GAMES if game_name(stem) == name), None)
    if stem is None:
        return _unlisted_refusal(name)
    need = f"set {ENV_VAR} to a folder holding GVGAI's {stem}.txt and {stem}_lvl0..4.txt"
    try:
        folder = corpus_dir()
        if folder is None:
            return f"game {name!r} is a GVGAI corpus game, not shipped with this package: {need}"
        playable_spec(folder / f"{stem}.txt")
    except VGDLError as error:
        return f"game {name!r} cannot be played yet: {error}"
    except (OSError, ValueError) as error:
        return f"game {name!r}: {error} ({need})"
    return None


def _unlisted_refusal(name: str) -> str | None:
    try:
        folder = corpus_dir()
    except ValueError:
        return None
    if folder is None:
        return None
    path = next(
        (path for path in folder.glob("*.txt") if "_lvl" not in path.stem and game_name(path.stem) == name),
        None,
    )
    if path is None:
        return None
    try:
        check_supported(parse_file(path))
    except VGDLError as error:
        return f"game {name!r} cannot be played yet: {error}"
    return (
        f"game {name!r} ({path}) has every feature the engine implements but is not verified against Java yet"
    )


def __getattr__(name: str) -> type:
    """A corpus game's rules (``GameSpec.rules`` names them ``gvgai_pcg.vgdl.corpus_games:<name>``):
    the generic step's class for its file; a game the engine cannot run is refused here."""
    if name not in _FILES:
        raise AttributeError(name)
    from gvgai_pcg.vgdl.engine import VGDLGame

    return type(VGDLGame.from_file(_FILES[name], name=name))
