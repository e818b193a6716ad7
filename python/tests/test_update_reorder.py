"""Grid.update (the next time step), Grid.reorder / restore_order and Grid.permutation."""
import threading

import numpy as np
import pytest

import frnn
from conftest import reference_pairs, uniform


def test_update_matches_a_fresh_grid(dtype, kind):
    rng = np.random.default_rng(31)
    points = uniform(3000, 3, 14.0, 31)
    g = frnn.Grid(points.astype(dtype), 1.0, grid=kind, threads=2)
    for step in range(3):
        points = points + rng.uniform(-0.05, 0.05, points.shape)
        g.update(points.astype(dtype))
        fresh = frnn.Grid(points.astype(dtype), 1.0, grid=kind, threads=2)
        np.testing.assert_array_equal(g.query_pairs(), fresh.query_pairs())
        np.testing.assert_array_equal(g.permutation, fresh.permutation)
    assert g.radius == 1.0 and g.dtype == dtype


def test_update_may_change_the_number_of_points():
    g = frnn.Grid(uniform(1000, 2, 20.0, 32), 1.0)
    points = uniform(1500, 2, 20.0, 33)
    g.update(points)
    assert g.n == 1500 and len(g) == 1500
    np.testing.assert_array_equal(g.query_pairs(), reference_pairs(points, 1.0, None))


def test_update_converts_to_the_grid_precision():
    points = uniform(800, 3, 8.0, 34)
    g = frnn.Grid(points.astype(np.float32), 1.0)
    g.update(points)  # float64 input, converted to float32
    assert g.dtype == np.float32
    np.testing.assert_array_equal(
        g.query_pairs(), frnn.Grid(points.astype(np.float32), 1.0).query_pairs())


def test_failed_update_leaves_the_grid_unchanged():
    points = uniform(500, 3, 6.0, 35)
    g = frnn.Grid(points, 1.0)
    before = g.query_pairs()
    bad = points.copy()
    bad[7, 1] = np.nan
    with pytest.raises(ValueError, match="NaN or infinite"):
        g.update(bad)
    with pytest.raises(ValueError, match=r"shape \(N, 3\)"):
        g.update(points[:, :2])
    np.testing.assert_array_equal(g.query_pairs(), before)


def test_reorder_and_permutation(kind):
    points = uniform(2000, 3, 12.0, 36)
    g = frnn.Grid(points, 1.0, grid=kind)
    perm = g.permutation
    assert perm.dtype == np.int64
    np.testing.assert_array_equal(np.sort(perm), np.arange(len(points)))
    sorted_points = g.reorder(points)
    np.testing.assert_array_equal(sorted_points, points[perm])
    # Any dtype and trailing shape; restore_order is the inverse.
    velocity = np.random.default_rng(36).random((len(points), 2, 3)).astype(np.float32)
    np.testing.assert_array_equal(g.restore_order(g.reorder(velocity)), velocity)
    ids = np.arange(len(points))
    np.testing.assert_array_equal(g.reorder(ids), perm)
    # Pairs of the reordered points are the same pairs, renumbered.
    renumbered = frnn.Grid(sorted_points, 1.0).query_pairs()
    mapped = np.sort(perm[renumbered], axis=1)
    mapped = mapped[np.lexsort((mapped[:, 1], mapped[:, 0]))]
    np.testing.assert_array_equal(mapped, g.query_pairs())


def test_cell_order_puts_near_points_together():
    """In cell order, neighbors sit much closer in memory than in a random order."""
    points = uniform(4000, 3, 16.0, 37)
    g = frnn.Grid(points, 1.0, grid="uniform")
    pairs = g.query_pairs()
    position = np.argsort(g.permutation)  # original index -> place in cell order
    gap_sorted = np.median(np.abs(position[pairs[:, 0]] - position[pairs[:, 1]]))
    gap_original = np.median(np.abs(pairs[:, 0] - pairs[:, 1]))
    assert gap_sorted * 4 < gap_original


@pytest.mark.parametrize("shape", [(10,), (2001, 3), ()])
def test_reorder_wrong_length_raises(shape):
    g = frnn.Grid(uniform(2000, 3, 12.0, 38), 1.0)
    with pytest.raises(ValueError, match="2000 rows"):
        g.reorder(np.zeros(shape))
    with pytest.raises(ValueError, match="2000 rows"):
        g.restore_order(np.zeros(shape))


def test_concurrent_queries_and_updates_are_consistent():
    """Threads query one Grid while another updates it: every answer is one of the two
    point sets' answers, never a mix (build and search run without the GIL)."""
    a = uniform(3000, 3, 14.0, 39)
    b = uniform(3000, 3, 14.0, 40)
    answers = [frnn.Grid(p, 1.0).query_pairs() for p in (a, b)]
    g = frnn.Grid(a, 1.0, threads=1)
    errors = []

    def query():
        try:
            for _ in range(15):
                got = g.query_pairs()
                if not any(got.shape == w.shape and np.array_equal(got, w) for w in answers):
                    errors.append("mixed result")
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(repr(e))

    def update():
        for step in range(15):
            g.update(b if step % 2 == 0 else a)

    threads = [threading.Thread(target=query) for _ in range(2)] + [threading.Thread(target=update)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
