import json

from gvgai_pcg.cli import main
from gvgai_pcg.generators import generate_level


def test_analyze_writes_figures_and_summaries_with_the_human_levels(tmp_path, capsys):
    code = main(["analyze", "--game", "solarfox", "--count", "100", "--seed", "0", "--out", str(tmp_path)])
    assert code == 0
    for name in ("solarfox_pca.png", "solarfox_levels.png", "solarfox_pca.json", "solarfox_pca.md"):
        assert (tmp_path / name).stat().st_size > 0, name
    assert (tmp_path / "solarfox_pca.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    summary = json.loads((tmp_path / "solarfox_pca.json").read_text())
    assert summary["generated_levels"] == 100 and summary["difficulties"] == [1.0]
    assert [h["index"] for h in summary["humans"]] == [0, 1, 2, 3, 4]
    for cluster in summary["clusters"]:
        assert cluster["representative_text"].count("\n") == 11  # a full 10x11 level
    markdown = (tmp_path / "solarfox_pca.md").read_text()
    assert "| 4 |" in markdown and "![solarfox_pca.png](solarfox_pca.png)" in markdown
    assert "solarfox:" in capsys.readouterr().out


def test_analyze_reads_a_folder_and_keeps_the_difficulty_in_file_names(tmp_path):
    levels = tmp_path / "levels"
    levels.mkdir()
    for d in (0.0, 1.0):
        for seed in range(15):
            level = generate_level("zelda", d, seed)
            (levels / f"{level.name}.txt").write_text(str(level))
    out = tmp_path / "out"
    assert main(["analyze", "--game", "zelda", "--levels", str(levels), "--out", str(out)]) == 0
    summary = json.loads((out / "zelda_pca.json").read_text())
    assert summary["generated_levels"] == 30 and summary["difficulties"] == [0.0, 1.0]
    assert (out / "zelda_pca.png").stat().st_size > 0
