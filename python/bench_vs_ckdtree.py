#!/usr/bin/python3
"""frnn against scipy.spatial.cKDTree on workloads W1 and W2 of BENCHMARKS.md, same process.

Usage: PYTHONPATH=<build>/python /usr/bin/python3 python/bench_vs_ckdtree.py [--side 64]

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
"""
import argparse
import os
import platform
import statistics
import sys
import time

import numpy as np
import scipy
from scipy.spatial import cKDTree

# Python puts this script's folder first on sys.path, and it holds the frnn sources without the
# compiled module: import the built package from PYTHONPATH instead.
_here = os.path.dirname(os.path.abspath(__file__))
sys.path = [p for p in sys.path if os.path.abspath(p or ".") != _here]
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


if __name__ == "__main__":
    main()
