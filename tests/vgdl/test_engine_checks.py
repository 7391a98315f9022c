"""The generic step refuses what it has no kernel for, in one line naming the file, the line and
the feature; and its state layout follows the draw-key rule (``vgdl/engine/layout.py``)."""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.games import rng
from gvgai_pcg.games.geometry import direction_dx, direction_dy
from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl import VGDLError
from gvgai_pcg.vgdl.engine import VGDLGame
from gvgai_pcg.vgdl.engine.layout import TableGroup

BASE = """BasicGame
    SpriteSet
        floor > Immovable
        bats >
            bat > RandomNPC cons=1
            bigbat > RandomNPC cons=2 cooldown=2
        rat > RandomNPC
        avatar > ShootAvatar stype=slash
        slash > OrientedFlicker singleton=True limit=2
{sprites}
    LevelMapping
        . > floor
        b > floor bat
        B > floor bigbat
        r > floor rat
    InteractionSet
        avatar wall > stepBack
        bats rat > killSprite scoreChange=3
        avatar bats > killSprite
{rules}
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
"""


def description(sprites: str = "", rules: str = "") -> str:
    return BASE.format(sprites=sprites, rules=rules)


def refusal(text: str) -> str:
    with pytest.raises(VGDLError) as caught:
        VGDLGame.from_text(text, "mine.txt")
    message = str(caught.value)
    assert "\n" not in message
    return message


def test_a_sprite_class_without_kernel_is_refused_at_its_line():
    message = refusal(description(sprites="        rock > Missile singleton=True"))
    assert message == "mine.txt:10: rock: a Missile held as a record (a singleton) has no kernel yet"


def test_an_eos_effect_without_kernel_is_refused_at_its_line():
    assert refusal(description(rules="        rat EOS > reverseDirection")) == (
        "mine.txt:20: EOS effect reverseDirection is not implemented by the generic step yet"
    )


def test_an_eos_wrap_around_of_a_sprite_without_orientation_is_refused():
    assert refusal(description(rules="        rat EOS > wrapAround")).startswith(
        "mine.txt:20: EOS wrapAround of rat (a RandomNPC, no orientation held) is not implemented"
    )


def test_an_effect_parameter_off_its_default_is_refused():
    message = refusal(description(rules="        rat wall > killSprite prob=0.5"))
    assert message == "mine.txt:20: killSprite: parameter prob=0.5 is not implemented"


def test_an_effect_without_kernel_is_refused():
    message = refusal(description(rules="        rat avatar > wrapAround"))
    assert message == "mine.txt:20: effect wrapAround is not implemented by the generic step yet"


def test_a_pull_by_something_else_than_missiles_is_refused():
    message = refusal(description(rules="        rat avatar > pullWithIt"))
    assert message.startswith("mine.txt:20: pullWithIt is implemented for a MovingAvatar pulled by Missiles")


def test_a_sprite_parameter_without_kernel_is_refused():
    message = refusal(description(sprites="        stone > Immovable solid=True"))
    assert message == "mine.txt:10: stone: parameter solid of Immovable is not implemented"


def test_an_immovable_portal_is_accepted_it_only_names_the_observation_category():
    # Java reads ``portal`` only for the category a state observation gives the sprite
    game = VGDLGame.from_text(description(sprites="        hole > Immovable portal=True"), "mine.txt")
    assert "hole" in game.layout.plan.types
    assert refusal(description(sprites="        hole > Immovable portal=True solid=True")) == (
        "mine.txt:10: hole: parameter solid of Immovable is not implemented"
    )


def test_a_feature_no_engine_has_is_refused_by_the_support_check():
    assert refusal(description(sprites="        hunter > Chaser stype=avatar")).startswith(
        "mine.txt:10: Chaser"
    )


def test_a_level_character_outside_the_mapping_is_refused():
    game = VGDLGame.from_text(description(), "mine.txt")
    with pytest.raises(ValueError, match="character 'x' is not in the game's LevelMapping"):
        game.compile([Level("zelda", ("A.x",), name="odd")], torch.zeros(1), "cpu")


def test_random_npcs_of_one_parent_share_a_table_and_each_table_its_stream():
    game = VGDLGame.from_text(description(), "mine.txt")
    assert game.layout.tables == (
        TableGroup("bats", ("bat", "bigbat"), "RandomNPC", 1),
        TableGroup("rat", ("rat",), "RandomNPC", 2),
    )
    # slots in (kind, row-major) order: the processing order of a rule naming ``bats``
    state = game.compile([Level("zelda", ("Bb.", "rbB", "A.."))], torch.zeros(1), "cpu")
    bats = state.get("bats")
    assert bats.get("kind")[0, :4].tolist() == [0, 0, 1, 1]
    assert list(zip(bats.get("x")[0, :4].tolist(), bats.get("y")[0, :4].tolist(), strict=True)) == [
        (10, 0),
        (10, 10),
        (0, 0),
        (20, 10),
    ]
    assert bats.batch_size[1] == 4 and state.get("rat").batch_size[1] == 2  # powers of two, at least 2


def test_a_creation_into_a_record_that_holds_its_sprite_stops_the_tick():
    game = VGDLGame.from_text(
        """BasicGame
    SpriteSet
        key > Immovable
        avatar > ShootAvatar stype=slash
            nokey >
            withkey >
        slash > Flicker singleton=True
    LevelMapping
        + > key
        A > nokey
        K > withkey
    InteractionSet
        nokey key > transformTo stype=withkey killSecond=True
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
""",
        "two.txt",
    )
    state = game.compile([Level("two", ("A+K",))], torch.zeros(1), "cpu")  # two avatars
    game.tick(state, torch.tensor([game.actions.index("NIL")]))
    with pytest.raises(RuntimeError, match=r"two.txt:13: transformTo into 'withkey', which already holds"):
        game.tick(state, torch.tensor([game.actions.index("RIGHT")]))  # nokey steps onto the key


def test_a_random_npc_draws_its_direction_by_slot_on_its_tables_stream():
    game = VGDLGame.from_text(description(), "mine.txt")
    seeds = torch.arange(8) * 977
    state = game.compile([Level("mine", ("A.r..", "....."))] * 8, seeds, "cpu")
    game.tick(state, torch.zeros(8, dtype=torch.int64))  # rat: cons 0, so it draws and moves at tick 0
    drawn = rng.randint(seeds, torch.zeros(8, dtype=torch.int64), 0, 2, 4)  # slot 0, stream 2
    rat = state.get("rat")
    moved = (rat.get("x")[:, 0] - 20, rat.get("y")[:, 0])
    assert moved[0].tolist() == (10 * direction_dx(drawn)).tolist()
    assert moved[1].tolist() == (10 * direction_dy(drawn)).tolist()
    assert len(set(drawn.tolist())) > 1  # the seeds draw different directions
