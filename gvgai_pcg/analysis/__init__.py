"""Level-distribution analysis (GENERATORS.md §5): where do the human levels fall among generated ones?

Levels are encoded as binary tile maps (``encoding``), projected to 2-D by PCA and clustered by
DBSCAN (``clustering``), and the human levels are placed among the generated ones, with their
distance to the generated set in the full feature space as a percentile (``distances``).
``distribution.analyze_levels`` runs it all; ``figures`` and ``summary`` present the result.
Training curves live with the training code, in ``gvgai_pcg.rl``.
"""

from gvgai_pcg.analysis.clustering import NOISE, Cluster, Projection, cluster_labels, clusters, project
from gvgai_pcg.analysis.distances import (
    distance_percentile,
    generated_nearest_distances,
    hamming_matrix,
    nearest_generated,
)
from gvgai_pcg.analysis.distribution import HumanPlacement, LevelDistribution, analyze_levels
from gvgai_pcg.analysis.encoding import encode_level, encode_levels, padded_rows, tileset

__all__ = [
    "NOISE",
    "Cluster",
    "HumanPlacement",
    "LevelDistribution",
    "Projection",
    "analyze_levels",
    "cluster_labels",
    "clusters",
    "distance_percentile",
    "encode_level",
    "encode_levels",
    "generated_nearest_distances",
    "hamming_matrix",
    "nearest_generated",
    "padded_rows",
    "project",
    "tileset",
]
