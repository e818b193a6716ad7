"""frnn.neighbor_list against ASE's neighbor_list (Debian python3-ase).

i, j and S must be equal, except pairs whose distance lies within 4 ulp of the cutoff (frnn and
ASE round D differently: ASE's S . cell is a matrix product); d and D within 2 ulp of the
scale max(|x_i|, |x_j|, |S . cell|). Without ASE these tests skip, except under FRNN_STRICT=1
(CI), where a missing ASE is an error.
"""
import os

import numpy as np
import pytest

import frnn

if os.environ.get("FRNN_STRICT") == "1":
    import ase  # noqa: F401  (CI installs python3-ase: its absence must fail, not skip)
else:
    pytest.importorskip("ase")
from ase import Atoms  # noqa: E402
from ase.build import bulk, graphene, molecule  # noqa: E402
from ase.neighborlist import natural_cutoffs  # noqa: E402
from ase.neighborlist import neighbor_list as ase_neighbor_list  # noqa: E402


def random_cell(rng, length, shear, left=False):
    cell = np.diag(length * (1 + 0.2 * rng.uniform(-1, 1, 3)))
    cell += shear * length * np.tril(rng.uniform(-1, 1, (3, 3)), -1)
    if left:
        cell[0] = -cell[0]
    return cell


def compare(positions, cell, pbc, cutoff, numbers=None, self_interaction=False, what=""):
    """frnn against ASE on the same atoms: returns the number of pairs."""
    positions = np.asarray(positions, dtype=np.float64)
    atoms = Atoms(numbers=numbers if numbers is not None else np.ones(len(positions), int),
                  positions=positions, cell=cell, pbc=pbc)
    got = frnn.neighbor_list("ijSdD", atoms, cutoff, self_interaction)
    want = ase_neighbor_list("ijSdD", atoms, cutoff, self_interaction)
    assert np.all(np.diff(got[0]) >= 0), "rows sorted by i"
    full_cell = np.asarray(atoms.get_cell(complete=True))
    if isinstance(cutoff, dict):
        limit = max(cutoff.values())
    elif np.ndim(cutoff) == 0:
        limit = float(cutoff)
    else:
        limit = 2 * float(np.max(cutoff))
    band = 4 * np.spacing(limit) * 8  # 4 ulp of the scale of the cutoff, with headroom for a sum
    def keyed(r):
        return {(int(i), int(j), tuple(int(v) for v in s)): k for k, (i, j, s) in enumerate(zip(*r[:3]))}
    g, w = keyed(got), keyed(want)
    def near_cutoff(row, r):
        return np.ndim(cutoff) != 0 or abs(r[3][row] - limit) <= band
    bad = [(k, got[3][g[k]]) for k in g.keys() - w.keys() if not near_cutoff(g[k], got)]
    bad += [(k, want[3][w[k]]) for k in w.keys() - g.keys() if not near_cutoff(w[k], want)]
    assert not bad, f"{what}: pairs that differ, not within 4 ulp of the cutoff: {bad[:10]}"
    both = list(g.keys() & w.keys())
    a = np.array([g[k] for k in both], dtype=np.int64)
    b = np.array([w[k] for k in both], dtype=np.int64)
    if len(both):
        i, j, s = got[0][a], got[1][a], got[2][a]
        scale = np.maximum.reduce([np.abs(positions[i]).max(axis=1), np.abs(positions[j]).max(axis=1),
                                   np.abs(s @ full_cell).max(axis=1)])
        tol = 2 * np.spacing(scale)
        assert np.all(np.abs(got[3][a] - want[3][b]) <= tol), what
        assert np.all(np.abs(got[4][a] - want[4][b]) <= tol[:, None]), what
    return len(want[0])


@pytest.mark.parametrize("ratio", [0.3, 0.6, 1.0, 2.5, 10.0])
@pytest.mark.parametrize("shear", [0.0, 0.3, 1.0])
def test_random_triclinic_cells_against_ase(ratio, shear):
    rng = np.random.default_rng(int(ratio * 100 + shear * 10))
    cutoff = 2.0
    found = 0
    for pbc in ([True, True, True], [True, False, True], [False, False, True], [False, False, False]):
        for left in (False, True):
            cell = random_cell(rng, ratio * cutoff, shear, left)
            # ASE's bins grow slow for atoms spread far along open axes: 2,000 atoms when periodic.
            n = 2 if ratio < 0.5 else 20 if ratio < 2 else 200 if ratio < 5 or not all(pbc) else 2000
            frac = rng.uniform(-1.2, 2.2, (n, 3))
            positions = frac @ cell
            found += compare(positions, cell, pbc, cutoff, what=f"ratio {ratio}, shear {shear}, pbc {pbc}")
    assert found > 0


def test_one_atom_and_exact_ties_on_lattices():
    # Simple cubic, one atom in a cell of 1, cutoffs at exact lattice distances: every pair at
    # distance 1, sqrt(2), 2 is a tie (strictly below: not listed, as ASE).
    for cutoff in (1.0, 1.5, 2.0, 2.5):
        n = compare([[0.0, 0.0, 0.0]], np.eye(3), True, cutoff, what=f"sc {cutoff}")
        assert n > 0 or cutoff == 1.0
    # An integer triclinic lattice, atoms out of the cell.
    cell = np.array([[2.0, 0, 0], [1, 2, 0], [1, 1, 2]])
    positions = np.array([[0.0, 0, 0], [1, 1, 1], [-3, 5, 2], [4, -2, 7]])
    for cutoff in (2.0, 3.0, 4.0):
        compare(positions, cell, True, cutoff, what=f"integer lattice {cutoff}")


def test_classic_cells():
    cu = bulk("Cu", "fcc", a=3.61)  # primitive cell of one atom, smaller than the cutoff
    assert compare(cu.positions, cu.cell, cu.pbc, 5.0) > 0
    diamond = bulk("C", "diamond", a=3.567, cubic=True)
    assert compare(diamond.positions, diamond.cell, diamond.pbc, 6.0) > 0
    sheet = graphene(vacuum=5.0)
    assert compare(sheet.positions, sheet.cell, sheet.pbc, 3.0) > 0
    water = molecule("H2O")
    water.center(vacuum=3.0)
    i = frnn.neighbor_list("i", water, 1.2)
    assert sorted(np.bincount(i)) == [1, 1, 2]
    assert compare(water.positions, water.cell, False, 1.2) == 4


def test_atoms_natural_cutoffs_dict_and_self_interaction():
    atoms = bulk("NaCl", "rocksalt", a=5.64) * (2, 2, 2)
    atoms.rattle(0.1, seed=3)
    for cutoff in (natural_cutoffs(atoms, mult=1.3), {("Na", "Cl"): 3.2, (11, 11): 4.1}, 3.5):
        got = frnn.neighbor_list("ijS", atoms, cutoff)
        want = ase_neighbor_list("ijS", atoms, cutoff)
        key = lambda r: sorted(zip(r[0].tolist(), r[1].tolist(), map(tuple, r[2].tolist())))  # noqa: E731
        assert key(got) == key(want) and len(want[0]) > 0
    i, j, S, d = frnn.neighbor_list("ijSd", atoms, 3.5, self_interaction=True)
    own = (i == j) & np.all(S == 0, axis=1)
    assert own.sum() == len(atoms) and np.all(d[own] == 0)
    assert frnn.neighbor_list("d", atoms, 3.5).dtype == np.float64


def test_tuple_input_2d_and_float32():
    rng = np.random.default_rng(5)
    cell2 = np.array([[3.0, 0.0], [1.4, 2.5]])
    positions2 = rng.uniform(-2, 6, (40, 2))
    i, j, S, d, D = frnn.neighbor_list("ijSdD", (positions2, cell2, [True, False]), 2.2)
    assert S.shape[1] == 2 and np.all(S[:, 1] == 0) and D.shape == (len(i), 2)
    # ASE is 3D: the 2D cell embedded with a non-periodic z.
    cell3 = np.zeros((3, 3))
    cell3[:2, :2] = cell2
    embedded = np.hstack([positions2, np.zeros((40, 1))])
    I, J, SS = ase_neighbor_list("ijS", Atoms("H40", positions=embedded, cell=cell3, pbc=[True, False, False]), 2.2)
    assert sorted(zip(i.tolist(), j.tolist(), S[:, 0].tolist())) == sorted(zip(I.tolist(), J.tolist(), SS[:, 0].tolist()))
    assert np.allclose(np.linalg.norm(D, axis=1), d)
    # float32 positions: results in float32, the same pairs away from the cutoff.
    d32 = frnn.neighbor_list("d", (positions2.astype(np.float32), cell2, [True, False]), 2.2)
    assert d32.dtype == np.float32 and abs(len(d32) - len(d)) <= 2
    # No atoms: empty arrays of the documented shapes.
    i, S, D = frnn.neighbor_list("iSD", (np.zeros((0, 3)), np.eye(3), True), 1.0)
    assert i.shape == (0,) and S.shape == (0, 3) and D.shape == (0, 3) and S.dtype == np.int64
    # One letter: one array; cell lengths accepted.
    assert frnn.neighbor_list("i", (positions2, [3.0, 3.0], True), 1.0).ndim == 1


def test_bad_input_says_what():
    positions = np.zeros((2, 3))
    with pytest.raises(ValueError, match="do not span space"):
        frnn.neighbor_list("ij", (positions, [[1, 0, 0], [0, 1, 0], [1, 1, 0]], True), 1.0)
    with pytest.raises(ValueError, match="component 0 is nan"):
        frnn.neighbor_list("ij", (positions, [[np.nan, 0, 0], [0, 1, 0], [0, 0, 1]], True), 1.0)
    with pytest.raises(ValueError, match="periodic images of the 2 atoms"):
        frnn.neighbor_list("ij", (positions, np.eye(3), True), 1e4)
    with pytest.raises(ValueError, match="one radius per atom"):
        frnn.neighbor_list("ij", (positions, np.eye(3), True), [1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="cell must have shape"):
        frnn.neighbor_list("ij", (positions, np.eye(2), True), 1.0)
    with pytest.raises(ValueError, match="pbc must hold 3"):
        frnn.neighbor_list("ij", (positions, np.eye(3), [True, False]), 1.0)
    with pytest.raises(ValueError, match="unsupported quantity 'x'"):
        frnn.neighbor_list("ix", (positions, np.eye(3), True), 1.0)
    with pytest.raises(ValueError, match="needs atomic numbers"):
        frnn.neighbor_list("ij", (positions, np.eye(3), True), {(1, 1): 1.0})
    with pytest.raises(TypeError, match="ase.Atoms or a tuple"):
        frnn.neighbor_list("ij", positions, 1.0)
