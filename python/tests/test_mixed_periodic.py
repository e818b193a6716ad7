"""Boxes periodic on some axes only: `periodic=(Lx, 0, Lz)` or `(Lx, None, Lz)`, against
cKDTree with `boxsize` 0 on the open axes."""
import numpy as np
import pytest
from scipy.spatial import cKDTree

import frnn
from conftest import csr_rows, exact, sorted_pairs

BOXES = {
    2: [(12.0, 0.0), (0.0, 9.0)],
    3: [(12.0, 0.0, 12.0), (10.0, 11.0, 0.0), (0.0, 0.0, 8.0)],
}


def points_in(box, n, seed, open_extent=7.0):
    """Uniform in [0, L) on the periodic axes and in [-1, open_extent) on the open ones."""
    rng = np.random.default_rng(seed)
    cols = [rng.uniform(0, L, n) if L > 0 else rng.uniform(-1, open_extent, n) for L in box]
    return np.stack(cols, axis=1)


def reference_tree(points, box):
    points = np.asarray(points, dtype=np.float64).copy()
    for a, L in enumerate(box):
        if L > 0:
            points[:, a] = np.mod(points[:, a], L)  # cKDTree needs [0, L) there
    return cKDTree(points, boxsize=np.asarray(box, dtype=np.float64))


CASES = [(dim, box, dtype) for dim in (2, 3) for box in BOXES[dim] for dtype in (np.float64, np.float32)]


@pytest.mark.parametrize("dim,box,dtype", CASES)
def test_pairs_and_ball_queries_match_ckdtree(dim, box, dtype):
    points = points_in(box, 1500, 7 + dim).astype(dtype)
    radius = 1.1
    g = frnn.Grid(points, radius, periodic=box)
    assert g.periodic == tuple(box)
    t = reference_tree(exact(points, dtype), box)
    # float32: leave out the pairs within rounding of r, where the two searches may differ.
    np.testing.assert_array_equal(_clear(g.query_pairs(), t, radius, dtype),
                                  _clear(sorted_pairs(t.query_pairs(radius, output_type="ndarray")),
                                         t, radius, dtype))
    # Queries inside the box and beyond the points on the open axes.
    queries = points_in(box, 200, 99, open_extent=12.0)
    offsets, indices = g.query_ball_point(queries.astype(dtype))
    want = t.query_ball_point(exact(queries.astype(dtype), dtype), radius)
    for q, (row, w) in enumerate(zip(csr_rows(offsets, indices), want)):
        near_r = _near_r(t, exact(queries.astype(dtype), dtype)[q], radius, dtype)
        assert set(map(int, row)) - near_r == set(w) - near_r, f"query {q}"


def _near_r(t, x, radius, dtype):
    """Indices within float32 rounding of r from x (none for float64)."""
    if dtype == np.float64:
        return set()
    return set(t.query_ball_point(x, radius * (1 + 1e-5))) - set(t.query_ball_point(x, radius * (1 - 1e-5)))


def _clear(pairs, t, radius, dtype):
    if dtype == np.float64:
        return pairs
    band = set(map(tuple, t.query_pairs(radius * (1 + 1e-5), output_type="ndarray"))) - set(
        map(tuple, t.query_pairs(radius * (1 - 1e-5), output_type="ndarray")))
    return sorted_pairs([p for p in map(tuple, pairs) if p not in band])


def test_none_leaves_an_axis_open():
    box = (12.0, 0.0, 12.0)
    points = points_in(box, 800, 3)
    with_zero = frnn.Grid(points, 1.0, periodic=box)
    with_none = frnn.Grid(points, 1.0, periodic=[12.0, None, 12.0])
    assert with_none.periodic == box
    np.testing.assert_array_equal(with_none.query_pairs(), with_zero.query_pairs())
    # Across the periodic faces pairs exist; across the open axis they do not.
    wrapped = frnn.Grid(np.array([[0.1, 0.1, 0.1], [11.9, 0.1, 0.1], [0.1, 6.9, 0.1]]), 1.0,
                        periodic=[12.0, None, 12.0])
    np.testing.assert_array_equal(wrapped.query_pairs(), [[0, 1]])


def test_errors_name_the_short_periodic_axis_only():
    points = points_in((12.0, 0.0, 12.0), 100, 5)
    with pytest.raises(Exception, match="axis 2"):
        frnn.Grid(points, 1.0, periodic=(12.0, 0.0, 1.5))
    # With r = 10 the periodic axis 0 is short; the open axis 1 has no length to be short.
    with pytest.raises(Exception, match="axis 0") as info:
        frnn.Grid(points, 10.0, periodic=(12.0, None, 30.0))
    assert "axis 1" not in str(info.value)
    with pytest.raises(Exception, match="axis 1"):
        frnn.Grid(points, 1.0, periodic=(12.0, -3.0, 12.0))
    with pytest.raises(ValueError, match="periodic"):
        frnn.Grid(points, 1.0, periodic=(12.0, "open", 12.0))
