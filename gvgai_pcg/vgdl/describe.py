"""A parsed description as text for people (``gvgai-pcg vgdl inspect``) and as JSON.

The text shows what a compiler works from, in Java's orders: the update order, EOS, the
collision pairs with their effects, the timed effects, the terminations, and each type's
Java class with its parameters, the ones the file sets and the class's defaults that decide
behaviour.
"""

from __future__ import annotations

from gvgai_pcg.vgdl.java_classes import Const, defaults_of, fields_of
from gvgai_pcg.vgdl.model import Effect, GameDescription, SpriteType
from gvgai_pcg.vgdl.support import IMPLEMENTED, required_features

# VGDLSprite's fields that decide behaviour (the rest draw it); a subclass's own fields are
# always shown.
BEHAVIOUR_FIELDS = (
    "speed",
    "cooldown",
    "orientation",
    "is_static",
    "solid",
    "singleton",
    "is_stochastic",
    "healthPoints",
    "maxHealthPoints",
    "limitHealthPoints",
    "rotateInPlace",
)
# The Java types a VGDL value can be stored in (the others are engine state).
SETTABLE = ("int", "long", "float", "double", "boolean", "String", "Color", "Direction")


def show(value: object) -> str:
    if isinstance(value, Const):
        return value.name
    if isinstance(value, bool):
        return "True" if value else "False"
    return str(value)


def describe(game: GameDescription) -> str:
    """Several lines of text, Java's orders kept."""
    lines = [f"{game.path}: {game.game_class} {_params(game.game_values)}".rstrip()]
    lines.append(f"update order (avatar first, then reverse drawing order): {', '.join(game.update_order)}")
    lines.append(f"drawing order: {', '.join(game.sprite_order)}")
    lines.append(f"EOS (in order, repeats applied again): {', '.join(game.eos) or '-'}")
    for name in dict.fromkeys(game.eos):
        lines.append(f"  {name} EOS: {', '.join(_effect(game.effects[i]) for i in game.eos_effects[name])}")
    lines.append(f"collision pairs (Java's processing order): {len(game.pairs)}")
    for number, pair in enumerate(game.pairs, start=1):
        effects = ", ".join(_effect(game.effects[i]) for i in pair.effects)
        lines.append(f"  {number:>2}. {pair.first} {pair.second}: {effects}")
    if game.time_effects:
        lines.append("timed effects: " + ", ".join(_effect(game.effects[i]) for i in game.time_effects))
    lines.append("terminations (first that holds ends the game):")
    for termination in game.terminations:
        lines.append(f"  line {termination.line}: {termination.java_class} {_params(termination.values)}")
    lines.append(
        "level characters: " + ", ".join(f"{c}={'+'.join(t)}" for c, t in game.level_mapping.items())
    )
    lines.append("types (registration order):")
    for sprite in game.types.values():
        lines.extend(_sprite(sprite))
    features = required_features(game)
    missing = [feature.name for feature in features if feature.name not in IMPLEMENTED]
    lines.append(f"features: {', '.join(feature.name for feature in features)}")
    lines.append(f"not implemented by the engine: {', '.join(missing) or 'none'}")
    return "\n".join(lines)


def _params(values: dict) -> str:
    return " ".join(f"{key}={show(value)}" for key, value in values.items())


def _effect(effect: Effect) -> str:
    text = f"{effect.name}(line {effect.line}"
    shown = {key: value for key, value in effect.values.items() if key != "repeat"}
    return text + (f", {_params(shown)})" if shown else ")")


def _sprite(sprite: SpriteType) -> list[str]:
    where = f"line {sprite.line}" if sprite.line else "Java's default"
    head = f"  {sprite.name}: {sprite.java_class or '(no class)'} ({where}"
    head += f", parent {sprite.parent}" if sprite.parent else ""
    head += ", singleton" if sprite.singleton else ""
    head += ")" if sprite.is_leaf else f"; subtypes {', '.join(sprite.subtypes)})"
    lines = [head]
    if sprite.java_class is None:
        return lines
    defaults = defaults_of("sprite", sprite.java_class)
    fields, base = fields_of("sprite", sprite.java_class), fields_of("sprite", "VGDLSprite")
    own_defaults = {key: defaults[key] for key in fields if key not in base and fields[key] in SETTABLE}
    shown = {key: defaults[key] for key in BEHAVIOUR_FIELDS if key in defaults} | own_defaults
    if sprite.values:
        lines.append(f"      set: {_params(dict(sprite.values))}")
    rest = {key: value for key, value in shown.items() if key not in sprite.values}
    if rest:
        lines.append(f"      defaults: {_params(rest)}")
    return lines


def encode(value: object) -> object:
    """``json.dumps``'s ``default``: Java constants as their names."""
    if isinstance(value, Const):
        return value.name
    raise TypeError(f"cannot encode {type(value).__name__}")
