#!/usr/bin/python3
"""A settled pack as a PeriDEM particle list: each grain's rigid pose in a trajectory frame, as a new CSV.

    /usr/bin/python3 scenarios/peridem/settled_pack.py TRAJECTORY.h5 PARTICLES.csv OUT.csv [--frame K]
        [--reference FIRST_TRAJECTORY.h5] [--shrink EPS] [--clear-walls R_C]

PARTICLES.csv is the particle list the run started from (PeriDEM's i, x, y, z, r, o: zone, centre, radius,
rotation about z). Grains are made zone by zone, file order within a zone (scenarios/common/peridem/grain_placement.hpp), and
OUT.csv keeps the rows in PARTICLES.csv's order. Each grain's pose in frame K (default: the last)
is the rigid motion that best maps its nodes as placed at step 0 onto frame K (2D Kabsch, volume-weighted;
the placement is frame 0 of --reference, by default of TRAJECTORY.h5: a run continued with --restart writes
trajectory.restart<step>.h5, whose frame 0 is the restart, so give the first chunk's trajectory.h5): the
rotation dtheta and the new centre follow, and OUT.csv holds the same rows with centre and rotation moved
(o + dtheta), the zone and radius kept. A run started from OUT.csv places each grain, undeformed and at rest,
where the frame had it: a long settle is run once and its pack reused by the runs that load it.

A pack at rest is held by its grains' elastic deformation, which a rigid pose drops: placed rigidly, the
grains of a settled pack overlap where they had flattened against each other (up to 0.3 um of 1 mm grains
with the paper's contact stiffness), and those overlaps throw the pack apart (measured on the 502-grain pack:
0.015 J/m of contact energy at once, a bond broken within 200 steps). --shrink EPS makes every grain smaller
by the fraction EPS about its centroid (radius r (1 - EPS), more digits written), which opens each contact by
about 2 EPS r: with EPS = 1e-3, 2 um, and the pack settles back by gravity from there.

A grain resting on a wall is within the contact radius R_c of it, and debris_peridem refuses a grain placed
that close to a wall (it would be thrown out of a wall it had been placed into). --clear-walls R_C moves each
such grain straight away from the wall nodes it is near, by the little it needs (its deepest contact, a few
um at rest, plus 1 um), so the pack can be loaded: it then settles back onto the wall from that height.

It prints what a user must know before reusing the pack: the frame's time, the grains' largest departure
from a rigid motion (their elastic strain is dropped), the mean and largest grain speed (dropped too), and
the top of the pack (the highest particle node), under which a lid must not be placed.
Needs numpy and h5py, and scipy for --clear-walls (Debian: python3-numpy python3-h5py python3-scipy). 2D runs only (rotation about z).
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


def wall_clearance(nodes, walls, rc):
    """The shift that takes a grain's nodes (the rigidly placed ones) to at least rc + 1 um from every wall
    node: straight away from the nodes it is near, grown until clear."""
    from scipy.spatial import cKDTree

    tree = cKDTree(walls)
    need = rc + 1e-6
    shift = np.zeros(2)
    for _ in range(200):
        d, j = tree.query(nodes + shift)
        close = d < need
        if not close.any():
            return shift
        away = (nodes + shift)[close] - walls[j[close]]
        direction = away.sum(axis=0)
        direction /= np.linalg.norm(direction)
        shift = shift + direction * (need - d[close].min())
    sys.exit("settled_pack.py: a grain cannot be moved clear of the walls (%.3g m short after %s)" % (need - d[close].min(), shift))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trajectory")
    ap.add_argument("particles")
    ap.add_argument("out")
    ap.add_argument("--frame", type=int, default=-1, help="frame index (default: the last)")
    ap.add_argument("--reference", default=None, help="trajectory whose frame 0 is the run's step 0")
    ap.add_argument("--shrink", type=float, default=0.0, metavar="EPS",
                    help="make each grain smaller by this fraction about its centroid (e.g. 1e-3)")
    ap.add_argument("--clear-walls", type=float, default=0.0, metavar="R_C",
                    help="move grains within this contact radius (m) of a wall node clear of it")
    args = ap.parse_args()
    # A wrong path is one line (exit 2), before anything is read or written.
    import os

    for what, path in (("trajectory", args.trajectory), ("particle list", args.particles),
                       ("--reference trajectory", args.reference)):
        if path is not None and not os.path.isfile(path):
            print("settled_pack.py: no such %s: %s" % (what, path), file=sys.stderr)
            sys.exit(2)
    if not os.path.isdir(os.path.dirname(args.out) or "."):
        print("settled_pack.py: no such directory for %s" % args.out, file=sys.stderr)
        sys.exit(2)

    import h5py

    with h5py.File(args.trajectory, "r", locking=False) as f:
        frames = sorted(f["frames"].keys(), key=int)
        frame = k = frames[args.frame]
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

    walls = pos[kind[grain] != 0]
    moved = []
    order = np.argsort(grain, kind="stable")
    bounds = np.searchsorted(grain[order], np.arange(len(kind) + 1))
    out, worst, speeds = [], 0.0, []
    # Grain k of the run is the k-th row in zone order (stable within a zone).
    by_zone = sorted(range(len(rows)), key=lambda r: int(rows[r][0]))
    grain_of_row = [0] * len(rows)
    for k, r in enumerate(by_zone):
        grain_of_row[r] = particles[k]
    for r, row in enumerate(rows):
        g = grain_of_row[r]
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
        # Shrunk about the centroid c1: nodes c1 + (1 - eps) (placed - c1).
        centre = c1 + (1.0 - args.shrink) * (centre - c1)
        placed = c1 + (1.0 - args.shrink) * (a @ rot.T)
        shift = np.zeros(2)
        if args.clear_walls > 0:
            shift = wall_clearance(placed, walls, args.clear_walls)
            moved.append(np.linalg.norm(shift))
        out.append([int(row[0]), centre[0] + shift[0], centre[1] + shift[1], row[3], row[4] * (1.0 - args.shrink),
                    row[5] + dtheta])
        speeds.append(np.linalg.norm(w @ vel[idx]))
    with open(args.out, "w", newline="") as f:
        f.write("i, x, y, z, r, o\n")
        for r in out:
            f.write("%d, %.9f, %.9f, %.6f, %.12f, %.9f\n" % tuple(r))

    is_particle = kind[grain] == 0
    top = pos[is_particle, 1].max()
    print("frame %s (t = %.6g s): %d grains written to %s" % (frame, time, len(out), args.out))
    print("largest departure from a rigid motion: %.3g of a grain's radius" % worst)
    print("grain speed: mean %.3g m/s, largest %.3g m/s" % (np.mean(speeds), np.max(speeds)))
    if args.clear_walls > 0:
        n = sum(1 for m in moved if m > 0)
        print("moved clear of the walls: %d grains, at most %.3g m" % (n, max(moved) if moved else 0.0))
    print("top of the pack (highest particle node): y = %.6g m" % top)


if __name__ == "__main__":
    main()
