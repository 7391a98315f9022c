"""Java's VGDL vocabulary: every sprite class, effect and termination GVGAI's registry knows,
with the public fields a VGDL line may set and the defaults Java gives them.

Read from GVGAI's sources (``VGDLFactory``'s name lists; each class's public fields, its
``loadDefaults()`` chain or, for effects and terminations, what its constructor sets before
``parseParameters``). A field is settable from VGDL iff it is public (Java's ``getFields``),
inherited fields included; Java logs any other parameter as an unknown field and ignores it,
this package refuses it. Defaults are what the field holds before the line's parameters are
applied; fields that Java derives after parsing (``itype`` from ``stype``, ...) are not listed
as defaults. ``Const("GRAY")`` is a named constant of Java's ``Types`` (a colour or a
direction, ``DNONE`` = no orientation); Types' int constants are written as their values.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass


@dataclass(frozen=True)
class Const:
    """A named constant of Java's ``Types`` (``GRAY``, ``DUP``, ``DNONE``, ...)."""

    name: str


@dataclass(frozen=True)
class JavaClass:
    """One Java class: its superclass (a key of the same table), its own public fields
    (name -> Java type, ``"... static"`` for a static one) and the defaults it sets."""

    parent: str | None
    fields: Mapping[str, str]
    defaults: Mapping[str, object]


SPRITE_CLASSES: dict[str, JavaClass] = {
    "Conveyor": JavaClass(
        "VGDLSprite",
        {},
        {
            "is_static": True,
            "color": Const("BLUE"),
            "jump_strength": 1,
            "draw_arrow": True,
            "is_oriented": True,
        },
    ),
    "VGDLSprite": JavaClass(
        None,
        {
            "name": "String",
            "is_static": "boolean",
            "only_active": "boolean",
            "is_avatar": "boolean",
            "is_stochastic": "boolean",
            "color": "Color",
            "cooldown": "int",
            "speed": "double",
            "stationary": "boolean",
            "mass": "double",
            "physicstype": "int",
            "physics": "Physics",
            "gravity": "double",
            "friction": "double",
            "shrinkfactor": "double",
            "is_oriented": "boolean",
            "draw_arrow": "boolean",
            "orientation": "Direction",
            "rect": "Rectangle",
            "lastrect": "Rectangle",
            "lastmove": "int",
            "jump_strength": "double",
            "singleton": "boolean",
            "is_resource": "boolean",
            "portal": "boolean",
            "invisible": "String",
            "hidden": "String",
            "autotiling": "boolean",
            "randomtiling": "double",
            "frameRate": "double",
            "frameRemaining": "double",
            "currentFrame": "int",
            "itypes": "ArrayList<Integer>",
            "image": "Image",
            "img": "String",
            "orientedImg": "String",
            "is_npc": "boolean",
            "spriteID": "int",
            "is_from_avatar": "boolean",
            "bucket": "int",
            "bucketSharp": "boolean",
            "rotateInPlace": "boolean",
            "isFirstTick": "boolean",
            "healthPoints": "int",
            "maxHealthPoints": "int",
            "limitHealthPoints": "int",
            "timeToLive": "int",
            "rotation": "double",
            "wMult": "double",
            "hMult": "double",
            "size": "Dimension",
            "on_ground": "boolean",
            "solid": "boolean",
            "max_speed": "double",
        },
        {
            "timeToLive": -1,
            "hMult": 1.0,
            "physicstype": 0,  # Types.GRID
            "physics": None,
            "gravity": 0.0,
            "friction": 0.0,
            "speed": 0,
            "stationary": False,
            "cooldown": 0,
            "color": None,
            "only_active": False,
            "is_static": False,
            "is_avatar": False,
            "is_stochastic": False,
            "is_from_avatar": False,
            "mass": 1,
            "shrinkfactor": 1.0,
            "autotiling": False,
            "randomtiling": -1,
            "frameRate": -1,
            "frameRemaining": 0,
            "currentFrame": -1,
            "is_oriented": False,
            "draw_arrow": False,
            "orientation": Const("DNONE"),
            "lastmove": 0,
            "invisible": "false",
            "rotateInPlace": False,
            "isFirstTick": True,
            "limitHealthPoints": 1000,
            "rotation": 0.0,
            "max_speed": -1.0,
            "wMult": 1.0,
        },
    ),
    "Flicker": JavaClass(
        "VGDLSprite",
        {"limit": "int", "age": "int"},
        {"limit": 1, "age": 0, "color": Const("RED")},
    ),
    "Immovable": JavaClass(
        "VGDLSprite",
        {},
        {"color": Const("GRAY"), "is_static": True},
    ),
    "OrientedFlicker": JavaClass(
        "Flicker",
        {},
        {"draw_arrow": True, "speed": 0, "is_oriented": True},
    ),
    "Passive": JavaClass(
        "VGDLSprite",
        {},
        {"color": Const("RED")},
    ),
    "Resource": JavaClass(
        "Passive",
        {"value": "int", "limit": "int", "resource_type": "int", "resource_name": "String"},
        {"limit": 2, "value": 1, "color": Const("YELLOW"), "resource_type": -1, "is_resource": True},
    ),
    "Spreader": JavaClass(
        "Flicker",
        {"spreadprob": "double", "stype": "String", "itype": "int"},
        {"spreadprob": 1.0},
    ),
    "ErraticMissile": JavaClass(
        "Missile",
        {},
        {},
    ),
    "Missile": JavaClass(
        "VGDLSprite",
        {},
        {"speed": 1, "is_oriented": True},
    ),
    "RandomMissile": JavaClass(
        "Missile",
        {},
        {"orientation": Const("DNIL")},
    ),
    "Walker": JavaClass(
        "VGDLSprite",
        {"airsteering": "boolean"},
        {
            "speed": 5,
            "max_speed": 5,
            "is_oriented": True,
            "airsteering": False,
            "is_stochastic": True,
            "on_ground": False,
        },
    ),
    "WalkerJumper": JavaClass(
        "Walker",
        {"probability": "double"},
        {"probability": 0.1, "jump_strength": 1, "max_speed": 5.0},
    ),
    "ResourcePack": JavaClass(
        "Resource",
        {},
        {"is_static": True},
    ),
    "Chaser": JavaClass(
        "RandomNPC",
        {"fleeing": "boolean", "stype": "String", "itype": "int", "maxDistance": "float"},
        {"fleeing": False, "maxDistance": -1},
    ),
    "RandomNPC": JavaClass(
        "VGDLSprite",
        {"cons": "int"},
        {"speed": 1, "cons": 0, "is_npc": True, "is_stochastic": True},
    ),
    "PathChaser": JavaClass(
        "RandomNPC",
        {"fleeing": "boolean", "stype": "String", "itype": "int", "maxDistance": "float"},
        {"fleeing": False, "maxDistance": -1},
    ),
    "Fleeing": JavaClass(
        "Chaser",
        {},
        {"fleeing": True},
    ),
    "RandomInertial": JavaClass(
        "RandomNPC",
        {},
        {"physicstype": 1, "is_oriented": True},  # physicstype = Types.CONT
    ),
    "AlternateChaser": JavaClass(
        "RandomNPC",
        {"fleeing": "boolean", "stype1": "String", "stype2": "String", "itype1": "int[]", "itype2": "int[]"},
        {"fleeing": False},
    ),
    "RandomAltChaser": JavaClass(
        "AlternateChaser",
        {"epsilon": "double"},
        {"epsilon": 0.0},
    ),
    "PathAltChaser": JavaClass(
        "AlternateChaser",
        {"randomTarget": "boolean"},
        {"fleeing": False, "randomTarget": False},
    ),
    "RandomPathAltChaser": JavaClass(
        "PathAltChaser",
        {"epsilon": "double"},
        {"epsilon": 0.0},
    ),
    "Bomber": JavaClass(
        "SpawnPoint",
        {},
        {
            "color": Const("ORANGE"),
            "is_static": False,
            "is_oriented": True,
            "orientation": Const("DRIGHT"),
            "is_npc": True,
        },
    ),
    "SpawnPoint": JavaClass(
        "SpriteProducer",
        {
            "prob": "double",
            "total": "int",
            "counter": "int",
            "stype": "String",
            "itype": "int",
            "spawnorientation": "Direction",
        },
        {
            "prob": 1.0,
            "total": 0,
            "color": Const("BLACK"),
            "cooldown": 1,
            "is_static": True,
            "spawnorientation": Const("DNONE"),
            "itype": -1,
        },
    ),
    "SpriteProducer": JavaClass(
        "VGDLSprite",
        {},
        {},
    ),
    "RandomBomber": JavaClass(
        "SpawnPoint",
        {},
        {
            "color": Const("ORANGE"),
            "is_static": False,
            "is_oriented": True,
            "orientation": Const("DRIGHT"),
            "is_npc": True,
            "is_stochastic": True,
            "speed": 1.0,
        },
    ),
    "Portal": JavaClass(
        "SpriteProducer",
        {"stype": "String", "itype": "int"},
        {"is_static": True, "portal": True, "color": Const("BLUE")},
    ),
    "Door": JavaClass(
        "Immovable",
        {},
        {"portal": True},
    ),
    "FlakAvatar": JavaClass(
        "HorizontalAvatar",
        {
            "stype": "String",
            "itype": "int",
            "ammo": "String",
            "ammoId": "int",
            "minAmmo": "int",
            "ammoCost": "int",
        },
        {"ammo": None, "ammoId": -1, "minAmmo": -1, "ammoCost": 1, "color": Const("GREEN")},
    ),
    "HorizontalAvatar": JavaClass(
        "MovingAvatar",
        {},
        {},
    ),
    "MovingAvatar": JavaClass(
        "VGDLSprite",
        {
            "actions": "ArrayList<Types.ACTIONS>",
            "actionsNIL": "ArrayList<Types.ACTIONS>",
            "player": "Player",
            "lastMovementType": "Types.MOVEMENT",
        },
        {"color": Const("WHITE"), "speed": 1, "is_avatar": True},
    ),
    "VerticalAvatar": JavaClass(
        "MovingAvatar",
        {},
        {},
    ),
    "MissileAvatar": JavaClass(
        "OrientedAvatar",
        {},
        {"speed": 1, "is_oriented": True},
    ),
    "OrientedAvatar": JavaClass(
        "MovingAvatar",
        {},
        {"orientation": Const("DRIGHT"), "draw_arrow": True, "is_oriented": True, "rotateInPlace": True},
    ),
    "ShootAvatar": JavaClass(
        "OrientedAvatar",
        {
            "ammo": "String",
            "ammos": "String[]",
            "ammoId": "int[]",
            "stype": "String",
            "stypes": "String[]",
            "itype": "int[]",
        },
        {"ammo": None, "stype": None},
    ),
    "OngoingAvatar": JavaClass(
        "OrientedAvatar",
        {},
        {"speed": 1, "is_oriented": True},
    ),
    "OngoingTurningAvatar": JavaClass(
        "OrientedAvatar",
        {"spawnBehind": "String"},
        {"speed": 1, "is_oriented": True},
    ),
    "BomberRandomMissile": JavaClass(
        "SpawnPoint",
        {"stypeMissile": "String"},
        {
            "color": Const("ORANGE"),
            "is_static": False,
            "is_oriented": True,
            "orientation": Const("DRIGHT"),
            "is_npc": True,
        },
    ),
    "OngoingShootAvatar": JavaClass(
        "ShootAvatar",
        {},
        {"speed": 1, "is_oriented": True},
    ),
    "NullAvatar": JavaClass(
        "HorizontalAvatar",
        {},
        {"color": Const("GREEN")},
    ),
    "AimedAvatar": JavaClass(
        "ShootAvatar",
        {"angle_diff": "double"},
        {"angle_diff": 0.15, "speed": 0, "stationary": True},
    ),
    "PlatformerAvatar": JavaClass(
        "MovingAvatar",
        {"ground_speedup_factor": "double", "air_slowdown_factor": "double"},
        {
            "draw_arrow": False,
            "jump_strength": 10,
            "on_ground": False,
            "ground_speedup_factor": 1.0,
            "air_slowdown_factor": 2.0,
            "max_speed": 30.0,
        },
    ),
    "BirdAvatar": JavaClass(
        "OrientedAvatar",
        {},
        {"draw_arrow": True, "jump_strength": 10},
    ),
    "SpaceshipAvatar": JavaClass(
        "ShootAvatar",
        {"angle_diff": "double"},
        {"angle_diff": 0.3, "speed": 5, "orientation": Const("DNONE")},
    ),
    "CarAvatar": JavaClass(
        "OrientedAvatar",
        {"angle_diff": "double", "facing": "double"},
        {"angle_diff": 0.15, "facing": 0, "speed": 0},
    ),
    "WizardAvatar": JavaClass(
        "MovingAvatar",
        {
            "ground_speedup_factor": "double",
            "air_slowdown_factor": "double",
            "stype": "String",
            "stypes": "String[]",
            "itype": "int[]",
            "facing_dir": "Direction",
            "last_block_time": "int",
        },
        {
            "draw_arrow": False,
            "jump_strength": 10,
            "on_ground": False,
            "speed": 0,
            "stype": None,
            "last_block_time": 0,
            "ground_speedup_factor": 1.0,
            "air_slowdown_factor": 2.0,
            "max_speed": 30.0,
        },
    ),
    "LanderAvatar": JavaClass(
        "OrientedAvatar",
        {"angle_diff": "double"},
        {"angle_diff": 0.3, "speed": 5, "orientation": Const("DNONE")},
    ),
    "ShootOnlyAvatar": JavaClass(
        "ShootAvatar",
        {},
        {},
    ),
    "SpawnPointMultiSprite": JavaClass(
        "SpriteProducer",
        {
            "prob": "double",
            "total": "int",
            "counter": "int",
            "spawnorientation": "Direction",
            "stypes": "String",
        },
        {
            "prob": 1.0,
            "total": 0,
            "color": Const("BLACK"),
            "cooldown": 1,
            "is_static": True,
            "spawnorientation": Const("DNONE"),
            "is_oriented": True,
            "orientation": Const("DRIGHT"),
            "is_npc": True,
        },
    ),
    "LOSChaser": JavaClass(
        "Chaser",
        {},
        {},
    ),
}
EFFECT_CLASSES: dict[str, JavaClass] = {
    "StepBack": JavaClass(
        "Effect",
        {"pixelPerfect": "boolean"},
        {"pixelPerfect": False},
    ),
    "Effect": JavaClass(
        None,
        {
            "is_kill_effect": "boolean",
            "is_stochastic": "boolean",
            "sequential": "boolean",
            "scoreChange": "String",
            "count": "boolean",
            "counter": "String",
            "countElse": "boolean",
            "counterElse": "String",
            "prob": "double",
            "applyScore": "boolean",
            "repeat": "int",
            "hashCode": "long",
            "enabled": "boolean",
            "inBatch": "boolean",
        },
        {
            "is_kill_effect": False,
            "is_stochastic": False,
            "sequential": False,
            "scoreChange": "0",
            "count": True,
            "counter": "0",
            "countElse": True,
            "counterElse": "0",
            "prob": 1,
            "applyScore": True,
            "repeat": 1,
            "inBatch": False,
        },
    ),
    "TurnAround": JavaClass(
        "Effect",
        {},
        {},
    ),
    "KillSprite": JavaClass(
        "Effect",
        {},
        {"is_kill_effect": True},
    ),
    "KillBoth": JavaClass(
        "Effect",
        {},
        {"is_kill_effect": True},
    ),
    "KillAll": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int"},
        {"is_kill_effect": True},
    ),
    "TransformTo": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int", "killSecond": "boolean", "forceOrientation": "boolean"},
        {"killSecond": False, "forceOrientation": False, "is_kill_effect": True},
    ),
    "TransformToSingleton": JavaClass(
        "Effect",
        {
            "stype": "String",
            "itype": "int",
            "takeOrientation": "boolean",
            "stype_other": "String",
            "itype_other": "int",
        },
        {"takeOrientation": False, "is_kill_effect": True},
    ),
    "TransformIfCount": JavaClass(
        "TransformTo",
        {
            "stypeCount": "String",
            "itypeCount": "int",
            "estype": "String",
            "eitype": "int",
            "geq": "int",
            "leq": "int",
        },
        {"geq": 0},
    ),
    "WrapAround": JavaClass(
        "Effect",
        {"offset": "double"},
        {},
    ),
    "ChangeResource": JavaClass(
        "Effect",
        {"resource": "String", "resourceId": "int", "value": "int", "killResource": "boolean"},
        {"value": 1, "resourceId": -1, "killResource": False},
    ),
    "KillIfHasLess": JavaClass(
        "Effect",
        {"resource": "String", "resourceId": "int", "limit": "int"},
        {"is_kill_effect": True, "resourceId": -1},
    ),
    "KillIfHasMore": JavaClass(
        "Effect",
        {"resource": "String", "resourceId": "int", "limit": "int"},
        {"is_kill_effect": True, "resourceId": -1},
    ),
    "CloneSprite": JavaClass(
        "Effect",
        {},
        {},
    ),
    "FlipDirection": JavaClass(
        "Effect",
        {},
        {"is_stochastic": True},
    ),
    "ReverseDirection": JavaClass(
        "Effect",
        {},
        {},
    ),
    "ShieldFrom": JavaClass(
        "Effect",
        {"stype": "String", "istype": "int", "ftype": "String", "iftype": "long"},
        {},
    ),
    "UndoAll": JavaClass(
        "Effect",
        {"notStype": "String"},
        {},
    ),
    "Spawn": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int"},
        {},
    ),
    "SpawnIfHasMore": JavaClass(
        "Effect",
        {
            "spend": "int",
            "resource": "String",
            "resourceId": "int",
            "limit": "int",
            "stype": "String",
            "itype": "int",
        },
        {"resourceId": -1, "spend": 0},
    ),
    "SpawnIfHasLess": JavaClass(
        "Effect",
        {"resource": "String", "resourceId": "int", "limit": "int", "stype": "String", "itype": "int"},
        {"resourceId": -1},
    ),
    "PullWithIt": JavaClass(
        "Effect",
        {"pixelPerfect": "boolean"},
        {"pixelPerfect": False},
    ),
    "WallStop": JavaClass(
        "Effect",
        {},
        {},
    ),
    "CollectResource": JavaClass(
        "Effect",
        {"killResource": "boolean"},
        {"killResource": True},
    ),
    "CollectResourceIfHeld": JavaClass(
        "Effect",
        {"killResource": "boolean", "heldResource": "String", "heldResourceId": "int", "value": "int"},
        {"value": 1, "killResource": True},
    ),
    "KillIfOtherHasMore": JavaClass(
        "Effect",
        {"resource": "String", "resourceId": "int", "limit": "int", "subtract": "boolean"},
        {"is_kill_effect": True, "resourceId": -1, "subtract": False},
    ),
    "KillIfFromAbove": JavaClass(
        "Effect",
        {},
        {"is_kill_effect": True},
    ),
    "TeleportToExit": JavaClass(
        "Effect",
        {},
        {},
    ),
    "BounceForward": JavaClass(
        "Effect",
        {},
        {},
    ),
    "AttractGaze": JavaClass(
        "Effect",
        {"align": "boolean"},
        {"align": False},
    ),
    "Align": JavaClass(
        "Effect",
        {"orient": "boolean"},
        {"orient": True},
    ),
    "SubtractHealthPoints": JavaClass(
        "Effect",
        {"value": "int", "stype": "String", "itype": "int", "limit": "int", "scoreChangeIfKilled": "String"},
        {
            "stype": "",
            "itype": -1,
            "is_kill_effect": True,
            "limit": 0,
            "value": 1,
            "scoreChangeIfKilled": "0",
        },
    ),
    "AddHealthPoints": JavaClass(
        "Effect",
        {"value": "int", "killSecond": "boolean"},
        {"killSecond": False, "value": 1},
    ),
    "TransformToAll": JavaClass(
        "TransformTo",
        {"stypeTo": "String", "itypeTo": "int"},
        {},
    ),
    "AddTimer": JavaClass(
        "TimeEffect",
        {"ftype": "String", "timerDelegate": "Effect"},
        {},
    ),
    "TimeEffect": JavaClass(
        "Effect",
        {
            "timer": "int",
            "nextExecution": "int",
            "repeating": "boolean",
            "itype": "int",
            "isNative": "boolean",
            "delegate": "Effect",
        },
        {"timer": -1, "nextExecution": -1, "repeating": False, "isNative": True},
    ),
    "KillIfScoreNegative": JavaClass(
        "Effect",
        {},
        {"is_kill_effect": True},
    ),
    "KillIfFrontal": JavaClass(
        "Effect",
        {},
        {"is_kill_effect": True},
    ),
    "KillIfNotFrontal": JavaClass(
        "Effect",
        {},
        {"is_kill_effect": True},
    ),
    "SpawnBehind": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int"},
        {},
    ),
    "UpdateSpawnType": JavaClass(
        "Effect",
        {"stype": "String", "spawnPoint": "String", "itype": "int", "ispawn": "int"},
        {},
    ),
    "RemoveScore": JavaClass(
        "Effect",
        {"killSecond": "boolean", "stype": "String", "itype": "int"},
        {"killSecond": False, "stype": "", "itype": -1},
    ),
    "IncreaseSpeedToAll": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int", "value": "double"},
        {"value": 0.1, "is_stochastic": True},
    ),
    "DecreaseSpeedToAll": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int", "value": "double"},
        {"value": 0.1, "is_stochastic": True},
    ),
    "SetSpeedForAll": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int", "value": "double"},
        {"value": 0, "is_stochastic": True},
    ),
    "TransformToRandomChild": JavaClass(
        "TransformTo",
        {},
        {},
    ),
    "AddHealthPointsToMax": JavaClass(
        "Effect",
        {"value": "int", "killSecond": "boolean"},
        {"killSecond": False, "value": 1},
    ),
    "SpawnIfCounterSubTypes": JavaClass(
        "Effect",
        {
            "stype": "String",
            "itype": "int",
            "estype": "String",
            "eitype": "int",
            "stypeCount": "String",
            "citype": "int",
            "subTypesNum": "int",
            "limit": "int",
        },
        {"subTypesNum": -1},
    ),
    "BounceDirection": JavaClass(
        "Effect",
        {"maxBounceAngleDeg": "double"},
        {"maxBounceAngleDeg": 60},
    ),
    "WallBounce": JavaClass(
        "Effect",
        {},
        {"inBatch": True},
    ),
    "KillIfSlow": JavaClass(
        "Effect",
        {"limspeed": "double"},
        {"is_kill_effect": True, "limspeed": 1.0},
    ),
    "KillIfAlive": JavaClass(
        "Effect",
        {},
        {"is_kill_effect": True},
    ),
    "WaterPhysics": JavaClass(
        "Effect",
        {},
        {},
    ),
    "HalfSpeed": JavaClass(
        "Effect",
        {},
        {},
    ),
    "KillIfNotUpright": JavaClass(
        "Effect",
        {},
        {"is_kill_effect": True},
    ),
    "KillIfFast": JavaClass(
        "Effect",
        {"limspeed": "double"},
        {"is_kill_effect": True, "limspeed": 1.0},
    ),
    "WallReverse": JavaClass(
        "Effect",
        {},
        {"inBatch": True},
    ),
    "SpawnAbove": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int", "stepBack": "boolean"},
        {"stepBack": False},
    ),
    "SpawnLeft": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int", "stepBack": "boolean"},
        {"stepBack": False},
    ),
    "SpawnRight": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int", "stepBack": "boolean"},
        {"stepBack": False},
    ),
    "SpawnBelow": JavaClass(
        "Effect",
        {"stype": "String", "itype": "int", "stepBack": "boolean"},
        {"stepBack": False},
    ),
}
TERMINATION_CLASSES: dict[str, JavaClass] = {
    "MultiSpriteCounter": JavaClass(
        "Termination",
        {
            "stype1": "String",
            "stype2": "String",
            "stype3": "String",
            "itype1": "int",
            "itype2": "int",
            "itype3": "int",
            "min": "boolean",
        },
        {"itype1": -1, "itype2": -1, "itype3": -1, "min": False},
    ),
    "Termination": JavaClass(
        None,
        {"win": "String", "limit": "int", "count_score": "boolean", "canEnd": "boolean static"},
        {"count_score": False, "canEnd": True},
    ),
    "SpriteCounter": JavaClass(
        "Termination",
        {"stype": "String", "itype": "int"},
        {},
    ),
    "SpriteCounterMore": JavaClass(
        "Termination",
        {"stype": "String", "itype": "int"},
        {},
    ),
    "MultiSpriteCounterSubTypes": JavaClass(
        "Termination",
        {"stype1": "String", "itype1": "int", "subTypesNum": "int"},
        {"itype1": -1, "subTypesNum": -1},
    ),
    "Timeout": JavaClass(
        "Termination",
        {"use_counter": "boolean", "compare": "boolean", "limits": "String"},
        {"use_counter": False, "compare": False, "limits": "0"},
    ),
    "StopCounter": JavaClass(
        "Termination",
        {
            "stype1": "String",
            "stype2": "String",
            "stype3": "String",
            "itype1": "int",
            "itype2": "int",
            "itype3": "int",
            "min": "boolean",
        },
        {"itype1": -1, "itype2": -1, "itype3": -1, "min": False},
    ),
}

# The game line's class (Game and BasicGame's public fields a VGDL line can set).
GAME_CLASSES: dict[str, JavaClass] = {
    "Game": JavaClass(
        None,
        {"key_handler": "String", "no_players": "int", "no_counters": "int"},
        {"no_players": 1, "no_counters": 0},
    ),
    "BasicGame": JavaClass("Game", {"square_size": "int", "obs": "String"}, {"square_size": -1}),
}

# VGDL's names for the effects (VGDLFactory.effectStrings -> effectClasses).
EFFECTS: dict[str, str] = {
    "stepBack": "StepBack",
    "turnAround": "TurnAround",
    "killSprite": "KillSprite",
    "killBoth": "KillBoth",
    "killAll": "KillAll",
    "transformTo": "TransformTo",
    "transformToSingleton": "TransformToSingleton",
    "transformIfCount": "TransformIfCount",
    "wrapAround": "WrapAround",
    "changeResource": "ChangeResource",
    "killIfHasLess": "KillIfHasLess",
    "killIfHasMore": "KillIfHasMore",
    "cloneSprite": "CloneSprite",
    "flipDirection": "FlipDirection",
    "reverseDirection": "ReverseDirection",
    "shieldFrom": "ShieldFrom",
    "undoAll": "UndoAll",
    "spawn": "Spawn",
    "spawnIfHasMore": "SpawnIfHasMore",
    "spawnIfHasLess": "SpawnIfHasLess",
    "pullWithIt": "PullWithIt",
    "wallStop": "WallStop",
    "collectResource": "CollectResource",
    "collectResourceIfHeld": "CollectResourceIfHeld",
    "killIfOtherHasMore": "KillIfOtherHasMore",
    "killIfFromAbove": "KillIfFromAbove",
    "teleportToExit": "TeleportToExit",
    "bounceForward": "BounceForward",
    "attractGaze": "AttractGaze",
    "align": "Align",
    "subtractHealthPoints": "SubtractHealthPoints",
    "addHealthPoints": "AddHealthPoints",
    "transformToAll": "TransformToAll",
    "addTimer": "AddTimer",
    "killIfScoreNegative": "KillIfScoreNegative",
    "killIfFrontal": "KillIfFrontal",
    "killIfNotFrontal": "KillIfNotFrontal",
    "spawnBehind": "SpawnBehind",
    "updateSpawnType": "UpdateSpawnType",
    "removeScore": "RemoveScore",
    "increaseSpeedToAll": "IncreaseSpeedToAll",
    "decreaseSpeedToAll": "DecreaseSpeedToAll",
    "setSpeedForAll": "SetSpeedForAll",
    "transformToRandomChild": "TransformToRandomChild",
    "addHealthPointsToMax": "AddHealthPointsToMax",
    "spawnIfCounterSubTypes": "SpawnIfCounterSubTypes",
    "bounceDirection": "BounceDirection",
    "wallBounce": "WallBounce",
    "killIfSlow": "KillIfSlow",
    "killIfAlive": "KillIfAlive",
    "waterPhysics": "WaterPhysics",
    "halfSpeed": "HalfSpeed",
    "killIfNotUpright": "KillIfNotUpright",
    "killIfFast": "KillIfFast",
    "wallReverse": "WallReverse",
    "spawnAbove": "SpawnAbove",
    "spawnLeft": "SpawnLeft",
    "spawnRight": "SpawnRight",
    "spawnBelow": "SpawnBelow",
}

# VGDL's names for the sprite classes and terminations are the Java class names.
SPRITES: tuple[str, ...] = (
    "Conveyor",
    "Flicker",
    "Immovable",
    "OrientedFlicker",
    "Passive",
    "Resource",
    "Spreader",
    "ErraticMissile",
    "Missile",
    "RandomMissile",
    "Walker",
    "WalkerJumper",
    "ResourcePack",
    "Chaser",
    "PathChaser",
    "Fleeing",
    "RandomInertial",
    "RandomNPC",
    "AlternateChaser",
    "RandomAltChaser",
    "PathAltChaser",
    "RandomPathAltChaser",
    "Bomber",
    "RandomBomber",
    "Portal",
    "SpawnPoint",
    "SpriteProducer",
    "Door",
    "FlakAvatar",
    "HorizontalAvatar",
    "VerticalAvatar",
    "MovingAvatar",
    "MissileAvatar",
    "OrientedAvatar",
    "ShootAvatar",
    "OngoingAvatar",
    "OngoingTurningAvatar",
    "BomberRandomMissile",
    "OngoingShootAvatar",
    "NullAvatar",
    "AimedAvatar",
    "PlatformerAvatar",
    "BirdAvatar",
    "SpaceshipAvatar",
    "CarAvatar",
    "WizardAvatar",
    "LanderAvatar",
    "ShootOnlyAvatar",
    "SpawnPointMultiSprite",
    "LOSChaser",
)
TERMINATIONS: tuple[str, ...] = (
    "MultiSpriteCounter",
    "SpriteCounter",
    "SpriteCounterMore",
    "MultiSpriteCounterSubTypes",
    "Timeout",
    "StopCounter",
)


def _chain(table: Mapping[str, JavaClass], name: str) -> list[JavaClass]:
    """The class and its superclasses, the root last."""
    chain = []
    current: str | None = name
    while current is not None:
        chain.append(table[current])
        current = table[current].parent
    return chain


def _table(kind: str) -> Mapping[str, JavaClass]:
    tables = {
        "sprite": SPRITE_CLASSES,
        "effect": EFFECT_CLASSES,
        "termination": TERMINATION_CLASSES,
        "game": GAME_CLASSES,
    }
    return tables[kind]


def java_class_name(kind: str, vgdl_name: str) -> str | None:
    """The Java class a VGDL word names (``"killSprite"`` -> ``"KillSprite"``), None if unknown."""
    if kind == "effect":
        return EFFECTS.get(vgdl_name)
    known = SPRITES if kind == "sprite" else TERMINATIONS
    return vgdl_name if vgdl_name in known else None


def fields_of(kind: str, java_class: str) -> dict[str, str]:
    """Every public field of the class, inherited ones included: name -> Java type."""
    fields: dict[str, str] = {}
    for cls in reversed(_chain(_table(kind), java_class)):
        fields.update(cls.fields)
    return fields


JAVA_ZERO = {"int": 0, "long": 0, "float": 0.0, "double": 0.0, "boolean": False}


def defaults_of(kind: str, java_class: str) -> dict[str, object]:
    """Each public field's value before a line's parameters apply: what the class (or the
    nearest superclass that sets it) assigns, else Java's zero for its type (0, False, null)."""
    defaults: dict[str, object] = {
        name: JAVA_ZERO.get(java_type.removesuffix(" static"))
        for name, java_type in fields_of(kind, java_class).items()
    }
    for cls in reversed(_chain(_table(kind), java_class)):
        defaults.update({name: value for name, value in cls.defaults.items() if name in defaults})
    return defaults
