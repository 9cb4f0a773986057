#!/usr/bin/python3
"""The amorphous patch tests at two sample sizes side by side (paper A, Figs 7, 8, A.6-A.8): relaxed volume
fraction, E / E_target, nu, tensile and shear strength over target against d0 / d_c (log axis), one line per
(sample size, s). Headless PNGs (Debian's python3-matplotlib).

    /usr/bin/python3 scenarios/patch/plot_sizes.py --size "L = 12 d0" out/patch_amorphous/cases.csv \\
        --size "L = 100 d0" out/full_a/cases.csv out/full_b/cases.csv --out scenarios/patch/pictures

Each --size takes a label and the cases.csv files of debris_patch runs at that size (several runs of one size
are merged; a case that appears twice keeps its last row). Writes amorphous_sizes.png (five panels) into --out
and prints the points it plotted per panel. A missing file or a file without debris_patch's columns is one
line and exit status 2, before anything is written.
"""
import argparse
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

NEEDED = {"test", "sample", "d0_over_dc", "s", "status", "E_dev", "nu", "volume_fraction", "strength_over_target"}

# (panel title, test whose rows carry it, value of a row, the paper's statement drawn as a dashed line)
PANELS = [
    ("relaxed volume fraction (Fig 7)", "elastic", lambda r: float(r["volume_fraction"]), None),
    ("E / E_target (Fig 8)", "elastic", lambda r: 1.0 + float(r["E_dev"]), (1.0, "target")),
    ("nu, target 0.15 (Fig A.6)", "elastic", lambda r: float(r["nu"]), (0.20, "paper: about 0.20")),
    ("tensile strength / target (Fig A.7)", "tension", lambda r: float(r["strength_over_target"]),
     (0.50, "paper: about 0.50")),
    ("shear strength / target (Fig A.8)", "shear", lambda r: float(r["strength_over_target"]),
     (0.56, "paper: about 0.56")),
]


def read_rows(paths):
    rows = {}
    for path in paths:
        p = pathlib.Path(path)
        if not p.is_file():
            raise SystemExit(f"plot_sizes.py: no such file: {path}")
        with p.open() as f:
            reader = csv.DictReader(f)
            missing = NEEDED - set(reader.fieldnames or [])
            if missing:
                raise SystemExit(f"plot_sizes.py: {path} is not a debris_patch cases.csv (no {sorted(missing)})")
            for r in reader:
                if r["sample"] != "amorphous" or r["status"] != "ok":
                    continue
                rows[(r["test"], float(r["d0_over_dc"]), float(r["s"]))] = r
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", nargs="+", action="append", required=True, metavar=("LABEL", "CSV"),
                    help="a label, then the cases.csv files of that size")
    ap.add_argument("--out", default=".", help="folder for amorphous_sizes.png")
    a = ap.parse_args()
    sizes = []
    for group in a.size:
        if len(group) < 2:
            ap.error("--size needs a label and at least one cases.csv")
        try:
            sizes.append((group[0], read_rows(group[1:])))
        except SystemExit as e:
            print(e, file=sys.stderr)
            return 2
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    fig, grid = plt.subplots(2, 3, figsize=(13, 7.6))
    axes = grid.flat
    grid[1][2].axis("off")
    styles = ["-o", "--s", ":^", "-.v"]
    for ax, (title, test, value, paper) in zip(axes, PANELS):
        printed = []
        for k, (label, rows) in enumerate(sizes):
            for s, colour in ((0.0, "tab:blue"), (0.5, "tab:red")):
                pts = sorted((d0, value(r)) for (t, d0, ss), r in rows.items() if t == test and ss == s)
                if not pts:
                    continue
                ax.plot([p[0] for p in pts], [p[1] for p in pts], styles[k % len(styles)], color=colour,
                        alpha=1.0 if k else 0.55, label=f"{label}, s = {s:g}")
                printed.append(f"{label} s={s:g}: {len(pts)}")
        if paper:
            ax.axhline(paper[0], color="black", linestyle=":", linewidth=1, label=paper[1])
        ax.set_xscale("log")
        ax.set_xlabel("d0 / d_c")
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=7)
        print(f"{title}: " + (", ".join(printed) if printed else "no points"))
    fig.tight_layout()
    path = out / "amorphous_sizes.png"
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
