import json
import warnings

import numpy as np
import pytest

from gvgai_pcg.analysis import NOISE, analyze_levels
from gvgai_pcg.analysis.figures import representatives_figure
from gvgai_pcg.generators import generate_level
from gvgai_pcg.levels import Level, human_levels

# Far from any generated Zelda level: nearly every cell holds an enemy.
CROWDED_ZELDA = """\
wwwwwwwwwwwww
w33333333333w
w33333333333w
w33333333333w
wA3333333333w
w11111111111w
w11111111111w
w11111111111w
wwwwwwwwwwwww
"""


@pytest.fixture(scope="module")
def zelda_generated() -> list[Level]:
    return [generate_level("zelda", 1.0, seed) for seed in range(100)]


def test_human_levels_are_analysed_last_with_their_indices(zelda_generated):
    humans = human_levels("zelda")
    analysis = analyze_levels(zelda_generated, humans, [1.0] * 100)
    summary = analysis.as_dict()
    assert summary["generated_levels"] == 100 and summary["human_levels"] == 5
    assert [h["index"] for h in summary["humans"]] == [0, 1, 2, 3, 4]
    assert [h["name"] for h in summary["humans"]] == [f"zelda_lvl{i}" for i in range(5)]
    assert [h.point for h in analysis.humans] == [100, 101, 102, 103, 104]
    assert analysis.projection.coords.shape == (105, 2)
    for h in analysis.humans:
        assert h.cluster == analysis.labels[h.point]
        assert 0.0 <= h.percentile <= 100.0
    assert sum(c["size"] for c in summary["clusters"]) + summary["noise_count"] == 105


def test_analysis_is_deterministic_for_a_fixed_seed(zelda_generated):
    first = analyze_levels(zelda_generated, human_levels("zelda"), seed=3)
    second = analyze_levels(zelda_generated, human_levels("zelda"), seed=3)
    np.testing.assert_array_equal(first.projection.coords, second.projection.coords)
    assert first.as_dict() == second.as_dict()


def test_a_human_level_far_from_everything_is_an_outlier_with_a_high_percentile(zelda_generated):
    far = Level.parse(CROWDED_ZELDA, "zelda", name="crowded")
    analysis = analyze_levels(zelda_generated, [*human_levels("zelda")[:4], far])
    placed = analysis.humans[4]
    assert placed.index == 4 and placed.name == "crowded"
    assert placed.cluster == NOISE and placed.outlier
    assert placed.percentile == 100.0
    assert placed.hamming > analysis.generated_nearest.max()
    assert placed.pca_distance == max(h.pca_distance for h in analysis.humans)


def test_too_few_generated_levels_are_refused():
    with pytest.raises(ValueError, match="at least 2 generated levels"):
        analyze_levels([generate_level("zelda", 1.0, 0)], human_levels("zelda"))


def test_identical_levels_give_a_strict_json_summary():
    """Identical levels leave PCA nothing to explain (sklearn's ratios are 0/0)."""
    level = generate_level("zelda", 0.5, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        analysis = analyze_levels([level] * 20, [])
    summary = json.loads(json.dumps(analysis.as_dict(), allow_nan=False))
    assert summary["pca_explained_variance_ratio"] == [0.0, 0.0]


def test_no_clusters_and_no_human_levels_still_draw_a_figure(tmp_path):
    analysis = analyze_levels([generate_level("zelda", 1.0, s) for s in range(12)], [], eps=1e-6)
    assert not analysis.clusters and not analysis.humans
    path = representatives_figure(analysis, tmp_path / "representatives.png")
    assert path.read_bytes()[:4] == b"\x89PNG"
