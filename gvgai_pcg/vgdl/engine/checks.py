"""What the generic step's kernels implement, narrower than ``support.IMPLEMENTED``: the rest is
refused in one line naming the file, the line and the feature, never run as something else.

``support`` lists the features some hand-written engine implements; the generic step has kernels
for the classes, effects (EOS rules too), terminations and parameters below (what Zelda and
Frogs use), and for the representations the plan gives them there. A description that passes
``check_supported`` but needs anything else (a parameter off its Java default, say) stops here.
"""

from __future__ import annotations

from gvgai_pcg.vgdl.engine.columns import held_columns, held_resources, oriented_table
from gvgai_pcg.vgdl.errors import VGDLError
from gvgai_pcg.vgdl.java_classes import defaults_of
from gvgai_pcg.vgdl.layout import GRID, RECORD, TABLE
from gvgai_pcg.vgdl.model import GameDescription
from gvgai_pcg.vgdl.plan import Plan, RulePlan, TypePlan
from gvgai_pcg.vgdl.support import STILL_CLASSES

# Per class, its representation and the behaviour parameters a file may set.
SPRITE_KERNELS: dict[str, tuple[str, frozenset[str]]] = {
    # singleton: Java's creation guard (``TypePlan.singleton_guard``); speed: an Immovable never
    # moves; portal (here and below): only the category an agent's observation gives it
    "Immovable": (GRID, frozenset({"singleton", "speed", "portal"})),
    "Door": (GRID, frozenset()),
    "Flicker": (RECORD, frozenset({"limit", "singleton"})),
    "OrientedFlicker": (RECORD, frozenset({"limit", "singleton"})),
    "ShootAvatar": (RECORD, frozenset({"stype", "speed"})),
    "RandomNPC": (TABLE, frozenset({"speed", "cooldown", "cons"})),
    "OngoingAvatar": (RECORD, frozenset({"speed"})),
    "Passive": (GRID, frozenset({"portal"})),
    "Resource": (GRID, frozenset({"limit", "value"})),
    "MovingAvatar": (RECORD, frozenset({"speed"})),
    "Missile": (TABLE, frozenset({"speed", "cooldown", "orientation"})),
    "SpawnPoint": (GRID, frozenset({"stype", "prob", "cooldown", "total", "portal"})),
}
# Classes whose kernels also hold them in another representation.
MORE_REPRESENTATIONS: dict[str, frozenset[str]] = {
    "Immovable": frozenset({TABLE}),
    "Passive": frozenset({TABLE}),
    "Flicker": frozenset({TABLE}),
    "SpawnPoint": frozenset({TABLE}),
}
# Parameters that change only how a sprite is drawn.
COSMETIC = frozenset(
    {"img", "color", "hidden", "invisible", "autotiling", "randomtiling", "frameRate", "shrinkfactor"}
)
# Per effect, the parameters its kernel reads; every other must keep Java's default.
EFFECT_KERNELS: dict[str, frozenset[str]] = {
    "stepBack": frozenset({"pixelPerfect"}),
    "killSprite": frozenset({"scoreChange"}),
    "transformTo": frozenset({"scoreChange", "stype", "killSecond"}),
    "spawn": frozenset({"scoreChange", "stype", "prob"}),
    "spawnIfHasMore": frozenset({"scoreChange", "stype", "resource", "limit"}),
    "changeResource": frozenset({"scoreChange", "resource", "value"}),
    "reverseDirection": frozenset(),
    "collectResource": frozenset({"scoreChange"}),
    "killIfOtherHasMore": frozenset({"scoreChange", "resource", "limit"}),
    "killIfFromAbove": frozenset({"scoreChange"}),
    "shieldFrom": frozenset({"scoreChange", "stype", "ftype", "istype", "iftype"}),
    "pullWithIt": frozenset(),
    "bounceForward": frozenset({"scoreChange"}),
    "undoAll": frozenset(),
    "killBoth": frozenset({"scoreChange"}),
}
# Effects that kill their first sprite, and those that also kill their second (a grid type no
# rule kills is read whole by ``undo``).
KILLING_FIRST = frozenset(
    {"killSprite", "transformTo", "collectResource", "killIfOtherHasMore", "killIfFromAbove", "killBoth"}
)
# Per effect an EOS rule may apply (``eos``), the parameters its kernel reads.
EDGE_KERNELS: dict[str, frozenset[str]] = {
    "stepBack": frozenset(),
    "killSprite": frozenset({"scoreChange"}),
    "wrapAround": frozenset({"scoreChange"}),
}
# Effects that read or change a record's resources (``resources``).
RESOURCE_EFFECTS = frozenset({"collectResource", "killIfOtherHasMore"})
TERMINATION_KERNELS = {
    "SpriteCounter": frozenset({"stype", "limit", "win"}),
    "MultiSpriteCounter": frozenset({"stype1", "stype2", "stype3", "limit", "win"}),
    "Timeout": frozenset({"limit", "win"}),
}


def check_engine(game: GameDescription, plan: Plan) -> None:
    """Refuse the first thing of ``plan`` the generic step has no kernel for."""
    path = plan.path
    for name, sprite in plan.types.items():
        if not _used(game, plan, name):
            continue
        kernel = SPRITE_KERNELS.get(sprite.java_class)
        if kernel is None:
            raise VGDLError(
                path,
                sprite.line,
                f"sprite class {sprite.java_class} ({name}) has no kernel in the generic step yet",
            )
        representation, settable = kernel
        if sprite.representation not in {representation} | MORE_REPRESENTATIONS.get(sprite.java_class, set()):
            raise VGDLError(
                path,
                sprite.line,
                f"{name}: a {sprite.java_class} held as a {sprite.representation} ({sprite.why}) "
                "has no kernel yet",
            )
        own = game.types[name].parameters if sprite.line else {}  # Java's pre-defined wall/avatar: its own
        for parameter in own:
            if parameter not in settable and parameter not in COSMETIC:
                raise VGDLError(
                    path,
                    sprite.line,
                    f"{name}: parameter {parameter} of {sprite.java_class} is not implemented",
                )
        if sprite.java_class == "ShootAvatar":
            _check_shooter(plan, name)
        if sprite.representation == TABLE and sprite.java_class in ("Flicker",) and sprite.singleton:
            raise VGDLError(path, sprite.line, f"{name}: a singleton Flicker in a table is not implemented")
        if sprite.java_class == "Missile":
            _check_missile(plan, name)
        if sprite.java_class == "SpawnPoint":
            _check_spawner(plan, name)
    for rule in plan.eos:
        _check_edge_rule(plan, rule)
    for rule in plan.timed:
        raise VGDLError(path, rule.line, "timed effects are not implemented by the generic step yet")
    for rule in plan.pairs:
        _check_rule(plan, rule)
    _check_off_grid(plan)
    for termination in plan.terminations:
        settable = TERMINATION_KERNELS.get(termination.java_class)
        if settable is None:
            raise VGDLError(
                path,
                termination.line,
                f"termination {termination.java_class} is not implemented by the generic step yet",
            )
        extra = [
            key
            for key in termination.values
            if key not in settable
            and key not in ("itype", "itype1", "itype2", "itype3", "min", "count_score", "canEnd")
            and key not in ("use_counter", "compare", "limits")  # Timeout's, refused below when set
        ]
        if termination.values.get("min"):
            extra.append("min")
        if termination.java_class == "Timeout":  # the counters decide the winner only with use_counter
            extra += [key for key in ("use_counter", "compare") if termination.values.get(key)]
        if extra or termination.values.get("count_score") or termination.values.get("canEnd") is False:
            raise VGDLError(
                path,
                termination.line,
                f"{termination.java_class}: {', '.join(extra) or 'count_score, canEnd'} not implemented",
            )


def _used(game: GameDescription, plan: Plan, name: str) -> bool:
    """A type whose sprites can exist: placed by a level character, created, or defined in the
    file (Java's pre-defined ``avatar``/``wall`` count only when placed)."""
    placed = any(name in types for types in plan.level_mapping.values())
    return placed or bool(plan.types[name].created_by) or game.types[name].line > 0


def _check_shooter(plan: Plan, name: str) -> None:
    sprite = plan.types[name]
    stype = sprite.values.get("stype")
    made = plan.types.get(stype) if isinstance(stype, str) else None
    if sprite.step_px != plan.cell:
        raise VGDLError(
            plan.path, sprite.line, f"{name}: a ShootAvatar moving {sprite.step_px} px is not implemented"
        )
    if made is None or made.representation != RECORD or made.java_class not in ("Flicker", "OrientedFlicker"):
        raise VGDLError(
            plan.path,
            sprite.line,
            f"{name}: ShootAvatar's stype must be a singleton Flicker in the generic step",
        )


def _check_missile(plan: Plan, name: str) -> None:
    orientation = getattr(plan.types[name].values.get("orientation"), "name", None)
    if orientation not in ("DLEFT", "DRIGHT", "DUP", "DDOWN", "DNONE"):
        raise VGDLError(
            plan.path, plan.types[name].line, f"{name}: a Missile oriented {orientation} is not implemented"
        )


def _check_spawner(plan: Plan, name: str) -> None:
    sprite = plan.types[name]
    stype = sprite.values.get("stype")
    made = plan.types.get(stype) if isinstance(stype, str) else None
    if (
        made is None
        or made.representation != TABLE
        or made.java_class not in ("Missile", "RandomNPC")
        or made.singleton_guard
    ):
        raise VGDLError(
            plan.path,
            sprite.line,
            f"{name}: a SpawnPoint is implemented for an stype of one Missile or RandomNPC type held "
            "in a table",
        )
    if sprite.representation == TABLE and (sprite.created_by or float(sprite.values.get("prob", 1)) < 1):
        raise VGDLError(
            plan.path,
            sprite.line,
            f"{name}: a SpawnPoint held as a table is implemented for level spawners with prob 1",
        )


def _check_edge_rule(plan: Plan, rule: RulePlan) -> None:
    path, line = plan.path, rule.line
    settable = EDGE_KERNELS.get(rule.name)
    if settable is None:
        raise VGDLError(path, line, f"EOS effect {rule.name} is not implemented by the generic step yet")
    defaults = defaults_of("effect", rule.java_class)
    for key, value in rule.values.items():
        if key in settable or key in ("scoreChange", "counter", "counterElse"):
            continue
        if key in defaults and value != defaults[key]:
            raise VGDLError(path, line, f"EOS {rule.name}: parameter {key}={value} is not implemented")
    if rule.name == "stepBack" and score_of(plan, rule) != 0:
        raise VGDLError(path, line, "stepBack with a scoreChange is not implemented")
    for name in rule.firsts:
        sprite = plan.types[name]
        oriented = sprite.representation == RECORD or sprite.java_class == "Missile"
        if rule.name == "wrapAround" and sprite.representation != GRID and not oriented:
            raise VGDLError(
                path,
                line,
                f"EOS wrapAround of {name} (a {sprite.java_class}, no orientation held) is not implemented",
            )
        if rule.name == "wrapAround" and int(sprite.values.get("cooldown") or 1) > 1:
            # Java's wrap sets lastmove := 0, which ``eos.edge_wrap`` does not hold
            raise VGDLError(path, line, f"EOS wrapAround of {name} (cooldown above 1) is not implemented")


def _check_rule(plan: Plan, rule: RulePlan) -> None:
    path, line = plan.path, rule.line
    settable = EFFECT_KERNELS.get(rule.name)
    if settable is None:
        raise VGDLError(path, line, f"effect {rule.name} is not implemented by the generic step yet")
    defaults = defaults_of("effect", rule.java_class)
    for key, value in rule.values.items():
        if key in settable or key in ("scoreChange", "counter", "counterElse"):
            continue
        if key in defaults and value != defaults[key]:
            raise VGDLError(path, line, f"{rule.name}: parameter {key}={value} is not implemented")
    score = score_of(plan, rule)  # refuses a score the step cannot hold
    if rule.name == "stepBack" and score != 0:
        raise VGDLError(path, line, "stepBack with a scoreChange is not implemented")
    representations = {plan.types[name].representation for name in rule.firsts}
    seconds = {plan.types[name].representation for name in rule.seconds}
    if rule.name not in ("stepBack", "undoAll") and GRID in representations and GRID in seconds:
        raise VGDLError(path, line, f"{rule.name} between two static types is not implemented")
    if rule.name in CREATION_CHECKS:
        CREATION_CHECKS[rule.name](plan, rule)
    if rule.name in RESOURCE_EFFECTS:
        _check_resource_rule(plan, rule)
    if rule.name == "killIfFromAbove" and GRID in representations | seconds:
        raise VGDLError(path, line, "killIfFromAbove with a still (grid) type is not implemented")
    if rule.name == "transformTo" and any(held_columns(plan, name) for name in rule.firsts):
        raise VGDLError(path, line, "transformTo of a sprite holding resources is not implemented")
    if rule.name == "transformTo" and not _into_grid(plan, rule) and not _into_table(plan, rule):
        stype = rule.values.get("stype")
        target = plan.types.get(stype) if isinstance(stype, str) else None
        if target is None or target.representation != RECORD or representations - {RECORD}:
            raise VGDLError(path, line, "transformTo is implemented from record types (the avatar) into one")
        if stype in rule.firsts and not _renewal_unseen(plan, rule, stype):
            # renewed in place, the record cannot also be the killed sprite Java keeps as a second
            raise VGDLError(
                path,
                line,
                f"transformTo of {stype} into itself, with {stype} a second of a rule, is not implemented",
            )
    if rule.name == "shieldFrom":
        _check_shield(plan, rule)
        return
    if rule.name == "pullWithIt":
        _check_pull(plan, rule)
        return
    if rule.name == "bounceForward":
        _check_push(plan, rule)
    if rule.name == "undoAll":
        _check_undo(plan, rule)
    if rule.name == "killBoth":
        _check_kill_both(plan, rule)
    if rule.name == "stepBack" and rule.values.get("pixelPerfect") and rule.kind == "F":
        raise VGDLError(path, line, "a pixelPerfect stepBack among sprites of one group is not implemented")
    if rule.kind == "F":
        same = set(rule.firsts) == set(rule.seconds)
        if rule.name != "stepBack" or not same or representations != {TABLE}:
            raise VGDLError(
                path, line, f"{rule.name} among sprites of one group is implemented for one table only"
            )
    elif (
        rule.kind not in ("P", "A")
        and not (rule.kind == "X" and _scanned(plan, rule))
        and rule.name != "undoAll"
    ):
        raise VGDLError(
            path, line, f"{rule.name}: a rule of kind {rule.kind} ({rule.why}) is not implemented"
        )


def _renewal_unseen(plan: Plan, rule: RulePlan, stype: str) -> bool:
    """Whether renewing ``stype``'s record in place (a transformTo into its own type) gives Java's
    result although Java keeps the killed sprite as a second beside the new one until cleanup: every
    rule after ``rule`` in the tick that has ``stype`` among its seconds is a killSprite of a type
    that is not a record, which kills its first at the first second it meets and so applies once
    whether it meets one such second or two at the same place (labyrinthdual's ``exit avatar``).
    Rules before it ran before the renewal; in later ticks there is one sprite."""
    index = next(i for i, other in enumerate(plan.pairs) if other is rule)
    return all(
        other.name == "killSprite" and all(plan.types[name].representation != RECORD for name in other.firsts)
        for other in plan.pairs[index + 1 :]
        if stype in other.seconds
    )


def _scanned(plan: Plan, rule: RulePlan) -> bool:
    """A rule of kind X with a kernel: collectResource, or a transformTo into a table that a
    singleton guards (``transform_table``: the first creation in processing order)."""
    stype = rule.values.get("stype")
    into_table = isinstance(stype, str) and plan.types[stype].representation == TABLE
    return rule.name == "collectResource" or (rule.name == "transformTo" and into_table)


def _transform_target(plan: Plan, rule: RulePlan, representation: str) -> tuple[object, TypePlan | None]:
    """A transformTo's ``stype`` and its type's plan where it is held as ``representation``
    (else None)."""
    stype = rule.values.get("stype")
    target = plan.types.get(stype) if isinstance(stype, str) else None
    return stype, target if target is not None and target.representation == representation else None


def _into_grid(plan: Plan, rule: RulePlan) -> bool:
    """transformTo from grid types, or table types or records on whole cells, into a grid type
    that no singleton guards (``transform_grid``); refuses the rest of what goes into a grid."""
    stype, target = _transform_target(plan, rule, GRID)
    if target is None:
        return False
    firsts = [plan.types[name] for name in rule.firsts]
    if (
        any(not sprite.aligned for sprite in firsts)
        or rule.values.get("killSecond")
        or stype in rule.firsts + rule.seconds
        or target.singleton_guard
    ):
        raise VGDLError(
            plan.path,
            rule.line,
            "transformTo into a still (grid) type is implemented from types on whole cells, without "
            "killSecond, into a type the rule does not name and no singleton guards",
        )
    return True


def _into_table(plan: Plan, rule: RulePlan) -> bool:
    """transformTo from tables or records into a table whose sprites hold no orientation, without
    killSecond (``transform_table``); refuses the rest of what goes into a table."""
    stype, target = _transform_target(plan, rule, TABLE)
    if target is None:
        return False
    firsts = [plan.types[name] for name in rule.firsts]
    if (
        any(sprite.representation == GRID for sprite in firsts)
        or rule.values.get("killSecond")
        or oriented_table(plan, (str(stype),))
    ):
        raise VGDLError(
            plan.path,
            rule.line,
            "transformTo into a table is implemented from tables or records, without killSecond, into "
            "a type that holds no orientation",
        )
    return True


def _check_off_grid(plan: Plan) -> None:
    """A grid type that a table transforms into also has sprites off the array (``off_grid``):
    read only as a second, a termination's count or collectResource's
    first."""
    made: dict[str, set[str]] = {}
    for rule in plan.pairs:
        stype = rule.values.get("stype")
        if rule.name == "transformTo" and isinstance(stype, str) and plan.types[stype].representation == GRID:
            tables = {name for name in rule.firsts if plan.types[name].representation == TABLE}
            if tables:
                made.setdefault(stype, set()).update(tables)
    for rule in plan.pairs:
        reads_first = rule.name not in ("stepBack", "collectResource") and set(rule.firsts) & set(made)
        kills_second = rule.name == "killBoth" or (
            rule.name == "transformTo" and rule.values.get("killSecond")
        )
        reads_second = kills_second and set(rule.seconds) & set(made)
        if reads_first or reads_second:
            raise VGDLError(
                plan.path,
                rule.line,
                f"{rule.name} of a type that transformTo makes from table sprites is not implemented",
            )


def _check_resource_rule(plan: Plan, rule: RulePlan) -> None:
    """collectResource and killIfOtherHasMore: a grid type as first (collectResource: a Resource),
    seconds on whole cells holding the resource: avatar records that collect it (killIfOtherHasMore:
    or records and tables that a rule gives it to)."""
    firsts = [plan.types[name] for name in rule.firsts]
    seconds = [plan.types[name] for name in rule.seconds]
    resource = rule.firsts[0] if rule.name == "collectResource" else str(rule.values.get("resource"))
    holders = (RECORD,) if rule.name == "collectResource" else (RECORD, TABLE)
    holds = held_resources if rule.name == "collectResource" else held_columns
    if (
        len(firsts) != 1
        or firsts[0].representation != GRID
        or (rule.name == "collectResource" and firsts[0].java_class != "Resource")
        or any(sprite.representation not in holders or not sprite.aligned for sprite in seconds)
        or any(resource not in holds(plan, name) for name in rule.seconds)
        or plan.types[resource].values.get("resource_name") is not None
    ):
        raise VGDLError(
            plan.path,
            rule.line,
            f"{rule.name} is implemented from one still (grid) type onto records"
            f"{'' if rule.name == 'collectResource' else ' or tables'} on whole cells that hold the resource",
        )


def _check_shield(plan: Plan, rule: RulePlan) -> None:
    if any(plan.types[name].representation == GRID for name in rule.firsts):
        raise VGDLError(plan.path, rule.line, "shieldFrom of a still (grid) type is not implemented")
    if str(rule.values.get("ftype")) not in EFFECT_KERNELS:
        raise VGDLError(plan.path, rule.line, f"shieldFrom: ftype={rule.values.get('ftype')} has no kernel")


def _check_pull(plan: Plan, rule: RulePlan) -> None:
    firsts = [plan.types[name] for name in rule.firsts]
    seconds = {plan.types[name].java_class for name in rule.seconds}
    same_line = [other for other in plan.pairs if other.effect == rule.effect]
    if (
        len(firsts) != 1
        or firsts[0].representation != RECORD
        or firsts[0].java_class != "MovingAvatar"
        or seconds != {"Missile"}
        or any(plan.types[name].representation != TABLE for name in rule.seconds)
        or len(same_line) != 1
        or score_of(plan, rule) != 0
    ):
        raise VGDLError(
            plan.path,
            rule.line,
            "pullWithIt is implemented for a MovingAvatar pulled by Missiles (one table), one pair a "
            "line, no score",
        )


def _check_push(plan: Plan, rule: RulePlan) -> None:
    """bounceForward (``push``): tables of still classes with no speed or cooldown of their own,
    pushed by records; a push among sprites of one type (a chain push) is refused."""
    firsts = [plan.types[name] for name in rule.firsts]
    if rule.kind == "F":
        raise VGDLError(
            plan.path, rule.line, "bounceForward among sprites of one type (a chain push) is not implemented"
        )
    if any(
        sprite.representation != TABLE
        or sprite.java_class not in STILL_CLASSES
        or float(sprite.values["speed"]) != 0
        or float(sprite.values["cooldown"]) != 0
        or sprite.values.get("rotateInPlace")
        for sprite in firsts
    ) or any(plan.types[name].representation != RECORD for name in rule.seconds):
        raise VGDLError(
            plan.path,
            rule.line,
            "bounceForward is implemented for still sprites in tables (no speed, no cooldown) pushed "
            "by records",
        )


def _check_undo(plan: Plan, rule: RulePlan) -> None:
    """undoAll (``undo``): no score; a grid first only of a type no rule kills."""
    if score_of(plan, rule) != 0:
        raise VGDLError(plan.path, rule.line, "undoAll with a scoreChange is not implemented")
    for name in rule.firsts:
        if plan.types[name].representation == GRID and _killed(plan, name):
            raise VGDLError(
                plan.path, rule.line, f"undoAll with {name}, a killed still type, as first is not implemented"
            )


def _check_kill_both(plan: Plan, rule: RulePlan) -> None:
    """killBoth (``kill_both``): pairs of types that share no type, no avatar first, seconds in
    tables only where their slots are Java's list order (nothing creates them)."""
    created = any(
        plan.types[name].representation == TABLE and plan.types[name].created_by for name in rule.seconds
    )
    avatar = any(plan.types[name].java_class.endswith("Avatar") for name in rule.firsts)
    if rule.kind != "P" or created or avatar:
        raise VGDLError(
            plan.path,
            rule.line,
            "killBoth is implemented between types that share none, with no avatar first, of seconds "
            "no rule creates in a table",
        )


def _killed(plan: Plan, name: str) -> bool:
    """Whether some rule kills sprites of type ``name``."""
    for rule in plan.pairs:
        if rule.name in KILLING_FIRST and name in rule.firsts:
            return True
        kills_second = rule.name == "killBoth" or rule.values.get("killSecond")
        if kills_second and name in rule.seconds:
            return True
    return False


def score_of(plan: Plan, rule: RulePlan) -> int:
    """The rule's scoreChange as an int (Java's first player's), refused otherwise."""
    text = str(rule.values.get("scoreChange", "0")).split(",")[0]
    try:
        return int(text)
    except ValueError:
        raise VGDLError(plan.path, rule.line, f"scoreChange={text} is not an integer score") from None


def _check_spawn(plan: Plan, rule: RulePlan) -> None:
    """spawn / spawnIfHasMore: firsts that move or are made (records, tables), into a grid or a
    table that is not a singleton; a spawnIfHasMore that spends nothing."""
    path, line = plan.path, rule.line
    stype = rule.values.get("stype")
    target = plan.types.get(stype) if isinstance(stype, str) else None
    if target is None or target.representation == RECORD or target.singleton_guard:
        raise VGDLError(
            path, line, f"{rule.name} into {stype!r}: only into a grid or a table, not a singleton"
        )
    if any(plan.types[name].representation == GRID for name in rule.firsts) and (
        rule.name != "spawn"
        or float(rule.values.get("prob", 1)) < 1
        or (target.representation == TABLE and target.java_class == "Missile")
        or any(plan.types[name].representation == GRID for name in rule.seconds)
    ):
        # a grid's cells spawn in row-major order, not list order: no draws, no list order kept
        raise VGDLError(
            path,
            line,
            f"{rule.name} from a still (grid) type is implemented for spawn with prob 1 into a grid or "
            "a table that keeps no list order, with records or tables as seconds",
        )
    if target.representation == GRID and not all(plan.types[name].aligned for name in rule.firsts):
        raise VGDLError(path, line, f"{rule.name} into a grid from sprites off the cells is not implemented")
    if rule.name == "spawnIfHasMore" and rule.values.get("spend"):
        raise VGDLError(path, line, "spawnIfHasMore with spend is not implemented")


def _check_change_resource(plan: Plan, rule: RulePlan) -> None:
    path, line = plan.path, rule.line
    if int(rule.values.get("value", 1)) <= 0 or rule.values.get("killResource"):
        raise VGDLError(path, line, "changeResource with a value below 1 or killResource is not implemented")
    if any(plan.types[name].representation == GRID for name in rule.firsts):
        raise VGDLError(path, line, "changeResource on a still (grid) type is not implemented")


def _check_reverse(plan: Plan, rule: RulePlan) -> None:
    if any(plan.types[name].java_class != "Missile" for name in rule.firsts):
        raise VGDLError(plan.path, rule.line, "reverseDirection is implemented for Missiles only")


# Effects that need more than their parameters checked.
CREATION_CHECKS = {
    "spawn": _check_spawn,
    "spawnIfHasMore": _check_spawn,
    "changeResource": _check_change_resource,
    "reverseDirection": _check_reverse,
}
