#!/usr/bin/python3
"""The discretisation study (paper A, appendix A.4, Fig A.9) from debris_patch's cases.csv: the tensile
strength of systems of fixed size L cut into n = L / d0 particles, against d0 / d_c (log-log), one line per
(L, d_l rule): solid for a fixed largest diameter, faint for d_l = 1.25 d0; one panel per s, with eq 20's
target. Headless PNG (Debian's python3-matplotlib).

    /usr/bin/python3 scenarios/patch/plot_discretisation.py out/disc_a/cases.csv out/disc_b/cases.csv \\
        --scaled-from-sweep out/patch_amorphous_full/cases.csv --sizes 60 120 240 480 960 1920 \\
        --out scenarios/patch/pictures

The cases.csv files are runs of amorphous_discretisation*.yaml (merged; a case that appears twice keeps its
last row). --scaled-from-sweep adds the tension rows of a d0 sweep at L = 100 d0 (amorphous_d0_sweep_full.yaml)
as n = 100 with d_l = 1.25 d0 at L = 100 d0 (--sweep-length): the same recipe, so the same samples, which
the study would make again; --sizes keeps those whose L is one of the study's. Writes discretisation.png
into --out and prints each line's strengths with their ratio to the line's coarsest. A missing file or a
file without debris_patch's columns is one line and exit status 2, before anything is written.
"""
import argparse
import csv
import pathlib
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

NEEDED = {"test", "sample", "d0_over_dc", "s", "status", "strength", "target_strength", "outcome",
          "system_size_over_dc"}
LABEL = re.compile(r"amorphous L=(?P<L>[0-9.e+]+) d_c, d_l (?P<rule>fixed|=)")


def read(path):
    p = pathlib.Path(path)
    if not p.is_file():
        raise SystemExit(f"plot_discretisation.py: no such file: {path}")
    with p.open() as f:
        reader = csv.DictReader(f)
        missing = NEEDED - set(reader.fieldnames or [])
        if missing:
            raise SystemExit(f"plot_discretisation.py: {path} is not a debris_patch cases.csv (no {sorted(missing)})")
        return [r for r in reader if r["test"] == "tension" and r["status"] == "ok"]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("cases", nargs="+", help="cases.csv of discretisation runs")
    ap.add_argument("--scaled-from-sweep", nargs="*", default=[], metavar="CSV",
                    help="cases.csv of a d0 sweep at L = --sweep-length d0: its tension rows as d_l = 1.25 d0")
    ap.add_argument("--sweep-length", type=float, default=100, help="the sweep's L in d0 (its n; default 100)")
    ap.add_argument("--sizes", nargs="*", type=float, default=[],
                    help="the study's L / d_c: sweep rows at another L are left out (default: keep all)")
    ap.add_argument("--out", default=".", help="folder for discretisation.png")
    a = ap.parse_args()
    points = {}  # (s, L, rule) -> {d0: (strength, target, outcome)}
    try:
        for path in a.cases:
            for r in read(path):
                m = LABEL.match(r["sample"])
                if not m:
                    continue
                key = (float(r["s"]), float(r["system_size_over_dc"]), "fixed" if m["rule"] == "fixed" else "scaled")
                points.setdefault(key, {})[float(r["d0_over_dc"])] = (float(r["strength"]),
                                                                      float(r["target_strength"]), r["outcome"])
        for path in a.scaled_from_sweep:
            for r in read(path):
                if r["sample"] != "amorphous":
                    continue
                d0 = float(r["d0_over_dc"])
                size = round(d0 * a.sweep_length, 6)
                if a.sizes and not any(abs(size - s) < 1e-6 * s for s in a.sizes):
                    continue
                key = (float(r["s"]), size, "scaled")
                points.setdefault(key, {})[d0] = (float(r["strength"]), float(r["target_strength"]), r["outcome"])
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 2
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    scalings = sorted({k[0] for k in points}) or [0.0]
    fig, axes = plt.subplots(1, len(scalings), figsize=(6.5 * len(scalings), 5.2), squeeze=False)
    sizes = sorted({k[1] for k in points})
    colours = plt.cm.viridis([i / max(1, len(sizes) - 1) for i in range(len(sizes))])
    for ax, s in zip(axes[0], scalings):
        for (ss, size, rule), pts in sorted(points.items()):
            if ss != s:
                continue
            xs = sorted(pts)
            ys = [pts[x][0] for x in xs]
            colour = colours[sizes.index(size)]
            ax.plot(xs, ys, "-o" if rule == "fixed" else "--s", color=colour, alpha=1.0 if rule == "fixed" else 0.4,
                    label=f"L = {size:g} d_c, d_l {'fixed' if rule == 'fixed' else '= 1.25 d0'}")
            coarse = ys[-1]  # the largest d0: the coarsest cut of this L
            ratios = ", ".join(f"n={round(size / x)} {y:.4g} ({y / coarse:.2f})" for x, y in zip(reversed(xs),
                                                                                                 reversed(ys)))
            print(f"s={s:g} L={size:g} d_l {rule}: {ratios}")
        target = {x: v[1] for (ss, _, _), pts in points.items() if ss == s for x, v in pts.items()}
        if target:
            ax.plot(sorted(target), [target[x] for x in sorted(target)], ":", color="black", label="target, eq 20")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("d0 / d_c")
        ax.set_ylabel("tensile strength (units of E)")
        ax.set_title(f"Fig A.9 at full size, s = {s:g}", fontsize=10)
        ax.legend(fontsize=6.5, ncol=2)
    fig.tight_layout()
    path = out / "discretisation.png"
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
