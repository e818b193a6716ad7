#!/usr/bin/env python3
"""frnn against PySPH on PySPH's 2D WCSPH dam break (pysph.examples.dam_break_2d).

Runs `frnn sim` on dam_break_2d.json (the same column, tank, spacing, h / dx, equation of state
and artificial viscosity) and, when PySPH is importable, PySPH's example with its default WCSPH
scheme on OpenMP, both on the same number of threads, alternating, and prints per tool the
median time per particle per step and the surge front's mean relative error against Martin &
Moyce (1952) over T in [0.5, 3] (frnn's own measure, sim/src/martin_moyce.cpp). PySPH's front is
its example's own, x_max / L; frnn's the fluid's extent from the wall, in units of a = L.

PySPH is not a dependency of frnn: install it by hand (Debian: apt-get install python3-pysph)
and run this script with the Python that imports it (/usr/bin/python3 on Debian).

  bench/pysph/compare_dam_break_2d.py [--frnn build/release/apps/frnn/frnn] [--threads 2] [--runs 5]
"""
import argparse
import csv
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(HERE, "dam_break_2d.json")
MARTIN_MOYCE = os.path.join(ROOT, "sim", "data", "martin-moyce-1952.csv")
T_LO, T_HI = 0.5, 3.0  # frnn's front_error_t_lo, front_error_t_hi
DURATION = 0.7         # seconds: past T = 3 for a = 1 m
COLUMN_WIDTH = 1.0     # PySPH's fluid_column_width, the a of T and Z
G = 9.81


def martin_moyce():
    """{a_inches: [(T, Z), ...]} from the data file frnn compiles in."""
    series = {}
    with open(MARTIN_MOYCE) as f:
        rows = [line for line in f if not line.startswith("#")]
    for row in csv.DictReader(rows):
        series.setdefault(float(row["a_in"]), []).append((float(row["T"]), float(row["Z"])))
    return series


def front_error(front, points):
    """Mean relative error of the front (sorted (T, Z)) at the measured T in [T_LO, T_HI],
    interpolating linearly, as frnn::sim::front_error does."""
    errors = []
    for T, Z in points:
        if T < T_LO or T > T_HI:
            continue
        if not front or front[0][0] > T or front[-1][0] < T:
            raise RuntimeError("front record does not cover T = %g" % T)
        k = next(k for k, (t, _) in enumerate(front) if t >= T)
        z = front[k][1]
        if front[k][0] > T:
            (t0, z0), (t1, z1) = front[k - 1], front[k]
            z = z0 + (z1 - z0) * (T - t0) / (t1 - t0)
        errors.append(abs(z - Z) / Z)
    return sum(errors) / len(errors)


def run_frnn(binary, threads, out):
    """(ns per particle per step, fluid particles, wall particles, steps, [front errors]) of one
    frnn run, its wall particles counted as PySPH's are; frames off, so the wall time is the
    stepping (and the front record) alone."""
    text = subprocess.run([binary, "sim", SCENE, "--threads", str(threads), "--quiet", "--every", "1000000000",
                           "--out", out], check=True, capture_output=True, text=True).stdout
    # summary.json's wall time, unrounded (the printed one has 2 decimals: 0.5% here).
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    particles, steps, wall = summary["particles"], summary["steps"], summary["wall_seconds"]
    wall_particles = summary.get("wall_particles", 0)
    errors = [float(e) / 100 for e in re.findall(r"([\d.]+)% \(a = ", text)]
    return 1e9 * wall / steps / (particles + wall_particles), particles, wall_particles, steps, errors


def pysph_importable():
    try:
        import pysph  # noqa: F401
        return True
    except ImportError:
        return False


def run_pysph(threads, out, with_output):
    """PySPH's example on OpenMP. Returns (ns per particle per step, particles, steps) from its
    own "Run took" time and step count, or with_output: the front [(T, Z)] of its saved files."""
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    args = [sys.executable, "-m", "pysph.examples.dam_break_2d", "--openmp", "--tf", str(DURATION), "-d", out]
    args += ["--pfreq", "10"] if with_output else ["--disable-output"]
    # The example's own post-processing needs matplotlib and fails without it, after the run:
    # the saved files decide.
    done = subprocess.run(args, capture_output=True, text=True, env=env)
    text = done.stdout
    if "Run took" not in text:
        raise RuntimeError("PySPH failed:\n" + text + done.stderr)
    if with_output:
        from pysph.solver.utils import get_files, iter_output
        factor = math.sqrt(2 * G / COLUMN_WIDTH)
        front = [(sd["t"] * factor, fluid.get("x").max() / COLUMN_WIDTH)
                 for sd, fluid in iter_output(get_files(out, "dam_break_2d"), "fluid")]
        return sorted(front)
    particles = int(re.search(r"Total: (\d+)", text).group(1))
    fluid = int(re.search(r"fluid: (\d+)", text).group(1))
    seconds = float(re.search(r"Run took: ([\d.]+) secs", text).group(1))
    with open(os.path.join(out, "profile_info.csv")) as f:
        steps = max(int(r["calls"]) for r in csv.DictReader(f) if r["function"] == "Integrator.initialize")
    return 1e9 * seconds / steps / particles, particles, fluid, steps


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--frnn", default=os.path.join(ROOT, "build", "release", "apps", "frnn", "frnn"))
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--runs", type=int, default=5)
    a = p.parse_args()
    have_pysph = pysph_importable()
    if not have_pysph:
        print("PySPH is not importable from %s: frnn alone is measured. Install it by hand (Debian: "
              "apt-get install python3-pysph) and run this script with that Python (/usr/bin/python3)."
              % sys.executable)
    work = tempfile.mkdtemp(prefix="frnn-pysph-")
    try:
        frnn_ns, pysph_ns = [], []
        for r in range(a.runs):
            ns, particles, frnn_walls, steps, frnn_errors = run_frnn(a.frnn, a.threads, os.path.join(work, "frnn%d" % r))
            frnn_ns.append(ns)
            if have_pysph:
                ns_p, pysph_particles, pysph_fluid, pysph_steps = run_pysph(a.threads, os.path.join(work, "pysph%d" % r), False)
                pysph_ns.append(ns_p)
        series = martin_moyce()
        names = ", ".join("a = %g in" % k for k in series)
        print("2D WCSPH dam break (PySPH's dam_break_2d), %d threads, median of %d runs:" % (a.threads, a.runs))
        frnn_m = statistics.median(frnn_ns)
        frnn_per_fluid = frnn_m * (particles + frnn_walls) / particles
        print("  frnn:  %7.1f ns per particle per step (%d particles: %d fluid and %d wall particles; %d steps); "
              "surge-front error %s: %s" % (frnn_m, particles + frnn_walls, particles, frnn_walls, steps, names,
                                             ", ".join("%.1f%%" % (100 * e) for e in frnn_errors)))
        print("  frnn per fluid particle: %.1f ns per step" % frnn_per_fluid)
        if have_pysph:
            front = run_pysph(a.threads, os.path.join(work, "pysph-front"), True)
            errors = [front_error(front, pts) for pts in series.values()]
            m = statistics.median(pysph_ns)
            print("  PySPH: %7.1f ns per particle per step (%d particles: %d fluid and its wall particles; %d steps); "
                  "surge-front error %s: %s" % (m, pysph_particles, pysph_fluid, pysph_steps, names,
                                                 ", ".join("%.1f%%" % (100 * e) for e in errors)))
            print("  PySPH per fluid particle: %.1f ns per step" % (m * pysph_particles / pysph_fluid))
            print("  frnn is %.2fx faster per particle per step (%.2fx per fluid particle)"
                  % (m / frnn_m, m * pysph_particles / pysph_fluid / frnn_per_fluid))
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
