"""frnn: fast fixed-radius neighbor search of particles.

    >>> import numpy as np, frnn
    >>> points = np.random.default_rng(0).random((1000, 3))
    >>> g = frnn.Grid(points, 0.1)
    >>> pairs = g.query_pairs()            # (M, 2) int64, i < j, sorted
    >>> offsets, indices = g.neighbors()   # CSR lists of every point

Two points are neighbors when their distance is <= radius (the real radius). See
help(frnn.Grid) and docs/PYTHON.md.
"""
from ._frnn import Error, Grid, __version__, query_pairs
from ._neighbor_list import neighbor_list

__all__ = ["Error", "Grid", "neighbor_list", "query_pairs", "__version__"]
