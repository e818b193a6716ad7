"""A radius per point: Grid(points, radii, rule=...) and query_ball_point(x, r_array), against
cKDTree (whose query_ball_point takes an array of radii) and a brute-force reference."""
import numpy as np
import pytest
from scipy.spatial import cKDTree

import frnn
from conftest import csr_rows, sorted_pairs


def points_and_radii(n, dim, seed, lo=0.2, hi=1.0, side=8.0):
    rng = np.random.default_rng(seed)
    return rng.uniform(0, side, (n, dim)), rng.uniform(lo, hi, n)


def brute_rows(points, radii, rule, queries=None, query_radii=None, box=None):
    """Row i: the j != i within radii[i] (gather) or max(radii[i], radii[j]) (symmetric)."""
    q = points if queries is None else queries
    qr = radii if query_radii is None else query_radii
    d = q[:, None, :] - points[None, :, :]
    if box is not None:
        d -= box * np.round(d / box)
    dist = np.sqrt((d * d).sum(axis=2))
    limit = qr[:, None] if rule == "gather" else np.maximum(qr[:, None], radii[None, :])
    hit = dist <= limit
    if queries is None:
        np.fill_diagonal(hit, False)
    return [np.flatnonzero(row) for row in hit]


@pytest.mark.parametrize("rule", ["gather", "symmetric"])
@pytest.mark.parametrize("dim", [2, 3])
def test_neighbors_match_brute_force(rule, dim):
    points, radii = points_and_radii(900, dim, 11 + dim)
    g = frnn.Grid(points, radii, rule=rule)
    assert g.rule == rule and g.radius == radii.max()
    np.testing.assert_array_equal(g.radii, radii)
    offsets, indices = g.neighbors()
    want = brute_rows(points, radii, rule)
    for i, (row, w) in enumerate(zip(csr_rows(offsets, indices), want)):
        np.testing.assert_array_equal(row, w, err_msg=f"row {i}")
    np.testing.assert_array_equal(g.count_neighbors(), [len(w) for w in want])


def test_gather_queries_match_ckdtree_with_radius_arrays():
    points, radii = points_and_radii(1200, 3, 21)
    queries, query_radii = points_and_radii(300, 3, 22, lo=0.05, hi=1.0)
    want = cKDTree(points).query_ball_point(queries, query_radii)
    for g in (frnn.Grid(points, radii), frnn.Grid(points, 1.0), frnn.Grid(points, 0.5)):
        # The last grid's radius is below some query radii: it answers through a grid of the
        # largest one.
        offsets, indices = g.query_ball_point(queries, query_radii)
        for q, (row, w) in enumerate(zip(csr_rows(offsets, indices), want)):
            np.testing.assert_array_equal(row, sorted(w), err_msg=f"query {q}")
        np.testing.assert_array_equal(g.query_ball_point(queries, query_radii, return_length=True),
                                      [len(w) for w in want])


def test_symmetric_queries_and_pairs():
    points, radii = points_and_radii(800, 2, 31)
    queries, query_radii = points_and_radii(200, 2, 32)
    g = frnn.Grid(points, radii, rule="symmetric")
    offsets, indices = g.query_ball_point(queries, query_radii)
    want = brute_rows(points, radii, "symmetric", queries, query_radii)
    for q, (row, w) in enumerate(zip(csr_rows(offsets, indices), want)):
        np.testing.assert_array_equal(row, w, err_msg=f"query {q}")
    pairs = sorted_pairs([(i, j) for i, row in enumerate(brute_rows(points, radii, "symmetric"))
                          for j in row if j > i])
    np.testing.assert_array_equal(g.query_pairs(), pairs)
    np.testing.assert_array_equal(frnn.query_pairs(points, radii), pairs)


def test_periodic_box_with_radii():
    points, radii = points_and_radii(700, 3, 41, side=6.0)
    box = np.array([6.0, 6.0, 6.0])
    for rule in ("gather", "symmetric"):
        g = frnn.Grid(points, radii, periodic=box, rule=rule)
        offsets, indices = g.neighbors()
        for i, (row, w) in enumerate(zip(csr_rows(offsets, indices), brute_rows(points, radii, rule, box=box))):
            np.testing.assert_array_equal(row, w, err_msg=f"{rule} row {i}")


def test_update_keeps_the_radii():
    points, radii = points_and_radii(500, 3, 51)
    g = frnn.Grid(points, radii)
    moved = points + np.random.default_rng(52).uniform(-0.05, 0.05, points.shape)
    g.update(moved)
    offsets, indices = g.neighbors()
    for row, w in zip(csr_rows(offsets, indices), brute_rows(moved, radii, "gather")):
        np.testing.assert_array_equal(row, w)


def test_bad_radii_name_the_index():
    points, radii = points_and_radii(50, 3, 61)
    for bad, where in ((np.nan, "radius 7"), (0.0, "radius 7"), (-1.0, "radius 7")):
        r = radii.copy()
        r[7] = bad
        with pytest.raises(ValueError, match=where):
            frnn.Grid(points, r)
    with pytest.raises(ValueError, match="one per point"):
        frnn.Grid(points, radii[:49])
    with pytest.raises(ValueError, match="rule"):
        frnn.Grid(points, radii, rule="both")
    g = frnn.Grid(points, radii)
    with pytest.raises(ValueError, match="radius per point"):
        g.query_ball_point(points[:3])
    with pytest.raises(ValueError, match="query radius 1"):
        g.query_ball_point(points[:3], [0.1, 5.0, 0.1])
    with pytest.raises(ValueError, match="not mutual"):
        g.query_pairs()
