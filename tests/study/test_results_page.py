"""The results pages say what the published data say: each generated block rebuilds from its
published folder, the claims in it rebuild from the runs, and every number a page's prose about
its runs states is in that page's block."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from gvgai_pcg.study import BUDGETS
from gvgai_pcg.study.pages.claims_page import claims_markdown
from gvgai_pcg.study.pages.curricula_page import END as CURRICULA_END
from gvgai_pcg.study.pages.curricula_page import START as CURRICULA_START
from gvgai_pcg.study.pages.page import END, START, results_block
from gvgai_pcg.study.verdicts.judging import study_claims
from gvgai_pcg.study.verdicts.results import collect

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "results.md"
# the folder the page's block was written from (its first line names it): small now, medium later
PUBLISHED = ROOT / re.search(r"Data: `([^`]+)`", PAGE.read_text()).group(1)
NUMBER = re.compile(r"(?<![\w.])\d+\.\d+|\d+ of \d+")

pytestmark = pytest.mark.skipif(not (PUBLISHED / "runs").is_dir(), reason="no published small runs")


def block_of(text: str, start: str = START, end: str = END) -> str:
    return start + text.split(start, 1)[1].split(end, 1)[0] + end


# each page's prose about its runs: its heading, the markers of the generated block whose numbers
# it states, and how many numbers it states at least (fewer: the prose lost its numbers)
PROSE = {
    "results.md": ("### What the three seeds show", START, END, 40),
    "results-medium.md": ("## What the runs show", START, END, 40),
    "results-curricula.md": ("## The answer", CURRICULA_START, CURRICULA_END, 20),
}


def numbers_in(text: str) -> list[str]:
    """The decimals and "k of n" counts of ``text``, signs dropped (the block writes +0.29)."""
    return NUMBER.findall(text.replace("-", " ").replace("+", " "))


def prose_of(text: str, heading: str, start: str) -> str:
    return text.split(heading, 1)[1].split(start, 1)[0]


@pytest.mark.parametrize("name", sorted(PROSE))
def test_every_number_the_prose_states_is_in_the_generated_block(name):
    heading, start, end, at_least = PROSE[name]
    text = (PAGE.parent / name).read_text()
    block = set(numbers_in(block_of(text, start, end)))
    stated = numbers_in(prose_of(text, heading, start))
    assert len(stated) > at_least, "the prose lost its numbers"
    assert sorted(set(stated) - block) == []


def published_pages() -> list[Path]:
    """Every results page with a generated block (docs/results.md, docs/results-medium.md)."""
    return sorted(page for page in PAGE.parent.glob("results*.md") if START in page.read_text())


@pytest.mark.parametrize("page_path", published_pages(), ids=lambda path: path.name)
def test_the_pages_block_rebuilds_from_the_published_folder(page_path, tmp_path):
    from gvgai_pcg.study.pages.page import page_images

    page = block_of(page_path.read_text())
    published = ROOT / re.search(r"Data: `([^`]+)`", page).group(1)
    commit = re.search(r"commit `(\w+)`", page).group(1)
    frames = BUDGETS[published.name].frames_range[0]
    prefix = page_images(page_path)[1]
    rebuilt = results_block(published, tmp_path / "images", prefix, frames, commit)
    # the first line names the machine that wrote it
    assert rebuilt.splitlines()[2:] == page.splitlines()[2:]


@pytest.mark.parametrize("page_path", published_pages(), ids=lambda path: path.name)
def test_the_published_claims_rebuild_from_the_runs(page_path):
    from gvgai_pcg.evaluation.checkpoints import find_runs
    from gvgai_pcg.evaluation.protocol import Protocol

    published = ROOT / re.search(r"Data: `([^`]+)`", page_path.read_text()).group(1)
    budget = BUDGETS[published.name]
    target = budget.frames_range[0]  # as the pipeline's write_claims is given
    games = collect(
        find_runs([published / "runs"]), published / "random", Protocol(**budget.protocol), target
    )
    sampling = budget.level_sampling  # medium's intervals include the test sets' levels
    rebuilt = claims_markdown(study_claims(games, target, sampling), games, sampling)
    assert rebuilt == (published / "report" / "claims.md").read_text()
    assert "Four levels transfer more" not in PAGE.read_text()  # the backwards sentence stays gone


def _claim_row(block: str, game: str, start: str) -> str:
    return next(line for line in block.splitlines() if line.startswith(f"| {game} | {start}"))


def _seed_range(row: str, pattern: str) -> str:
    seeds = sorted(int(n) for n in re.findall(pattern + r"[^;]*; 80 % power at about (\d+) seeds", row))
    return f"{seeds[0]}-{seeds[-1]}"


def test_the_medium_pages_statements_are_what_its_claims_carry():
    """The statements a review found the data do not carry: seeds at 80 % power, Lv 0-3's gains
    apart from its lowest training level, Frogs' human-level wins per agent, Solarfox at d = 0.5
    against the claim, no "undertraining", and the study's Boulderdash Max in all columns."""
    text = (PAGE.parent / "results-medium.md").read_text()
    block, prose = block_of(text), prose_of(text, "## What the runs show", START)
    assert "decided with 80 % power (the noncentral t" in block and "at 80 % power" in prose
    four = _claim_row(block, "zelda", "Trained on four human levels")
    assert (
        "Lv 0-3, its lowest training level: +0.71 [+0.45, +0.96], Holm p 1 (claim > 0.7; more than 30" in four
    )
    above, under = _seed_range(four, r"\(claim > 0"), _seed_range(four, r"\(claim < 0\.5")
    assert f"{above} seeds to show each above 0, {under} to show each under the bound of 0.5" in prose
    assert "Lv 0-3's lowest training level (+0.71 [+0.45, +0.96], on the same" in prose
    frogs = _claim_row(block, "frogs", "No generated-level agent")
    assert "| **does not hold** |" in frogs and "0 of 150, 4 of 150, 26 of 150, 13 of 150" in frogs
    assert 'One claim is contradicted: "no generated-level agent wins a human Frogs level"' in prose
    solarfox = _claim_row(block, "solarfox", "PCG 1 scores higher than PPCG on the generated")
    assert "on pcg0.5: -0.19 [-0.41, +0.03], Holm p 0.492 (claim > 0; the estimate lies against" in solarfox
    assert "points against the study at d = 0.5: PCG 1 is below" in prose
    assert "undertraining, and it is gone" not in text and "cannot say the gap was undertraining" in prose
    assert "Boulderdash Max is the package's formula in all seven columns" in block
    assert "21.51 / 25.73 on the generated sets" in block and "the paper prints 31.50 / 29.80" in block
    assert "Boulderdash on 12 of 14 at 1.02" in prose
    readme = (ROOT / "README.md").read_text()
    assert "undertraining" not in readme and "one claim is contradicted" in readme


CURRICULA_PAGE = PAGE.parent / "results-curricula.md"


@pytest.mark.skipif(not CURRICULA_PAGE.is_file(), reason="no curricula page")
def test_the_curricula_pages_block_rebuilds_from_its_published_folders(tmp_path):
    """The block rebuilds from the published folder and the budget's fair folder its data line
    names, on the commit it names (figures go to tmp)."""
    from gvgai_pcg.study.pages.curricula_page import curricula_block
    from gvgai_pcg.study.pages.page import page_images

    page = block_of(CURRICULA_PAGE.read_text(), CURRICULA_START, CURRICULA_END)
    published = Path(re.search(r"Data: `([^`]+)`", page).group(1))
    if not (ROOT / published / "runs").is_dir():
        pytest.skip("no published curricula runs")
    commit = re.search(r"commit `(\w+)`", page).group(1)
    budget = BUDGETS[published.name]
    assert budget.fair and f"`{published.parent / budget.fair}`" in page.splitlines()[1]
    prefix = page_images(CURRICULA_PAGE)[1]
    import os

    cwd = os.getcwd()
    os.chdir(ROOT)  # the data line names the folders relative to the repository
    try:
        rebuilt = curricula_block(published, budget, tmp_path / "images", prefix, commit)
    finally:
        os.chdir(cwd)
    # the data line names the machine that wrote it
    assert rebuilt.splitlines()[2:] == page.splitlines()[2:]
    assert "#### The reference setting (shown, never judged)" in page
