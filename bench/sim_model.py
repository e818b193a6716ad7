#!/usr/bin/env python3
"""The cost model of one WCSPH step across ranks as `mpirun frnn sim` runs it (docs/SCALING.md):
slabs of the one-process grid's cell planes along one axis, at 8 to 4,096 ranks, from measured
costs per particle and the network assumptions of bench/mpi_model.py. Prints a Markdown table.

Geometry: the fluid a cube of N particles at spacing 1, the grid's cells 2h = 2.6 spacings
(h = 1.3 spacings), slabs of width L / P (L = N^(1/3)), ghosts `depth` cells deep on both faces
of a slab (2 with wall particles: a wall particle takes its pressure from the fluid within one
radius of it). A slab is at least one cell plane thick: ranks beyond the number of planes hold
no particles and wait. A slab thinner than its ghost layers takes ghosts from several ranks: a
rank then holds more ghosts than particles.

Per step, counted from sim/src/distribution.hpp and sph.cpp: 3 MPI_Alltoallv (particles that
move, ghosts, the ghosts' density and pressure), each after an MPI_Alltoall of one int per rank,
and 3 MPI_Allgather (the largest speed and acceleration for the time step, the finite check).
Open MPI's Alltoallv posts a message to every rank. Each ghost is 56 bytes (its key, id,
position, velocity, acceleration) and 8 more for its refresh.
"""
import argparse
import math

p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
p.add_argument("--n-total", type=float, default=1e8, help="fluid particles in all (strong scaling)")
p.add_argument("--local-ns", type=float, required=True, help="measured: one process's step per particle at 1 thread (ns)")
p.add_argument("--ghost-ns", type=float, required=True, help="measured: a ghost's grid entry and neighbor row (ns)")
p.add_argument("--exchange-ns", type=float, required=True, help="measured: the exchange's own work per particle held (ns)")
p.add_argument("--depth", type=int, default=2, help="ghost layers, in cells (2 with wall particles)")
p.add_argument("--alpha-us", type=float, default=2.0, help="latency of one message (us)")
p.add_argument("--overhead-us", type=float, default=0.3, help="cost of posting one more message (us)")
p.add_argument("--bandwidth-gbs", type=float, default=1.0, help="bandwidth per rank (GB/s)")
a = p.parse_args()

cell, ghost_bytes, refresh_bytes = 2.6, 56, 8
alpha, o, beta = a.alpha_us * 1e-6, a.overhead_us * 1e-6, a.bandwidth_gbs * 1e9
t1 = a.local_ns * 1e-9 * a.n_total
side = a.n_total ** (1 / 3)
print(f"N = {a.n_total:,.0f} (a cube of side {side:,.0f} spacings); ghosts {a.depth} cells deep; alpha {a.alpha_us} us, "
      f"{a.overhead_us} us per extra message, {a.bandwidth_gbs} GB/s per rank; 1 rank: {t1 * 1e3:,.0f} ms\n")
print("| ranks | ranks with particles | particles/rank | slab width (spacings) | ghost fraction | bytes/particle | local ms | exchange ms | messages ms | step ms | efficiency |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
planes = max(1, math.floor(side / cell))
for ranks in (8, 64, 512, 4096):
    working = min(ranks, planes)
    n = a.n_total / working
    width = side / working
    ghosts = min(2 * a.depth * cell * side**2, a.n_total - n)
    local = a.local_ns * 1e-9 * n + a.ghost_ns * 1e-9 * ghosts
    exchange = a.exchange_ns * 1e-9 * (n + ghosts)
    sent = ghosts * (ghost_bytes + refresh_bytes)  # what it receives, it also sends
    log = math.log2(ranks)
    alltoall = alpha * log + 4 * ranks * log / 2 / beta  # the counts: Bruck's algorithm
    alltoallv = alpha + ranks * o  # a message to every rank; the bytes below
    allgather = alpha * log + 8 * ranks / beta
    messages = 3 * (alltoall + alltoallv) + sent / beta + 3 * allgather
    total = local + exchange + messages
    print(f"| {ranks:,} | {working:,} | {n:,.0f} | {width:,.1f} | {ghosts / n:.3f} | {sent / n:.1f} | {local * 1e3:,.1f} | "
          f"{exchange * 1e3:,.2f} | {messages * 1e3:.2f} | {total * 1e3:,.1f} | {t1 / (ranks * total):.0%} |")
