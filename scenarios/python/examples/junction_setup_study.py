#!/usr/bin/env python3
"""The sheared junction's set-up study (paper A, section 4; scenarios/wear/RESULTS.md) written with the
module: does the verdict depend on the normal load, on settling before the slide, or on the sample (seed)?
No YAML is written by hand: each case is the shipped D = 10 nm, d0 = 6 nm junction input read as a dict and
changed in Python; the wear analysis's verdict and its last window come back as values, and one matplotlib
figure shows the tangential force on the top wall against its slide for every case.

    PYTHONPATH=build/python /usr/bin/python3 scenarios/python/examples/junction_setup_study.py --out out/study
    # 7-10 s per case of 10 ns on a 2-core AMD EPYC (Zen 5); --slide-ns 1 for a quick look

Prints one line per case (verdict, mean tangential force over the last window) and writes
<out>/tangential_force.png and <out>/<case>/ (each run's thermo.csv, wear.csv, checkpoint.h5).
"""

import argparse
import os
import pathlib

import debris

REPO = pathlib.Path(__file__).resolve().parents[3]
WEAR = REPO / "scenarios" / "wear"


def junction(seed):
    """The shipped junction input of this sample as a dict, its data file made absolute."""
    name = "junction_D10_d0_6nm" + ("" if seed == 1 else f"_seed{seed}") + ".yaml"
    values = debris.load_input(str(WEAR / name))
    values["particles"]["lammps_data"] = str((WEAR / values["particles"]["lammps_data"]).resolve())
    return values


def case_input(seed, load_mpa, settle_ns, slide_ns, out):
    values = junction(seed)
    settle, slide = values["stages"]
    top = next(g for g in values["groups"] if g["name"] == values["wear"]["top_wall"])
    top["stress"] = [0, f"-{load_mpa} MPa", 0]
    for change in slide.get("groups", []):
        if change["name"] == top["name"]:
            change["stress"] = [0, f"-{load_mpa} MPa", 0]
    slide["duration"] = f"{slide_ns} ns"
    if settle_ns > 0:
        settle["duration"] = f"{settle_ns} ns"
    else:
        values["stages"] = [slide]  # no settling: the slide starts from the carved state
        slide["global_damping"] = 0
    values["output"].update(directory=str(out), pictures=False, dump_every=0)
    if "surfaces" in values:  # the census's window must fit in the run: a quick look slides less than 2 ns
        values["surfaces"]["window"] = f"{min(2.0, slide_ns)} ns"
    return values


CASES = {  # name: (seed, load in MPa, settling in ns)
    "baseline": (1, 100, 0.2),
    "load_10MPa": (1, 10, 0.2),
    "no_settling": (1, 100, 0.0),
    "seed2": (2, 100, 0.2),
    "seed3": (3, 100, 0.2),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out/junction_setup_study")
    ap.add_argument("--slide-ns", type=float, default=10.0, help="sliding time of each case (the paper: 10 ns)")
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated subset of " + ", ".join(CASES))
    ap.add_argument("--threads", type=int, default=1)
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    results = {}
    for name in args.cases.split(","):
        seed, load, settle = CASES[name]
        sim = debris.Dem(case_input(seed, load, settle, args.slide_ns, out / name), threads=args.threads, quiet=True)
        sim.run()
        wear = sim.wear()
        results[name] = wear
        last = wear["last"]  # its means are over the verdict's last window (wear.verdict_span)
        span = 1e-9 * min(1.0, args.slide_ns / 2)
        window = [s["wall_force"] for s in wear["samples"] if s["time"] >= last["time"] - span]
        print(f"{name:12s} seed {seed} load {load:3d} MPa settle {settle:.1f} ns: {wear['verdict']:9s} "
              f"mean tangential force {sum(window) / len(window) * 1e9:8.2f} nN over the last {span * 1e9:.2g} ns, "
              f"junction in a third body {last['junction_in_third']:.2f}, walls joined {bool(last['walls_joined'])} "
              f"({len(wear['samples'])} samples, {sim.pass_table()['total']:.1f} s)")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4))
    for name, wear in results.items():
        slide = [s["wall_slide"] * 1e9 for s in wear["samples"]]
        force = [s["wall_force"] * 1e9 for s in wear["samples"]]
        ax.plot(slide, force, label=f"{name} ({wear['verdict']})")
    ax.set_xlabel("top wall slide (nm)")
    ax.set_ylabel("tangential force (nN)")
    ax.set_title("sheared junction D = 10 nm, d0 = 6 nm: set-up study")
    ax.legend(fontsize=8)
    fig.tight_layout()
    os.makedirs(out, exist_ok=True)
    fig.savefig(out / "tangential_force.png", dpi=120)
    print(f"wrote {out / 'tangential_force.png'}")


if __name__ == "__main__":
    main()
