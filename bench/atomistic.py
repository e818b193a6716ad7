#!/usr/bin/env python3
"""frnn.neighbor_list beside vesin, ASE and MDAnalysis on diamond supercells.

Systems: the cubic diamond cell (a = 3.567 A, 8 atoms) repeated n x n x n, every coordinate
moved by uniform(-0.05, 0.05) A (seed 7, so no distance ties), periodic on all axes; and the
same fractional positions in the sheared cell (b += 0.3 a, c += 0.2 a + 0.1 b). Cutoffs 3.5 and
6 A, double precision. Every method returns the full list (both directions) with i, j, the
shift S and the distance d, as ASE's neighbor_list("ijSd", ...) does; MDAnalysis's
self_capped_distance returns each pair once without shifts and runs only where its minimum
image allows (cutoff below half the cell's smallest height).

Each row times one call (build and list) per method, rounds alternating between the methods,
the median of `--repeat` rounds, each round as many calls as fill `--min-time` seconds.
vesin is not part of frnn: build its CPU part from its sources (vesin/src, no GPU part) into a
shared library and give its path with --vesin.
"""
import argparse
import ctypes
import statistics
import sys
import time

import numpy as np

import frnn

DIAMOND = np.array([[0, 0, 0], [0, .5, .5], [.5, 0, .5], [.5, .5, 0],
                    [.25, .25, .25], [.25, .75, .75], [.75, .25, .75], [.75, .75, .25]])
A = 3.567


def system(n, sheared):
    cubic = np.eye(3) * A
    frac = (DIAMOND[None, None, None, :, :] + np.stack(np.meshgrid(*[np.arange(n)] * 3, indexing="ij"), -1)[..., None, :])
    frac = frac.reshape(-1, 3) / n
    cell = cubic * n
    if sheared:
        cell = cell.copy()
        cell[1] += 0.3 * cell[0]
        cell[2] += 0.2 * cell[0] + 0.1 * cell[1]
    rng = np.random.default_rng(7)
    positions = frac @ cell + rng.uniform(-0.05, 0.05, frac.shape)
    return np.ascontiguousarray(positions), cell


class Vesin:
    """vesin_neighbors through ctypes (vesin's C API)."""

    class Options(ctypes.Structure):
        _fields_ = [("cutoff", ctypes.c_double), ("full", ctypes.c_bool), ("sorted", ctypes.c_bool),
                    ("algorithm", ctypes.c_int), ("n_threads", ctypes.c_int32), ("return_shifts", ctypes.c_bool),
                    ("return_distances", ctypes.c_bool), ("return_vectors", ctypes.c_bool),
                    ("skin", ctypes.c_double)]

    class Device(ctypes.Structure):
        _fields_ = [("type", ctypes.c_int), ("device_id", ctypes.c_int)]

    class List(ctypes.Structure):
        pass

    List._fields_ = [("length", ctypes.c_size_t), ("device", Device), ("pairs", ctypes.c_void_p),
                     ("shifts", ctypes.c_void_p), ("distances", ctypes.c_void_p), ("vectors", ctypes.c_void_p),
                     ("opaque", ctypes.c_void_p)]

    def __init__(self, path):
        self.lib = ctypes.CDLL(path)
        self.lib.vesin_neighbors.restype = ctypes.c_int
        self.lib.vesin_free.argtypes = [ctypes.POINTER(self.List)]

    def __call__(self, positions, cell, cutoff, threads):
        out = self.List()
        err = ctypes.c_char_p()
        opts = self.Options(cutoff, True, True, 0, threads, True, True, False, 0.0)
        pbc = (ctypes.c_bool * 3)(True, True, True)
        box = np.ascontiguousarray(cell, dtype=np.float64)
        status = self.lib.vesin_neighbors(positions.ctypes.data_as(ctypes.c_void_p), ctypes.c_size_t(len(positions)),
                                          box.ctypes.data_as(ctypes.c_void_p), pbc, self.Device(1, 0), opts,
                                          ctypes.byref(out), ctypes.byref(err))
        if status != 0:
            raise RuntimeError("vesin: " + err.value.decode())
        n = out.length
        # The arrays as numpy arrays (one copy each, as vesin's Python package makes them).
        pairs = np.ctypeslib.as_array(ctypes.cast(out.pairs, ctypes.POINTER(ctypes.c_size_t)), (n, 2)).copy() if n else np.empty((0, 2))
        shifts = np.ctypeslib.as_array(ctypes.cast(out.shifts, ctypes.POINTER(ctypes.c_int32)), (n, 3)).copy() if n else np.empty((0, 3))
        d = np.ctypeslib.as_array(ctypes.cast(out.distances, ctypes.POINTER(ctypes.c_double)), (n,)).copy() if n else np.empty(0)
        self.lib.vesin_free(ctypes.byref(out))
        return pairs, shifts, d


def timed(call, min_time):
    """Seconds per call: as many calls as fill min_time, at least one."""
    calls, start = 0, time.perf_counter()
    while True:
        result = call()
        calls += 1
        elapsed = time.perf_counter() - start
        if elapsed >= min_time:
            return elapsed / calls, result


def smallest_height(cell):
    volume = abs(np.linalg.det(cell))
    return min(volume / np.linalg.norm(np.cross(cell[(k + 1) % 3], cell[(k + 2) % 3])) for k in range(3))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="1,2,3,4,6,8,12,16,24", help="supercell repeats n (8 n^3 atoms)")
    ap.add_argument("--cutoffs", default="3.5,6")
    ap.add_argument("--cells", default="cubic,sheared")
    ap.add_argument("--threads", type=int, default=2, help="threads of frnn and vesin")
    ap.add_argument("--repeat", type=int, default=5, help="rounds; the median is reported")
    ap.add_argument("--min-time", type=float, default=0.1, help="seconds of calls per round and method")
    ap.add_argument("--vesin", help="path of a libvesin.so built from vesin's sources (its CPU part)")
    ap.add_argument("--ase-max-atoms", type=int, default=4096,
                    help="largest system ASE runs (its time grows past minutes beyond)")
    args = ap.parse_args()

    methods = {"frnn": lambda p, c, r: frnn.neighbor_list("ijSd", (p, c, True), r, threads=args.threads)}
    if args.vesin:
        vesin = Vesin(args.vesin)
        methods["vesin"] = lambda p, c, r: vesin(p, c, r, args.threads)
    else:
        print("vesin: not run (no --vesin library given)", file=sys.stderr)
    try:
        from ase.neighborlist import neighbor_list as ase_list
        methods["ASE"] = lambda p, c, r: ase_list("ijSd", _atoms(p, c), r)
    except ImportError:
        print("ASE: not run (not installed)", file=sys.stderr)
    try:
        from MDAnalysis.lib.distances import self_capped_distance
        from MDAnalysis.lib.mdamath import triclinic_box
        methods["MDAnalysis"] = lambda p, c, r: self_capped_distance(p, r, box=triclinic_box(*c))
    except ImportError:
        print("MDAnalysis: not run (not installed)", file=sys.stderr)

    names = list(methods)
    print("| cell | atoms | cutoff | pairs (full) | " + " | ".join(f"{m} ms" for m in names) +
          " | frnn ns/pair | " + " | ".join(f"{m} / frnn" for m in names[1:]) + " |")
    print("|---|---:|---:|---:|" + "---:|" * (2 * len(names)))
    for shape in args.cells.split(","):
        for cutoff in (float(c) for c in args.cutoffs.split(",")):
            for n in (int(s) for s in args.sizes.split(",")):
                positions, cell = system(n, shape == "sheared")
                run = {m: [] for m in names}
                skipped = {}
                counts = {}
                for m in names:
                    if m == "ASE" and len(positions) > args.ase_max_atoms:
                        skipped[m] = "not run (time)"
                    if m == "MDAnalysis" and cutoff >= smallest_height(cell) / 2:
                        skipped[m] = "not run (minimum image)"
                for _ in range(args.repeat):
                    for m in names:
                        if m in skipped:
                            continue
                        seconds, result = timed(lambda: methods[m](positions, cell, cutoff), args.min_time)
                        run[m].append(seconds)
                        counts[m] = len(result[0]) * (2 if m == "MDAnalysis" else 1)
                pairs = counts["frnn"]
                for m, c in counts.items():
                    if c != pairs:
                        print(f"{m} found {c} pairs, frnn {pairs} ({shape}, n {n}, cutoff {cutoff})", file=sys.stderr)
                ms = {m: statistics.median(run[m]) * 1e3 for m in names if m not in skipped}
                cells = [f"{ms[m]:.3g}" if m in ms else skipped[m] for m in names]
                ratios = [f"{ms[m] / ms['frnn']:.1f}x" if m in ms else "" for m in names[1:]]
                per_pair = ms["frnn"] * 1e6 / pairs if pairs else float("nan")
                print(f"| {shape} | {len(positions)} | {cutoff:g} | {pairs} | " + " | ".join(cells) +
                      f" | {per_pair:.1f} | " + " | ".join(ratios) + " |", flush=True)


def _atoms(positions, cell):
    from ase import Atoms
    return Atoms(numbers=np.full(len(positions), 6), positions=positions, cell=cell, pbc=True)


if __name__ == "__main__":
    main()
