#!/usr/bin/env python3
"""Strong scaling of one WCSPH simulation across MPI ranks (docs/SCALING.md).

Runs the same scene, in alternating rounds, as: one process of 1 thread (T1), one process of
2 threads, and `mpirun -np 2` of 1 thread each (T2), and optionally 4 ranks of 1 thread
(oversubscribed on 2 cores). Each run's time per step is the mean without output from its
summary.json; the table gives medians over the rounds, the efficiency T1 / (2 T2), the ranks'
speed against the 2 threads, and from the ranks' summaries the ghosts per particle, the bytes
sent per particle per step, the share of the step spent exchanging, and the balance.
Every run writes the same frames and checkpoint (checked here by comparing the checkpoints).
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile


def run(args, out, ranks, threads):
    cmd = [args.frnn, "sim", "--scene", args.scene, "--solver", "sph", "--dim", str(args.dim),
           "--particles", str(args.particles), "--steps", str(args.steps), "--every", str(args.steps),
           "--threads", str(threads), "--quiet", "--out", out]
    if ranks > 1:
        cmd = [args.mpirun, "--oversubscribe", "-np", str(ranks)] + cmd
    env = dict(os.environ, FRNN_NUM_THREADS=str(threads), OMP_NUM_THREADS=str(threads))
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, env=env)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, "checkpoint.bin"), "rb") as f:
        checkpoint = f.read()
    return summary, checkpoint


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--frnn", default="frnn", help="the frnn tool (default: frnn on PATH)")
    p.add_argument("--mpirun", default="mpirun")
    p.add_argument("--scene", default="dam-break")
    p.add_argument("--dim", type=int, default=3)
    p.add_argument("--particles", type=int, default=1000000)
    p.add_argument("--steps", type=int, default=20)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--four", action="store_true", help="also 4 ranks of 1 thread (oversubscribed on 2 cores)")
    args = p.parse_args()
    configs = [("1 process, 1 thread", 1, 1), ("1 process, 2 threads", 1, 2), ("2 ranks, 1 thread each", 2, 1)]
    if args.four:
        configs.append(("4 ranks, 1 thread each (oversubscribed)", 4, 1))
    times = {name: [] for name, _, _ in configs}
    last = {}
    work = tempfile.mkdtemp(prefix="frnn-sim-scaling-")
    try:
        reference = None
        for r in range(args.rounds):
            order = configs if r % 2 == 0 else list(reversed(configs))
            for name, ranks, threads in order:
                out = os.path.join(work, f"run-{ranks}-{threads}")
                summary, checkpoint = run(args, out, ranks, threads)
                if reference is None:
                    reference = checkpoint
                elif checkpoint != reference:
                    sys.exit(f"sim_scaling.py: {name} wrote another checkpoint than the first run")
                times[name].append(summary["step_ms_without_output"])
                last[name] = summary
                shutil.rmtree(out)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    med = {name: statistics.median(t) for name, t in times.items()}
    one = last[configs[0][0]]
    print(f"{args.scene} {args.dim}D WCSPH: {one['particles']:,} particles, {one['wall_particles']:,} wall particles, "
          f"{args.steps} steps, medians of {args.rounds} alternating rounds (ms per step without output)\n")
    print("| run | ms/step | range | exchange share | ghosts per particle | bytes sent per particle-step | largest imbalance |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, ranks, _ in configs:
        s = last[name]
        cells = ["", "", "", ""]
        if ranks > 1:
            per_rank = s["ranks"]["per_rank"]
            n = sum(r["particles"] for r in per_rank)
            ghosts = sum(r["ghosts"] for r in per_rank)
            sent = sum(r["bytes_sent"] for r in per_rank)
            share = s["mean_ms_per_step"].get("rank exchange", 0) / s["step_ms_without_output"]
            balance = s["ranks"]["balance"]
            cells = [f"{100 * share:.1f}%", f"{ghosts / n:.3f}", f"{sent / n / s['steps']:.1f}",
                     f"{balance['largest_imbalance']:.3f}" if balance["checks"] else "no check"]
        t = times[name]
        print(f"| {name} | {med[name]:.1f} | {min(t):.1f}-{max(t):.1f} | " + " | ".join(cells) + " |")
    for name, ranks, _ in configs:
        if ranks > 1:
            parts = [f"rank {q}: {r['local_ms_per_step']:.1f} local + {r['exchange_ms_per_step']:.1f} exchange "
                     f"({r['waiting_ms_per_step']:.1f} of it waiting)" for q, r in enumerate(last[name]["ranks"]["per_rank"])]
            print(f"\n{name}, last round, ms per step: " + "; ".join(parts))
    t1, t2 = med[configs[0][0]], med[configs[2][0]]
    print(f"\nefficiency at 2 ranks, T1 / (2 T2): {t1 / (2 * t2):.1%}")
    print(f"2 ranks against 1 process of 2 threads: {med[configs[1][0]] / t2:.2f}x the speed")


if __name__ == "__main__":
    main()
