"""Type stubs of frnn: fast fixed-radius neighbor search (the compiled module frnn._frnn)."""
from typing import Any, Dict, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

class Error(ValueError):
    """Raised for invalid arguments and failures inside frnn (a ValueError)."""

_Real = Union[np.float32, np.float64]
_Sort = Optional[Literal["index", "distance"]]
_CSR = Tuple[npt.NDArray[np.int64], npt.NDArray[np.uint32]]
_CSRDist = Tuple[npt.NDArray[np.int64], npt.NDArray[np.uint32], npt.NDArray[_Real]]

class Grid:
    """Fixed-radius neighbor search over one point set: |x_i - x_j| <= radius, i != j (or a
    radius per point: <= radius[i] under rule "gather", <= max(radius[i], radius[j]) under
    "symmetric")."""

    def __init__(
        self,
        points: npt.ArrayLike,
        radius: Union[float, npt.ArrayLike],
        *,
        grid: Literal["auto", "uniform", "hash"] = "auto",
        cell_size: Optional[float] = None,
        periodic: Union[None, float, Sequence[Optional[float]]] = None,
        threads: Optional[int] = None,
        rule: Literal["gather", "symmetric"] = "gather",
    ) -> None: ...
    def query_pairs(self) -> npt.NDArray[np.int64]:
        """(M, 2) int64 pairs i < j within radius, sorted lexicographically."""
    @overload
    def neighbors(
        self, return_distances: Literal[False] = ..., sort: _Sort = ..., half: bool = ...,
        *, rows: Optional[int] = ...
    ) -> _CSR: ...
    @overload
    def neighbors(
        self, return_distances: Literal[True], sort: _Sort = ..., half: bool = ...,
        *, rows: Optional[int] = ...
    ) -> _CSRDist: ...
    def count_neighbors(self) -> npt.NDArray[np.int64]:
        """Neighbors of every point (itself excluded)."""
    @overload
    def query_ball_point(
        self,
        x: npt.ArrayLike,
        r: Union[None, float, npt.ArrayLike] = ...,
        *,
        return_distances: Literal[False] = ...,
        sort: _Sort = ...,
        return_length: Literal[False] = ...,
    ) -> _CSR: ...
    @overload
    def query_ball_point(
        self,
        x: npt.ArrayLike,
        r: Union[None, float, npt.ArrayLike] = ...,
        *,
        return_distances: Literal[True],
        sort: _Sort = ...,
        return_length: Literal[False] = ...,
    ) -> _CSRDist: ...
    @overload
    def query_ball_point(
        self,
        x: npt.ArrayLike,
        r: Union[None, float, npt.ArrayLike] = ...,
        *,
        return_distances: bool = ...,
        sort: _Sort = ...,
        return_length: Literal[True],
    ) -> npt.NDArray[np.int64]: ...
    def query_knn(self, k: int, x: Optional[npt.ArrayLike] = None) -> _CSRDist:
        """At most k nearest neighbors within radius, rows sorted by distance then index."""
    def cell_of(self, x: npt.ArrayLike) -> Tuple[int, ...]:
        """The integer coordinates of the cell of point x."""
    def cells_within(self, x: npt.ArrayLike) -> Tuple[Tuple[int, ...], Tuple[int, ...]]:
        """(first, last): the block of cells a query at x visits."""
    def cell_bounds(self, cell: Sequence[int]) -> Tuple[Tuple[float, ...], Tuple[float, ...]]:
        """Lower and upper corner of a cell, in the points' units."""
    def update(self, points: npt.ArrayLike) -> None:
        """Rebuild over new positions with the same radius and options."""
    def reorder(self, array: npt.ArrayLike) -> np.ndarray:
        """array.take(permutation, axis=0): the array in cell order."""
    def restore_order(self, array: npt.ArrayLike) -> np.ndarray:
        """The inverse of reorder()."""
    @property
    def permutation(self) -> npt.NDArray[np.int64]:
        """permutation[s]: the caller's index of the s-th point in cell order."""
    @property
    def n(self) -> int: ...
    @property
    def radius(self) -> float: ...
    @property
    def radii(self) -> Optional[npt.NDArray[_Real]]: ...
    @property
    def rule(self) -> Optional[Literal["gather", "symmetric"]]: ...
    @property
    def dim(self) -> Literal[2, 3]: ...
    @property
    def dtype(self) -> np.dtype: ...
    @property
    def kind(self) -> Literal["uniform", "hash"]: ...
    @property
    def slots(self) -> int: ...
    @property
    def occupied_slots(self) -> int: ...
    @property
    def cell_size(self) -> float: ...
    @property
    def periodic(self) -> Optional[Tuple[float, ...]]: ...
    @property
    def threads(self) -> int: ...
    @property
    def memory_bytes(self) -> int: ...
    def __len__(self) -> int: ...

def query_pairs(
    points: npt.ArrayLike,
    radius: Union[float, npt.ArrayLike],
    *,
    grid: Literal["auto", "uniform", "hash"] = "auto",
    cell_size: Optional[float] = None,
    periodic: Union[None, float, Sequence[Optional[float]]] = None,
    threads: Optional[int] = None,
    rule: Literal["gather", "symmetric"] = "symmetric",
) -> npt.NDArray[np.int64]:
    """All pairs i < j within radius: Grid(points, radius, **kw).query_pairs()."""

def neighbor_list(
    quantities: str,
    a: Any,
    cutoff: Union[float, npt.ArrayLike, Dict[Tuple[Union[int, str], Union[int, str]], float]],
    self_interaction: bool = False,
    *,
    threads: Optional[int] = None,
) -> Union[npt.NDArray[Any], Tuple[npt.NDArray[Any], ...]]:
    """ASE's neighbor_list on frnn's search: a is an ase.Atoms or (positions, cell, pbc[,
    numbers]); one array per letter of quantities ("ijdDS"), rows sorted by i, d < cutoff."""
