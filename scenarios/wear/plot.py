#!/usr/bin/python3
"""Pictures of a sheared-junction run (paper A section 4): side views (x-y) at several times, coloured by the
body each particle started in (as Figs 9, 10, A.10), and the top wall's tangential force against its
sliding distance. Headless PNGs (Debian's python3-matplotlib; ParaView cannot render without a display).

    /usr/bin/python3 scenarios/wear/plot.py out/wear/junction_D20_d0_6nm [--frames 0,4,10,20] [--out DIR]

Reads dump.lammpstrj (id, x, y, z, radius, ix, mol) and wear.csv from the run's directory; writes
side_views.png and force.png into --out (default: the run's directory).
"""
import argparse
import csv
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402

COLOURS = {0: "#999999", 1: "#4c72b0", 2: "#dd8452", 3: "#c44e52", 4: "#2f2f2f", 5: "#2f2f2f"}
NAMES = {1: "bottom", 2: "top", 3: "junction", 4: "walls"}


def read_frames(path):
    frames = []
    with open(path) as f:
        lines = f.read().split("\n")
    k = 0
    while k < len(lines):
        if lines[k] != "ITEM: TIMESTEP":
            k += 1
            continue
        step = int(lines[k + 1])
        n = int(lines[k + 3])
        box = [tuple(map(float, lines[k + 5 + a].split()[:2])) for a in range(3)]
        cols = lines[k + 8].split()[2:]
        rows = [list(map(float, lines[k + 9 + i].split())) for i in range(n)]
        frames.append((step, box, {c: [r[i] for r in rows] for i, c in enumerate(cols)}))
        k += 9 + n
    return frames


def slides(wear_csv):
    """Top wall's sliding distance by step, from wear.csv (empty without one)."""
    if not wear_csv.exists():
        return {}
    with open(wear_csv) as f:
        return {int(float(r["step"])): float(r["wall_slide"]) for r in csv.DictReader(f)}


def side_views(frames, picks, out, title, slide=None):
    cols = 2 if len(picks) > 1 else 1
    rows = (len(picks) + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(5.2 * cols, 3.9 * rows), squeeze=False)
    for ax in axes.flat[len(picks):]:
        ax.axis("off")
    for ax, k in zip(axes.flat, picks):
        step, box, c = frames[k]
        lx = box[0][1] - box[0][0]
        # Back to front along z so nearer particles cover farther ones; x wrapped into the box.
        order = sorted(range(len(c["id"])), key=lambda i: c["z"][i])
        xs = [((c["x"][i] - box[0][0]) % lx) * 1e9 for i in order]
        ys = [c["y"][i] * 1e9 for i in order]
        ds = [2 * c["radius"][i] * 1e9 for i in order]
        col = [COLOURS.get(int(c.get("mol", [0] * len(order))[i]), "#999999") for i in order]
        ax.add_collection(EllipseCollection(ds, ds, 0, units="xy", offsets=list(zip(xs, ys)),
                                            transOffset=ax.transData, facecolors=col, edgecolors="k",
                                            linewidths=0.2))
        ax.set_xlim(0, lx * 1e9)
        ax.set_ylim(box[1][0] * 1e9 - 2, box[1][1] * 1e9 + 2)
        ax.set_aspect("equal")
        ax.set_ylabel("y (nm)")
        moved = (slide or {}).get(step)
        ax.set_title(f"step {step}" + (f", top wall slid {moved * 1e9:.0f} nm" if moved is not None else ""), fontsize=9)
        ax.set_xlabel("x (nm), periodic", fontsize=8)
    handles = [plt.Line2D([], [], marker="o", ls="", color=COLOURS[k], label=v) for k, v in NAMES.items()]
    axes[0, 0].legend(handles=handles, fontsize=7, loc="upper right", ncol=4)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    plt.close(fig)


def force_plot(wear_csv, out, title):
    with open(wear_csv) as f:
        rows = list(csv.DictReader(f))
    slide = [float(r["wall_slide"]) * 1e9 for r in rows]
    force = [-float(r["wall_force"]) * 1e9 for r in rows]  # the force the wall exerts: minus its reaction
    fig, ax = plt.subplots(figsize=(6.5, 3.2))
    ax.plot(slide, force, lw=0.8)
    ax.set_xlabel("sliding distance of the top wall (nm)")
    ax.set_ylabel("tangential force (nN)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", type=pathlib.Path)
    ap.add_argument("--frames", default="", help="frame indices, e.g. 0,4,10,20 (default: 4 spread over the run)")
    ap.add_argument("--out", type=pathlib.Path)
    ap.add_argument("--title", default="")
    ap.add_argument("--prefix", default="", help="prefix of the PNG names (e.g. the case name)")
    a = ap.parse_args()
    out = a.out or a.run
    out.mkdir(parents=True, exist_ok=True)
    frames = read_frames(a.run / "dump.lammpstrj")
    picks = [int(k) for k in a.frames.split(",")] if a.frames else sorted(
        {0, len(frames) // 3, 2 * len(frames) // 3, len(frames) - 1})
    title = a.title or a.run.name
    side_views(frames, picks, out / f"{a.prefix}side_views.png", title, slides(a.run / "wear.csv"))
    if (a.run / "wear.csv").exists():
        force_plot(a.run / "wear.csv", out / f"{a.prefix}force.png", title)
    print(f"wrote {out / (a.prefix + 'side_views.png')} and {out / (a.prefix + 'force.png')}")


if __name__ == "__main__":
    main()
