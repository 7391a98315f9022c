import numpy as np

from gvgai_pcg.analysis.distances import (
    distance_percentile,
    generated_nearest_distances,
    hamming_matrix,
    nearest_generated,
)


def test_hamming_matrix_counts_differing_features():
    a = np.array([[1, 0, 1, 1], [0, 0, 0, 0]], dtype=np.uint8)
    b = np.array([[1, 0, 1, 1], [0, 1, 0, 0], [1, 1, 1, 1]], dtype=np.uint8)
    assert hamming_matrix(a, b).tolist() == [[0, 4, 1], [3, 1, 4]]


def test_nearest_generated_and_leave_one_out_distances():
    generated = np.array([[0, 0, 0, 0], [1, 0, 0, 0], [1, 1, 1, 1]], dtype=np.uint8)
    assert generated_nearest_distances(generated).tolist() == [1, 1, 3]
    nearest = nearest_generated(np.array([[1, 1, 1, 0]], dtype=np.uint8), generated)
    assert nearest.index.tolist() == [2] and nearest.distance.tolist() == [1]


def test_percentile_counts_ties_half():
    reference = np.array([1, 2, 2, 3])
    assert distance_percentile(0, reference) == 0.0
    assert distance_percentile(2, reference) == 50.0
    assert distance_percentile(4, reference) == 100.0
