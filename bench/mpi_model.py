#!/usr/bin/env python3
"""The cost model of docs/SCALING.md: one rebuild of frnn::mpi::domain (balance with the cuts
kept, ghosts, local grid, neighbor lists) at 8 to 4,096 ranks, from the measured single-rank
cost per particle and stated network assumptions. Prints a Markdown table.

Geometry: density 1, radius h = 2 (W1, W2), sub-domains cubes of side L = (n / density)^(1/3)
with every face inside the system (the worst case: no outer faces). A rank receives the
particles within h of its cube: the Minkowski shell 6 L^2 h + 3 pi L h^2 + 4/3 pi h^3 (the halo
reaches by Euclidean distance, so edges and corners are rounded), each 23 bytes in float
(3 image bytes with the plan, 12 of coordinates, 8 of id).

Per rebuild, counted from src/mpi: 5 rounds of messages with the k neighbors (migration:
coordinates, ids; halo: images, coordinates, ids), 2 MPI_Alltoall of one int per rank (the
counts of the two plans), 1 MPI_Reduce_scatter_block of one double per rank (the imbalance
test), and about 10 small MPI_Allreduce (collective checks, the search scale). A re-cut, when
the imbalance passes 10%, adds about 70 reductions per level of the bisection tree.
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("--n-total", type=float, default=1e8, help="particles in all (strong scaling)")
p.add_argument("--local-ns", type=float, required=True, help="measured local work per particle at 1 rank (ns)")
p.add_argument("--ghost-ns", type=float, required=True, help="grid cost per ghost (ns): assumed, not measured apart from the local work")
p.add_argument("--alpha-us", type=float, default=2.0, help="latency of one message (us)")
p.add_argument("--overhead-us", type=float, default=0.3, help="cost of posting one more message (us)")
p.add_argument("--bandwidth-gbs", type=float, default=1.0, help="bandwidth per rank (GB/s)")
p.add_argument("--neighbors", type=int, default=26, help="ranks each rank exchanges with")
a = p.parse_args()

h, ghost_bytes = 2.0, 23
alpha, o, beta = a.alpha_us * 1e-6, a.overhead_us * 1e-6, a.bandwidth_gbs * 1e9
t1 = a.local_ns * 1e-9 * a.n_total
print(f"N = {a.n_total:,.0f}; alpha {a.alpha_us} us, {a.overhead_us} us per extra message, "
      f"{a.bandwidth_gbs} GB/s per rank, {a.neighbors} neighbors; 1 rank: {t1 * 1e3:,.0f} ms\n")
print("| ranks | particles/rank | ghost fraction | bytes/particle | local ms | neighbor messages ms | collectives ms | rebuild ms | efficiency | re-cut ms |")
print("|---|---|---|---|---|---|---|---|---|---|")
for ranks in (8, 64, 512, 4096):
    n = a.n_total / ranks
    side = n ** (1 / 3)
    shell = 6 * side**2 * h + 3 * math.pi * side * h**2 + 4 / 3 * math.pi * h**3
    ghosts = min(shell, a.n_total - n)
    local = a.local_ns * 1e-9 * n + a.ghost_ns * 1e-9 * ghosts
    sent = ghosts * ghost_bytes  # what it receives, it also sends (symmetric)
    rounds = 5 * (alpha + a.neighbors * o) + sent / beta
    log = math.log2(ranks)
    allreduce = 2 * alpha * log
    alltoall = alpha * log + 4 * ranks * log / 2 / beta  # Bruck's algorithm for small blocks
    reduce_scatter = allreduce + 8 * ranks / beta
    collectives = 10 * allreduce + 2 * alltoall + reduce_scatter
    total = local + rounds + collectives
    recut = 70 * log * allreduce
    print(f"| {ranks:,} | {n:,.0f} | {ghosts / n:.3f} | {sent / n:.2f} | {local * 1e3:.2f} | {rounds * 1e3:.3f} | "
          f"{collectives * 1e3:.3f} | {total * 1e3:.2f} | {t1 / (ranks * total):.0%} | {recut * 1e3:.1f} |")
