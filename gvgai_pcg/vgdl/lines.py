"""Java's indent tree: a VGDL file's lines as nested nodes, read as ``VGDLParser`` reads them.

What must stay true (each is a quirk of Java's ``indentTreeParser`` and ``Node``):

- a comment starts at the first ``#`` (also inside a value: ``color=#fff`` loses its value);
- the indent is the number of leading characters up to the first visible one: a tab counts
  as ONE character (Java's ``replaceAll("\\t", "    ")`` discards its result);
- runs of whitespace inside a line are one space (Java's ``Utils.formatString``);
- a line is the child of the nearest line above it with a smaller indent.

Where Java logs an error and goes on with a silently different tree (a line that is only
``#``, a line indented no deeper than the first line, siblings with different indents),
the description is refused instead.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from gvgai_pcg.vgdl.errors import VGDLError

_WHITESPACE_RUN = re.compile(r"[ \t\x0b\f\r]+")  # Java's \s less \n


@dataclass
class Node:
    """One non-empty line: its text (comment cut, whitespace collapsed) and its children."""

    text: str
    indent: int
    line: int  # 1-based
    children: list[Node] = field(default_factory=list)
    parent: Node | None = None

    def words(self) -> list[str]:
        """The line split on single spaces, as Java's ``line.split(" ")``."""
        return self.text.split(" ")


def java_trim(text: str) -> str:
    """``String.trim()``: strips every character up to U+0020, and nothing else."""
    start, end = 0, len(text)
    while start < end and text[start] <= " ":
        start += 1
    while end > start and text[end - 1] <= " ":
        end -= 1
    return text[start:end]


def strip_comment(raw: str, path: str, number: int) -> str:
    """Cut at the first ``#``. Java's ``split("#")[0]`` fails on a line of only ``#``s."""
    if "#" not in raw:
        return raw
    if raw.strip("#") == "":
        raise VGDLError(path, number, "a line of only '#' stops Java's parser (write '# ...')")
    return raw.split("#", 1)[0]


def read_tree(text: str, path: str) -> Node:
    """The root node (the first non-empty line, the game line) with every other line below it."""
    root: Node | None = None
    last: Node | None = None
    for number, raw in enumerate(re.split(r"\r\n|\r|\n", text), start=1):
        line = strip_comment(raw, path, number)
        content = java_trim(line)
        if not content:
            continue
        indent = len(line) - len(line.lstrip("".join(chr(c) for c in range(33))))
        node = Node(_WHITESPACE_RUN.sub(" ", content), indent, number)
        if last is None:
            root = last = node
            continue
        _insert(last, node, path)
        last = node
    if root is None:
        raise VGDLError(path, 0, "the file has no VGDL lines")
    return root


def _insert(last: Node, node: Node, path: str) -> None:
    """Java's ``Node.insert``: climb from the last line to the first one indented less."""
    parent: Node | None = last
    while parent is not None and parent.indent >= node.indent:
        parent = parent.parent
    if parent is None:
        raise VGDLError(
            path, node.line, f"{node.text!r} is indented no deeper than the game line (Java drops it)"
        )
    if parent.children and parent.children[0].indent != node.indent:
        first = parent.children[0]
        raise VGDLError(
            path,
            node.line,
            f"indent {node.indent} differs from its sibling's {first.indent} (line {first.line})",
        )
    parent.children.append(node)
    node.parent = parent
