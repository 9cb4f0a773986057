#!/usr/bin/python3
"""compression.csv, the pressure plot and the damage pictures of a debris_peridem compression run.

    /usr/bin/python3 scenarios/peridem/compression.py OUT_DIR [--press-start 0.12] [--time-offset -0.06]
        [--lid-speed 0.06] [--lid-length 68.94e-3] [--window 1e-3] [--marks 0.102,0.118,0.126,0.134]
        [--zoom=x0,x1,y0,y1] [--pictures DIR]

OUT_DIR is the run's output directory (thermo.csv, trajectory.h5). Defaults are those of
compression_n500.yaml (paper B, section 4.4): the lid is placed at run time 0.12 s with its lower edge at
31.2 mm and moves down at 0.06 m/s (the paper places it at 0.06 s: the deck settles 0.06 s longer, so the
paper's time is the run's - 0.06 s); the lid is 68.94 mm long; the paper's t1-t4 are marked.

A run that starts from a settled pack (compression_n500_from_pack.yaml) places its lid lower, at y0, at its
run time t_p (there 30.6 mm at 0.02 s): the lid would have been at 31.2 mm at the run time --press-start =
t_p - (31.2 mm - y0) / 0.06 m/s (there 0.01 s). With --time-offset = 0.06 s - press start (there 0.05 s) the
lid is where the paper's is at every time printed, plotted and marked, which are the paper's (run time +
offset); lid travel is counted from 31.2 mm.

compression.csv, one row per thermo row from the press on:
  time (s), lid_travel (m): how far the lid has gone down since it was placed,
  lid_force (N/m): the grains' push on the lid, +y, as debris reports it; in 2D every force is per metre of
    thickness (node volumes are areas), so this is a force per unit length of the out-of-plane axis,
  lid_pressure (Pa): lid_force / lid length, the mean normal stress under the lid,
  lid_force_avg, lid_pressure_avg: the same averaged over the window (centred, --window seconds; the
    instantaneous force of a pack of bouncing grains is noise, the paper averages too, over three windows),
  broken_bonds, max_damage (Z of eq 14),
  lid_pressure_avg_<W>ms: the pressure averaged over each further window when --window lists several.
Pictures (PNG, headless): pressure against lid travel with the marks, and the pack coloured by damage at the
frames nearest to each mark, from trajectory.h5 and the trajectory.restart<step>.h5 of each --restart
continuation (damage_picture.py). Needs numpy, matplotlib and h5py (Debian: python3-numpy python3-matplotlib
python3-h5py).

A wrong OUT_DIR (no such directory, no thermo.csv in it, no lid column) and a run that ended before the
press started (no thermo row from --press-start on) are one line on stderr and exit status 2, with nothing
written.
"""
import argparse
import csv
import os
import sys

import numpy as np


def fail(message):
    print("compression.py: " + message, file=sys.stderr)
    sys.exit(2)


def read_thermo(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    if not rows:
        fail("%s is empty" % path)
    head = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]]).reshape(len(rows) - 1, len(head))
    return {name: data[:, k] for k, name in enumerate(head)}


def centred_mean(t, v, window):
    out = np.empty_like(v)
    for k in range(len(t)):
        sel = np.abs(t - t[k]) <= 0.5 * window
        out[k] = v[sel].mean()
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("--press-start", type=float, default=0.12,
                    help="run time at which the lid is (or would be) at its paper place, 31.2 mm (s)")
    ap.add_argument("--time-offset", type=float, default=-0.06, help="the paper's time less the run's (s)")
    ap.add_argument("--lid-speed", type=float, default=0.06, help="lid speed (m/s)")
    ap.add_argument("--lid-length", type=float, default=68.94e-3, help="lid length (m)")
    ap.add_argument("--lid", default="lid", help="the lid's wall name (thermo columns <lid>_fy)")
    ap.add_argument("--window", default="1e-3",
                    help="averaging window(s) (s), comma-separated; the paper averages over three")
    ap.add_argument("--marks", default="0.102,0.118,0.126,0.134", help="paper times to mark and picture (s)")
    ap.add_argument("--zoom", default=None, help="x0,x1,y0,y1 (mm) of the damage pictures (default: everything)")
    ap.add_argument("--pictures", default=None, help="where the PNGs go (default: OUT_DIR)")
    args = ap.parse_args()

    if not os.path.isdir(args.out_dir):
        fail("no such output directory: %s" % args.out_dir)
    thermo = os.path.join(args.out_dir, "thermo.csv")
    if not os.path.isfile(thermo):
        fail("%s has no thermo.csv (not a debris_peridem output directory?)" % args.out_dir)
    th = read_thermo(thermo)
    col = args.lid + "_fy"
    if col not in th:
        fail("%s has no column %s (no wall named '%s': --lid)" % (thermo, col, args.lid))
    for name in ("time", "broken_bonds", "max_damage"):
        if name not in th:
            fail("%s has no column %s (not a debris_peridem run?)" % (thermo, name))
    if not len(th["time"]):
        fail("%s has no rows: the run wrote none" % thermo)
    keep = th["time"] >= args.press_start - 1e-12
    if not keep.any():
        fail("the run ends at run time %.6g s, before the press starts at %.6g s (--press-start): too short, "
             "nothing written" % (th["time"][-1], args.press_start))
    run_t = th["time"][keep]
    t = run_t + args.time_offset  # the paper's time axis
    press_start = args.press_start + args.time_offset
    force = th[col][keep]
    travel = args.lid_speed * (t - press_start)
    pressure = force / args.lid_length
    windows = [float(x) for x in args.window.split(",") if x]
    force_avgs = [centred_mean(t, force, w) for w in windows]
    force_avg = force_avgs[0]
    pressure_avg = force_avg / args.lid_length
    broken = th["broken_bonds"][keep]
    damage = th["max_damage"][keep]
    out_csv = os.path.join(args.out_dir, "compression.csv")
    with open(out_csv, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "lid_travel", "lid_force", "lid_pressure", "lid_force_avg", "lid_pressure_avg",
                    "broken_bonds", "max_damage"] + ["lid_pressure_avg_%gms" % (1e3 * x) for x in windows[1:]])
        for k, row in enumerate(zip(t, travel, force, pressure, force_avg, pressure_avg, broken, damage)):
            more = [fa[k] / args.lid_length for fa in force_avgs[1:]]
            w.writerow(["%.9g" % x for x in list(row) + more])
    print("wrote %s (%d rows, t = %.4g to %.4g s)" % (out_csv, len(t), t[0] if len(t) else 0, t[-1] if len(t) else 0))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pic_dir = args.pictures or args.out_dir
    os.makedirs(pic_dir, exist_ok=True)
    marks = [float(x) for x in args.marks.split(",") if x]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(1e3 * travel, 1e-3 * pressure, color="0.8", lw=0.5, label="instantaneous")
    for k, (w_s, fa) in enumerate(zip(windows, force_avgs)):
        ax.plot(1e3 * travel, 1e-3 * fa / args.lid_length, color=("C0", "C2", "C4", "C5")[k % 4], lw=1.5 if k == 0 else 1.0,
                label="averaged over %.3g ms" % (1e3 * w_s))
    for k, m in enumerate(marks):
        if t.size and t[0] <= m <= t[-1]:
            ax.axvline(1e3 * args.lid_speed * (m - press_start), color="C3", lw=0.8, ls="--")
            ax.text(1e3 * args.lid_speed * (m - press_start), ax.get_ylim()[1] * 0.95, " t%d" % (k + 1),
                    color="C3", va="top")
    ax.set_xlabel("lid travel from its paper place (mm)")
    ax.set_ylabel("lid pressure (kPa: force per m / lid length)")
    ax2 = ax.twinx()
    ax2.plot(1e3 * travel, broken, color="C1", lw=1.0)
    ax2.set_ylabel("broken bonds", color="C1")
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    png = os.path.join(pic_dir, "compression_pressure.png")
    fig.savefig(png, dpi=110)
    print("wrote " + png)

    if os.path.exists(os.path.join(args.out_dir, "trajectory.h5")):
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from damage_picture import damage_pictures

        labels = ["t%d = %.4g s" % (k + 1, m) for k, m in enumerate(marks)]
        run_marks = [m - args.time_offset for m in marks]
        zoom = [float(x) for x in args.zoom.split(",")] if args.zoom else None
        for png in damage_pictures(args.out_dir, run_marks, "compression_damage_t", pic_dir, labels, zoom):
            print("wrote " + png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
