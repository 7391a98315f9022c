"""What a VGDL description is, once parsed as Java parses it: plain frozen dataclasses.

The names of sprite types are the keys everywhere (Java's integer ids are only the order in
which types were registered, ``GameDescription.type_ids``). Everything a later stage needs
to build a plan is here in Java's own orders: the update order, the collision pairs as Java
processes them (an effect repeated ``repeat`` times appears that many times), the EOS list
(duplicates included: Java applies a type's EOS effects once per entry), the time effects,
the terminations in declaration order, and each type's subtypes in ``iSubTypes`` order.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from gvgai_pcg.vgdl.java_classes import defaults_of


@dataclass(frozen=True)
class SpriteType:
    """One sprite type of the SpriteSet (or ``wall``/``avatar`` as Java pre-defines them).

    ``java_class`` is the class Java instantiates: the nearest ancestor's class word wins over
    the type's own (None for a parent type that no ancestor gives a class; it has no sprites).
    ``parameters`` are the raw texts, inherited ones included; ``values`` the typed values
    Java stores, over the class's defaults.
    """

    name: str
    line: int  # 0 for a pre-defined type
    java_class: str | None
    parent: str | None
    children: tuple[str, ...]
    parameters: Mapping[str, str]
    values: Mapping[str, object]
    singleton: bool
    subtypes: tuple[str, ...]

    @property
    def is_leaf(self) -> bool:
        return not self.children

    def value(self, field: str) -> object:
        """The field's value: the line's own, else the Java class's default."""
        if field in self.values:
            return self.values[field]
        return defaults_of("sprite", self.java_class).get(field) if self.java_class else None


@dataclass(frozen=True)
class Effect:
    """One interaction line, one Java effect object: every pair of the line shares it (a
    per-object guard or a rewritten score is shared too)."""

    index: int  # declaration order among the InteractionSet's lines
    line: int
    first: str
    seconds: tuple[str, ...]
    name: str  # VGDL's name, ``killSprite``
    java_class: str
    parameters: Mapping[str, str]
    values: Mapping[str, object]

    @property
    def repeat(self) -> int:
        return int(self.values.get("repeat", 1))

    @property
    def is_time(self) -> bool:
        return self.first.upper() == "TIME" or self.seconds[0].upper() == "TIME"

    def value(self, field: str) -> object:
        if field in self.values:
            return self.values[field]
        return defaults_of("effect", self.java_class).get(field)


@dataclass(frozen=True)
class CollisionPair:
    """A (first, second) type pair in Java's processing order, with its effects in the order
    Java applies them (indices into ``GameDescription.effects``, repeats included)."""

    first: str
    second: str
    effects: tuple[int, ...]


@dataclass(frozen=True)
class Termination:
    """One TerminationSet line; Java checks them in declaration order, the first that holds wins."""

    line: int
    java_class: str
    parameters: Mapping[str, str]
    values: Mapping[str, object]

    def value(self, field: str) -> object:
        if field in self.values:
            return self.values[field]
        return defaults_of("termination", self.java_class).get(field)


@dataclass(frozen=True)
class GameDescription:
    path: str
    game_class: str
    game_parameters: Mapping[str, str]
    game_values: Mapping[str, object]
    types: Mapping[str, SpriteType]  # in registration order (Java's ids)
    sprite_order: tuple[str, ...]  # drawing order; the update order is its reverse, avatar first
    effects: tuple[Effect, ...]
    pairs: tuple[CollisionPair, ...]
    eos: tuple[str, ...]  # Java's definedEOSEffects, duplicates included
    eos_effects: Mapping[str, tuple[int, ...]]
    time_effects: tuple[int, ...]
    terminations: tuple[Termination, ...]
    level_mapping: Mapping[str, tuple[str, ...]]  # BasicGame's 'w' and 'A' included

    @property
    def update_order(self) -> tuple[str, ...]:
        """Java's tick moves the avatar first, then every other type in reverse drawing order."""
        return tuple(reversed(self.sprite_order))

    @property
    def type_ids(self) -> dict[str, int]:
        return {name: index for index, name in enumerate(self.types)}
