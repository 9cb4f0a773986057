#!/usr/bin/python3
"""A settled pack as a PeriDEM particle list: each grain's rigid pose in a trajectory frame, as a new CSV.

    /usr/bin/python3 scenarios/peridem/settled_pack.py TRAJECTORY.h5 PARTICLES.csv OUT.csv [--frame K]
        [--reference FIRST_TRAJECTORY.h5]

PARTICLES.csv is the particle list the run started from (PeriDEM's i, x, y, z, r, o: zone, centre, radius,
rotation about z), so that grain k of the run is its row k. Each grain's pose in frame K (default: the last)
is the rigid motion that best maps its nodes as placed at step 0 onto frame K (2D Kabsch, volume-weighted;
the placement is frame 0 of --reference, by default of TRAJECTORY.h5: a run continued with --restart writes
trajectory.restart<step>.h5, whose frame 0 is the restart, so give the first chunk's trajectory.h5): the
rotation dtheta and the new centre follow, and OUT.csv holds the same rows with centre and rotation moved
(o + dtheta), the zone and radius kept. A run started from OUT.csv places each grain, undeformed and at rest,
where the frame had it: a long settle is run once and its pack reused by the runs that load it.

It prints what a user must know before reusing the pack: the frame's time, the grains' largest departure
from a rigid motion (their elastic strain is dropped), the mean and largest grain speed (dropped too), and
the top of the pack (the highest particle node), under which a lid must not be placed.
Needs numpy and h5py (Debian: python3-numpy python3-h5py). 2D runs only (rotation about z).
"""
import argparse
import csv
import sys

import numpy as np


def read_particles(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head = [h.strip() for h in rows[0]]
    if head[:6] != ["i", "x", "y", "z", "r", "o"]:
        sys.exit("settled_pack.py: %s: expected the header i, x, y, z, r, o" % path)
    return [[float(x) for x in r[:6]] for r in rows[1:] if r]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trajectory")
    ap.add_argument("particles")
    ap.add_argument("out")
    ap.add_argument("--frame", type=int, default=-1, help="frame index (default: the last)")
    ap.add_argument("--reference", default=None, help="trajectory whose frame 0 is the run's step 0")
    args = ap.parse_args()

    import h5py

    with h5py.File(args.trajectory, "r", locking=False) as f:
        frames = sorted(f["frames"].keys(), key=int)
        k = frames[args.frame]
        grain = f["nodes/grain"][:]
        volume = f["nodes/volume"][:]
        kind = f["grains/kind"][:]
        pos = f["frames/%s/position" % k][:, :2]
        vel = f["frames/%s/velocity" % k][:, :2]
        time = f["frames/%s" % k].attrs.get("time", float("nan"))
    with h5py.File(args.reference or args.trajectory, "r", locking=False) as f:
        first = sorted(f["frames"].keys(), key=int)[0]
        if f["frames/%s" % first].attrs.get("step", 0) != 0:
            sys.exit("settled_pack.py: frame 0 of %s is not step 0: give the first chunk's trajectory as --reference"
                     % (args.reference or args.trajectory))
        if not np.array_equal(f["nodes/grain"][:], grain):
            sys.exit("settled_pack.py: the reference trajectory holds other nodes")
        ref = f["frames/%s/position" % first][:, :2]
    rows = read_particles(args.particles)
    particles = [g for g in range(len(kind)) if kind[g] == 0]
    if len(particles) != len(rows):
        sys.exit("settled_pack.py: the trajectory has %d particle grains, %s has %d rows"
                 % (len(particles), args.particles, len(rows)))

    order = np.argsort(grain, kind="stable")
    bounds = np.searchsorted(grain[order], np.arange(len(kind) + 1))
    out, worst, speeds = [], 0.0, []
    for g, row in zip(particles, rows):
        idx = order[bounds[g]:bounds[g + 1]]
        w = volume[idx] / volume[idx].sum()
        p0, p1 = ref[idx], pos[idx]
        c0, c1 = w @ p0, w @ p1
        a, b = p0 - c0, p1 - c1
        dtheta = np.arctan2(np.sum(w * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])),
                            np.sum(w * (a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1])))
        rot = np.array([[np.cos(dtheta), -np.sin(dtheta)], [np.sin(dtheta), np.cos(dtheta)]])
        worst = max(worst, np.max(np.linalg.norm(b - a @ rot.T, axis=1)) / row[4])
        # The grain's placement centre (the mesh origin) moves with the same rigid motion.
        centre = c1 + rot @ (np.array(row[1:3]) - c0)
        out.append([int(row[0]), centre[0], centre[1], row[3], row[4], row[5] + dtheta])
        speeds.append(np.linalg.norm(w @ vel[idx]))
    with open(args.out, "w", newline="") as f:
        f.write("i, x, y, z, r, o\n")
        for r in out:
            f.write("%d, %.9f, %.9f, %.6f, %.6f, %.6f\n" % tuple(r))

    is_particle = kind[grain] == 0
    top = pos[is_particle, 1].max()
    print("frame %s (t = %.6g s): %d grains written to %s" % (k, time, len(out), args.out))
    print("largest departure from a rigid motion: %.3g of a grain's radius" % worst)
    print("grain speed: mean %.3g m/s, largest %.3g m/s" % (np.mean(speeds), np.max(speeds)))
    print("top of the pack (highest particle node): y = %.6g m" % top)


if __name__ == "__main__":
    main()
