#!/usr/bin/python3
"""Pictures of a debris_peridem trajectory coloured by damage (Z of eq 14, clipped at 1), headless.

    /usr/bin/python3 scenarios/peridem/damage_picture.py OUT_DIR TIME [TIME ...] [--prefix damage] [--to DIR]
        [--zoom=x0,x1,y0,y1 (mm)] [--vmax Z]

One PNG per time, from the frame of OUT_DIR/trajectory.h5 (and of its restarted chunks,
trajectory.restart*.h5) nearest to it (skipped when none lies within
1.5 frame intervals). Walls grey. --vmax sets the top of the colour scale (default 1: Z >= 1, a broken
bond in the neighbourhood, is red; paper B's Fig 21 uses 2). Write --zoom with '=' when x0 is negative. Needs numpy, matplotlib and h5py (Debian: python3-h5py).
"""
import argparse
import glob
import os
import sys

import numpy as np


def damage_pictures(out_dir, times, prefix, to_dir, labels=None, zoom=None, vmax=1.0):
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = []
    # A run continued with --restart writes its frames to trajectory.restart<STEP>.h5 beside trajectory.h5:
    # take the frames of every chunk (a frame written twice, at a restart step, once).
    paths = [os.path.join(out_dir, "trajectory.h5")] + sorted(glob.glob(os.path.join(out_dir, "trajectory.restart*.h5")))
    files = [h5py.File(p, "r") for p in paths if os.path.exists(p)]
    try:
        f = files[0]
        kind = f["grains/kind"][:]
        wall = kind[f["nodes/grain"][:]] == 1
        by_time = {}
        for g in files:
            for k in g["frames"]:
                by_time.setdefault(float(g["frames/" + k].attrs["time"]), g["frames/" + k])
        frames = sorted(by_time.items(), key=lambda p: p[0])
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
    to = args.to or args.out_dir
    os.makedirs(to, exist_ok=True)
    zoom = [float(x) for x in args.zoom.split(",")] if args.zoom else None
    for png in damage_pictures(args.out_dir, args.times, args.prefix, to, zoom=zoom, vmax=args.vmax):
        print("wrote " + png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
