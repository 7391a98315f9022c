"""The table of Java's VGDL vocabulary is whole: every name Java's registry knows, every class's
superclass, and defaults only for fields the class has."""

from __future__ import annotations

from gvgai_pcg.vgdl.java_classes import (
    EFFECT_CLASSES,
    EFFECTS,
    SPRITE_CLASSES,
    SPRITES,
    TERMINATION_CLASSES,
    TERMINATIONS,
    Const,
    defaults_of,
    fields_of,
)


def test_every_name_of_java_registry_has_its_class():
    assert (len(SPRITES), len(EFFECTS), len(TERMINATIONS)) == (50, 59, 6)  # VGDLFactory's lists
    assert all(name in SPRITE_CLASSES for name in SPRITES)
    assert all(java in EFFECT_CLASSES for java in EFFECTS.values())
    assert all(name in TERMINATION_CLASSES for name in TERMINATIONS)


def test_superclasses_are_in_the_table_and_defaults_name_fields():
    for kind, table in (
        ("sprite", SPRITE_CLASSES),
        ("effect", EFFECT_CLASSES),
        ("termination", TERMINATION_CLASSES),
    ):
        for name, cls in table.items():
            assert cls.parent is None or cls.parent in table, name
            assert set(cls.defaults) <= set(fields_of(kind, name)), name


def test_defaults_follow_the_class_chain_and_java_zeros():
    assert defaults_of("sprite", "ShootAvatar")["orientation"] == Const("DRIGHT")  # OrientedAvatar's
    assert defaults_of("sprite", "MovingAvatar")["orientation"] == Const("DNONE")  # VGDLSprite's
    assert defaults_of("sprite", "Immovable")["healthPoints"] == 0  # never assigned: Java's zero
    assert defaults_of("effect", "TransformTo")["is_kill_effect"] is True
    assert defaults_of("effect", "KillSprite")["repeat"] == 1
    assert defaults_of("termination", "SpriteCounter")["limit"] == 0
    assert fields_of("termination", "Termination")["canEnd"] == "boolean static"
