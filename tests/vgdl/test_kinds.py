"""Each rule's kind: what a batched step needs to apply it as Java does, pair by pair."""

from __future__ import annotations

import textwrap

from gvgai_pcg.vgdl import parse_vgdl
from gvgai_pcg.vgdl.kinds import rule_kind

SPRITES = """
    SpriteSet
        floor > Immovable
        box > Passive
        gem > Resource limit=3
        shot > Missile
        enemy > RandomNPC
        flash > Flicker singleton=True
        group > singleton=True
            glow > Immovable
        hero > MovingAvatar
"""


def kinds(rules: str) -> list[str]:
    """The kind of each (line, second) pair of ``rules``, in line order."""
    body = SPRITES + "    InteractionSet\n" + textwrap.indent(textwrap.dedent(rules).strip("\n"), " " * 8)
    game = parse_vgdl("BasicGame\n" + textwrap.indent(textwrap.dedent(body).strip("\n"), "    ") + "\n")
    return [rule_kind(game, effect, second)[0] for effect in game.effects for second in effect.seconds]


def test_masked_ops_and_creations_in_order():
    assert kinds("""
        hero shot > killSprite scoreChange=-1
        shot floor wall > stepBack
        box hero > spawn stype=shot
        box shot > transformTo stype=gem
        hero EOS > stepBack
    """) == ["P", "P", "P", "A", "A", "P"]


def test_a_prefix_scan_where_one_pair_changes_what_the_next_may_do():
    assert kinds("""
        gem hero > collectResource
        box hero > spawn stype=flash
        box shot > transformTo stype=glow
        box box > killBoth
        box box > transformTo stype=gem killSecond=True
    """) == ["X", "X", "X", "X", "X"]  # glow is a singleton through its parent's word


def test_a_same_type_transform_that_spares_the_second_is_order_free():
    assert kinds("box box > transformTo stype=gem") == ["A"]


def test_globals_and_timers():
    assert kinds("""
        hero box > undoAll
        hero shot > shieldFrom stype=box ftype=killSprite
        hero TIME > killSprite timer=10
    """) == ["G", "G", "G"]


def test_fixed_points_only_among_sprites_that_move_themselves():
    assert kinds("""
        enemy enemy > stepBack
        box box > stepBack
        box box > bounceForward
    """) == ["F", "P", "F"]
