#!/usr/bin/python3
"""Compares two builds of frnn: their results byte for byte and, with --bench, their speed.

Used by scripts/compare_builds, which builds the two trees. A reshaping of the code must not
change any result; this runs both builds on the same inputs and reports every difference:

- `frnn query` outputs (.npy, .csv, .npz) on point sets like the oracle tests' (uniform,
  lattices with pairs at exactly r, clusters, far outliers, duplicates; 2D and 3D; float and
  double): the default grid, hashed, uniform with small cells, periodic, kNN, --self and
  --queries;
- the Python module's arrays for the same sets, traversal order included (neighbors with
  sort=None, half lists, counts, ball queries, kNN, the permutation);
- `frnn sim` output after 50 steps of each shipped scene and of the 2D WCSPH dam break:
  checkpoint, frames and front record (not summary.json, which holds timings).

With --bench it then times both: `frnn bench --workload all` and the default scene's per-stage
table, the two binaries alternately, and flags every figure whose new/old ratio of medians
differs from 1 by more than max(3%, the spread of the runs).

Exit status: 0 when every result is identical (and, with --bench, every figure within its
bound), 1 otherwise.
"""
import argparse
import csv
import filecmp
import os
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

THREADS = "2"


def point_sets():
    """name -> (points, radius, periodic box or None); fixed seeds, so both builds get the same."""
    rng = np.random.default_rng(20261202)
    sets = {}
    sets["uniform3_f64"] = (rng.uniform(0, 16, (4000, 3)), 1.3, 16.0)
    sets["uniform3_f32"] = (sets["uniform3_f64"][0].astype(np.float32), 1.3, 16.0)
    g = np.arange(12, dtype=np.float64)
    lattice = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    sets["lattice3_ties"] = (lattice, 1.0, 12.0)
    g2 = np.arange(60, dtype=np.float64)
    sets["lattice2_ties"] = (np.stack(np.meshgrid(g2, g2, indexing="ij"), -1).reshape(-1, 2), 1.0, 60.0)
    centers = rng.uniform(0, 20, (12, 3))
    clusters = centers[rng.integers(0, 12, 5000)] + rng.normal(0, 0.4, (5000, 3))
    sets["clusters3_f32"] = (clusters.astype(np.float32), 0.3, None)
    bulk = rng.uniform(0, 14, (3000, 3))
    far = np.array([[1e6, 1e6, 1e6], [1e6, 1e6, 1e6], [-1e9, 3, 3], [5, 1e15, 5], [2e4, -2e4, 7]])
    sets["outliers3_f64"] = (np.insert(bulk, [100, 900, 1500, 2200, 2900], far, axis=0), 1.0, None)
    base2 = rng.uniform(0, 30, (500, 2)).astype(np.float32)
    sets["duplicates2_f32"] = (np.concatenate([base2, base2, base2]), 0.9, 30.0)
    sets["uniform2_f64"] = (rng.uniform(0, 50, (3000, 2)), 1.5, 50.0)
    return sets


def query_points(points):
    rng = np.random.default_rng(7)
    lo, hi = points.min(axis=0), points.max(axis=0)
    lo, hi = np.maximum(lo, -100), np.minimum(hi, 100)
    return rng.uniform(lo - 1, hi + 1, (500, points.shape[1])).astype(points.dtype)


def query_variants(name, radius, box, dim):
    """(label, extra arguments, output extension) for `frnn query`."""
    r = repr(radius)
    out = [("pairs", [], ".npy"), ("text", [], ".csv"), ("lists", [], ".npz"),
           ("hashed", ["--grid", "hash"], ".npz"), ("small_cells", ["--cell-size", repr(radius / 2)], ".npz"),
           ("knn", ["--knn", "5"], ".csv"), ("self", ["--self"], ".npy"),
           ("queries", ["--queries", f"{name}_q.npy"], ".npz")]
    if box is not None:
        out.append(("periodic", ["--periodic", ",".join([repr(box)] * dim)], ".npz"))
    return [(label, ["--radius", r] + extra, ext) for label, extra, ext in out]


PYTHON_DUMP = r"""
import sys, numpy as np, frnn
points_file, queries_file, radius, box, out = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4], sys.argv[5]
p, q = np.load(points_file), np.load(queries_file)
arrays = {}
def keep(name, value):
    if isinstance(value, tuple):
        for i, v in enumerate(value): keep(f"{name}.{i}", v)
    else:
        arrays[name] = np.asarray(value)
grids = {"auto": frnn.Grid(p, radius, threads=2), "hash": frnn.Grid(p, radius, grid="hash", threads=2)}
if box != "none":
    grids["periodic"] = frnn.Grid(p, radius, periodic=float(box), threads=2)
for label, g in grids.items():
    keep(f"{label}.kind", np.array([g.kind]))
    keep(f"{label}.permutation", g.permutation)
    keep(f"{label}.pairs", g.query_pairs())
    keep(f"{label}.counts", g.count_neighbors())
    keep(f"{label}.traversal", g.neighbors(sort=None, return_distances=True))
    keep(f"{label}.by_index", g.neighbors(return_distances=True))
    keep(f"{label}.by_distance", g.neighbors(sort="distance", return_distances=True))
    keep(f"{label}.half", g.neighbors(sort=None, half=True))
    keep(f"{label}.half_by_index", g.neighbors(half=True, return_distances=True))
    keep(f"{label}.ball", g.query_ball_point(q, return_distances=True))
    keep(f"{label}.ball_traversal", g.query_ball_point(q, sort=None))
    keep(f"{label}.knn", g.query_knn(4))
    keep(f"{label}.knn_queries", g.query_knn(3, q))
np.savez(out, **arrays)
"""

SIM_RUNS = [("dam-break", []), ("droplet", []), ("block-drop", []), ("dam-break-sph-2d", ["--solver", "sph", "--dim", "2"])]


class comparison:
    def __init__(self, old, new, work):
        self.build = {"old": Path(old).resolve(), "new": Path(new).resolve()}
        self.work = Path(work)
        self.differences = []
        self.compared = 0

    def tool(self, which):
        return str(self.build[which] / "apps" / "frnn" / "frnn")

    def run(self, args, **kw):
        result = subprocess.run(args, capture_output=True, text=True, **kw)
        if result.returncode != 0:
            raise SystemExit(f"compare_builds: {' '.join(map(str, args))} failed:\n{result.stderr}")
        return result

    def differ(self, what):
        self.differences.append(what)
        print(f"  DIFFERENT: {what}")

    def compare_files(self, a, b, what):
        self.compared += 1
        if not filecmp.cmp(a, b, shallow=False):
            self.differ(what)

    def queries(self, sets):
        print("frnn query outputs")
        for name, (points, radius, box) in sets.items():
            np.save(self.work / f"{name}.npy", points)
            np.save(self.work / f"{name}_q.npy", query_points(points))
            for label, args, ext in query_variants(name, radius, box, points.shape[1]):
                outs = {}
                for which in ("old", "new"):
                    outs[which] = self.work / f"{name}.{label}.{which}{ext}"
                    self.run([self.tool(which), "query", f"{name}.npy", "-o", outs[which].name, "--threads", THREADS] + args,
                             cwd=self.work)
                self.compare_files(outs["old"], outs["new"], f"frnn query {name} {label} ({ext})")
        print(f"  {self.compared} outputs compared")

    def python_arrays(self, sets):
        print("Python arrays")
        before = self.compared
        for name, (points, radius, box) in sets.items():
            dumps = {}
            for which in ("old", "new"):
                dumps[which] = self.work / f"{name}.py.{which}.npz"
                env = dict(os.environ, PYTHONPATH=str(self.build[which] / "python"), PYTHONDONTWRITEBYTECODE="1")
                self.run([sys.executable, "-c", PYTHON_DUMP, str(self.work / f"{name}.npy"),
                          str(self.work / f"{name}_q.npy"), repr(radius), "none" if box is None else repr(box),
                          str(dumps[which])], env=env)
            with np.load(dumps["old"]) as old, np.load(dumps["new"]) as new:
                for key in sorted(set(old.files) | set(new.files)):
                    self.compared += 1
                    if key not in old.files or key not in new.files:
                        self.differ(f"Python {name} {key}: only in one build")
                    elif old[key].dtype != new[key].dtype or old[key].shape != new[key].shape or \
                            old[key].tobytes() != new[key].tobytes():
                        self.differ(f"Python {name} {key}")
        print(f"  {self.compared - before} arrays compared")

    def sims(self):
        print("frnn sim, 50 steps")
        before = self.compared
        for label, extra in SIM_RUNS:
            scene = label.split("-sph")[0]
            dirs = {}
            for which in ("old", "new"):
                dirs[which] = self.work / f"sim.{label}.{which}"
                self.run([self.tool(which), "sim", "--scene", scene, "--steps", "50", "--threads", THREADS, "--quiet",
                          "--out", str(dirs[which])] + extra)
            files = {which: sorted(p.relative_to(dirs[which]) for p in dirs[which].rglob("*")
                                   if p.is_file() and p.name != "summary.json") for which in dirs}
            if files["old"] != files["new"]:
                self.differ(f"frnn sim {label}: different files")
            for f in files["old"]:
                if f in files["new"]:
                    self.compare_files(dirs["old"] / f, dirs["new"] / f, f"frnn sim {label} {f}")
        print(f"  {self.compared - before} files compared")


def bench_rows(path):
    rows = {}
    for r in csv.DictReader(open(path)):
        if r["method"] != "frnn":
            continue
        rows[(r["workload"], r["n"], r["threads"], r["phase"])] = float(r["ms"])
    return rows


def sim_stages(text):
    stages = {}
    for line in text.splitlines():
        m = re.match(r"^(\S.*?)\s{2,}([0-9.]+)\s", line)
        if m and not line.startswith("stage"):
            stages[m.group(1)] = float(m.group(2))
    return stages


def within(old, new):
    """Whether median(new) / median(old) is within max(3%, the spread of all runs)."""
    mo, mn = statistics.median(old), statistics.median(new)
    spread = max((max(v) - min(v)) / statistics.median(v) for v in (old, new))
    bound = max(0.03, spread)
    return mn / mo, bound, abs(mn / mo - 1) <= bound


def bench(c, rounds):
    print(f"frnn bench --workload all and the default sim scene, {rounds} alternate rounds")
    runs = {"old": [], "new": []}
    sims = {"old": [], "new": []}
    for k in range(rounds):
        for which in ("old", "new"):
            out = c.work / f"bench.{which}.{k}.csv"
            c.run([c.tool(which), "bench", "--workload", "all", "--csv", str(out)])
            runs[which].append(bench_rows(out))
            text = c.run([c.tool(which), "sim", "--steps", "100", "--threads", THREADS, "--quiet",
                          "--out", str(c.work / f"simbench.{which}.{k}")]).stdout
            sims[which].append(sim_stages(text))
    failed = 0
    print("| workload | N | threads | phase | old ms | new ms | new/old | bound |")
    print("|---|---:|---:|---|---:|---:|---:|---:|")
    for key in runs["old"][0]:
        old = [r[key] for r in runs["old"] if key in r]
        new = [r[key] for r in runs["new"] if key in r]
        if len(old) != rounds or len(new) != rounds:
            continue
        ratio, bound, ok = within(old, new)
        failed += not ok
        print(f"| {' | '.join(key)} | {statistics.median(old):.3f} | {statistics.median(new):.3f} | {ratio:.3f} | "
              f"{bound:.3f}{'' if ok else ' OUT'} |")
    print("\n| sim stage | old ms/step | new ms/step | new/old | bound |")
    print("|---|---:|---:|---:|---:|")
    for stage in sims["old"][0]:
        old = [s[stage] for s in sims["old"]]
        new = [s[stage] for s in sims["new"]]
        ratio, bound, ok = within(old, new)
        failed += not ok
        print(f"| {stage} | {statistics.median(old):.3f} | {statistics.median(new):.3f} | {ratio:.3f} | "
              f"{bound:.3f}{'' if ok else ' OUT'} |")
    return failed


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old_build", help="build tree of the old commit (with apps/frnn/frnn and python/)")
    parser.add_argument("new_build", help="build tree of the new commit")
    parser.add_argument("--bench", type=int, metavar="ROUNDS", default=0,
                        help="also time both, ROUNDS alternate rounds (at least 3)")
    args = parser.parse_args()
    if args.bench and args.bench < 3:
        parser.error("--bench needs at least 3 rounds to measure a spread")
    with tempfile.TemporaryDirectory(prefix="frnn-compare.") as work:
        c = comparison(args.old_build, args.new_build, work)
        sets = point_sets()
        c.queries(sets)
        c.python_arrays(sets)
        c.sims()
        print(f"results: {c.compared} compared, {len(c.differences)} different")
        failed = bench(c, args.bench) if args.bench else 0
        if args.bench:
            print(f"speed: {failed} figures outside their bound")
    return 1 if c.differences or failed else 0


if __name__ == "__main__":
    sys.exit(main())
