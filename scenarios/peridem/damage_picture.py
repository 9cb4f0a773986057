#!/usr/bin/python3
"""Pictures of a debris_peridem trajectory coloured by damage (Z of eq 14, clipped at 1), headless.

    /usr/bin/python3 scenarios/peridem/damage_picture.py OUT_DIR TIME [TIME ...] [--prefix damage] [--to DIR]
        [--zoom=x0,x1,y0,y1 (mm)] [--vmax Z]

One PNG per time, from the frame of OUT_DIR/trajectory.h5 (and of its restarted chunks,
trajectory.restart<step>.h5, in step order; a later chunk's frames replace an earlier chunk's from its
first step on) nearest to it (skipped when none lies within 1.5 frame intervals). A wrong OUT_DIR (none, or
no debris_peridem trajectory in it) is one line and exit status 2, before --to is created. Walls grey.
--vmax sets the top of the colour scale (default 1: Z >= 1, a broken
bond in the neighbourhood, is red; paper B's Fig 21 uses 2). Write --zoom with '=' when x0 is negative. Needs numpy, matplotlib and h5py (Debian: python3-h5py).
"""
import argparse
import glob
import os
import re
import sys

import numpy as np


def trajectory_chunks(out_dir):
    """trajectory.h5 then every trajectory.restart<step>.h5, in step order (those present)."""
    restarts = []
    for p in glob.glob(os.path.join(out_dir, "trajectory.restart*.h5")):
        m = re.fullmatch(r"trajectory\.restart(\d+)\.h5", os.path.basename(p))
        if m:
            restarts.append((int(m.group(1)), p))
    first = os.path.join(out_dir, "trajectory.h5")
    return ([first] if os.path.isfile(first) else []) + [p for _, p in sorted(restarts)]


def damage_pictures(out_dir, times, prefix, to_dir, labels=None, zoom=None, vmax=1.0):
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = []
    # A run continued with --restart writes its frames to trajectory.restart<STEP>.h5 beside trajectory.h5:
    # take the frames of every chunk in step order, each chunk's cut where the next one starts (its first
    # frame repeats the checkpoint's step; a killed run's frames after its checkpoint are superseded).
    files = [h5py.File(p, "r") for p in trajectory_chunks(out_dir)]
    try:
        if not files:
            raise FileNotFoundError("no trajectory.h5 in %s" % out_dir)
        f = files[0]
        kind = f["grains/kind"][:]
        wall = kind[f["nodes/grain"][:]] == 1
        frames = []
        for g in files:
            chunk = sorted(((float(g["frames/" + k].attrs["time"]), g["frames/" + k]) for k in g["frames"]),
                           key=lambda p: p[0])
            if chunk:
                frames = [p for p in frames if p[0] < chunk[0][0] - 1e-15] + chunk
        t = np.array([p[0] for p in frames])
        interval = np.median(np.diff(t)) if len(t) > 1 else 0.0
        for k, m in enumerate(times):
            j = int(np.argmin(np.abs(t - m)))
            if abs(t[j] - m) > 1.5 * interval + 1e-12:
                continue  # the run has not reached it
            pos = 1e3 * frames[j][1]["position"][:]
            dmg = np.minimum(frames[j][1]["damage"][:], vmax)
            fig, ax = plt.subplots(figsize=(6, 4.2))
            ax.scatter(pos[wall, 0], pos[wall, 1], s=0.5, color="0.5")
            sc = ax.scatter(pos[~wall, 0], pos[~wall, 1], s=0.5 if len(pos) > 5000 else 4, c=dmg[~wall], cmap="jet",
                            vmin=0, vmax=vmax)
            if zoom:
                ax.set_xlim(zoom[0], zoom[1])
                ax.set_ylim(zoom[2], zoom[3])
            ax.set_aspect("equal")
            label = labels[k] if labels else "t = %.4g s" % m
            ax.set_title("%s (frame at %.4g s): damage Z, clipped at %g" % (label, t[j], vmax), fontsize=9)
            ax.set_xlabel("x (mm)")
            ax.set_ylabel("y (mm)")
            fig.colorbar(sc, ax=ax, shrink=0.8)
            fig.tight_layout()
            png = os.path.join(to_dir, "%s_%d.png" % (prefix, k + 1))
            fig.savefig(png, dpi=110)
            plt.close(fig)
            written.append(png)
    finally:
        for g in files:
            g.close()
    return written


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("times", nargs="+", type=float)
    ap.add_argument("--prefix", default="damage")
    ap.add_argument("--to", default=None)
    ap.add_argument("--zoom", default=None)
    ap.add_argument("--vmax", type=float, default=1.0)
    args = ap.parse_args()
    if not os.path.isdir(args.out_dir):
        print("damage_picture.py: no such output directory: %s" % args.out_dir, file=sys.stderr)
        return 2
    if not trajectory_chunks(args.out_dir):
        print("damage_picture.py: %s has no trajectory.h5 (not a debris_peridem output directory, or no "
              "output.trajectory_every?)" % args.out_dir, file=sys.stderr)
        return 2
    import h5py

    with h5py.File(trajectory_chunks(args.out_dir)[0], "r") as f:
        if "grains/kind" not in f or "nodes/grain" not in f:
            print("damage_picture.py: %s is not a debris_peridem trajectory (no grains/kind, nodes/grain)"
                  % f.filename, file=sys.stderr)
            return 2
    to = args.to or args.out_dir
    os.makedirs(to, exist_ok=True)
    zoom = [float(x) for x in args.zoom.split(",")] if args.zoom else None
    for png in damage_pictures(args.out_dir, args.times, args.prefix, to, zoom=zoom, vmax=args.vmax):
        print("wrote " + png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
