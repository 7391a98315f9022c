"""Curricula: where a resetting env's next level comes from, as plug-ins (see
``gvgai_pcg.curricula.base`` for the contract, ``docs/howto/add-a-curriculum.md`` for a new one)."""

from gvgai_pcg.curricula.base import Curriculum
from gvgai_pcg.curricula.registry import (
    ENTRY_POINT_GROUP,
    get_curriculum,
    register_curriculum,
    registered_curricula,
    unregister_curriculum,
)

__all__ = [
    "ENTRY_POINT_GROUP",
    "Curriculum",
    "get_curriculum",
    "register_curriculum",
    "registered_curricula",
    "unregister_curriculum",
]
