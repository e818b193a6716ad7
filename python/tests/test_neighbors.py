"""Grid.neighbors and Grid.count_neighbors against cKDTree.query_ball_point."""
import numpy as np
import pytest

import frnn
from conftest import (ambiguous_pairs, csr_rows, exact, pairs_from_rows, reference_pairs,
                      reference_rows, tree, uniform, without)


def distances_of(points, i, js, box):
    d = points[js] - points[i]
    if box is not None:
        d -= box * np.round(d / box)
    return np.sqrt((d * d).sum(axis=1))


def test_neighbors_match_ckdtree(case, dtype):
    name, points, radius, box = case
    g = frnn.Grid(points.astype(dtype), radius, periodic=box)
    offsets, indices, dists = g.neighbors(return_distances=True)
    assert offsets.dtype == np.int64 and indices.dtype == np.uint32 and dists.dtype == dtype
    assert len(offsets) == len(points) + 1 and offsets[0] == 0 and offsets[-1] == len(indices)
    rows = csr_rows(offsets, indices)
    for i, row in enumerate(rows):
        assert i not in row
        assert np.all(np.diff(row.astype(np.int64)) > 0)  # sort="index"
    points = exact(points, dtype)
    drop = ambiguous_pairs(points, radius, box, dtype)
    np.testing.assert_array_equal(without(pairs_from_rows(rows), drop),
                                  without(reference_pairs(points, radius, box), drop))
    # Distances in the input's precision: compare with float64 arithmetic on the same values.
    eps = np.finfo(dtype).eps
    atol = 8 * eps * max(1.0, np.abs(points).max())
    for i in range(0, len(points), 97):
        want = distances_of(points, i, rows[i].astype(np.int64), box)
        np.testing.assert_allclose(dists[offsets[i]:offsets[i + 1]], want, rtol=4 * eps,
                                   atol=atol)


def test_neighbor_lists_are_symmetric(case):
    name, points, radius, box = case
    offsets, indices = frnn.Grid(points, radius, periodic=box).neighbors()
    rows = np.repeat(np.arange(len(points)), np.diff(offsets))
    forward = set(zip(rows.tolist(), indices.tolist()))
    assert forward == {(j, i) for i, j in forward}


def row_ids(offsets):
    return np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))


def test_sort_orders_and_half(case, dtype):
    name, points, radius, box = case
    g = frnn.Grid(points.astype(dtype), radius, periodic=box)
    off_i, idx_i = g.neighbors(sort="index")
    off_d, idx_d, dist_d = g.neighbors(return_distances=True, sort="distance")
    off_n, idx_n = g.neighbors(sort=None)
    np.testing.assert_array_equal(off_d, off_i)
    np.testing.assert_array_equal(off_n, off_i)
    rows = row_ids(off_i)
    # sort="distance": increasing distance inside each row, ties by increasing index.
    order = np.lexsort((idx_d, dist_d, rows))
    np.testing.assert_array_equal(order, np.arange(len(idx_d)))
    # Every order holds the same neighbors in each row.
    for idx in (idx_d, idx_n):
        np.testing.assert_array_equal(idx[np.lexsort((idx, rows))], idx_i)
    # half=True keeps exactly the entries j > i, in the same order.
    off_h, idx_h = g.neighbors(half=True)
    keep = idx_i > rows
    np.testing.assert_array_equal(idx_h, idx_i[keep])
    np.testing.assert_array_equal(np.diff(off_h), np.bincount(rows[keep], minlength=len(points)))


def test_count_neighbors_matches_ckdtree(case, dtype):
    name, points, radius, box = case
    g = frnn.Grid(points.astype(dtype), radius, periodic=box)
    counts = g.count_neighbors()
    assert counts.dtype == np.int64
    offsets, _ = g.neighbors(sort=None)
    np.testing.assert_array_equal(counts, np.diff(offsets))
    points = exact(points, dtype)
    want = tree(points, box).query_ball_point(points, radius, return_length=True) - 1
    if dtype == np.float64:
        np.testing.assert_array_equal(counts, want)
    else:
        # Borderline pairs may flip in float32: each moves two counts by one.
        drop = ambiguous_pairs(points, radius, box, dtype)
        assert np.abs(counts - want).sum() <= 2 * len(drop)


def test_results_own_their_buffers_without_copies():
    """The CSR arrays wrap the C++ vectors (a capsule is their base): no copy was made."""
    g = frnn.Grid(uniform(500, 3, 5.0, 11), 1.0)
    for a in g.neighbors(return_distances=True) + (g.query_pairs(),):
        assert type(a.base).__name__ == "PyCapsule"
        assert a.flags.c_contiguous and a.flags.owndata is False


def test_rows_match_ckdtree_lists():
    points = uniform(2000, 3, 12.0, 12)
    offsets, indices = frnn.Grid(points, 1.1).neighbors()
    want = reference_rows(points, 1.1, None)
    for i, row in enumerate(csr_rows(offsets, indices)):
        np.testing.assert_array_equal(row, want[i][want[i] != i])


@pytest.mark.parametrize("sort", ["nearest", 1, "INDEX"])
def test_bad_sort_raises(sort):
    g = frnn.Grid(uniform(10, 2, 1.0, 0), 0.5)
    with pytest.raises(ValueError, match="sort must be"):
        g.neighbors(sort=sort)


@pytest.mark.parametrize("half", [False, True])
def test_rows_of_the_first_points_are_those_of_the_full_lists(case, half):
    name, points, radius, box = case
    g = frnn.Grid(points, radius, periodic=box)
    full = g.neighbors(return_distances=True, half=half)
    n = len(points)
    for m in sorted({0, 1, n // 3, n}):
        offsets, indices, dists = g.neighbors(return_distances=True, half=half, rows=m)
        assert len(offsets) == m + 1
        np.testing.assert_array_equal(offsets, full[0][:m + 1])
        np.testing.assert_array_equal(indices, full[1][:full[0][m]])
        np.testing.assert_array_equal(dists, full[2][:full[0][m]])


@pytest.mark.parametrize("rows, error, message", [(-1, ValueError, "rows must be >= 0"), (11, ValueError, "11"),
                                                  (2.5, TypeError, "rows must be an integer, got 2.5")])
def test_bad_rows_raise(rows, error, message):
    g = frnn.Grid(uniform(10, 2, 1.0, 0), 0.5)
    with pytest.raises(error, match=message):
        g.neighbors(rows=rows)
    assert len(g.neighbors(rows=np.int64(3))[0]) == 4
