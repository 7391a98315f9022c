"""What a batched step needs for each rule: one masked op, or something more sequential.

Java applies a rule pair by pair in list order (CORPUS.md, "Java's tick"); most rules give the
same result when every (first, second) pair is applied at once. The kinds, from cheapest:

- ``P``: one masked operation over all pairs;
- ``A``: a masked operation that also creates sprites, whose slots follow Java's creation
  order (a cumulative sum over the pairs in list order);
- ``X``: a prefix scan, because an earlier pair changes what a later one may do (a resource
  taken until the holder is full, a creation refused once a singleton exists, a same-type
  ``killBoth`` or ``transformTo killSecond=True``, whose second, killed, is then skipped as a
  first);
- ``G``: a per-env global operation (``undoAll``, ``transformToAll``, ``shieldFrom``,
  ``killAll``, timers);
- ``F``: a loop or fixed point, since one sprite's result depends on another's in the same
  rule (chain pushes, a ``stepBack`` between sprites of one moving type).

``rule_kind`` classifies one (effect line, second type) pair; on GVGAI's corpus it agrees with
``rule_order.json`` beside CORPUS.md on all 1,546 pairs (a test). A creation into a type
marked ``singleton`` by an ancestor only is ``X`` as there, though Java checks only the type
whose own line says it: the cautious choice costs a scan, never a wrong result.
"""

from __future__ import annotations

from gvgai_pcg.vgdl.model import Effect, GameDescription
from gvgai_pcg.vgdl.support import STILL_CLASSES

KINDS = ("P", "A", "X", "G", "F")
GLOBAL_EFFECTS = frozenset({"undoAll", "transformToAll", "shieldFrom", "killAll", "addTimer"})
PREFIX_EFFECTS = frozenset({"collectResource", "collectResourceIfHeld"})
# Effects that create a sprite of ``stype`` where their first sprite is (``cloneSprite``: of the
# first's own type).
CREATING_EFFECTS = frozenset(
    {
        "spawn",
        "spawnIfHasMore",
        "spawnIfHasLess",
        "transformTo",
        "transformToSingleton",
        "transformIfCount",
        "transformToRandomChild",
        "cloneSprite",
    }
)
# Effects whose Java code draws from the game's random generator at every application.
RANDOM_EFFECTS = frozenset(
    {
        "attractGaze",
        "flipDirection",
        "spawn",
        "spawnIfHasLess",
        "spawnIfHasMore",
        "teleportToExit",
        "transformToRandomChild",
    }
)


def leaves(game: GameDescription, name: str) -> tuple[str, ...]:
    """The types with sprites a rule naming ``name`` reaches, in Java's ``iSubTypes`` order:
    the drawn ones (leaves, and ``avatar`` which Java always draws) that have a class; none
    for ``EOS``/``TIME``."""
    sprite = game.types.get(name)
    if sprite is None:
        return ()
    drawn = set(game.sprite_order)
    return tuple(sub for sub in sprite.subtypes if sub in drawn and game.types[sub].java_class)


def marked_singleton(game: GameDescription, name: str) -> bool:
    """A type whose line or an ancestor's says ``singleton=True``."""
    sprite = game.types.get(name)
    if sprite is None:
        return False
    return sprite.singleton or str(sprite.parameters.get("singleton", "")).lower() == "true"


def created_types(game: GameDescription, effect: Effect) -> tuple[str, ...]:
    """The leaf types a creating effect may create (empty for any other effect)."""
    if effect.name not in CREATING_EFFECTS:
        return ()
    if effect.name == "cloneSprite":
        return leaves(game, effect.first)
    stype = effect.value("stype")
    if not isinstance(stype, str) or stype not in game.types:
        return ()
    if effect.name == "transformToRandomChild":
        return tuple(child for child in leaves(game, stype) if child != stype)
    return leaves(game, stype)


def rule_kind(game: GameDescription, effect: Effect, second: str) -> tuple[str, str]:
    """The kind of the pair (``effect.first``, ``second``) under ``effect``, and why in a phrase."""
    if effect.is_time:
        return "G", "a timed effect: a per-env timer"
    if effect.name in GLOBAL_EFFECTS:
        return "G", f"{effect.name} acts on whole types of the env"
    shared = set(leaves(game, effect.first)) & set(leaves(game, second))
    if effect.name == "bounceForward" and shared:
        return "F", "a push among sprites of one type: chain pushes"
    moving = {name for name in shared if game.types[name].java_class not in STILL_CLASSES}
    if effect.name == "stepBack" and moving:
        return "F", f"a stepBack among moving {', '.join(sorted(moving))}: resolved in list order"
    if effect.name in PREFIX_EFFECTS:
        return "X", "each take is capped by what the holder already has"
    if shared and (
        effect.name == "killBoth" or (effect.name == "transformTo" and effect.value("killSecond"))
    ):
        return "X", "kills its second, which is then skipped as a first of the same rule"
    if effect.name in CREATING_EFFECTS:
        made = created_types(game, effect)
        stype = effect.value("stype")
        if marked_singleton(game, stype if isinstance(stype, str) else "") or any(
            marked_singleton(game, name) for name in made
        ):
            return "X", "creates a singleton: refused once one exists"
        return "A", "creates sprites: slots in creation order"
    return "P", "one masked operation"
