#!/usr/bin/env bash
# The strong scaling of the distributed rebuild (frnn_mpi_bench) on W1 and W2 of bench/README.md:
# 1 and 2 ranks of one thread each, and 4 ranks, which oversubscribe a 2-core machine (marked
# so). Prints a Markdown table: medians of the rounds, efficiency T1 / (P * TP), bytes sent to
# other ranks per particle per rebuild, and the time split into exchange and local work; then
# weak scaling of W2 (half the points on 1 rank against all on 2).
# Usage: bench/mpi_scaling.sh [BUILD_DIR] [ROUNDS] [SIZES]   (defaults: build/release 9 "262144 1000000")
# While it measures, /tmp/frnn-quiet exists (the machine's other users pause their builds).
set -euo pipefail
build=${1:-build/release}
rounds=${2:-9}
sizes=${3:-262144 1000000}
bench=$build/bench/frnn_mpi_bench
[ -x "$bench" ] || { echo "mpi_scaling.sh: $bench not built (needs MPI and FRNN_BUILD_BENCHMARKS)" >&2; exit 1; }
while [ -e /tmp/frnn-quiet ]; do sleep 10; done  # someone else is measuring
touch /tmp/frnn-quiet
lines=$(mktemp)
trap 'rm -f /tmp/frnn-quiet "$lines"' EXIT
# Percent of CPU time idle over 3 s (from /proc/stat), to wait for builds already running.
idle_percent() {
    local a b
    read -r -a a < <(grep '^cpu ' /proc/stat)
    sleep 3
    read -r -a b < <(grep '^cpu ' /proc/stat)
    local total=0 k
    for k in 1 2 3 4 5 6 7 8; do total=$((total + b[k] - a[k])); done
    echo $(( 100 * (b[4] - a[4]) / (total > 0 ? total : 1) ))
}
for _ in $(seq 60); do
    idle=$(idle_percent)
    [ "$idle" -ge 90 ] && break
done
echo "mpi_scaling.sh: the CPUs were ${idle}% idle when the measurements began" >&2
for w in W1 W2; do
    for n in $sizes; do
        for p in 1 2 4; do
            FRNN_NUM_THREADS=1 OMP_NUM_THREADS=1 mpirun --oversubscribe --allow-run-as-root -np "$p" \
                "$bench" --workload "$w" --n "$n" --rounds "$rounds" >>"$lines"
        done
    done
done
# Weak scaling: W2 with half the points on 1 rank against all of them on 2 (the same
# particles per rank; W1's lattice sizes cannot halve exactly).
for n in $sizes; do
    FRNN_NUM_THREADS=1 OMP_NUM_THREADS=1 mpirun --oversubscribe --allow-run-as-root -np 1 \
        "$bench" --workload W2 --n $((n / 2)) --rounds "$rounds" | sed 's/^{/{"weak": true, /' >>"$lines"
done
rm -f /tmp/frnn-quiet
python3 - "$lines" <<'PY'
import json, sys
everything = [json.loads(l) for l in open(sys.argv[1])]
rows = [r for r in everything if not r.get("weak")]
one = {(r["workload"], r["n"]): r for r in rows if r["ranks"] == 1}
print("| workload | N | ranks | rebuild ms | efficiency | exchange ms | local ms (grid + lists) | bytes/particle (ghosts) | ghost fraction | pairs | single-process grid ms |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    base = one[(r["workload"], r["n"])]
    p = r["ranks"]
    eff = base["step_ms"] / (p * r["step_ms"])
    mark = " (oversubscribed)" if p > 2 else ""
    void = "" if r["pairs"] == base["pairs"] else " VOID: pairs differ"
    print(f'| {r["workload"]} | {r["n"]:,} | {p}{mark} | {r["step_ms"]:.1f} | {eff:.0%} | {r["exchange_ms"]:.1f} | '
          f'{r["local_ms"]:.1f} ({r["grid_ms"]:.1f} + {r["lists_ms"]:.1f}) | {r["bytes_per_particle"]:.2f} '
          f'({r["halo_bytes_per_particle"]:.2f}) | {r["ghost_fraction"]:.4f} | {r["pairs"]:,.0f}{void} | '
          f'{r["serial_ms"]:.1f} |' if p == 1 else
          f'| {r["workload"]} | {r["n"]:,} | {p}{mark} | {r["step_ms"]:.1f} | {eff:.0%} | {r["exchange_ms"]:.1f} | '
          f'{r["local_ms"]:.1f} ({r["grid_ms"]:.1f} + {r["lists_ms"]:.1f}) | {r["bytes_per_particle"]:.2f} '
          f'({r["halo_bytes_per_particle"]:.2f}) | {r["ghost_fraction"]:.4f} | {r["pairs"]:,.0f}{void} | |')
print()
for half in (r for r in everything if r.get("weak")):
    two = next(r for r in rows if r["workload"] == "W2" and r["ranks"] == 2 and r["n"] == 2 * half["n"])
    print(f'Weak scaling, W2 at {half["n"]:,} points per rank: 1 rank {half["step_ms"]:.1f} ms, 2 ranks '
          f'{two["step_ms"]:.1f} ms, efficiency {half["step_ms"] / two["step_ms"]:.0%}')
print()
for r in rows:
    if r["ranks"] > 1:
        print(f'{r["workload"]} N={r["n"]}: first build (particles from their initial slices to their sub-domains, '
              f'then ghosts) at {r["ranks"]} ranks: {r["first_build_bytes_per_particle"]:.1f} bytes/particle')
PY
