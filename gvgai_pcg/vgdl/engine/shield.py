"""shieldFrom (RULES.md §3): a first that overlaps a second raises a shield on its type for the
rest of the tick: every later rule of the pair (its type, ``stype``) whose effect is ``ftype`` is
skipped (Java's ``shieldedEffects``, keyed by the pair's declared types and the effect; cleared at
cleanup, and a frame lives one tick). A shield is per env: one mask ``[B]`` per key.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from gvgai_pcg.vgdl.engine.frame import Frame

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule


def shield_from(frame: Frame, rule: Rule) -> None:
    """Raise the shields, one per first leaf type with a sprite that overlaps a second; the
    score per application (Java applies it to every overlapping pair)."""
    layout = frame.layout
    stype, ftype = str(rule.plan.values["stype"]), str(rule.plan.values["ftype"])
    for first in rule.firsts:
        x, y = frame.xy(first)
        hits = frame.overlap_count(x, y, first.aligned, first, list(rule.seconds)) * frame.eligible(first)
        if rule.score:
            frame.add_score(rule.score * hits.sum(-1))
        group = layout.group(first.key) if first.key not in layout.records else None
        for code in first.kinds:
            leaf = layout.group(first.key).kinds[code] if group is not None else first.key
            mine = hits > 0
            if group is not None:
                mine = mine & (frame.entry(first.key).get("kind") == code)
            key = (leaf, stype, ftype)
            raised = mine.any(-1)
            frame.shields[key] = raised if key not in frame.shields else frame.shields[key] | raised
