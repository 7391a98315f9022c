"""A parameter's text as the typed value Java stores in the field (``VGDLFactory.parseParameters``).

Java reads a value as, in this order: a named constant of ``Types`` (``UP`` becomes the
direction ``DUP``, ``RED`` a colour), an int, a double (neither for ``scoreChange``: that
stays text, whatever it holds), a boolean (never for ``win``, ``hidden``, ``invisible``,
which stay text), else text; then stores it in the field if Java's reflection accepts it
(an int widens to a double; a double never narrows to an int). Where reflection refuses,
Java silently keeps the default; this package refuses the line instead.
"""

from __future__ import annotations

import re

from gvgai_pcg.vgdl.java_classes import Const

DIRECTIONS = ("NIL", "NONE", "RIGHT", "LEFT", "UP", "DOWN")
COLORS = (
    "GREEN BLUE RED GRAY WHITE BROWN BLACK ORANGE YELLOW PINK GOLD LIGHTRED LIGHTORANGE LIGHTBLUE "
    "LIGHTGREEN DARKGREEN LIGHTYELLOW LIGHTGRAY DARKGRAY DARKBLUE RANDOM"
).split()
# Types' public int constants: a value spelled as one of them is that int (``physicstype=GRID``).
INT_CONSTANTS = {
    "PHYSICS_NONE": -1,
    "GRID": 0,
    "CONT": 1,
    "VGDL_GAME_DEF": 0,
    "VGDL_SPRITE_SET": 1,
    "VGDL_INTERACTION_SET": 2,
    "VGDL_LEVEL_MAPPING": 3,
    "VGDL_TERMINATION_SET": 4,
    "VGDL_PARAMETER_SET": 5,
    "NUM_LEARNING_LEVELS": 6,
    "NUM_TRAINING_LEVELS": 6,
    "LEARNING_RESULT_DISQ": -1,
    "LEARNING_FINISH_ROUND": -2,
    "DEFAULT_SINGLE_PLAYER_KEYIDX": 0,
    "SCORE_DISQ": -1000,
    "TYPE_AVATAR": 0,
    "TYPE_RESOURCE": 1,
    "TYPE_PORTAL": 2,
    "TYPE_NPC": 3,
    "TYPE_STATIC": 4,
    "TYPE_FROMAVATAR": 5,
    "TYPE_MOVABLE": 6,
}
TEXT_ONLY_NUMBERS = ("scoreChange", "scoreChangeIfKilled")
TEXT_ONLY_BOOLEANS = ("win", "hidden", "invisible")
_INT = re.compile(r"[+-]?\d+")
_DOUBLE = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?[fFdD]?|[+-]?(NaN|Infinity)")
_JAVA_INT = (-(2**31), 2**31 - 1)


def read_value(name: str, text: str) -> int | float | bool | str | Const:
    """What Java makes of the text before it tries the field (``Types.processField`` and on)."""
    if text in DIRECTIONS:
        return Const("D" + text)
    if text in COLORS or (text.startswith("D") and text[1:] in DIRECTIONS):
        return Const(text)
    if text in INT_CONSTANTS:
        return INT_CONSTANTS[text]
    if name in TEXT_ONLY_NUMBERS:
        return text
    if _INT.fullmatch(text) and _JAVA_INT[0] <= int(text) <= _JAVA_INT[1]:
        return int(text)
    if _DOUBLE.fullmatch(text):
        return float(text.rstrip("fFdD"))
    if text.lower() in ("true", "false") and name not in TEXT_ONLY_BOOLEANS:
        return text.lower() == "true"
    return text


def assign(java_type: str, value: int | float | bool | str | Const) -> int | float | bool | str | Const:
    """The value stored in a field of ``java_type``; ValueError where Java's reflection refuses."""
    kind = java_type.removesuffix(" static")
    if isinstance(value, bool):
        ok = kind == "boolean"
    elif isinstance(value, int):
        ok = kind in ("int", "long", "double", "float")
        value = float(value) if kind in ("double", "float") else value
    elif isinstance(value, float):
        ok = kind == "double"
    elif isinstance(value, Const):
        ok = kind == ("Direction" if value.name[1:] in DIRECTIONS else "Color")
    else:
        ok = kind == "String"
    if not ok:
        shown = value.name if isinstance(value, Const) else value
        raise ValueError(f"{shown!r} cannot be stored in a Java {kind} (Java silently keeps the default)")
    return value
