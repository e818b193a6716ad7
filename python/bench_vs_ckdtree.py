#!/usr/bin/python3
"""frnn against scipy.spatial.cKDTree on workloads W1, W2 and W8 of bench/README.md, same process.

Usage: PYTHONPATH=<build>/python /usr/bin/python3 python/bench_vs_ckdtree.py [--side 64] [--md-cells 20]

W1: jittered cubic lattice (spacing 1, jitter uniform(-0.1, 0.1)), side^3 points, r = 2.
W2: side^3 uniform points in a cube of edge side (density 1), r = 2.
Points come from numpy.random.default_rng(42), not std::mt19937_64: the sets have the same
distribution as the C++ benchmarks' but are not the same points.

Each task is timed as the median of --repeats runs after one warm-up run, and every pair of
implementations must report the same number of pairs (or the script fails). Tasks and their
cKDTree equivalents:
  build        frnn.Grid(points, r)                   cKDTree(points)
  pairs        Grid(points, r).query_pairs()          cKDTree(points).query_pairs(r, output_type='ndarray')
               (build included on both sides; frnn's pairs are also sorted, cKDTree's are not)
  lists        g.neighbors(sort=None): CSR lists      tree.query_ball_point(points, r, return_sorted=False)
               (query only; cKDTree's rows include the point itself and are Python lists)
  distances    g.neighbors(return_distances=True,     tree.sparse_distance_matrix(tree, r, output_type='ndarray')
               sort=None)                             (query only; includes the N self-pairs)
  counts       g.count_neighbors()                    tree.query_ball_point(points, r, return_length=True)
cKDTree's build, query_pairs and sparse_distance_matrix are single-threaded; query_ball_point
takes workers. frnn runs with threads=1 and with all cores; cKDTree with workers=1 and -1.

W8 (molecular dynamics): 4 * cells^3 atoms of an fcc lattice at density 0.8442, each coordinate
moved by uniform(-0.05, 0.05) lattice constants, in a periodic cube; r = 2.8. Every method builds
and finds each pair once: frnn Grid(points, r, periodic=L).query_pairs() (sorted pairs) and
neighbors(half=True, sort=None), cKDTree(points, boxsize=L).query_pairs, MDAnalysis's
FastNS(r, points, box, pbc=True).self_search() (python3-mdanalysis; float32 coordinates) and
ASE's neighbor_list("ij", ...) (python3-ase; both directions, halved), and LAMMPS's neighbor
build on one rank (`lmp`, Debian package lammps: the atoms in a data file, `pair_style zero`
at r - 0.3, `neighbor 0.3 bin`, `neigh_modify every 1 delay 0 check no`, `run 20`; its "Neigh"
time over its builds, a run per repetition). MDAnalysis, ASE and LAMMPS are skipped with a
message when absent. The atoms are rounded to float32 first, so that every method sees the
same points.
"""
import argparse
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy
from scipy.spatial import cKDTree

# Python puts this script's folder first on sys.path, and it holds the frnn sources without the
# compiled module: import the built package from PYTHONPATH instead.
# Compared as real paths: the script may be called through a symbolic link.
_here = os.path.dirname(os.path.realpath(__file__))
sys.path = [p for p in sys.path if os.path.realpath(p or ".") != _here]
import frnn  # noqa: E402


def w1(side, rng):
    axis = np.arange(side, dtype=np.float64)
    grid = np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)
    return grid + rng.uniform(-0.1, 0.1, grid.shape)


def w2(side, rng):
    return rng.uniform(0.0, side, (side ** 3, 3))


def median_ms(f, repeats):
    f()  # warm-up: page faults, caches, thread pools
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        times.append((time.perf_counter() - t0) * 1e3)
    return statistics.median(times)


class Table:
    def __init__(self, n):
        self.n = n
        print(f"{'task':<22}{'frnn ms':>10}{'ns/pt':>8}{'cKDTree ms':>12}{'ns/pt':>8}"
              f"{'ratio':>8}{'pairs':>12}")

    def row(self, task, frnn_ms, ckd_ms, pairs):
        ns = 1e6 / self.n
        print(f"{task:<22}{frnn_ms:>10.1f}{frnn_ms * ns:>8.0f}{ckd_ms:>12.1f}{ckd_ms * ns:>8.0f}"
              f"{ckd_ms / frnn_ms:>7.1f}x{pairs:>12,}", flush=True)


def check(what, a, b):
    if a != b:
        sys.exit(f"pair counts differ for {what}: frnn {a}, cKDTree {b}: comparison void")


def run(name, points, r, repeats, cores):
    n = len(points)
    print(f"\n{name}: {n:,} points, r = {r}")
    t = Table(n)
    tree = cKDTree(points)
    pairs = len(tree.query_pairs(r, output_type="ndarray"))

    for threads in (1, cores):
        tag = f"t={threads}"
        g = frnn.Grid(points, r, threads=threads)
        t.row(f"build {tag}", median_ms(lambda: frnn.Grid(points, r, threads=threads), repeats),
              median_ms(lambda: cKDTree(points), repeats), pairs)

        got = len(frnn.Grid(points, r, threads=threads).query_pairs())
        check(f"pairs {tag}", got, pairs)
        t.row(f"pairs {tag}",
              median_ms(lambda: frnn.Grid(points, r, threads=threads).query_pairs(), repeats),
              median_ms(lambda: cKDTree(points).query_pairs(r, output_type="ndarray"), repeats),
              got)

        workers = 1 if threads == 1 else -1
        offsets, _ = g.neighbors(sort=None)
        lengths = tree.query_ball_point(points, r, return_length=True, workers=workers)
        check(f"lists {tag}", int(offsets[-1]), int(lengths.sum()) - n)
        t.row(f"lists {tag}", median_ms(lambda: g.neighbors(sort=None), repeats),
              median_ms(lambda: tree.query_ball_point(points, r, return_sorted=False,
                                                      workers=workers), repeats),
              int(offsets[-1]) // 2)

        t.row(f"counts {tag}", median_ms(g.count_neighbors, repeats),
              median_ms(lambda: tree.query_ball_point(points, r, return_length=True,
                                                      workers=workers), repeats),
              int(g.count_neighbors().sum()) // 2)

    g = frnn.Grid(points, r, threads=cores)
    entries = len(tree.sparse_distance_matrix(tree, r, output_type="ndarray"))
    check("distances", int(g.neighbors(sort=None)[0][-1]) + n, entries)
    t.row(f"distances t={cores}/1",
          median_ms(lambda: g.neighbors(return_distances=True, sort=None), repeats),
          median_ms(lambda: tree.sparse_distance_matrix(tree, r, output_type="ndarray"), repeats),
          (entries - n) // 2)


def md_points(cells, rng):
    a = (4 / 0.8442) ** (1 / 3)
    box = cells * a
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    axis = np.arange(cells)
    z, y, x = np.meshgrid(axis, axis, axis, indexing="ij")
    corners = np.stack([x, y, z], axis=-1).reshape(-1, 1, 3)
    points = ((corners + basis[None]) * a).reshape(-1, 3)
    points += rng.uniform(-0.05, 0.05, points.shape) * a
    points = np.mod(points, box).astype(np.float32).astype(np.float64)
    points[points >= box] = 0.0
    return points, box


def md_methods(points, box, r):
    """name -> function building and returning the number of pairs (each once)."""
    box3 = np.array([box] * 3)
    methods = {
        "frnn query_pairs": lambda t: len(frnn.Grid(points, r, periodic=box, threads=t).query_pairs()),
        "frnn half lists": lambda t: int(frnn.Grid(points, r, periodic=box, threads=t)
                                         .neighbors(half=True, sort=None)[0][-1]),
        "cKDTree": lambda t: len(cKDTree(points, boxsize=box3).query_pairs(r, output_type="ndarray")),
    }
    try:
        from MDAnalysis.lib.nsgrid import FastNS
        dims = np.array([box, box, box, 90, 90, 90], dtype=np.float32)
        single = points.astype(np.float32)
        methods["MDAnalysis FastNS"] = lambda t: len(FastNS(r, single, dims, pbc=True).self_search().get_pairs())
    except ImportError:
        print("MDAnalysis skipped: not installed (Debian: python3-mdanalysis)")
    try:
        from ase.neighborlist import primitive_neighbor_list
        methods["ASE neighbor_list"] = lambda t: len(primitive_neighbor_list(
            "i", [True] * 3, np.diag(box3), points, r, self_interaction=False)) // 2
    except ImportError:
        print("ASE skipped: not installed (Debian: python3-ase)")
    return methods


def lammps_build(points, box, r):
    """LAMMPS's neighbor build on one rank: (ms per build, pairs), or None without `lmp`."""
    if shutil.which("lmp") is None:
        print("LAMMPS skipped: no `lmp` on PATH (Debian: lammps)")
        return None
    with tempfile.TemporaryDirectory(prefix="frnn-lammps-") as folder:
        with open(os.path.join(folder, "atoms.data"), "w") as f:
            f.write(f"W8\n\n{len(points)} atoms\n1 atom types\n\n")
            for axis in "xyz":
                f.write(f"0 {box!r} {axis}lo {axis}hi\n")
            f.write("\nMasses\n\n1 1.0\n\nAtoms # atomic\n\n")
            for i, (x, y, z) in enumerate(points.tolist()):
                f.write(f"{i + 1} 1 {x!r} {y!r} {z!r}\n")
        with open(os.path.join(folder, "in.neighbors"), "w") as f:
            f.write(f"units lj\natom_style atomic\nboundary p p p\nread_data atoms.data\n"
                    f"pair_style zero {r - 0.3!r}\npair_coeff * *\nneighbor 0.3 bin\n"
                    f"neigh_modify every 1 delay 0 check no\nvelocity all set 0.0 0.0 0.0\n"
                    f"fix 1 all nve\nrun 20\n")
        out = subprocess.run(["lmp", "-in", "in.neighbors", "-log", "none"], cwd=folder,
                             capture_output=True, text=True, check=True).stdout
    neigh = re.search(r"^Neigh\s*\|\s*\S+\s*\|\s*(\S+)", out, re.M)
    builds = re.search(r"Neighbor list builds = (\d+)", out)
    pairs = re.search(r"Total # of neighbors = (\d+)", out)
    if not (neigh and builds and pairs):
        sys.exit("LAMMPS's output lacks its Neigh time, build count or neighbor count")
    return float(neigh.group(1)) * 1e3 / int(builds.group(1)), int(pairs.group(1))


def run_md(cells, repeats, cores):
    points, box = md_points(cells, np.random.default_rng(42))
    r = 2.8
    print(f"\nW8 md: {len(points):,} atoms, periodic cube of side {box:.4f}, r = {r}; build + each pair once")
    print(f"{'method':<20}{'threads':>8}{'ms':>10}{'ns/atom':>9}{'vs frnn':>9}{'pairs':>12}")
    methods = md_methods(points, box, r)
    reference = methods["frnn query_pairs"](1)
    lammps = [lammps_build(points, box, r) for _ in range(repeats)] if shutil.which("lmp") else [lammps_build(points, box, r)]
    for threads in (1, cores):
        frnn_ms = None
        for name, f in methods.items():
            # Only frnn takes threads; the others run once, at the first thread count.
            if threads != 1 and not name.startswith("frnn"):
                continue
            pairs = f(threads)
            ms = median_ms(lambda: f(threads), repeats)
            frnn_ms = frnn_ms or ms
            flag = "" if pairs == reference else f"  VOID: {pairs:,} pairs, frnn {reference:,}"
            print(f"{name:<20}{threads:>8}{ms:>10.1f}{ms * 1e6 / len(points):>9.0f}{ms / frnn_ms:>8.1f}x"
                  f"{pairs:>12,}{flag}", flush=True)
        if threads == 1 and lammps[0] is not None:
            ms = statistics.median(t for t, _ in lammps)
            pairs = lammps[0][1]
            flag = "" if pairs == reference else f"  VOID: {pairs:,} pairs, frnn {reference:,}"
            print(f"{'LAMMPS neighbor build':<20}{1:>8}{ms:>10.1f}{ms * 1e6 / len(points):>9.0f}"
                  f"{ms / frnn_ms:>8.1f}x{pairs:>12,}{flag}", flush=True)


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--side", type=int, default=64, help="points = side^3 (64: 262,144)")
    ap.add_argument("--repeats", type=int, default=5, help="timed runs after the warm-up")
    ap.add_argument("--radius", type=float, default=2.0)
    ap.add_argument("--md-cells", type=int, default=20, help="W8 atoms = 4 * cells^3 (20: 32,000); 0: skip W8")
    args = ap.parse_args()
    cores = os.cpu_count() or 1
    print(f"frnn {frnn.__version__} vs scipy {scipy.__version__} cKDTree, numpy {np.__version__}, "
          f"Python {platform.python_version()}")
    print(f"machine: {cpu_model()}, {cores} cores; median of {args.repeats} after 1 warm-up")
    print("points: numpy.random.default_rng(42) (not the C++ benchmarks' std::mt19937_64 "
          "stream); ratio = cKDTree time / frnn time")
    rng = np.random.default_rng(42)
    run("W1 lattice", w1(args.side, rng), args.radius, args.repeats, cores)
    run("W2 uniform", w2(args.side, rng), args.radius, args.repeats, cores)
    if args.md_cells > 0:
        run_md(args.md_cells, args.repeats, cores)


if __name__ == "__main__":
    main()
