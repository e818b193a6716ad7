"""Grid.query_pairs and frnn.query_pairs against cKDTree.query_pairs."""
import numpy as np
import pytest

import frnn
from conftest import (POINT_SETS, ambiguous_pairs, exact, lattice, reference_pairs, tree, uniform,
                      without)


def test_query_pairs_matches_ckdtree(case, dtype, kind):
    name, points, radius, box = case
    g = frnn.Grid(points.astype(dtype), radius, grid=kind, periodic=box)
    assert g.dtype == dtype and g.n == len(points)
    if box is None:  # periodic grids are uniform whatever was asked
        assert g.kind == kind
    got = g.query_pairs()
    assert got.dtype == np.int64 and got.shape[1] == 2
    assert np.all(got[:, 0] < got[:, 1])
    # Sorted lexicographically, without duplicates.
    assert np.all(np.diff(got[:, 0]) >= 0)
    same_row = np.diff(got[:, 0]) == 0
    assert np.all(np.diff(got[:, 1])[same_row] > 0)

    points = exact(points, dtype)
    want = reference_pairs(points, radius, box)
    drop = ambiguous_pairs(points, radius, box, dtype)
    assert len(drop) <= max(2, len(want) // 1000), "too many borderline pairs for a fair test"
    np.testing.assert_array_equal(without(got, drop), without(want, drop))


@pytest.mark.parametrize("name", ["lattice3d_r1", "lattice3d_r2", "lattice2d_r2",
                                  "periodic_lattice3d"])
def test_ties_at_exactly_r_are_neighbors(name, dtype):
    """On integer lattices many pairs lie at exactly r: both cKDTree and frnn keep them."""
    points, radius, box = POINT_SETS[name]
    got = frnn.Grid(points.astype(dtype), radius, periodic=box).query_pairs()
    d = points[got[:, 1]] - points[got[:, 0]]
    if box is not None:
        d -= box * np.round(d / box)
    dist = np.sqrt((d * d).sum(axis=1))
    at_r = np.count_nonzero(dist == radius)
    assert at_r > 0
    # cKDTree's query_pairs also uses <= r: it finds the same tied pairs.
    want = reference_pairs(points, radius, box)
    np.testing.assert_array_equal(got, want)
    below = tree(points, box).query_pairs(np.nextafter(radius, 0), output_type="ndarray")
    assert len(want) - len(below) == at_r


def test_one_shot_query_pairs(dtype):
    points = uniform(1500, 3, 10.0, 7).astype(dtype)
    want = frnn.Grid(points, 1.0, grid="hash", threads=1).query_pairs()
    got = frnn.query_pairs(points, 1.0, grid="hash", threads=1)
    np.testing.assert_array_equal(got, want)
    np.testing.assert_array_equal(frnn.query_pairs(points, 1.0), want)


def test_results_do_not_depend_on_threads_or_cell_size():
    points = uniform(4000, 3, 15.0, 8)
    base = frnn.Grid(points, 1.0, threads=1).query_pairs()
    for kw in ({"threads": 2}, {"threads": 4}, {"cell_size": 0.5}, {"cell_size": 0.25},
               {"grid": "hash", "cell_size": 0.5}):
        np.testing.assert_array_equal(frnn.Grid(points, 1.0, **kw).query_pairs(), base)


def test_duplicates_and_far_outlier():
    points = np.concatenate([lattice(6, 3), lattice(6, 3), [[1e7, 1e7, 1e7]]])
    g = frnn.Grid(points, 1.0)
    assert g.kind == "hash"  # a bounded grid would need ~1e21 cells
    np.testing.assert_array_equal(g.query_pairs(), reference_pairs(points, 1.0, None))


def test_tiny_inputs():
    assert frnn.Grid(np.zeros((0, 3)), 1.0).query_pairs().shape == (0, 2)
    assert frnn.Grid(np.zeros((1, 2)), 1.0).query_pairs().shape == (0, 2)
    np.testing.assert_array_equal(frnn.Grid(np.zeros((2, 2)), 1.0).query_pairs(), [[0, 1]])


@pytest.mark.parametrize("box", [2.0, 2.5, 3.0, 4.5])
def test_small_periodic_boxes(box, dtype):
    """Boxes of 2 to 4.5 radii: stencils wrap onto the same cells; each pair is found once."""
    points = uniform(400, 3, box, 9)
    drop = ambiguous_pairs(exact(points, dtype), 1.0, box, dtype)
    got = frnn.Grid(points.astype(dtype), 1.0, periodic=box).query_pairs()
    want = reference_pairs(exact(points, dtype), 1.0, box)
    np.testing.assert_array_equal(without(got, drop), without(want, drop))
