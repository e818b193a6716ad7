#!/usr/bin/env python3
"""frnn against SPlisHSPlasH on the 3D WCSPH dam break of `frnn sim --scene dam-break --solver sph
--dim 3`.

Runs frnn's scene and, given where SPlisHSPlasH is installed, its WCSPH on the same fluid block
(wcsph_dam_break_3d.json: fluid 0.25 x 0.5 x 1.0 m at spacing 0.015625 m in the 2 x 1 x 1 m tank,
Tait's exponent 7, Akinci boundary particles sampled from SPlisHSPlasH's own unit box mesh, a
fixed time step of 1e-4 s), both on the same number of threads, alternating, to the same
simulated time, and prints per tool the median step time per fluid particle, the stage split
(frnn's stage table; SPlisHSPlasH's timers: neighborhood search, non-pressure forces, the rest)
and the time to the simulated time (steps x step time: start-up, sampling and output excluded).

SPlisHSPlasH is not part of frnn: build it from its sources (CMake, Release,
-DUSE_DOUBLE_PRECISION=OFF -DUSE_PYTHON_BINDINGS=OFF -DUSE_THIRD_PARTY_METHODS=OFF) and give the
folder of that build's source tree (it holds bin/SPHSimulator and data/models/UnitBox.obj) or
the SPHSimulator binary. Without it the script measures frnn alone.

  bench/splishsplash/compare_dam_break_3d.py [SPLISHSPLASH] [--frnn build/release/apps/frnn/frnn]
      [--threads 2] [--runs 3] [--time 0.02]
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SCENE = os.path.join(HERE, "wcsph_dam_break_3d.json")


def locate(where):
    """(SPHSimulator, UnitBox.obj) from a build's source folder or its binary."""
    binary = where
    if not os.path.exists(where):
        raise SystemExit("%s: no such file or folder (SPlisHSPlasH's build, or its SPHSimulator)" % where)
    if os.path.isdir(where):
        binary = next((os.path.join(where, p) for p in ("bin/SPHSimulator", "src/bin/SPHSimulator", "SPHSimulator")
                       if os.path.isfile(os.path.join(where, p))), None)
        if binary is None:
            raise SystemExit("no SPHSimulator under %s (bin/, src/bin/)" % where)
    top = os.path.dirname(os.path.dirname(os.path.abspath(binary)))
    model = os.path.join(top, "data", "models", "UnitBox.obj")
    if not os.path.isfile(model):
        raise SystemExit("no data/models/UnitBox.obj beside %s" % binary)
    return binary, model


def run_frnn(binary, threads, seconds, out):
    """One frnn run: its summary.json."""
    subprocess.run([binary, "sim", "--scene", "dam-break", "--solver", "sph", "--dim", "3", "--threads", str(threads),
                    "--time", str(seconds), "--every", "1000000000", "--quiet", "--out", out],
                   check=True, capture_output=True, text=True)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    stages = s["mean_ms_per_step"]
    return {
        "fluid": s["particles"], "boundary": s.get("wall_particles", 0), "steps": s["steps"],
        "simulated": s["simulated_seconds"],
        "step": s["step_ms_without_output"], "search": stages["grid build + reorder"] + stages["neighbor lists"],
        "split": "density %.2f, forces %.2f, other %.2f" % (
            stages["density"], stages["forces"],
            s["step_ms_without_output"] - sum(v for k, v in stages.items() if k in (
                "grid build + reorder", "neighbor lists", "density", "forces"))),
    }


def run_splishsplash(binary, model, threads, seconds, work):
    """One SPlisHSPlasH run (no GUI, no cache, no output): counts and average timers of its log."""
    with open(SCENE) as f:
        scene = json.loads(f.read().replace("UNITBOX", model))
    scene["Configuration"]["stopAt"] = seconds  # the scene's value wins over --stopAt
    path = os.path.join(work, "scene.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    done = subprocess.run([binary, "--no-gui", "--no-initial-pause", "--no-cache", "--output-dir",
                           os.path.join(work, "out"), path], capture_output=True, text=True, env=env)
    log = done.stdout + done.stderr
    def number(pattern):
        m = re.search(pattern, log)
        if not m:
            raise RuntimeError("SPlisHSPlasH's log lacks %r:\n%s" % (pattern, log[-2000:]))
        return float(m.group(1))
    step = number(r"Average time: SimStep: ([\d.eE+-]+) ms")
    search = number(r"Average time: neighborhood_search: ([\d.eE+-]+) ms")
    forces = number(r"Average time: computeNonPressureForces: ([\d.eE+-]+) ms")
    return {
        "fluid": int(number(r"Number of fluid particles: (\d+)")),
        "boundary": int(number(r"Number of boundary particles: (\d+)")),
        "steps": int(round(number(r"Time sum: SimStep: ([\d.eE+-]+) ms") / step)),
        "simulated": number(r"Total number: Time step size: ([\d.eE+-]+)"),
        "step": step, "search": search,
        "split": "non-pressure forces %.2f, density + pressure + integration %.2f" % (forces, step - search - forces),
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("splishsplash", nargs="?", help="SPlisHSPlasH's build (source folder with bin/) or SPHSimulator")
    p.add_argument("--frnn", default=os.path.join(ROOT, "build", "release", "apps", "frnn", "frnn"))
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--time", type=float, default=0.02, help="simulated seconds (default 0.02)")
    a = p.parse_args()
    peer = locate(a.splishsplash) if a.splishsplash else None
    if peer is None:
        print("No SPlisHSPlasH given: frnn alone is measured.")
    work = tempfile.mkdtemp(prefix="frnn-splishsplash-")
    try:
        runs = {"frnn": [], "SPlisHSPlasH": []}
        for r in range(a.runs):  # alternating
            runs["frnn"].append(run_frnn(a.frnn, a.threads, a.time, os.path.join(work, "frnn%d" % r)))
            if peer:
                os.makedirs(os.path.join(work, "sph%d" % r))
                runs["SPlisHSPlasH"].append(run_splishsplash(*peer, a.threads, a.time, os.path.join(work, "sph%d" % r)))
        print("3D WCSPH dam break to t = %g s, %d threads, medians (and ranges) of %d runs, in ms per step" % (
            a.time, a.threads, a.runs))
        print("| | fluid | boundary | steps to t | step | neighbor search | other stages | ns per fluid particle-step "
              "| time to t |")
        print("|---|---:|---:|---:|---:|---:|---|---:|---:|")
        per_fluid = {}
        for name, rs in runs.items():
            if not rs:
                continue
            step = statistics.median(r["step"] for r in rs)
            middle = min(rs, key=lambda r: abs(r["step"] - step))  # the median run's split
            per_fluid[name] = 1e6 * step / rs[0]["fluid"]
            steps = [r["step"] for r in rs]
            print("| %s | %d | %d | %d (to %.4f s) | %.2f (%.2f-%.2f) | %.2f | %s | %.0f | %.2f s |" % (
                name, rs[0]["fluid"], rs[0]["boundary"], rs[0]["steps"], rs[0]["simulated"], step, min(steps),
                max(steps), middle["search"], middle["split"], per_fluid[name], step * rs[0]["steps"] / 1000))
        if len(per_fluid) == 2:
            frnn_time = statistics.median(r["step"] for r in runs["frnn"]) * runs["frnn"][0]["steps"]
            peer_time = statistics.median(r["step"] for r in runs["SPlisHSPlasH"]) * runs["SPlisHSPlasH"][0]["steps"]
            print("frnn is %.2fx SPlisHSPlasH per fluid particle-step, %.2fx to the same simulated time"
                  % (per_fluid["SPlisHSPlasH"] / per_fluid["frnn"], peer_time / frnn_time))
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
