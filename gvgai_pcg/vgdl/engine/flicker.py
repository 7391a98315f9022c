"""Flicker in a table (RULES.md §2): each sprite is killed once its age exceeds its type's
``limit``, then one older (the record case, a singleton, is ``npcs.flicker``)."""

from __future__ import annotations

from gvgai_pcg.games.lookup import lookup
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.layout import TableGroup


def table_flicker(frame: Frame, group: TableGroup) -> None:
    table = frame.entry(group.key)
    alive, age = table.get("alive"), table.get("age")
    types = frame.layout.plan.types
    limit = lookup(tuple(int(types[name].values["limit"]) for name in group.kinds), table.get("kind"))
    frame.mark_killed(group.key, alive & (age > limit))
    table.set("age", age + alive)
