"""changeResource: the first's count of ``resource`` grows by ``value`` at each application
where the result stays within the resource type's ``limit`` (Java's ``getResourceLimit``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import torch

from gvgai_pcg.vgdl.engine.columns import resource_column
from gvgai_pcg.vgdl.engine.frame import Frame
from gvgai_pcg.vgdl.engine.spawn import applications
from gvgai_pcg.vgdl.layout import RECORD

if TYPE_CHECKING:
    from gvgai_pcg.vgdl.engine.effects import Rule


def change_resource(frame: Frame, rule: Rule) -> None:
    """``value`` is positive (``checks``): of ``n`` applications the first ``(limit - held) //
    value`` fire, each scoring."""
    resource = str(rule.plan.values["resource"])
    value = int(rule.plan.values["value"])
    limit = int(frame.layout.plan.types[resource].values["limit"])
    column = resource_column(resource)
    for first in rule.firsts:
        _, _, hits = applications(frame, rule, first)
        entry = frame.entry(first.key)
        held = entry.get(column)
        if first.representation == RECORD:
            hits = hits.squeeze(-1)
        fired = torch.minimum(hits, ((limit - held) // value).clamp(min=0))
        entry.set(column, held + value * fired)
        frame.add_score(rule.score * fired.reshape(fired.shape[0], -1).sum(-1))
