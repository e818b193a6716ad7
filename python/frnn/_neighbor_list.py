"""frnn.neighbor_list: ASE's neighbor_list, on frnn's search (C++: frnn::lattice_grid)."""
import numbers as _numbers

import numpy as np

from ._frnn import _lattice_pairs


def _atoms_parts(a):
    """(positions, cell, pbc, numbers) of an ase.Atoms or of a (positions, cell, pbc[, numbers])."""
    if hasattr(a, "get_positions") and hasattr(a, "get_cell") and hasattr(a, "get_pbc"):
        return (a.get_positions(), np.asarray(a.get_cell(complete=True)), np.asarray(a.get_pbc()),
                a.get_atomic_numbers())
    if isinstance(a, (tuple, list)) and len(a) in (3, 4):
        positions = np.asarray(a[0])
        if positions.ndim != 2 or positions.shape[1] not in (2, 3):
            raise ValueError(f"positions must have shape (N, 2) or (N, 3); got shape {positions.shape}")
        dim = positions.shape[1]
        cell = np.asarray(a[1], dtype=np.float64)
        if cell.ndim == 1 and cell.shape == (dim,):  # cell lengths, as ASE accepts
            cell = np.diag(cell)
        pbc = np.asarray(a[2], dtype=bool)
        if pbc.ndim == 0:
            pbc = np.full(dim, bool(pbc))
        numbers = None if len(a) == 3 or a[3] is None else np.asarray(a[3])
        if numbers is not None and numbers.shape != (len(positions),):
            raise ValueError(f"numbers must have shape ({len(positions)},); got shape {numbers.shape}")
        return positions, cell, pbc, numbers
    raise TypeError("a must be an ase.Atoms or a tuple (positions, cell, pbc[, numbers])")


def _atomic_number(key):
    if isinstance(key, _numbers.Integral):
        return int(key)
    try:
        from ase.data import atomic_numbers
    except ImportError:
        raise ValueError(f"cutoff: element symbol {key!r} needs ASE installed; give atomic numbers instead") from None
    if key not in atomic_numbers:
        raise ValueError(f"cutoff: {key!r} is not an element symbol")
    return atomic_numbers[key]


def neighbor_list(quantities, a, cutoff, self_interaction=False, *, threads=None):
    """Neighbor list of atoms in a periodic cell, with ASE's signature and results.

    Parameters
    ----------
    quantities : str
        Any of "i" (first atom), "j" (second atom), "d" (distance), "D" (distance vector,
        x_j - x_i + S . cell) and "S" (integer shift of j's image), in the order returned.
    a : ase.Atoms or tuple
        An ase.Atoms (ASE is optional: never imported for anything else), or
        (positions, cell, pbc[, numbers]): positions (N, 3) or (N, 2), cell (3, 3) or (2, 2)
        with the lattice vectors as rows (or their lengths), pbc one bool per axis (or one).
        The cell may be triclinic and smaller than the cutoff: a pair appears once per image.
    cutoff : float, sequence of float or dict
        One cutoff for all pairs; one radius per atom (pairs within r_i + r_j, e.g. ASE's
        natural_cutoffs); or a dict {(Z1, Z2): cutoff} by pair of atomic numbers or symbols
        (pairs not in the dict are never neighbors).
    self_interaction : bool
        Also list each atom as its own neighbor with S = 0 and d = 0.
    threads : int, optional
        Threads (default: FRNN_NUM_THREADS, else OMP_NUM_THREADS, else every CPU). Results
        are identical for any thread count.

    Returns
    -------
    One array per letter of ``quantities`` (a single array for one letter): i, j int64 (M,),
    d (M,), D (M, dim), S int64 (M, dim); rows sorted by i. Pairs with d < cutoff (strictly,
    as ASE), D and d computed as ASE does, in the positions' precision (float32 positions
    give float32 d and D).
    """
    positions, cell, pbc, atomic_numbers = _atoms_parts(a)
    for q in quantities:
        if q not in "ijdDS":
            raise ValueError(f"unsupported quantity {q!r}: use letters of 'ijdDS'")
    per_pair = None
    if isinstance(cutoff, dict):
        if atomic_numbers is None:
            raise ValueError("cutoff by pair of elements needs atomic numbers: pass (positions, cell, pbc, numbers)")
        per_pair = {}
        for (z1, z2), c in cutoff.items():
            z1, z2 = _atomic_number(z1), _atomic_number(z2)
            per_pair[(z1, z2)] = per_pair[(z2, z1)] = float(c)
        search = max(per_pair.values()) if per_pair else 0.0
        if search <= 0:
            search = np.nextafter(0.0, 1.0)
    elif np.isscalar(cutoff) or np.ndim(cutoff) == 0:
        search = float(cutoff)
    else:
        search = np.asarray(cutoff, dtype=np.float64)
    i, j, S, d, D = _lattice_pairs(positions, cell, pbc, search, self_interaction, True, threads)
    if per_pair is not None:
        zi, zj = atomic_numbers[i], atomic_numbers[j]
        limit = np.zeros(len(i))
        for (z1, z2), c in per_pair.items():
            limit[(zi == z1) & (zj == z2)] = c
        keep = d < limit
        i, j, S, d, D = i[keep], j[keep], S[keep], d[keep], D[keep]
    out = tuple({"i": i, "j": j, "d": d, "D": D, "S": S}[q] for q in quantities)
    return out[0] if len(out) == 1 else out
