"""Every ```python block in docs/**/*.md runs, so the documentation cannot rot.

The blocks of one page run in order in one namespace (a page may build on its earlier blocks),
in a fresh working directory. A block opts out only with the marker ``<!-- no-test -->`` on the
line just before its fence (for things like multi-hour training or third-party libraries that
are not dependencies); docs/reference/docs-examples.md says so to writers.
"""

from __future__ import annotations

import os
import re
import textwrap
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"
NO_TEST = "<!-- no-test -->"
FENCE = re.compile(r"^(?P<indent>[ \t]*)```python[ \t]*$")


def python_blocks(text: str) -> list[tuple[int, str, bool]]:
    """(first line number, code, runs) of each ```python block, in page order."""
    lines = text.splitlines()
    blocks, i = [], 0
    while i < len(lines):
        match = FENCE.match(lines[i])
        if not match:
            i += 1
            continue
        start, indent = i, match.group("indent")
        i += 1
        while i < len(lines) and lines[i].strip() != "```":
            i += 1
        code = textwrap.dedent("\n".join(line.removeprefix(indent) for line in lines[start + 1 : i]))
        runs = start == 0 or lines[start - 1].strip() != NO_TEST
        blocks.append((start + 1, code, runs))
        i += 1
    return blocks


def pages() -> list[Path]:
    return sorted(path for path in DOCS.rglob("*.md") if "```python" in path.read_text())


def test_the_extractor_sees_fences_and_the_marker() -> None:
    text = (
        "x\n```python\na = 1\n```\n"
        "<!-- no-test -->\n```python\nraise SystemExit\n```\n"
        "  ```python\n  b = 2\n  ```\n"
    )
    assert python_blocks(text) == [(2, "a = 1", True), (6, "raise SystemExit", False), (9, "b = 2", True)]


@pytest.fixture
def isolated_registries():
    """A page may register its own generator or game (and its Gymnasium id); keep that out of the
    other tests."""
    import gymnasium

    from gvgai_pcg.games import registry

    tables = (registry._SPECS, registry._GAMES, registry._RULES, registry._GENERATORS)
    saved = [dict(table) for table in tables]
    ids = set(gymnasium.registry)
    yield
    for table, before in zip(tables, saved, strict=True):
        table.clear()
        table.update(before)
    for added in set(gymnasium.registry) - ids:
        del gymnasium.registry[added]


@pytest.mark.parametrize("page", pages(), ids=lambda path: str(path.relative_to(DOCS)))
def test_page_examples_run(page: Path, tmp_path: Path, isolated_registries) -> None:
    namespace: dict[str, object] = {"__name__": f"docs_{page.stem}"}
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        for line, code, runs in python_blocks(page.read_text()):
            if runs:
                exec(compile(code, f"{page}:{line}", "exec"), namespace)  # noqa: S102
    finally:
        os.chdir(cwd)
