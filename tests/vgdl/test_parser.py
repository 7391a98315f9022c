"""The parser keeps each quirk of Java's VGDLParser; every snippet here is a few lines of our own.

Each test names the quirk it pins; the Java behaviour it copies is in the docstring of
``gvgai_pcg/vgdl/parser.py`` and ``lines.py``.
"""

from __future__ import annotations

import textwrap

import pytest

from gvgai_pcg.vgdl import VGDLError, parse_vgdl
from gvgai_pcg.vgdl.java_classes import Const


def vgdl(body: str) -> str:
    return "BasicGame\n" + textwrap.indent(textwrap.dedent(body).strip("\n"), "    ") + "\n"


def parse(body: str):
    return parse_vgdl(vgdl(body), "game.txt")


def refused(body: str) -> VGDLError:
    with pytest.raises(VGDLError) as caught:
        parse(body)
    return caught.value


BASE = """
SpriteSet
    floor > Immovable
    rock > Passive
    hero > MovingAvatar
InteractionSet
    hero rock > stepBack
"""


def test_wall_and_avatar_are_predefined_with_java_defaults():
    game = parse(BASE)
    assert list(game.types)[:2] == ["wall", "avatar"]  # Java's ids 0 and 1
    assert game.sprite_order == ("wall", "floor", "rock", "hero", "avatar")  # avatar always last
    assert game.update_order == ("avatar", "hero", "rock", "floor", "wall")
    assert game.types["wall"].java_class == "Immovable"
    assert game.types["wall"].value("solid") is True
    assert game.types["wall"].value("color") == Const("DARKGRAY")
    assert game.types["avatar"].java_class == "MovingAvatar"
    assert game.level_mapping["w"] == ("wall",) and game.level_mapping["A"] == ("avatar",)


def test_a_redefined_leaf_moves_to_the_end_of_the_drawing_order():
    game = parse("""
        SpriteSet
            a > Immovable
            b > Immovable
            wall > Immovable
            a > Passive
    """)
    assert game.sprite_order == ("b", "wall", "a", "avatar")
    assert game.types["a"].java_class == "Passive"  # the last definition counts


def test_the_nearest_ancestor_class_word_overrides_a_child_own():
    game = parse("""
        SpriteSet
            top > Immovable
                middle > Passive
                    leaf > Missile
            plain > Missile
    """)
    assert game.types["middle"].java_class == "Immovable"  # its parent's word wins
    assert game.types["leaf"].java_class == "Passive"  # its nearest ancestor's own word
    assert game.types["plain"].java_class == "Missile"


def test_parameters_inherit_and_a_child_overrides_them():
    game = parse("""
        SpriteSet
            shot > Missile speed=0.5 color=RED
                fast > speed=1
                slow >
    """)
    assert game.types["fast"].values["speed"] == 1.0 and game.types["fast"].value("color") == Const("RED")
    assert game.types["slow"].values["speed"] == 0.5
    assert game.types["slow"].value("orientation") == Const("DNONE")  # the class's default


def test_singleton_marks_only_the_type_whose_own_line_says_it():
    game = parse("""
        SpriteSet
            shots > Missile singleton=True
                up >
            laser > Missile singleton=true
    """)
    assert game.types["shots"].singleton and game.types["laser"].singleton
    assert not game.types["up"].singleton  # Java's singletons[] holds the parent's id only
    assert game.types["up"].values["singleton"] is True  # ... but the field is inherited


def test_subtypes_are_the_path_then_the_children_subtypes():
    game = parse("""
        SpriteSet
            enemy > RandomNPC
                small >
                big >
                    huge >
    """)
    assert game.types["enemy"].subtypes == ("enemy", "small", "big", "huge")
    assert game.types["huge"].subtypes == ("enemy", "big", "huge")
    assert game.types["small"].subtypes == ("enemy", "small")
    assert game.types["wall"].subtypes == ("wall",)


def test_one_effect_object_per_rule_line_shared_by_its_pairs():
    game = parse("""
        SpriteSet
            a > Immovable
            b > Immovable
            c > Immovable
        InteractionSet
            avatar a b > stepBack
            avatar c > stepBack
    """)
    assert [(p.first, p.second, p.effects) for p in game.pairs] == [
        ("avatar", "a", (0,)),
        ("avatar", "b", (0,)),  # the same effect as the pair above
        ("avatar", "c", (1,)),
    ]


def test_pairs_keep_the_order_of_first_declaration_and_repeat_adds_copies():
    game = parse("""
        SpriteSet
            a > Immovable
            b > Immovable
        InteractionSet
            avatar a > stepBack
            avatar b > killSprite repeat=3
            avatar a > killSprite scoreChange=2
    """)
    assert [(p.first, p.second, p.effects) for p in game.pairs] == [
        ("avatar", "a", (0, 2)),
        ("avatar", "b", (1, 1, 1)),
    ]
    assert game.effects[2].values["scoreChange"] == "2"  # Java keeps scoreChange as text


def test_eos_is_matched_case_insensitively_and_each_line_adds_its_type_again():
    game = parse("""
        SpriteSet
            shot > Missile
        InteractionSet
            shot EOS > killSprite
            avatar eos > stepBack
            eOs shot > reverseDirection
    """)
    assert game.eos == ("shot", "avatar", "shot")  # Java's definedEOSEffects keeps duplicates
    assert game.eos_effects == {"shot": (0, 2), "avatar": (1,)}
    assert game.pairs == ()


def test_time_rules_are_timed_effects_not_pairs():
    game = parse("""
        SpriteSet
            a > Immovable
        InteractionSet
            a TIME > killSprite timer=10 repeating=True
    """)
    assert game.time_effects == (0,) and game.pairs == () and game.eos == ()
    assert game.effects[0].values["timer"] == 10


def test_a_tab_is_one_indent_character():
    # Children at one tab below a parent indented by four spaces are deeper (5 > 4) ...
    game = parse_vgdl("BasicGame\n    SpriteSet\n        a > Immovable\n        \tb > Passive\n", "t.txt")
    assert game.types["b"].parent == "a" and game.types["b"].java_class == "Immovable"
    # ... and a tab-indented line is NOT as deep as a four-space one: its siblings must match.
    with pytest.raises(VGDLError, match=r"t\.txt:4: indent 1 differs"):
        parse_vgdl("BasicGame\n  SpriteSet\n    a > Immovable\n\tb > Passive\n", "t.txt")


def test_a_comment_starts_at_the_first_hash_even_inside_a_value():
    game = parse("""
        SpriteSet  # the sprites
            a > Immovable img=x#y color=RED
    """)
    assert game.types["a"].parameters == {"img": "x"}


def test_whitespace_runs_are_one_space():
    game = parse("SpriteSet\n    a   >\t Immovable   color=RED")
    assert game.types["a"].values == {"color": Const("RED")}


def test_directions_become_java_direction_constants():
    game = parse("""
        SpriteSet
            shot > Missile orientation=LEFT
    """)
    assert game.types["shot"].values["orientation"] == Const("DLEFT")


def test_a_class_default_comes_from_its_load_defaults_chain():
    game = parse("""
        SpriteSet
            hero > ShootAvatar stype=wall
            spawner > SpawnPoint stype=wall
    """)
    assert game.types["hero"].value("orientation") == Const("DRIGHT")
    assert game.types["hero"].value("speed") == 1
    assert game.types["spawner"].value("cooldown") == 1 and game.types["spawner"].value("prob") == 1.0


@pytest.mark.parametrize(
    ("body", "line", "message"),
    [
        ("SpriteSet\n    a > Imovable", 3, "unknown sprite class 'Imovable'"),
        (
            "SpriteSet\n    a > Immovable\nInteractionSet\n    a wall > killSprit",
            5,
            "unknown effect 'killSprit'",
        ),
        ("TerminationSet\n    SpriteCount stype=wall limit=0", 3, "unknown termination 'SpriteCount'"),
        ("SpriteSet\n    a > Immovable sped=2", 3, "unknown parameter 'sped' of a"),
        ("SpriteSet\n    a > Missile cooldown=1.5", 3, "cooldown=1.5: 1.5 cannot be stored in a Java int"),
        ("InteractionSet\n    avatar ghost > killSprite", 3, "undefined sprite type 'ghost'"),
        ("SpriteSet\n    a > SpawnPoint stype=ghost", 3, "stype=ghost names an undefined sprite type"),
        ("InteractionSet\n    avatar wall > transformTo stype=ghost", 3, "undefined sprite type 'ghost'"),
        ("SpriteSet\n    a Immovable", 3, "has no '>'"),
        ("SpriteSet\n    a > Immovable Passive", 3, "more than one class"),
        ("SpriteSet\n    group >\n        a > color=RED", 4, "sprite type 'a' has no class"),
        ("SpriteSet\n    a > Immovable color=", 3, "not key=value"),
        ("InteractionSet\n    avatar wall stepBack", 3, "is not 'first second... > effect'"),
        ("spriteset\n    a > Immovable", 2, "case-sensitively"),
        ("Sprites\n    a > Immovable", 2, "unknown block 'Sprites'"),
        ("SpriteSet\n    a > Immovable\nSpriteSet\n    b > Immovable", 4, "a second SpriteSet"),
        ("LevelMapping\n    a > wall\n    a > avatar", 4, "mapped again (line 3"),
        (
            "InteractionSet\n    avatar wall > stepBack\n        avatar wall > killSprite",
            4,
            "cannot have indented",
        ),
    ],
)
def test_what_java_would_misread_is_refused_in_one_line_with_file_and_line(body, line, message):
    error = refused(body)
    assert str(error).startswith(f"game.txt:{line}: ") and message in str(error)
    assert "\n" not in str(error) and isinstance(error, ValueError)


def test_a_rule_may_only_name_types_defined_above_it():
    text = (
        "BasicGame\n    InteractionSet\n        avatar a > stepBack\n    SpriteSet\n        a > Immovable\n"
    )
    with pytest.raises(VGDLError, match=r"x\.txt:3: .*undefined sprite type 'a'"):
        parse_vgdl(text, "x.txt")


def test_a_line_indented_no_deeper_than_the_game_line_is_refused():
    with pytest.raises(VGDLError, match=r"g\.txt:3: 'InteractionSet' is indented no deeper"):
        parse_vgdl("BasicGame\n    SpriteSet\nInteractionSet\n", "g.txt")


def test_a_line_of_only_hashes_is_refused():
    with pytest.raises(VGDLError, match=r"g\.txt:2: a line of only '#'"):
        parse_vgdl("BasicGame\n###\n", "g.txt")


def test_the_game_line_parameters_are_typed():
    game = parse_vgdl("BasicGame square_size=20 key_handler=Pulse\n", "g.txt")
    assert game.game_values == {"square_size": 20, "key_handler": "Pulse"}
    with pytest.raises(VGDLError, match="unknown parameter 'size' of BasicGame"):
        parse_vgdl("BasicGame size=20\n", "g.txt")
    with pytest.raises(VGDLError, match="game class 'GameSpace'"):
        parse_vgdl("GameSpace\n", "g.txt")


def test_the_parser_imports_no_torch():
    import subprocess
    import sys

    code = "import sys, gvgai_pcg.vgdl; assert 'torch' not in sys.modules, 'torch imported'"
    subprocess.run([sys.executable, "-c", code], check=True)
