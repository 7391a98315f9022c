"""Levels: the ``Level`` value, its file format, and the human-designed levels."""

from gvgai_pcg.levels.formats import LEVEL_FORMATS, LevelFormat, level_format
from gvgai_pcg.levels.human import human_level, human_levels, resolve_level
from gvgai_pcg.levels.level import Level, LevelFormatError

__all__ = [
    "LEVEL_FORMATS",
    "Level",
    "LevelFormat",
    "LevelFormatError",
    "human_level",
    "human_levels",
    "level_format",
    "resolve_level",
]
