"""The specs the code cites are in the repository, every cited section exists, and the copies
match the shared originals (where a checkout has them beside it)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SPEC = ROOT / "docs" / "spec"
SHARED = ROOT.parent / "shared" / "gvgai"
COPIES = {"RULES.md": "RULES.md", "GENERATORS.md": "GENERATORS.md", "golden-traces.md": "golden/README.md"}
CITATION = re.compile(r"(RULES|GENERATORS)\.md ?§ ?(\d+(?:\.\d+)*)")


def _sections(name: str) -> set[str]:
    text = (SPEC / name).read_text()
    return set(re.findall(r"^#{2,4} (\d+(?:\.\d+)*)\.? ", text, flags=re.M))


def _cited() -> set[tuple[str, str, str]]:
    found = set()
    for path in [*ROOT.glob("gvgai_pcg/**/*.py"), *ROOT.glob("tests/**/*.py"), *ROOT.glob("docs/**/*.md")]:
        if SPEC in path.parents:
            continue
        for spec, section in CITATION.findall(path.read_text()):
            found.add((f"{spec}.md", section, str(path.relative_to(ROOT))))
    return found


def test_every_cited_section_is_in_the_copied_spec():
    sections = {name: _sections(name) for name in ("RULES.md", "GENERATORS.md")}
    cited = _cited()
    assert len(cited) > 30  # the code leans on the specs throughout
    missing = sorted(
        f"{where}: {spec} §{section}" for spec, section, where in cited if section not in sections[spec]
    )
    assert not missing, missing


@pytest.mark.parametrize("copy", sorted(COPIES))
def test_the_copies_match_the_shared_originals(copy):
    original = SHARED / COPIES[copy]
    if not original.is_file():
        pytest.skip("no shared/ beside this checkout")
    text = (SPEC / copy).read_text()
    assert text.split("-->\n\n", 1)[1] == original.read_text()
