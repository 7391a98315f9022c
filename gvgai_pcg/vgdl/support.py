"""Which VGDL features the package's engine implements today, and what a description needs.

The parser accepts everything Java's registry knows; a later stage (the plan compiler) asks
``check_supported`` and refuses the rest by the same route, one line naming the file, the
line and the feature. A feature is a sprite class, an effect, a termination, or an engine
flag that changes how the step must run:

- ``@EOS``: a rule with the end of the screen;
- ``@singleton``: a type that refuses a second sprite (Java's check reads only the type whose
  own line says ``singleton=True``; a parent's word is still inherited into the sprites'
  ``singleton`` field, so it is counted here too);
- ``@subcell``: a type whose speed is not a whole number of cells;
- ``@F:<effect>``: one sprite's result depends on another's in the same rule (a loop or a
  fixed point): a ``bounceForward`` between types that share a type (chain pushes), or a
  ``stepBack`` between types that share a type whose class moves by itself;
- ``@TIME``: timed effects (``TIME`` rules or ``addTimer``);
- ``@obs_pathfinding``: ``obs=...`` on the game line (path-finding obstacles);
- ``@continuous_physics``: a type with ``physicstype`` other than ``GRID`` (no corpus game).

``key_handler=Pulse`` is not a feature: it changes how a human's keys are read, not the step.

``STUDY_FEATURES`` is what the four study games use (31 features): the hand-written engines
implement exactly these. ``IMPLEMENTED`` adds what only the generic step has: ``Timeout``, and
``bounceForward``, ``killBoth`` and ``undoAll`` (the Sokoban family).
"""

from __future__ import annotations

from dataclasses import dataclass

from gvgai_pcg.vgdl.errors import VGDLError
from gvgai_pcg.vgdl.model import GameDescription

STUDY_FEATURES: frozenset[str] = frozenset(
    {
        # engine flags
        "@EOS",
        "@F:stepBack",
        "@singleton",
        "@subcell",
        # sprite classes
        "Door",
        "Flicker",
        "Immovable",
        "Missile",
        "MovingAvatar",
        "OngoingAvatar",
        "OrientedFlicker",
        "Passive",
        "RandomNPC",
        "Resource",
        "ShootAvatar",
        "SpawnPoint",
        # terminations
        "MultiSpriteCounter",
        "SpriteCounter",
        # effects
        "changeResource",
        "collectResource",
        "killIfFromAbove",
        "killIfOtherHasMore",
        "killSprite",
        "pullWithIt",
        "reverseDirection",
        "shieldFrom",
        "spawn",
        "spawnIfHasMore",
        "stepBack",
        "transformTo",
        "wrapAround",
    }
)
IMPLEMENTED: frozenset[str] = STUDY_FEATURES | {"Timeout", "bounceForward", "killBoth", "undoAll"}
# Classes whose own update never moves a sprite (a stepBack among them undoes only pushes).
STILL_CLASSES = frozenset(
    "Immovable Passive Resource ResourcePack Door Flicker OrientedFlicker Spreader Portal "
    "SpawnPoint SpriteProducer SpawnPointMultiSprite Conveyor".split()
)


@dataclass(frozen=True)
class Feature:
    name: str
    line: int  # where the description first needs it


def required_features(game: GameDescription) -> list[Feature]:
    """Every feature the description needs, each once, at the first line that needs it."""
    found: dict[str, int] = {}

    def need(name: str, line: int) -> None:
        found.setdefault(name, line)

    used = _used_types(game)
    for name in used:
        sprite = game.types[name]
        if sprite.java_class is None:  # `avatar` as a parent with no class word: it has no sprites
            continue
        need(sprite.java_class, sprite.line)
        if sprite.singleton or str(sprite.parameters.get("singleton", "")).lower() == "true":
            need("@singleton", sprite.line)
        if sprite.value("physicstype") != 0:
            need("@continuous_physics", sprite.line)
        speed = sprite.value("speed")
        if isinstance(speed, float) and not speed.is_integer():
            need("@subcell", sprite.line)
    for effect in game.effects:
        need(effect.name, effect.line)
        if effect.is_time or effect.name == "addTimer":
            need("@TIME", effect.line)
    for name in game.eos:
        need("@EOS", min(game.effects[i].line for i in game.eos_effects[name]))
    for pair in game.pairs:
        shared = _leaves(game, pair.first) & _leaves(game, pair.second)
        moving = {name for name in shared if game.types[name].java_class not in STILL_CLASSES}
        for index in pair.effects:
            effect = game.effects[index]
            if (effect.name == "bounceForward" and shared) or (effect.name == "stepBack" and moving):
                need(f"@F:{effect.name}", effect.line)
    for termination in game.terminations:
        need(termination.java_class, termination.line)
    if "obs" in game.game_parameters:
        need("@obs_pathfinding", 1)
    return [Feature(name, line) for name, line in sorted(found.items(), key=lambda item: item[1])]


def unsupported_features(game: GameDescription) -> list[Feature]:
    return [feature for feature in required_features(game) if feature.name not in IMPLEMENTED]


def check_supported(game: GameDescription) -> None:
    """Refuse, at its line, the first feature the engine does not implement."""
    missing = unsupported_features(game)
    if missing:
        first = missing[0]
        others = f" (and {len(missing) - 1} more)" if len(missing) > 1 else ""
        raise VGDLError(game.path, first.line, f"{first.name} is not implemented by the engine yet{others}")


def _leaves(game: GameDescription, name: str) -> set[str]:
    return {sub for sub in game.types[name].subtypes if game.types[sub].is_leaf}


def _used_types(game: GameDescription) -> list[str]:
    """The leaf types a level can hold or a rule can create: every drawn type.

    ``wall`` and ``avatar`` count only where the file defines them or a level character,
    a rule or a parameter can bring them in; Java's default avatar is a MovingAvatar."""
    return [name for name in game.sprite_order if game.types[name].line or name == "avatar"]
