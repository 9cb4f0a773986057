#!/usr/bin/env python3
"""PeriDEM's two-particle restitution test (paper B, section 4.1, Table 2) as a sweep written with the
module: a fixed bottom disc and a top disc dropped from H0 = 1 mm under g = 10 m/s^2, both of material M1
(Table 1, with the 3D LPS constants the authors' code used on 2D grains), for each contact restitution
epsilon of Table 2; C_R = sqrt(H1 / H0) (eq 37), H1 the rebound height of the top disc.

As debris_restitution measures it (scenarios/restitution/two_particle_drop.hpp): the fall is exact free
flight, so the top disc starts 0.2 mm above the bottom one at the speed of the remaining fall, and once it
has left the contact (free and rising for 100 steps) its centre rises ballistically, H1 = h + v^2 / 2g.
The loop that watches for that runs in Python, one step per call, on values the module returns.

    PYTHONPATH=build/python /usr/bin/python3 scenarios/python/examples/peridem_restitution_sweep.py
    # the five rows of Table 2, under a second each (2,900 steps of 300 nodes); --eps 0.95 for one row

Prints each row with the paper's value beside it.
"""

import argparse
import math
import pathlib

import debris

TABLE2 = {1.0: 1.0, 0.95: 0.946, 0.9: 0.893, 0.85: 0.845, 0.8: 0.796}  # epsilon: C_R of the paper
RADIUS, H0, GAP0, G, DT = 1e-3, 1e-3, 2e-4, 10.0, 2e-7


def drop_input(eps, out):
    v0 = math.sqrt(2 * G * (H0 - GAP0))  # the speed after falling H0 - GAP0 from rest
    return {
        "dimension": 2,
        "materials": {"M1": {"density": "1200 kg/m^3", "bulk_modulus": "0.0216 GPa", "shear_modulus": "0.01296 GPa",
                             "fracture_energy": "50 J/m^2", "horizon": "0.6 mm", "lps_constants": "peridem_code"}},
        "shapes": {"disc": {"type": "circle", "radius": f"{RADIUS * 1e3} mm", "mesh_size": "0.2 mm"}},
        "grains": [
            {"name": "bottom", "shape": "disc", "material": "M1", "centre": [0, 0, 0], "fixed": True},
            {"name": "top", "shape": "disc", "material": "M1", "centre": [0, f"{(2 * RADIUS + GAP0) * 1e3} mm", 0],
             "rotation": math.pi / 2, "velocity": [0, f"{-v0} m/s", 0]},
        ],
        "contact": {"contact_radius_factor": 0.95, "restitution": eps, "damping_factor": 100, "friction": 0,
                    "damping": "grain_centres", "damping_onset_factor": 1.01},
        "gravity": [0, f"{-G} m/s^2", 0],
        "run": {"time_step": f"{DT * 1e6} us", "allow_unstable_time_step": True, "steps": 200000},
        "output": {"directory": str(out), "thermo_every": 1000, "trajectory_every": 0, "checkpoint_every": 0},
    }


def restitution(eps, out):
    """C_R of one drop, and the steps it took."""
    sim = debris.Peridem(drop_input(eps, out), quiet=True)
    grains = sim.grains
    centre_gap0 = grains["top"]["centre"][1] - grains["bottom"]["centre"][1]
    touched, free_rising = False, 0
    while not sim.done:
        sim.run(1, finish=False)
        if sim.touching_pairs() > 0:
            touched, free_rising = True, 0
            continue
        if not touched:
            continue
        grains = sim.grains
        v = grains["top"]["velocity"][1] - 0.5 * DT * G  # stored velocities are half a step behind the positions
        free_rising = free_rising + 1 if v > 0 else 0
        if free_rising >= 100:
            h = GAP0 + (grains["top"]["centre"][1] - grains["bottom"]["centre"][1]) - centre_gap0
            return math.sqrt((h + v * v / (2 * G)) / H0), sim.step
    raise RuntimeError(f"epsilon {eps}: the top disc did not leave the contact in {sim.step} steps")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--eps", default=",".join(str(e) for e in TABLE2), help="the epsilons to run (Table 2's rows)")
    ap.add_argument("--out", default="out/peridem_restitution_sweep")
    args = ap.parse_args()
    print("epsilon   C_R (debris)   C_R (paper, Table 2)   steps")
    for eps in (float(e) for e in args.eps.split(",")):
        c, steps = restitution(eps, pathlib.Path(args.out) / f"eps{eps}")
        print(f"{eps:7.2f}   {c:12.4f}   {TABLE2.get(eps, float('nan')):20.3f}   {steps:5d}")


if __name__ == "__main__":
    main()
