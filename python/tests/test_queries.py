"""Grid.query_ball_point and Grid.query_knn against cKDTree."""
import numpy as np
import pytest

import frnn
from conftest import POINT_SETS, csr_rows, exact, lattice, reference_rows, tree, uniform


def other_points(points, box, seed):
    """Query points over the same region, plus a few copies of grid points (distance 0)."""
    rng = np.random.default_rng(seed)
    lo, hi = points.min(axis=0), points.max(axis=0)
    if box is not None:
        lo, hi = np.zeros(points.shape[1]), np.full(points.shape[1], box * 0.999)
    q = lo + rng.random((400, points.shape[1])) * (hi - lo)
    return np.concatenate([q, points[:5]])


@pytest.mark.parametrize("name", sorted(POINT_SETS))
def test_query_ball_point_matches_ckdtree(name):
    points, radius, box = POINT_SETS[name]
    g = frnn.Grid(points, radius, periodic=box)
    q = other_points(points, box, 21)
    offsets, indices = g.query_ball_point(q)
    assert len(offsets) == len(q) + 1
    want = reference_rows(points, radius, box, q)
    for row, w in zip(csr_rows(offsets, indices), want):
        np.testing.assert_array_equal(row, w)
    np.testing.assert_array_equal(g.query_ball_point(q, return_length=True),
                                  [len(w) for w in want])


@pytest.mark.parametrize("name", ["lattice3d_r2", "uniform3d", "periodic3d"])
def test_query_ball_point_with_other_radius(name):
    points, radius, box = POINT_SETS[name]
    g = frnn.Grid(points, radius, periodic=box, cell_size=radius / 2)
    q = other_points(points, box, 22)
    for r in (radius / 2, radius * 1.5):
        want = reference_rows(points, r, box, q)
        offsets, indices, dists = g.query_ball_point(q, r, return_distances=True)
        for row, w in zip(csr_rows(offsets, indices), want):
            np.testing.assert_array_equal(row, w)
        assert np.all(dists <= r)
    assert g.radius == radius  # the grid itself is unchanged


def test_query_ball_point_single_point_and_dtypes(dtype):
    points = uniform(1000, 3, 8.0, 23).astype(dtype)
    g = frnn.Grid(points, 1.0)
    x = [4.0, 4.0, 4.0]
    offsets, indices, dists = g.query_ball_point(x, return_distances=True, sort="distance")
    assert offsets.shape == (2,) and dists.dtype == dtype
    want = reference_rows(exact(points, dtype), 1.0, None, [x])[0]
    np.testing.assert_array_equal(np.sort(indices), want)
    assert np.all(np.diff(dists) >= 0)
    # Integer query points are accepted and converted.
    np.testing.assert_array_equal(g.query_ball_point(np.array([[4, 4, 4]]))[1], want)


def knn_reference(points, radius, box, k, queries=None, every=1):
    """Rows of at most k (index, distance) within r, sorted by distance then index: every
    `every`-th row, None for the others."""
    t = tree(points, box)
    q = points if queries is None else queries
    rows = t.query_ball_point(q, radius)
    out = []
    for i, row in enumerate(rows):
        if i % every:
            out.append(None)
            continue
        row = np.array([j for j in row if queries is not None or j != i], dtype=np.int64)
        d = np.sqrt(((t.data[row] - np.asarray(q[i], dtype=np.float64)) ** 2).sum(axis=1)) \
            if box is None else _periodic_dist(t.data[row], q[i], box)
        order = np.lexsort((row, d))[:k]
        out.append((row[order], d[order]))
    return out


def _periodic_dist(a, x, box):
    d = a - np.mod(np.asarray(x, dtype=np.float64), box)
    d -= box * np.round(d / box)
    return np.sqrt((d * d).sum(axis=1))


@pytest.mark.parametrize("name", sorted(POINT_SETS))
def test_query_knn_matches_reference(name):
    points, radius, box = POINT_SETS[name]
    g = frnn.Grid(points, radius, periodic=box)
    counts = g.count_neighbors()
    for k in (1, 4, 50):
        offsets, indices, dists = g.query_knn(k)
        want = knn_reference(points, radius, box, k, every=7)
        for i, (row, w) in enumerate(zip(csr_rows(offsets, indices), want)):
            if w is None:
                assert len(row) == min(k, counts[i])
                continue
            np.testing.assert_array_equal(row, w[0])
            np.testing.assert_allclose(dists[offsets[i]:offsets[i + 1]], w[1], rtol=1e-12,
                                       atol=1e-12)


def test_query_knn_agrees_with_ckdtree_query():
    """cKDTree.query(p, k + 1, distance_upper_bound=b) pads rows with inf and keeps only
    distances < b (strict), the point itself first: with b the next double above r, the same
    neighbors as query_knn(k)."""
    points = uniform(2000, 3, 10.0, 24)
    g = frnn.Grid(points, 1.0)
    k = 6
    d, i = tree(points, None).query(points, k + 1, distance_upper_bound=np.nextafter(1.0, np.inf))
    offsets, indices, dists = g.query_knn(k)
    for p in range(len(points)):
        keep = np.isfinite(d[p]) & (i[p] != p)
        np.testing.assert_array_equal(indices[offsets[p]:offsets[p + 1]], i[p][keep][:k])
        np.testing.assert_allclose(dists[offsets[p]:offsets[p + 1]], d[p][keep][:k], rtol=1e-12)


def test_query_knn_keeps_ties_at_r_that_ckdtree_bound_r_drops():
    """On an integer lattice with r = 1 every neighbor lies at exactly r: query_knn keeps them,
    cKDTree.query(distance_upper_bound=r) finds none (its bound is strict), and the next double
    above r finds the same ones."""
    points = lattice(6, 3)
    offsets, indices, dists = frnn.Grid(points, 1.0).query_knn(8)
    assert np.all(dists == 1.0)
    assert (np.diff(offsets).min(), np.diff(offsets).max()) == (3, 6)  # corners .. interior
    t = tree(points, None)
    d, _ = t.query(points, 9, distance_upper_bound=1.0)
    assert np.all(d[:, 0] == 0) and np.all(np.isinf(d[:, 1:]))  # only the point itself
    d, i = t.query(points, 9, distance_upper_bound=np.nextafter(1.0, np.inf))
    for p in range(len(points)):
        keep = np.isfinite(d[p]) & (i[p] != p)
        # Equal distances: frnn's row is in index order.
        np.testing.assert_array_equal(indices[offsets[p]:offsets[p + 1]], np.sort(i[p][keep]))


def test_query_knn_of_other_points():
    points, radius, box = POINT_SETS["lattice3d_r2"]
    g = frnn.Grid(points, radius)
    q = other_points(points, box, 25)
    offsets, indices, dists = g.query_knn(7, q)
    for row, w in zip(csr_rows(offsets, indices), knn_reference(points, radius, box, 7, q)):
        np.testing.assert_array_equal(row, w[0])
    one = g.query_knn(3, q[0])
    assert len(one[0]) == 2
