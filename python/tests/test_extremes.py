"""Radii and coordinates at the limits of float32 and float64, against cKDTree.

cKDTree computes in float64 and its squares overflow beyond 1e154, so the references here use
sets where every pair is far from r (no rounding question) and compare the pairs themselves.
"""
import numpy as np
import pytest
from scipy.spatial import cKDTree

import frnn


def all_pairs(n):
    i, j = np.triu_indices(n, 1)
    return np.stack([i, j], axis=1).astype(np.int64)


@pytest.mark.parametrize("radius", [1e200, 1e300, np.finfo(np.float64).max])
def test_radius_beyond_every_distance_float64(radius):
    points = np.random.default_rng(1).random((5, 3)) * 20 - 10
    g = frnn.Grid(points, radius)
    np.testing.assert_array_equal(g.query_pairs(), all_pairs(5))
    assert list(g.count_neighbors()) == [4] * 5
    offsets, indices = g.neighbors()
    assert list(offsets) == [0, 4, 8, 12, 16, 20] and indices.max() == 4


@pytest.mark.parametrize("radius", [1e20, 1e38])
def test_radius_beyond_every_distance_float32(radius):
    points = (np.random.default_rng(2).random((40, 3)) * 20 - 10).astype(np.float32)
    g = frnn.Grid(points, radius)
    np.testing.assert_array_equal(g.query_pairs(), all_pairs(40))
    assert list(g.count_neighbors()) == [39] * 40


@pytest.mark.parametrize("scale", [2.0**300, 2.0**-300])
def test_scaled_set_matches_ckdtree_on_the_unscaled_one(scale):
    """A set times a power of two has the same pairs at the radius times that power."""
    points = np.random.default_rng(3).random((800, 3)) * 10
    want = cKDTree(points).query_pairs(1.0, output_type="ndarray")
    want = want[np.lexsort((want[:, 1], want[:, 0]))]
    got = frnn.Grid(points * scale, 1.0 * scale).query_pairs()
    np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("grid", ["auto", "uniform", "hash"])
def test_far_query_point_has_no_hits(grid):
    points = np.random.default_rng(4).random((500, 3)) * 10
    g = frnn.Grid(points, 1.0, grid=grid)
    far = np.array([[1e20, 0, 0], [-1e20, 5, 5], [5, 5, 1e300]])
    assert list(g.query_ball_point(far, return_length=True)) == [0, 0, 0]
    offsets, indices = g.query_ball_point(far)
    assert list(offsets) == [0, 0, 0, 0] and len(indices) == 0
    # (cKDTree itself overflows at 1e300: compared on the first two.)
    assert all(len(row) == 0 for row in cKDTree(points).query_ball_point(far[:2], 1.0))
