"""The short Markdown summary of one game's level-distribution analysis, for people and docs."""

from __future__ import annotations

from gvgai_pcg.analysis.distribution import HumanPlacement, LevelDistribution
from gvgai_pcg.analysis.figures import game_title

HUMAN_TABLE_HEADER = [
    "| level | cluster | PCA distance to nearest generated | nearest generated | Hamming | percentile |",
    "|---|---|---|---|---|---|",
]


def human_status(analysis: LevelDistribution) -> str:
    """One line: each human level's cluster or outlier status, e.g. ``0: cluster 5, 4: outlier``."""
    return ", ".join(
        f"{h.index}: {'outlier' if h.outlier else f'cluster {h.cluster}'}" for h in analysis.humans
    )


def _settings(analysis: LevelDistribution) -> str:
    difficulties = sorted({d for d in analysis.difficulties if d is not None})
    at = f" (d = {', '.join(f'{d:g}' for d in difficulties)})" if difficulties else ""
    variance = ", ".join(f"{v:.3f}" for v in analysis.projection.explained_variance_ratio)
    return (
        f"{analysis.generated_count} generated levels{at} and {analysis.human_count} human levels; "
        f"{analysis.encoding} encoding, {analysis.feature_size} binary features; PCA to 2-D "
        f"(explained variance {variance}); DBSCAN eps {analysis.eps:g}, min_samples {analysis.min_samples}."
    )


def _human_row(analysis: LevelDistribution, h: HumanPlacement) -> str:
    status = "outlier" if h.outlier else str(h.cluster)
    nearest = analysis.levels[h.nearest_generated].name
    return f"| {h.index} | {status} | {h.pca_distance:.3f} | {nearest} | {h.hamming} | {h.percentile:.1f} |"


def markdown_summary(analysis: LevelDistribution, figures: list[str] | None = None) -> str:
    """Settings, clusters with their representative level as text, and the human levels' placement."""
    lines = [
        f"# Level distribution: {game_title(analysis.game)}",
        "",
        _settings(analysis),
        "",
        f"**{len(analysis.clusters)} cluster(s)**, {analysis.noise_count} noise point(s). "
        f"Human levels: {human_status(analysis)}.",
        "",
    ]
    if figures:
        lines += [*(f"![{name}]({name})" for name in figures), ""]
    if analysis.humans:
        lines += [
            "## Human levels",
            "",
            "Hamming: features differing from the nearest generated level (full feature space). "
            "Percentile: that distance ranked among each generated level's distance to its own nearest "
            "generated neighbour (100 = farther than every generated level is from its neighbour).",
            "",
            *HUMAN_TABLE_HEADER,
            *(_human_row(analysis, h) for h in analysis.humans),
            "",
        ]
    lines += ["## Clusters", ""]
    for cluster in analysis.clusters:
        representative = analysis.levels[cluster.representative]
        humans = [str(h.index) for h in analysis.humans if h.cluster == cluster.label]
        with_humans = f", human levels {', '.join(humans)}" if humans else ""
        lines += [
            f"### Cluster {cluster.label}: {cluster.size} levels{with_humans}",
            "",
            f"Representative ({representative.name}):",
            "",
            "```",
            str(representative).rstrip("\n"),
            "```",
            "",
        ]
    return "\n".join(lines)
