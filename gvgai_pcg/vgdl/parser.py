"""GVGAI's ``VGDLParser``, in Python: a VGDL file to a ``GameDescription`` with Java's orders.

Each quirk of Java's parse is kept, because the engine's behaviour follows from it:

- ``wall`` and ``avatar`` are registered before the SpriteSet (ids 0 and 1) and exist with
  Java's default classes (Immovable, MovingAvatar) when the file does not define them;
- the drawing order lists leaf types as they are defined, ``wall`` and ``avatar`` first; a
  leaf defined again moves to the end; ``avatar`` is always put last;
- a type's class is the nearest ancestor's class word, over its own; parameters inherit;
- ``singleton=true`` marks only the type whose own line says it;
- a type's subtypes are its path from the root, then its children's subtypes, in order;
- one interaction line is one effect object, shared by all its pairs; pairs are processed
  in order of first declaration, each pair's effects in line order, ``repeat=n`` times;
- ``EOS`` and ``TIME`` are recognised case-insensitively, and only where no sprite type
  has the name; each ``X EOS`` line adds X to the EOS list again;
- blocks are read in file order, so a rule may only name types registered above it.

Where Java would log an error and continue with something else, the file is refused, with
its path and line (``VGDLError``): unknown classes, effects, terminations and parameters,
values Java cannot store, references to undefined types, malformed lines.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from gvgai_pcg.vgdl.errors import VGDLError
from gvgai_pcg.vgdl.java_classes import EFFECT_CLASSES, fields_of, java_class_name
from gvgai_pcg.vgdl.lines import Node, read_tree
from gvgai_pcg.vgdl.model import (
    CollisionPair,
    Effect,
    GameDescription,
    SpriteType,
    Termination,
)
from gvgai_pcg.vgdl.values import assign, read_value

BLOCKS = ("SpriteSet", "InteractionSet", "LevelMapping", "TerminationSet")
GAME_CLASSES = ("BasicGame",)
# Fields Java resolves through its type registry (comma-separated lists for the plural ones).
TYPE_REFERENCES = frozenset(
    "stype stype1 stype2 stype3 stypes stypes1 stypes2 resource estype ammo spawnBehind "
    "stype_other stypeTo stypeCount spawnPoint heldResource stypeMissile notStype".split()
)
# Java's default constructors for the two pre-registered types (Game.initSprites).
# BasicGame's own level characters; a LevelMapping line may redefine them.
DEFAULT_MAPPING = {"w": ("wall",), "A": ("avatar",)}
PREDEFINED = {"wall": ("Immovable", {"color": "DARKGRAY", "solid": "True"}), "avatar": ("MovingAvatar", {})}


def parse_file(path: str | Path) -> GameDescription:
    """Parse a VGDL file (UTF-8); see ``parse_vgdl``."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as error:
        raise VGDLError(str(path), 0, f"not UTF-8 text ({error.reason})") from None
    return parse_vgdl(text, str(path))


def parse_vgdl(text: str, path: str = "<vgdl>") -> GameDescription:
    """Parse VGDL text as Java's ``VGDLParser`` does; ``path`` names it in errors."""
    return _Parser(path).parse(text)


@dataclass
class _TypeLine:
    """One SpriteSet line as Java's ``SpriteContent`` holds it while the set is parsed."""

    name: str
    line: int
    java_class: str | None
    parent: str | None
    children: list[str]
    parameters: dict[str, str]
    subtypes: list[str]


@dataclass
class _Words:
    """A line's words sorted the way Java's contents sort them."""

    parameters: dict[str, str] = field(default_factory=dict)
    arrow: bool = False
    bare: list[str] = field(default_factory=list)


class _Parser:
    def __init__(self, path: str) -> None:
        self.path = path
        self.registry: list[str] = ["wall", "avatar"]
        self.definitions: dict[str, _TypeLine] = {}
        self.order: list[str] = ["wall", "avatar"]
        self.singletons: set[str] = set()
        self.effects: list[Effect] = []
        self.pairs: dict[tuple[str, str], list[int]] = {}
        self.eos: list[str] = []
        self.eos_effects: dict[str, list[int]] = {}
        self.time_effects: list[int] = []
        self.terminations: list[Termination] = []
        self.mapping: dict[str, tuple[str, ...]] = dict(DEFAULT_MAPPING)
        self.mapped_at: dict[str, int] = {}
        self.game_values: dict[str, object] = {}

    def fail(self, line: int, message: str) -> VGDLError:
        return VGDLError(self.path, line, message)

    # -- the file -------------------------------------------------------------------------

    def parse(self, text: str) -> GameDescription:
        root = read_tree(text, self.path)
        game_words = root.words()
        game_class = game_words[0]
        if game_class not in GAME_CLASSES:
            raise self.fail(
                root.line, f"game class {game_class!r}: only {', '.join(GAME_CLASSES)} is supported"
            )
        found = self.words(root, game_words[1:])
        if found.bare or found.arrow:
            raise self.fail(root.line, f"game line {root.text!r} has words that are not key=value")
        game_parameters = found.parameters
        self.game_values = self.typed(root.line, game_parameters, fields_of("game", game_class), game_class)
        seen: dict[str, int] = {}
        for block in root.children:
            name = block.text
            if name not in BLOCKS:
                hint = next((b for b in BLOCKS if b.lower() == name.lower()), None)
                reason = (
                    f"block {name!r}: Java matches {hint!r} case-sensitively and would skip it"
                    if hint
                    else f"unknown block {name!r} (expected one of {', '.join(BLOCKS)})"
                )
                raise self.fail(block.line, reason)
            if name in seen:
                raise self.fail(block.line, f"a second {name} (the first is at line {seen[name]})")
            seen[name] = block.line
            if name == "SpriteSet":
                self.sprite_set(block.children)
            elif name == "InteractionSet":
                for node in block.children:
                    self.interaction(node)
            elif name == "LevelMapping":
                for node in block.children:
                    self.level_mapping(node)
            else:
                for node in block.children:
                    self.termination(node)
        return self.description(game_class, game_parameters)

    def words(self, node: Node, words: list[str]) -> _Words:
        """``key=value`` parameters, the ``>`` and the bare words of a line."""
        found = _Words()
        for word in words:
            if "=" in word:
                key, _, value = word.partition("=")
                if not key or not value or "=" in value:
                    raise self.fail(node.line, f"parameter {word!r} is not key=value")
                found.parameters[key] = value
            elif word == ">":
                found.arrow = True
            elif word:
                found.bare.append(word)
        return found

    def no_children(self, node: Node, where: str) -> None:
        if node.children:
            raise self.fail(node.children[0].line, f"a {where} line cannot have indented lines below it")

    # -- SpriteSet ------------------------------------------------------------------------

    def sprite_set(self, nodes: list[Node]) -> None:
        self.sprite_lines(nodes, None, {}, [], None)
        for definition in self.definitions.values():
            self.check_references("sprite", definition.java_class, definition.parameters, definition.line)

    def sprite_lines(
        self,
        nodes: list[Node],
        inherited_class: str | None,
        inherited: dict[str, str],
        path: list[str],
        parent: str | None,
    ) -> list[_TypeLine]:
        """Java's ``_parseSprites``: one level of the SpriteSet tree; returns its lines."""
        lines = []
        for node in nodes:
            words = node.words()
            name, found = words[0], self.words(node, words[1:])
            if not found.arrow:
                raise self.fail(
                    node.line, f"sprite line {node.text!r} has no '>' (Java skips it and its siblings)"
                )
            if len(found.bare) > 1:
                raise self.fail(
                    node.line, f"sprite {name!r} names more than one class: {' '.join(found.bare)}"
                )
            own_class = found.bare[0] if found.bare else None
            if own_class is not None and java_class_name("sprite", own_class) is None:
                raise self.fail(node.line, f"unknown sprite class {own_class!r}")
            if name not in self.registry:
                self.registry.append(name)
            type_path = [*path, name]
            parameters = {**inherited, **found.parameters}
            if found.parameters.get("singleton", "").lower() == "true":
                self.singletons.add(name)
            definition = _TypeLine(
                name,
                node.line,
                inherited_class if inherited_class is not None else own_class,
                parent,
                [child.words()[0] for child in node.children],
                parameters,
                list(type_path),  # Java's itypes: the path from the root, as written
            )
            self.definitions.pop(name, None)
            self.definitions[name] = definition
            self.check_parameters("sprite", definition.java_class, parameters, node.line, name)
            if not node.children:
                if definition.java_class is None:
                    raise self.fail(
                        node.line, f"sprite type {name!r} has no class (Java creates no sprite of it)"
                    )
                if name in self.order:
                    self.order.remove(name)
                self.order.append(name)
            else:
                below = own_class if own_class is not None else inherited_class
                for child in self.sprite_lines(node.children, below, parameters, type_path, name):
                    for subtype in child.subtypes:
                        if subtype not in definition.subtypes:
                            definition.subtypes.append(subtype)
            lines.append(definition)
        return lines

    # -- InteractionSet -------------------------------------------------------------------

    def interaction(self, node: Node) -> None:
        self.no_children(node, "rule")
        words = node.words()
        first = words[0]
        seconds = []
        for word in words[1:]:
            if word == ">":
                break
            seconds.append(word)
        found = self.words(node, words[1 + len(seconds) :])
        if not found.arrow or not seconds:
            raise self.fail(node.line, f"rule {node.text!r} is not 'first second... > effect'")
        if len(found.bare) != 1:
            raise self.fail(node.line, f"rule {node.text!r} needs exactly one effect after '>'")
        name = found.bare[0]
        java_class = java_class_name("effect", name)
        if java_class is None:
            raise self.fail(node.line, f"unknown effect {name!r}")
        is_time = first.upper() == "TIME" or seconds[0].upper() == "TIME"
        values = self.effect_values(node, java_class, found.parameters, is_time or "addTimer" in node.text)
        self.check_references("effect", java_class, found.parameters, node.line)
        index = len(self.effects)
        effect = Effect(index, node.line, first, tuple(seconds), name, java_class, found.parameters, values)
        self.effects.append(effect)
        for second in seconds:
            if first in self.registry and second in self.registry:
                self.pairs.setdefault((first, second), []).extend([index] * effect.repeat)
            elif second.upper() == "EOS" or first.upper() == "EOS":
                target = first if second.upper() == "EOS" else second
                if target not in self.registry:
                    raise self.fail(node.line, f"rule names an undefined sprite type {target!r}")
                self.eos.append(target)
                self.eos_effects.setdefault(target, []).append(index)
            elif is_time or second.upper() == "TIME":
                if index not in self.time_effects:
                    self.time_effects.append(index)
            else:
                unknown = first if first not in self.registry else second
                raise self.fail(node.line, f"rule names an undefined sprite type {unknown!r}")

    def effect_values(self, node: Node, java_class: str, parameters: dict[str, str], timed: bool) -> dict:
        """Typed values; a timed line's parameters may also be the timer's (Java's TimeEffect),
        and an ``addTimer`` line's those of the effect it schedules."""
        if not timed:
            return self.check_parameters("effect", java_class, parameters, node.line, java_class)
        fields = fields_of("effect", java_class)
        extra = fields_of("effect", "TimeEffect")
        if java_class == "AddTimer":
            for other in EFFECT_CLASSES:
                extra = {**fields_of("effect", other), **extra}
        return self.typed(node.line, parameters, {**extra, **fields}, java_class)

    # -- LevelMapping and TerminationSet --------------------------------------------------

    def level_mapping(self, node: Node) -> None:
        self.no_children(node, "level mapping")
        # Java checks the named types only when a level uses the character (two corpus games
        # map characters to types they never define): the level reader refuses them there.
        words = node.words()
        if len(words[0]) != 1 or len(words) < 3 or words[1] != ">":
            raise self.fail(node.line, f"level mapping {node.text!r} is not 'c > type...'")
        if words[0] in self.mapped_at:
            first = self.mapped_at[words[0]]
            raise self.fail(
                node.line, f"character {words[0]!r} is mapped again (line {first}; Java keeps the last)"
            )
        self.mapped_at[words[0]] = node.line
        self.mapping[words[0]] = tuple(words[2:])

    def termination(self, node: Node) -> None:
        self.no_children(node, "termination")
        words = node.words()
        java_class = java_class_name("termination", words[0])
        if java_class is None:
            raise self.fail(node.line, f"unknown termination {words[0]!r}")
        found = self.words(node, words[1:])
        if found.bare or found.arrow:
            raise self.fail(node.line, f"termination {node.text!r} has words that are not key=value")
        values = self.check_parameters("termination", java_class, found.parameters, node.line, java_class)
        self.check_references("termination", java_class, found.parameters, node.line)
        self.terminations.append(Termination(node.line, java_class, found.parameters, values))

    # -- parameters -----------------------------------------------------------------------

    def check_parameters(
        self, kind: str, java_class: str | None, parameters: dict[str, str], line: int, owner: str
    ) -> dict[str, object]:
        if java_class is None:
            return {}
        return self.typed(line, parameters, fields_of(kind, java_class), owner)

    def typed(self, line: int, parameters: dict[str, str], fields: dict[str, str], owner: str) -> dict:
        values = {}
        for key, text in parameters.items():
            if key not in fields:
                raise self.fail(line, f"unknown parameter {key!r} of {owner}")
            try:
                values[key] = assign(fields[key], read_value(key, text))
            except ValueError as error:
                raise self.fail(line, f"parameter {key}={text}: {error}") from None
        return values

    def check_references(
        self, kind: str, java_class: str | None, parameters: dict[str, str], line: int
    ) -> None:
        if java_class is None:
            return
        fields = fields_of(kind, java_class)
        for key, text in parameters.items():
            if key in TYPE_REFERENCES and key in fields:
                for name in text.split(","):
                    if name not in self.registry:
                        raise self.fail(
                            line, f"parameter {key}={text} names an undefined sprite type {name!r}"
                        )

    # -- the result -----------------------------------------------------------------------

    def description(self, game_class: str, game_parameters: dict[str, str]) -> GameDescription:
        types = {name: self.sprite_type(name) for name in self.registry}
        order = [name for name in self.order if name != "avatar"] + ["avatar"]
        return GameDescription(
            path=self.path,
            game_class=game_class,
            game_parameters=game_parameters,
            game_values=self.game_values,
            types=types,
            sprite_order=tuple(order),
            effects=tuple(self.effects),
            pairs=tuple(CollisionPair(a, b, tuple(e)) for (a, b), e in self.pairs.items()),
            eos=tuple(self.eos),
            eos_effects={name: tuple(e) for name, e in self.eos_effects.items()},
            time_effects=tuple(self.time_effects),
            terminations=tuple(self.terminations),
            level_mapping=dict(self.mapping),
        )

    def sprite_type(self, name: str) -> SpriteType:
        definition = self.definitions.get(name)
        if definition is None:  # wall or avatar, as Java pre-defines them
            java_class, parameters = PREDEFINED[name]
            values = self.check_parameters("sprite", java_class, parameters, 0, name)
            return SpriteType(name, 0, java_class, None, (), parameters, values, False, (name,))
        subtypes = definition.subtypes
        if name in PREDEFINED and name not in subtypes:
            subtypes = [*subtypes, name]
        return SpriteType(
            name=name,
            line=definition.line,
            java_class=definition.java_class,
            parent=definition.parent,
            children=tuple(definition.children),
            parameters=definition.parameters,
            values=self.check_parameters(
                "sprite", definition.java_class, definition.parameters, definition.line, name
            ),
            singleton=name in self.singletons,
            subtypes=tuple(subtypes),
        )
