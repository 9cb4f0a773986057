#!/usr/bin/env python3
"""What stepping from Python costs: N calls of one step (sim.run(1)) against one call of N steps
(sim.run(N)), from the same state, on the default DEM input (the junction, 525 particles) and on a
32,000-particle HCP sample (hcp_wall_load.yaml with 20 x 20 x 20 cells), one thread, outputs off. The
per-call overhead is the difference over N. A measurement for the record (README, issue notes), not a
target: it prints one line per case, with the CPU it ran on.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_step_overhead.py [--steps 1000] [--repeats 3]
"""

import argparse
import pathlib
import platform
import subprocess
import tempfile
import time

import debris

REPO = pathlib.Path(__file__).resolve().parents[1]


def cpu():
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def default_input(out):
    values = debris.load_input(str(REPO / "scenarios/dem/default.yaml"))
    values["particles"]["lammps_data"] = str((REPO / "scenarios/dem" / values["particles"]["lammps_data"]).resolve())
    values["output"].update(directory=str(out), pictures=False, dump_every=0, checkpoint_every=0, thermo_every=10 ** 9)
    return values


def hcp_input(out, cells=20):
    values = debris.load_input(str(REPO / "scenarios/dem/hcp_wall_load.yaml"))
    values["particles"]["lattice"]["cells"] = [cells, cells, cells]
    half_c = 100 * (2.0 / 3.0) ** 0.5  # layer spacing along the c axis (y) for a spacing of 100
    values["groups"][1]["region"] = {"y": [(2 * cells - 2) * half_c - 30, "inf"]}  # the top two layers
    values["run"]["steps"] = 10 ** 9
    values["output"].update(directory=str(out), dump_every=0, checkpoint_every=0, thermo_every=10 ** 9)
    return values


def measure(make, steps, repeats):
    best_one, best_many = float("inf"), float("inf")
    for _ in range(repeats):
        sim = make()
        t0 = time.perf_counter()
        for _ in range(steps):
            sim.run(1, finish=False)
        best_one = min(best_one, time.perf_counter() - t0)
        sim = make()
        t0 = time.perf_counter()
        sim.run(steps, finish=False)
        best_many = min(best_many, time.perf_counter() - t0)
    return best_one, best_many


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    print(f"{cpu()}, 1 thread, {args.steps} steps, best of {args.repeats}")
    with tempfile.TemporaryDirectory() as work:
        cases = {"default input (525 particles)": lambda: debris.Dem(default_input(work), threads=1, quiet=True),
                 "HCP 32,000 particles": lambda: debris.Dem(hcp_input(work), threads=1, quiet=True)}
        for name, make in cases.items():
            one, many = measure(make, args.steps, args.repeats)
            per_call = (one - many) / args.steps * 1e6
            print(f"{name}: {args.steps} x run(1) {one:.3f} s, run({args.steps}) {many:.3f} s: "
                  f"{per_call:.1f} us per call ({100 * (one - many) / many:.1f}% of the stepping)")


if __name__ == "__main__":
    main()
