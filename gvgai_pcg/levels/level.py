"""``Level``: one game's level as an immutable rectangular character grid.

A Level is the unit every other part exchanges: generators return one, the engine compiles
batches of them, analysis encodes them. Parsing is strict so that a bad file fails here, with
its file, line and column, and never later inside a batched tick. A ``Level`` built by hand is
held to the same format by ``Level.check``, which the env's level sources run on the levels they
are given, so that a bad one is refused when the env is made.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from gvgai_pcg.levels.formats import LevelFormat, level_format

BOM = "\ufeff"  # the UTF-8 byte-order mark some editors (Notepad) write at the start of a file


class LevelFormatError(ValueError):
    """A level text that is not a valid level of its game.

    ``source``, ``line`` and ``column`` (1-based; ``None`` where the error has no single
    position) say where the problem is.
    """

    def __init__(self, message: str, source: str, line: int | None = None, column: int | None = None) -> None:
        self.source, self.line, self.column = source, line, column
        where = source
        if line is not None:
            where += f", line {line}"
        if column is not None:
            where += f", column {column}"
        super().__init__(f"{where}: {message}")


@dataclass(frozen=True)
class Level:
    """A level of ``game``: ``rows`` are equal-length strings, row 0 at the top."""

    game: str
    rows: tuple[str, ...]
    name: str | None = None  # e.g. "zelda_lvl0"; informative only, not part of equality
    seed: int | None = None  # the generator seed this level came from, if generated

    def __post_init__(self) -> None:
        object.__setattr__(self, "rows", tuple(self.rows))
        # Kept: levels are dict keys at every reset (the compiled-level bank looks up hundreds).
        object.__setattr__(self, "_hash", hash((self.game, self.rows)))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Level) and (self.game, self.rows) == (other.game, other.rows)

    def __hash__(self) -> int:
        return self._hash

    def __reduce__(self) -> tuple:
        # Rebuilt through __init__: the kept hash of str is only valid in the process that made it.
        return (type(self), (self.game, self.rows, self.name, self.seed))

    @property
    def height(self) -> int:
        return len(self.rows)

    @property
    def width(self) -> int:
        return len(self.rows[0])

    @property
    def format(self) -> LevelFormat:
        return level_format(self.game)

    def __str__(self) -> str:
        return "\n".join(self.rows) + "\n"

    def count(self, char: str) -> int:
        """How many cells hold ``char``."""
        return sum(row.count(char) for row in self.rows)

    def find(self, char: str) -> list[tuple[int, int]]:
        """(row, column) of every cell holding ``char``, in row-major order."""
        return [(r, c) for r, row in enumerate(self.rows) for c, ch in enumerate(row) if ch == char]

    @classmethod
    def parse(cls, text: str, game: str, source: str = "<string>", name: str | None = None) -> Level:
        """Parse and validate a level text; trailing newlines (empty last lines) are dropped.

        A leading UTF-8 byte-order mark is ignored, and Windows (CRLF) and old Mac (CR) line
        ends read as newlines."""
        level_format(game)  # an unknown game first
        text = text.removeprefix(BOM).replace("\r\n", "\n").replace("\r", "\n").rstrip("\n")
        if not text.strip():
            raise LevelFormatError(f"empty level (a {game} level needs at least one row)", source)
        rows = text.split("\n")
        check_rows(rows, game, source)
        return cls(game=game, rows=tuple(rows), name=name)

    def check(self) -> Level:
        """This level, if its game's format accepts it as :meth:`parse` would; a ``Level`` built by
        hand that it refuses (ragged rows, an unknown character, no avatar or two, too large) is
        refused with a ``LevelFormatError`` naming the level, the problem and where it is."""
        source = self.name or f"a {self.game} level built by hand"
        if not all(isinstance(row, str) for row in self.rows):
            raise LevelFormatError(f"a level's rows are strings; got {self.rows!r}", source)
        if not any(self.rows):
            raise LevelFormatError(f"empty level (a {self.game} level needs at least one row)", source)
        check_rows(self.rows, self.game, source)
        return self

    @classmethod
    def load(cls, path: str | Path, game: str | None = None) -> Level:
        """Read a level file; the game defaults to the file name's prefix (``zelda_lvl0.txt``)."""
        path = Path(path)
        if game is None:
            game = path.name.split("_")[0]
        return cls.parse(decode(path.read_bytes(), str(path)), game, source=str(path), name=path.stem)


def check_rows(rows: Sequence[str], game: str, source: str) -> None:
    """Refuse rows that are not a level of ``game`` (``LevelFormatError`` with the line and
    column of the first problem): ragged, with a character outside the legend or a line break,
    larger than the game's grid, or without exactly one avatar."""
    fmt = level_format(game)
    width = len(rows[0])
    for r, row in enumerate(rows):
        if len(row) != width:
            raise LevelFormatError(
                f"ragged rows: this row has {len(row)} characters, row 1 has {width}",
                source,
                r + 1,
                min(len(row), width) + 1,
            )
        for c, ch in enumerate(row):
            if ch not in fmt.chars:
                raise LevelFormatError(
                    f"character {ch!r} is not in the {game} legend; "
                    f"valid characters are {' '.join(fmt.chars)}",
                    source,
                    r + 1,
                    c + 1,
                )
    if len(rows) > fmt.height or width > fmt.width:
        raise LevelFormatError(
            f"grid is {width}x{len(rows)} (WxH) but a {game} level is at most {fmt.width}x{fmt.height}",
            source,
        )
    avatars = [(r, c) for r, row in enumerate(rows) for c, ch in enumerate(row) if ch in fmt.avatar_chars]
    if not avatars:
        raise LevelFormatError(
            f"no avatar: a {game} level needs exactly one of {' '.join(fmt.avatar_chars)}", source
        )
    if len(avatars) > 1:
        r, c = avatars[1]
        raise LevelFormatError(
            f"a second avatar (first at line {avatars[0][0] + 1}, column {avatars[0][1] + 1}); "
            f"a {game} level needs exactly one",
            source,
            r + 1,
            c + 1,
        )


def decode(data: bytes, source: str) -> str:
    """A level file's bytes as text: UTF-8, with or without a byte-order mark. Anything else is
    refused with the file and the line and column of the first byte that is not UTF-8."""
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        column = error.start - (data.rfind(b"\n", 0, error.start) + 1) + 1
        raise LevelFormatError(
            f"not UTF-8 text (byte 0x{data[error.start]:02x} cannot be decoded); "
            "save the level as UTF-8 (plain ASCII is UTF-8)",
            source,
            line,
            column,
        ) from None
