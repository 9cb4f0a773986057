#!/usr/bin/python3
"""Pictures of a sheared-junction run (paper A section 4): side views (x-y) at several times, coloured by the
body each particle started in (as Figs 9, 10, A.10), and the top wall's tangential force against its
sliding distance. Headless PNGs (Debian's python3-matplotlib; ParaView cannot render without a display).

    /usr/bin/python3 scenarios/wear/plot.py out/wear/junction_D20_d0_6nm [--frames 0,4,10,20] [--out DIR]

Reads dump.lammpstrj (id, x, y, z, radius, ix, mol), followed by the dump.restart<step>.lammpstrj of each
--restart continuation in step order (a restart's first frame repeats its checkpoint's step: a later
chunk's frames replace an earlier chunk's from its first step on), and wear.csv from the run's directory;
writes side_views.png and, with a wear.csv, force.png into --out (default: the run's directory), and prints
how many frames it read and what it wrote. A wrong run directory (none, or no dump file in it) or frame
index is one line and exit status 2, before anything is created.
"""
import argparse
import csv
import pathlib
import re
import sys

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


def dump_chunks(run):
    """dump.lammpstrj then every dump.restart<step>.lammpstrj, in step order (those present)."""
    restarts = []
    for p in run.glob("dump.restart*.lammpstrj"):
        m = re.fullmatch(r"dump\.restart(\d+)\.lammpstrj", p.name)
        if m:
            restarts.append((int(m.group(1)), p))
    first = [run / "dump.lammpstrj"] if (run / "dump.lammpstrj").is_file() else []
    return first + [p for _, p in sorted(restarts)]


def read_run_frames(chunks):
    """The frames of all chunks, each chunk's cut where the next one starts (a restart's first frame repeats
    the checkpoint's step; a killed run's frames after its checkpoint are replaced by the restart's)."""
    frames = []
    for path in chunks:
        chunk = read_frames(path)
        if not chunk:
            continue
        frames = [f for f in frames if f[0] < chunk[0][0]] + chunk
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

    def fail(message):
        print(f"plot.py: {message}", file=sys.stderr)
        sys.exit(2)

    # Everything is checked before anything is created: a mistyped run directory leaves nothing behind.
    if not a.run.is_dir():
        fail(f"no such run directory: {a.run}")
    chunks = dump_chunks(a.run)
    if not chunks:
        fail(f"{a.run} has no dump.lammpstrj (not a debris_dem output directory, or output.dump_every: 0?)")
    try:
        frames = read_run_frames(chunks)
    except (ValueError, IndexError) as e:
        fail(f"cannot read the frames of {', '.join(str(c) for c in chunks)}: {e} (a truncated dump?)")
    if not frames:
        fail(f"no frames in {', '.join(str(c) for c in chunks)}")
    try:
        picks = [int(k) for k in a.frames.split(",")] if a.frames else sorted(
            {0, len(frames) // 3, 2 * len(frames) // 3, len(frames) - 1})
    except ValueError:
        fail(f"--frames {a.frames}: expected frame indices, e.g. 0,4,10,20")
    bad = [k for k in picks if not -len(frames) <= k < len(frames)]
    if bad:
        fail(f"--frames {a.frames}: the run has {len(frames)} frames (indices 0 to {len(frames) - 1})")
    if a.out is not None and a.out.exists() and not a.out.is_dir():
        fail(f"--out {a.out} is not a directory")
    print(f"read {len(frames)} frames (steps {frames[0][0]} to {frames[-1][0]}) from "
          f"{', '.join(c.name for c in chunks)}; side views of steps {', '.join(str(frames[k][0]) for k in picks)}")
    out = a.out or a.run
    out.mkdir(parents=True, exist_ok=True)
    title = a.title or a.run.name
    written = [out / f"{a.prefix}side_views.png"]
    side_views(frames, picks, written[0], title, slides(a.run / "wear.csv"))
    if (a.run / "wear.csv").exists():
        written.append(out / f"{a.prefix}force.png")
        force_plot(a.run / "wear.csv", written[-1], title)
    print("wrote " + " and ".join(str(p) for p in written))


if __name__ == "__main__":
    main()
