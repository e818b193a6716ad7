#!/usr/bin/python3
"""Prints the main tables of docs/PERFORMANCE.md from the CSV of a full `frnn bench` run
(bench/measure_all.sh writes docs/performance-report.csv), so that they are copied, never typed:

    bench/performance_tables.py [docs/performance-report.csv]

1. build + full lists, ns per particle: frnn and nanoflann at 2 threads, the textbook cell list
   at 1, with the ratios baseline / frnn, for W1 and W2 at every size;
2. frnn per phase at 1,000,000 points (W5: 1,000,001) at 1 and 2 threads, with build + list per
   list entry at 2 threads;
3. the speed-up over the baselines of W3, W4 and W5 at 2 threads (cell list at 1);
4. W8 (ms): frnn's phases and half lists beside LAMMPS's neighbor build, when the run had it.
"""
import csv
import sys
from collections import defaultdict
from pathlib import Path


def load(path):
    rows = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(row for row in f if not row.startswith("#")):
            key = (r["workload"], int(r["n"]), int(r["threads"]), r["method"], r["phase"])
            rows[key] = r
    return rows


def ns(rows, w, n, t, method, phase):
    r = rows.get((w, n, t, method, phase))
    return float(r["ns_per_particle"]) if r else None


def fmt(x, digits=1):
    return "-" if x is None else f"{x:,.{digits}f}"


def ratio(base, frnn):
    return "-" if base is None or frnn is None else f"{base / frnn:.1f}x"


def against_baselines(rows, sizes, workloads):
    """Rows of build + list: frnn and nanoflann at 2 threads, the cell list at 1, and ratios."""
    for w in workloads:
        for n in sorted(sizes[w]):
            f = ns(rows, w, n, 2, "frnn", "build+list")
            nf = ns(rows, w, n, 2, "nanoflann", "build+list")
            cl = ns(rows, w, n, 1, "cell-list", "build+list")
            print(f"| {w} | {n:,} | {fmt(f)} | {fmt(nf)} | {ratio(nf, f)} | {fmt(cl)} | {ratio(cl, f)} |")


def main():
    path = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent / "docs" / "performance-report.csv")
    rows = load(path)
    sizes = defaultdict(set)
    for (w, n, t, m, p) in rows:
        sizes[w].add(n)

    print("| workload | N | frnn | nanoflann | ratio | cell list | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    against_baselines(rows, sizes, ("W1", "W2"))
    print()

    print("| workload | threads | build | count | list | build+list | update | ns per list entry |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for w in ("W1", "W2", "W3", "W4", "W5"):
        n = next((n for n in sorted(sizes[w]) if n in (1000000, 1000001)), None)
        if n is None:
            continue
        for t in (1, 2):
            phases = [ns(rows, w, n, t, "frnn", p) for p in ("build", "count", "list", "build+list", "update")]
            per_entry = ""
            if t == 2:
                r = rows.get((w, n, t, "frnn", "list"))
                entries = float(r["pairs"]) / n if r and r["pairs"] else None
                if entries and phases[3] is not None:
                    per_entry = f"{phases[3] / entries:.2f} ({entries:.1f})"
            print(f"| {w} | {t} | " + " | ".join(fmt(x) for x in phases) + f" | {per_entry} |")
    print()

    print("| workload | N | frnn, 2 threads | nanoflann, 2 threads | ratio | cell list, 1 thread | ratio |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    against_baselines(rows, sizes, ("W3", "W4", "W5"))
    print()

    if sizes["W8"]:
        print("| atoms | threads | build | count | full lists | half | half, grid's numbering | half, rows by index "
              "| build + half by index | LAMMPS neighbor build (ranks = threads) | LAMMPS / frnn |")
        print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for n in sorted(sizes["W8"]):
            for t in (1, 2):
                ms = {p: float(r["ms"]) for (w, m, tt, method, p), r in rows.items()
                      if (w, m, tt, method) == ("W8", n, t, "frnn")}
                lammps = rows.get(("W8", n, t, "lammps", "build+half"))
                lammps = float(lammps["ms"]) if lammps else None
                f = ms.get("build+half by-index")
                cells = [ms.get(p) for p in ("build", "count")]
                more = [ms.get(p) for p in ("list", "half", "half sorted-space", "half by-index", "build+half by-index")]
                print(f"| {n:,} | {t} | " + " | ".join(fmt(x, 2) for x in cells) + " | "
                      + " | ".join(fmt(x) for x in more) + f" | {fmt(lammps)} | "
                      + ("-" if lammps is None or f is None else f"{lammps / f:.2f}x") + " |")

if __name__ == "__main__":
    main()
