"""How far the human levels are from the generated distribution in the full feature space.

Beyond the study: the 2-D PCA picture can hide or invent distance, so each human level's
nearest generated level is found in the full binary feature space, where the Euclidean distance
is the square root of the number of differing features (a Hamming distance, reported as such).
That distance is ranked among the generated levels' own nearest-neighbour distances (each to
the nearest *other* generated level): percentile 50 means the human level sits as close to the
generated set as a typical generated level does; 100 means farther than every generated level
is from its neighbour. Ties count half, so a level identical to a generated one can score above 0.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class NearestGenerated:
    """For each query level: the index of its nearest generated level and the Hamming distance."""

    index: np.ndarray
    distance: np.ndarray


def hamming_matrix(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``[Na, Nb]`` count of differing features between rows of 0/1 matrices ``a`` and ``b``."""
    a, b = a.astype(np.float32), b.astype(np.float32)
    distance = a.sum(axis=1)[:, None] + b.sum(axis=1)[None, :] - 2.0 * (a @ b.T)
    return np.rint(distance).astype(np.int64)


def nearest_generated(queries: np.ndarray, generated: np.ndarray) -> NearestGenerated:
    """The nearest row of ``generated`` ``[G, F]`` for each row of ``queries`` ``[Q, F]``."""
    distance = hamming_matrix(queries, generated)
    index = distance.argmin(axis=1)
    return NearestGenerated(index=index, distance=distance[np.arange(len(queries)), index])


def generated_nearest_distances(generated: np.ndarray) -> np.ndarray:
    """``[G]`` each generated level's Hamming distance to the nearest other generated level."""
    if len(generated) < 2:
        raise ValueError(
            f"nearest-neighbour distances need at least 2 generated levels, got {len(generated)}"
        )
    distance = hamming_matrix(generated, generated)
    np.fill_diagonal(distance, np.iinfo(np.int64).max)
    return distance.min(axis=1)


def distance_percentile(distance: float, reference: np.ndarray) -> float:
    """Percent of ``reference`` distances below ``distance`` (ties count half), in [0, 100]."""
    below = np.count_nonzero(reference < distance)
    ties = np.count_nonzero(reference == distance)
    return 100.0 * (below + 0.5 * ties) / len(reference)
