#!/usr/bin/python3
"""Pictures of a debris_peridem trajectory coloured by damage (Z of eq 14, clipped at 1), headless.

    /usr/bin/python3 scenarios/peridem/damage_picture.py OUT_DIR TIME [TIME ...] [--prefix damage] [--to DIR]
        [--zoom x0,x1,y0,y1 (mm)]

One PNG per time, from the frame of OUT_DIR/trajectory.h5 nearest to it (skipped when none lies within
1.5 frame intervals). Walls grey. Needs numpy, matplotlib and h5py (Debian: python3-h5py).
"""
import argparse
import os
import sys

import numpy as np


def damage_pictures(out_dir, times, prefix, to_dir, labels=None, zoom=None):
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = []
    with h5py.File(os.path.join(out_dir, "trajectory.h5"), "r") as f:
        kind = f["grains/kind"][:]
        wall = kind[f["nodes/grain"][:]] == 1
        frames = sorted(((f["frames/" + k].attrs["time"], k) for k in f["frames"]), key=lambda p: p[0])
        t = np.array([p[0] for p in frames])
        interval = np.median(np.diff(t)) if len(t) > 1 else 0.0
        for k, m in enumerate(times):
            j = int(np.argmin(np.abs(t - m)))
            if abs(t[j] - m) > 1.5 * interval + 1e-12:
                continue  # the run has not reached it
            pos = 1e3 * f["frames/%s/position" % frames[j][1]][:]
            dmg = np.minimum(f["frames/%s/damage" % frames[j][1]][:], 1.0)
            fig, ax = plt.subplots(figsize=(6, 4.2))
            ax.scatter(pos[wall, 0], pos[wall, 1], s=0.5, color="0.5")
            sc = ax.scatter(pos[~wall, 0], pos[~wall, 1], s=0.5 if len(pos) > 5000 else 4, c=dmg[~wall], cmap="jet",
                            vmin=0, vmax=1)
            if zoom:
                ax.set_xlim(zoom[0], zoom[1])
                ax.set_ylim(zoom[2], zoom[3])
            ax.set_aspect("equal")
            label = labels[k] if labels else "t = %.4g s" % m
            ax.set_title("%s (frame at %.4g s): damage Z, clipped at 1" % (label, t[j]), fontsize=9)
            ax.set_xlabel("x (mm)")
            ax.set_ylabel("y (mm)")
            fig.colorbar(sc, ax=ax, shrink=0.8)
            fig.tight_layout()
            png = os.path.join(to_dir, "%s_%d.png" % (prefix, k + 1))
            fig.savefig(png, dpi=110)
            plt.close(fig)
            written.append(png)
    return written


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("times", nargs="+", type=float)
    ap.add_argument("--prefix", default="damage")
    ap.add_argument("--to", default=None)
    ap.add_argument("--zoom", default=None)
    args = ap.parse_args()
    to = args.to or args.out_dir
    os.makedirs(to, exist_ok=True)
    zoom = [float(x) for x in args.zoom.split(",")] if args.zoom else None
    for png in damage_pictures(args.out_dir, args.times, args.prefix, to, zoom=zoom):
        print("wrote " + png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
