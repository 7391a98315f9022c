import numpy as np

from gvgai_pcg.analysis.clustering import NOISE, cluster_labels, clusters, project


def _blobs() -> np.ndarray:
    rng = np.random.default_rng(3)
    return np.concatenate([rng.normal(0, 0.1, (30, 2)), rng.normal(5, 0.1, (20, 2)), [[20.0, 20.0]]])


def test_projection_and_clustering_are_deterministic_for_a_fixed_seed():
    features = (np.random.default_rng(0).random((300, 600)) < 0.2).astype(np.uint8)
    first, second = project(features, seed=7), project(features, seed=7)
    np.testing.assert_array_equal(first.coords, second.coords)
    assert first.coords.shape == (300, 2)
    np.testing.assert_array_equal(cluster_labels(first.coords), cluster_labels(second.coords))


def test_two_blobs_are_two_clusters_and_the_stray_point_is_noise():
    points = _blobs()
    labels = cluster_labels(points, eps=0.5, min_samples=10)
    assert labels[50] == NOISE
    assert len(set(labels[:30])) == 1 and len(set(labels[30:50])) == 1 and labels[0] != labels[30]
    found = clusters(points, labels)
    assert [c.size for c in found] == [30, 20]


def test_representative_is_the_member_closest_to_the_cluster_mean():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.9, 0.1], [3.0, 0.0]])
    (cluster,) = clusters(points, np.zeros(5, dtype=int))
    np.testing.assert_allclose(cluster.centroid, [1.38, 0.02])
    assert cluster.representative == 1
