"""The level-distribution analysis of one game: encode, project, cluster, and place the human levels.

Generated and human levels are analysed together (the human ones last), as in the study: both
enter the PCA fit and the clustering, so a human level can join a cluster or be noise. The
result keeps every number the figures and summaries show, so those only format it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from gvgai_pcg.analysis.clustering import NOISE, Cluster, Projection, cluster_labels, clusters, project
from gvgai_pcg.analysis.distances import (
    distance_percentile,
    generated_nearest_distances,
    nearest_generated,
)
from gvgai_pcg.analysis.encoding import encode_levels, tileset
from gvgai_pcg.levels import Level


@dataclass(frozen=True)
class HumanPlacement:
    """Where human level ``index`` (0-4) falls: its cluster (``NOISE`` = outlier) and distances."""

    index: int
    name: str | None
    point: int  # row of this level in the analysed set (generated levels first)
    cluster: int
    coords: np.ndarray  # [2] PCA coordinates
    nearest_generated: int  # row of the nearest generated level in the full feature space
    hamming: int  # features differing from that level
    pca_distance: float  # 2-D distance to the nearest generated level in the PCA plane
    percentile: float  # hamming ranked among the generated levels' own nearest-neighbour distances

    @property
    def outlier(self) -> bool:
        return self.cluster == NOISE


@dataclass(frozen=True)
class LevelDistribution:
    """Everything the analysis of one game found; ``levels`` are the generated then the human levels."""

    game: str
    levels: list[Level]
    difficulties: list[float | None]  # None for human levels and for files without a difficulty
    human_count: int
    encoding: str  # "study" or "complete"
    eps: float
    min_samples: int
    seed: int
    feature_size: int
    projection: Projection
    labels: np.ndarray  # [N] DBSCAN labels
    clusters: list[Cluster]
    humans: list[HumanPlacement]
    generated_nearest: np.ndarray  # [G] Hamming distance of each generated level to its nearest other

    @property
    def generated_count(self) -> int:
        return len(self.levels) - self.human_count

    @property
    def noise_count(self) -> int:
        return int(np.count_nonzero(self.labels == NOISE))

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready summary: settings, clusters with representatives, and the human levels."""
        return {
            "game": self.game,
            "generated_levels": self.generated_count,
            "human_levels": self.human_count,
            "difficulties": sorted({d for d in self.difficulties if d is not None}),
            "encoding": self.encoding,
            "tileset": tileset(self.game, self.encoding == "complete"),
            "feature_size": self.feature_size,
            "pca_explained_variance_ratio": [
                round(float(v), 6) for v in self.projection.explained_variance_ratio
            ],
            "dbscan": {"eps": self.eps, "min_samples": self.min_samples},
            "seed": self.seed,
            "cluster_count": len(self.clusters),
            "noise_count": self.noise_count,
            "clusters": [self._cluster_dict(cluster) for cluster in self.clusters],
            "generated_nearest_hamming": {
                "median": float(np.median(self.generated_nearest)),
                "p95": float(np.percentile(self.generated_nearest, 95)),
                "max": int(self.generated_nearest.max()),
            },
            "humans": [self._human_dict(human) for human in self.humans],
        }

    def _cluster_dict(self, cluster: Cluster) -> dict[str, Any]:
        representative = self.levels[cluster.representative]
        return {
            "label": cluster.label,
            "size": cluster.size,
            "centroid": [round(float(v), 6) for v in cluster.centroid],
            "representative": {"point": cluster.representative, "name": representative.name},
            "representative_text": str(representative),
            "human_levels": [h.index for h in self.humans if h.cluster == cluster.label],
        }

    def _human_dict(self, human: HumanPlacement) -> dict[str, Any]:
        return {
            "index": human.index,
            "name": human.name,
            "point": human.point,
            "cluster": human.cluster,
            "outlier": human.outlier,
            "pca": [round(float(v), 6) for v in human.coords],
            "pca_distance_to_nearest_generated": round(human.pca_distance, 6),
            "nearest_generated": self.levels[human.nearest_generated].name,
            "hamming_to_nearest_generated": human.hamming,
            "distance_percentile": round(human.percentile, 2),
        }


def analyze_levels(
    generated: Sequence[Level],
    human: Sequence[Level],
    difficulties: Sequence[float | None] | None = None,
    eps: float = 0.5,
    min_samples: int = 10,
    complete: bool = False,
    seed: int = 0,
) -> LevelDistribution:
    """Analyse ``generated`` levels together with ``human`` ones (all of one game)."""
    if len(generated) < 2:
        raise ValueError(f"the analysis needs at least 2 generated levels, got {len(generated)}")
    levels = [*generated, *human]
    difficulties = list(difficulties) if difficulties is not None else [None] * len(generated)
    if len(difficulties) != len(generated):
        raise ValueError(f"got {len(difficulties)} difficulties for {len(generated)} generated levels")
    features = encode_levels(levels, complete)
    projection = project(features, seed)
    labels = cluster_labels(projection.coords, eps, min_samples)
    generated_features, human_features = features[: len(generated)], features[len(generated) :]
    own_nearest = generated_nearest_distances(generated_features)
    placements = _place_humans(
        human, projection.coords, labels, generated_features, human_features, own_nearest
    )
    return LevelDistribution(
        game=levels[0].game,
        levels=levels,
        difficulties=[*difficulties, *[None] * len(human)],
        human_count=len(human),
        encoding="complete" if complete else "study",
        eps=eps,
        min_samples=min_samples,
        seed=seed,
        feature_size=features.shape[1],
        projection=projection,
        labels=labels,
        clusters=clusters(projection.coords, labels),
        humans=placements,
        generated_nearest=own_nearest,
    )


def _place_humans(
    human: Sequence[Level],
    coords: np.ndarray,
    labels: np.ndarray,
    generated_features: np.ndarray,
    human_features: np.ndarray,
    own_nearest: np.ndarray,
) -> list[HumanPlacement]:
    count = len(generated_features)
    if not human:
        return []
    nearest = nearest_generated(human_features, generated_features)
    placements = []
    for i, level in enumerate(human):
        point = count + i
        pca_distance = float(np.linalg.norm(coords[:count] - coords[point], axis=1).min())
        placements.append(
            HumanPlacement(
                index=i,
                name=level.name,
                point=point,
                cluster=int(labels[point]),
                coords=coords[point],
                nearest_generated=int(nearest.index[i]),
                hamming=int(nearest.distance[i]),
                pca_distance=pca_distance,
                percentile=distance_percentile(nearest.distance[i], own_nearest),
            )
        )
    return placements
