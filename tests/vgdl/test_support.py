"""What a description needs from the engine, and the one-line refusal of what it lacks."""

from __future__ import annotations

import textwrap

import pytest

from gvgai_pcg.vgdl import VGDLError, parse_vgdl
from gvgai_pcg.vgdl.support import IMPLEMENTED, STUDY_FEATURES, check_supported, required_features


def needs(body: str) -> dict[str, int]:
    text = "BasicGame\n" + textwrap.indent(textwrap.dedent(body).strip("\n"), "    ") + "\n"
    return {feature.name: feature.line for feature in required_features(parse_vgdl(text, "g.txt"))}


def test_the_declared_table_is_the_four_study_games_features_timeout_and_the_sokoban_effects():
    assert len(STUDY_FEATURES) == 31
    assert {"@EOS", "@F:stepBack", "@singleton", "@subcell", "shieldFrom", "OngoingAvatar"} <= STUDY_FEATURES
    added = {"Timeout", "bounceForward", "killBoth", "undoAll"}
    assert not added & STUDY_FEATURES and IMPLEMENTED == STUDY_FEATURES | added
    assert "@F:bounceForward" not in IMPLEMENTED


def test_classes_effects_terminations_and_flags_at_their_first_line():
    found = needs("""
        SpriteSet
            shot > Missile speed=0.5
            enemy > RandomNPC
        InteractionSet
            shot EOS > killSprite
            enemy enemy > stepBack
            avatar shot > killSprite
        TerminationSet
            Timeout limit=100 win=True
    """)
    assert found == {
        "Missile": 3,
        "@subcell": 3,
        "RandomNPC": 4,
        "MovingAvatar": 0,  # Java's default avatar
        "killSprite": 6,
        "@EOS": 6,
        "stepBack": 7,
        "@F:stepBack": 7,  # RandomNPCs stepping back from each other: a fixed point
        "Timeout": 10,
    }


def test_a_step_back_among_still_types_and_whole_speeds_need_no_flag():
    found = needs("""
        SpriteSet
            box > Passive
            shot > Missile speed=2
        InteractionSet
            box box > stepBack
    """)
    assert "@F:stepBack" not in found and "@subcell" not in found


def test_chain_pushes_timers_and_inherited_singletons_are_flagged():
    found = needs("""
        SpriteSet
            box > Passive
            shots > Missile singleton=True
                up >
        InteractionSet
            box box > bounceForward
            up TIME > killSprite timer=5
    """)
    assert found["@F:bounceForward"] == 7 and found["@TIME"] == 8 and found["@singleton"] == 5


def test_continuous_physics_is_a_feature_of_its_own():
    found = needs("SpriteSet\n    ship > Missile physicstype=CONT")
    assert found["@continuous_physics"] == 3
    assert "@continuous_physics" not in needs("SpriteSet\n    ship > Missile physicstype=GRID")


def test_check_supported_refuses_the_first_missing_feature_in_one_line():
    ready = "BasicGame\n    SpriteSet\n        rock > Passive\n    InteractionSet\n"
    ready += "        avatar rock > stepBack\n"
    check_supported(parse_vgdl(ready, "ready.txt"))
    text = ready + "        rock wall > attractGaze\n    TerminationSet\n"
    text += "        SpriteCounterMore stype=rock limit=0 win=True\n"
    with pytest.raises(VGDLError) as caught:
        check_supported(parse_vgdl(text, "g.txt"))
    assert str(caught.value) == "g.txt:6: attractGaze is not implemented by the engine yet (and 1 more)"
