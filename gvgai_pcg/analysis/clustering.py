"""PCA to two dimensions and DBSCAN on the result, as the study's notebook does (GENERATORS.md §5).

The features are used as they are (binary, no scaling), PCA is fitted on generated and human
levels together, and DBSCAN runs on the unscaled 2-D coordinates. A cluster's representative is
its member closest to the cluster mean in the 2-D plane. Label -1 is DBSCAN's noise: an outlier.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from sklearn.cluster import DBSCAN
from sklearn.decomposition import PCA

NOISE = -1


@dataclass(frozen=True)
class Projection:
    """2-D PCA coordinates ``[N, 2]`` and the variance ratio each axis explains ``[2]``."""

    coords: np.ndarray
    explained_variance_ratio: np.ndarray


@dataclass(frozen=True)
class Cluster:
    """One DBSCAN cluster: its label, members (indices into the analysed levels), mean and representative."""

    label: int
    members: np.ndarray
    centroid: np.ndarray
    representative: int

    @property
    def size(self) -> int:
        return len(self.members)


def project(features: np.ndarray, seed: int = 0) -> Projection:
    """PCA of ``features`` ``[N, F]`` to 2-D; ``seed`` fixes sklearn's randomized SVD solver."""
    pca = PCA(n_components=2, random_state=seed)
    with np.errstate(invalid="ignore", divide="ignore"):
        coords = pca.fit_transform(features.astype(np.float64))
    # Identical levels have no variance to explain: sklearn's 0/0 ratios become 0 (NaN is no JSON).
    ratio = np.nan_to_num(pca.explained_variance_ratio_, nan=0.0)
    return Projection(coords=coords, explained_variance_ratio=ratio)


def cluster_labels(coords: np.ndarray, eps: float = 0.5, min_samples: int = 10) -> np.ndarray:
    """DBSCAN label per point ``[N]`` (``NOISE`` for outliers); DBSCAN itself is deterministic."""
    return DBSCAN(eps=eps, min_samples=min_samples).fit_predict(coords)


def clusters(coords: np.ndarray, labels: np.ndarray) -> list[Cluster]:
    """The clusters in label order, each with the member closest to its mean as representative."""
    found = []
    for label in sorted(set(labels.tolist()) - {NOISE}):
        members = np.flatnonzero(labels == label)
        centroid = coords[members].mean(axis=0)
        closest = members[np.argmin(np.linalg.norm(coords[members] - centroid, axis=1))]
        found.append(Cluster(label=label, members=members, centroid=centroid, representative=int(closest)))
    return found
