"""Point sets and reference answers shared by the frnn tests.

Every expectation comes from scipy.spatial.cKDTree (float64 distances) run on exactly the
coordinates frnn sees (`exact`: the input rounded to its dtype). frnn computes float32
distances in float32, so a pair whose exact distance lies within float32 rounding of r (but
not exactly at r) may legitimately go either way: `ambiguous_pairs` finds those pairs, the
comparisons drop them, and the tests assert that such pairs are rare so the comparison still
means something. Integer lattices have exact distances in both precisions: nothing is dropped.
"""
import numpy as np
import pytest
from scipy.spatial import cKDTree

# Relative band around r inside which float32 and float64 decisions may differ.
FLOAT32_BAND = 1e-5


def uniform(n, dim, side, seed):
    return np.random.default_rng(seed).random((n, dim)) * side


def clustered(n, dim, seed):
    """Dense gaussian blobs with empty space between them (uneven cells)."""
    rng = np.random.default_rng(seed)
    centres = rng.random((8, dim)) * 60.0
    return centres[rng.integers(0, 8, n)] + rng.normal(0.0, 1.5, (n, dim))


def lattice(n_side, dim):
    """Integer lattice: many pairs at exactly distance 1, 2, sqrt(2), ... (ties at r)."""
    axes = [np.arange(n_side, dtype=np.float64)] * dim
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)


# name -> (points float64, radius, periodic box or None)
def point_sets():
    return {
        "uniform3d": (uniform(3000, 3, 14.0, 1), 1.0, None),
        "clustered3d": (clustered(3000, 3, 2), 0.7, None),
        "uniform2d": (uniform(3000, 2, 50.0, 3), 1.5, None),
        "lattice3d_r1": (lattice(12, 3), 1.0, None),
        "lattice3d_r2": (lattice(10, 3), 2.0, None),
        "lattice2d_r2": (lattice(30, 2), 2.0, None),
        "periodic3d": (uniform(3000, 3, 12.0, 4), 1.2, 12.0),
        "periodic2d": (uniform(2000, 2, 40.0, 5), 2.0, 40.0),
        "periodic_lattice3d": (lattice(10, 3), 2.0, 10.0),
    }


POINT_SETS = point_sets()


@pytest.fixture(params=sorted(POINT_SETS))
def case(request):
    points, radius, box = POINT_SETS[request.param]
    return request.param, points, radius, box


@pytest.fixture(params=[np.float64, np.float32], ids=["f64", "f32"])
def dtype(request):
    return request.param


@pytest.fixture(params=["uniform", "hash"])
def kind(request):
    return request.param


def exact(points, dtype):
    """The coordinates frnn searches, as float64 (exact for float32 values)."""
    return np.asarray(points).astype(dtype).astype(np.float64)


def tree(points, box):
    points = np.asarray(points, dtype=np.float64)
    if box is not None:
        points = np.mod(points, box)  # cKDTree needs [0, L); rounding may have reached L
    return cKDTree(points, boxsize=box)


def sorted_pairs(pairs):
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]


def reference_pairs(points, radius, box):
    """cKDTree pairs i < j with |xi - xj| <= r, sorted."""
    return sorted_pairs(tree(points, box).query_pairs(radius, output_type="ndarray"))


def ambiguous_pairs(points, radius, box, dtype):
    """Pairs of `points` (float64) whose distance is within float32 rounding of r, but not
    exactly r (none for float64)."""
    if dtype == np.float64:
        return np.zeros((0, 2), dtype=np.int64)
    t = tree(points, box)
    outer = t.query_pairs(radius * (1 + FLOAT32_BAND), output_type="ndarray")
    inner = t.query_pairs(radius * (1 - FLOAT32_BAND), output_type="ndarray")
    band = set(map(tuple, outer)) - set(map(tuple, inner))
    at_r = set(map(tuple, t.query_pairs(radius, output_type="ndarray"))) - set(
        map(tuple, t.query_pairs(np.nextafter(radius, 0), output_type="ndarray")))
    return np.array(sorted(band - at_r), dtype=np.int64).reshape(-1, 2)


def without(pairs, drop):
    drop = set(map(tuple, np.asarray(drop).reshape(-1, 2)))
    return sorted_pairs([p for p in map(tuple, pairs) if p not in drop])


def csr_rows(offsets, indices):
    return [indices[offsets[i]:offsets[i + 1]] for i in range(len(offsets) - 1)]


def pairs_from_rows(rows, half=True):
    out = [(i, int(j)) for i, row in enumerate(rows) for j in row if not half or j > i]
    return sorted_pairs(out)


def reference_rows(points, radius, box, queries=None):
    """Row q: sorted indices of points within r of queries[q] (self included if a query)."""
    t = tree(points, box)
    q = points if queries is None else queries
    return [np.array(sorted(r), dtype=np.int64) for r in t.query_ball_point(q, radius)]
