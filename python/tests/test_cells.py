"""Grid.cell_of, cells_within and cell_bounds against what the search finds: every neighbor
within r of a query lies in a cell that cells_within names, and a cell's corners enclose the
points of that cell (uniform, hashed and periodic grids, 2D and 3D, float32 and float64)."""
import numpy as np
import pytest

import frnn
from conftest import uniform


def cells_per_axis(g, box):
    """Cells per axis of a periodic grid: the box over one cell's width."""
    lower, upper = g.cell_bounds((0,) * g.dim)
    return [round(b / (u - l)) for b, u, l in zip(box, upper, lower)]


def in_range(cell, first, last, dims):
    for a, c in enumerate(cell):
        if dims is None:
            if not first[a] <= c <= last[a]:
                return False
        elif last[a] - first[a] + 1 < dims[a] and (c - first[a]) % dims[a] > last[a] - first[a]:
            return False
    return True


CASES = [(dim, dtype, grid, periodic)
         for dim in (2, 3) for dtype in (np.float32, np.float64)
         for grid, periodic in (("uniform", False), ("hash", False), ("auto", True))]


@pytest.mark.parametrize("dim,dtype,grid,periodic", CASES)
def test_neighbors_lie_in_the_cells_within(dim, dtype, grid, periodic):
    side = 20.0 if dim == 2 else 10.0
    points = uniform(2000, dim, side, 5).astype(dtype)
    box = (side,) * dim if periodic else None
    g = frnn.Grid(points, 1.0, grid=grid, periodic=box)
    dims = cells_per_axis(g, box) if periodic else None
    cells = [g.cell_of(p) for p in points]
    queries = np.concatenate([points[:50], uniform(50, dim, side, 6).astype(dtype)])
    offsets, indices = g.query_ball_point(queries)
    assert offsets[-1] > len(queries)  # the check below has neighbors to look at
    for q, x in enumerate(queries):
        first, last = g.cells_within(x)
        assert all(f <= c <= l for f, c, l in zip(first, g.cell_of(x), last))
        for j in indices[offsets[q]:offsets[q + 1]]:
            assert in_range(cells[j], first, last, dims), (q, j)


@pytest.mark.parametrize("dim,dtype,grid,periodic", CASES)
def test_cell_bounds_enclose_their_points(dim, dtype, grid, periodic):
    side = 20.0 if dim == 2 else 10.0
    points = uniform(500, dim, side, 7).astype(dtype)
    g = frnn.Grid(points, 1.0, grid=grid, periodic=(side,) * dim if periodic else None)
    for p in points:
        lower, upper = g.cell_bounds(g.cell_of(p))
        # Border cells of a uniform grid hold points just beyond their corners (the grid's
        # rounding margin): a tolerance of a millionth of a cell.
        tol = 1e-6 * (upper[0] - lower[0])
        assert all(lo - tol <= x <= hi + tol for lo, x, hi in zip(lower, p, upper)), p


def test_bad_points_are_refused():
    g = frnn.Grid(uniform(100, 3, 5.0, 1), 1.0)
    with pytest.raises(ValueError, match="needs 3 coordinates"):
        g.cell_of([1.0, 2.0])
    with pytest.raises(ValueError, match="not finite"):
        g.cells_within([1.0, np.nan, 2.0])
    with pytest.raises(ValueError, match="cell needs 3 integers"):
        g.cell_bounds((1, 2))
