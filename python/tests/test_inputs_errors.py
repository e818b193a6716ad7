"""Input conversion (dtypes, layouts, copies) and errors: bad input raises, never crashes."""
import tracemalloc

import numpy as np
import pytest

import frnn
from conftest import lattice, reference_pairs, uniform

POINTS = uniform(300, 3, 4.0, 41)


def test_error_is_a_value_error():
    assert issubclass(frnn.Error, ValueError)
    with pytest.raises(frnn.Error, match="radius"):
        frnn.Grid(POINTS, -1.0)


@pytest.mark.parametrize("bad", [
    np.zeros((5, 3), dtype=np.complex128),
    np.zeros((5, 3), dtype=bool),
    np.array([["a", "b"], ["c", "d"]]),
    np.array([[object(), 1.0]], dtype=object),
])
def test_unsupported_dtypes_raise_type_error(bad):
    with pytest.raises(TypeError, match="float32 or float64"):
        frnn.Grid(bad, 1.0)


@pytest.mark.parametrize("shape", [(10,), (10, 4), (10, 1), (2, 5, 3), ()])
def test_wrong_shapes_raise(shape):
    with pytest.raises(ValueError, match=r"shape \(N, 2\) or \(N, 3\)"):
        frnn.Grid(np.zeros(shape), 1.0)


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_non_finite_points_raise(value, dtype):
    points = POINTS.astype(dtype)
    points[17, 2] = value
    with pytest.raises(ValueError, match="point 17"):
        frnn.Grid(points, 1.0)
    g = frnn.Grid(POINTS.astype(dtype), 1.0)
    with pytest.raises(ValueError, match="non-finite"):
        g.query_ball_point([[1.0, 1.0, value]])
    with pytest.raises(ValueError, match="non-finite"):
        g.query_knn(2, [1.0, value, 1.0])


@pytest.mark.parametrize("kwargs, match", [
    ({"radius": 0.0}, "radius"),
    ({"radius": np.nan}, "radius"),
    ({"radius": 1e300, "dtype": np.float32}, "radius"),
    ({"grid": "octree"}, "grid kind"),
    ({"cell_size": 0.1}, "cell size"),
    ({"cell_size": 2.0}, "cell size"),
    ({"periodic": 1.5}, "periodic"),
    ({"periodic": [10.0, 10.0]}, "periodic"),
    ({"periodic": "big"}, "periodic"),
    ({"threads": 0}, "threads"),
    ({"threads": 100_000}, "threads"),
])
def test_bad_options_raise_value_error(kwargs, match):
    kwargs = dict(kwargs)
    radius = kwargs.pop("radius", 1.0)
    points = POINTS.astype(kwargs.pop("dtype", np.float64))
    with pytest.raises(ValueError, match=match):
        frnn.Grid(points, radius, **kwargs)


def test_bad_query_arguments_raise():
    g = frnn.Grid(POINTS, 1.0)
    with pytest.raises(ValueError, match=r"shape \(N, 3\) or \(3,\)"):
        g.query_ball_point([1.0, 2.0])
    with pytest.raises(ValueError, match=r"shape \(N, 3\)"):
        g.query_ball_point(np.zeros((4, 2)))
    with pytest.raises(TypeError, match="float32 or float64"):
        g.query_ball_point(np.zeros((4, 3), dtype=complex))
    for k in (0, -2, np.int64(-1)):
        with pytest.raises(ValueError, match=rf"query_knn: k must be >= 1, got {int(k)}$"):
            g.query_knn(k)
    with pytest.raises(ValueError, match="radius"):
        g.query_ball_point([1.0, 1.0, 1.0], r=-2.0)
    with pytest.raises(TypeError):
        frnn.Grid(POINTS, 1.0, "uniform")  # options are keyword-only


def test_periodic_accepts_scalar_and_per_axis_lengths():
    points = uniform(1000, 2, 1.0, 42) * [10.0, 20.0]
    g = frnn.Grid(points, 1.0, periodic=[10.0, 20.0])
    assert g.periodic == (10.0, 20.0)
    from scipy.spatial import cKDTree
    want = cKDTree(points, boxsize=[10.0, 20.0]).query_pairs(1.0, output_type="ndarray")
    assert len(g.query_pairs()) == len(want)
    assert frnn.Grid(points * [1, 0.5], 1.0, periodic=10).periodic == (10.0, 10.0)
    assert frnn.Grid(points, 1.0).periodic is None


def test_layouts_and_dtypes_give_the_same_pairs():
    want = reference_pairs(POINTS, 1.0, None)
    fortran = np.asfortranarray(POINTS)
    strided = np.zeros((len(POINTS), 6))
    strided[:, ::2] = POINTS
    big_endian = POINTS.astype(">f8")
    for points in (fortran, strided[:, ::2], big_endian, POINTS.tolist()):
        g = frnn.Grid(points, 1.0)
        assert g.dtype == np.float64
        np.testing.assert_array_equal(g.query_pairs(), want)
    ints = lattice(6, 3).astype(np.int32)
    g = frnn.Grid(ints, 1.0)
    assert g.dtype == np.float64
    np.testing.assert_array_equal(g.query_pairs(), reference_pairs(ints, 1.0, None))
    assert frnn.Grid(POINTS.astype(np.float16), 1.0).dtype == np.float64
    assert frnn.Grid(POINTS.astype(np.float32), 1.0).dtype == np.float32


def _numpy_bytes_allocated_by(f):
    """Peak bytes numpy allocated while f ran (numpy reports its buffers to tracemalloc)."""
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        before = tracemalloc.get_traced_memory()[0]
        f()
        return tracemalloc.get_traced_memory()[1] - before
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_contiguous_points_are_read_without_a_copy(dtype):
    points = uniform(200_000, 3, 50.0, 43).astype(dtype)
    copied = _numpy_bytes_allocated_by(lambda: frnn.Grid(np.asfortranarray(points), 0.5))
    assert copied >= points.nbytes  # the check can see a copy
    in_place = _numpy_bytes_allocated_by(lambda: frnn.Grid(points, 0.5))
    assert in_place < points.nbytes // 10


def test_threads_give_identical_results():
    points = uniform(5000, 3, 17.0, 44)
    one = frnn.Grid(points, 1.0, threads=1)
    two = frnn.Grid(points, 1.0, threads=2)
    assert one.threads == 1 and two.threads == 2
    for a, b in zip(one.neighbors(return_distances=True, sort=None),
                    two.neighbors(return_distances=True, sort=None)):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(one.permutation, two.permutation)


def test_properties_and_repr():
    g = frnn.Grid(POINTS.astype(np.float32), 1.0, grid="uniform", cell_size=0.5)
    assert (g.n, g.dim, g.radius, g.kind) == (300, 3, 1.0, "uniform")
    assert 0.5 <= g.cell_size < 0.75
    assert g.slots >= g.occupied_slots > 0 and g.memory_bytes > 0
    assert repr(g) == ("frnn.Grid(n=300, dim=3, radius=1.0, kind='uniform', "
                       "dtype=float32)")
    assert frnn.__version__
    assert "radius" in frnn.Grid.__doc__ and "float32" in frnn.Grid.__doc__
