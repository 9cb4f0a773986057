#!/usr/bin/python3
"""The timing study of paper B (section 5, Fig 24): time per pass against degrees of freedom.

    /usr/bin/python3 scenarios/peridem/timing_study.py --bin build/bin/debris_peridem --work DIR
        [--grains 25,51,96,200,403] [--threads 1,2] [--steps 10000] [--mesh-scale 0.72] [--csv F] [--plot F]
        [--check]

The paper runs its compressive test (section 4.4) with 25, 51, 96, 200 and 403 grains for 10,000 steps of
0.1 us (T = 1 ms, the first millisecond of the settle) and splits the time by model component. It gives the
degrees of freedom (2 per node in 2D): 13,029, 24,405, 42,900, 84,744 and 164,859, about 200 nodes per grain
plus some 1,500 wall nodes. It does not give its meshes or containers, so here:
  - the grains are the first N of compressive_n500's particle list (the list fills the box from the floor
    up, so each N is a packed bottom layer, as a smaller compressive test would be);
  - the grain meshes are the deck's own .geo files meshed again by gmsh with every length scaled by
    --mesh-scale (0.72 gives ~200 nodes per grain, the paper's count; the deck's meshes have ~114);
  - the container is the deck's (3,870 nodes, more than the paper's walls, so the smallest cases carry
    relatively more wall nodes; both counts are in the table); the lid is left out: in the first
    millisecond it is 30 mm above the grains and takes no part;
  - the horizon and the rest of the material are the deck's; dt = 0.1 us as in the paper.
Each case runs once per thread count with that count fixed (--threads), and the pass table debris_peridem
prints at the end of a run is parsed: set-up, integration, neighbours (contact list), bonds, contact,
other, output, rest. Output is one thermo row per 1,000 steps and a frame and a checkpoint at the end.

Writes a CSV (one row per case and thread count) and a stacked-bar plot like Fig 24, and prints the slope of
stepping time against degrees of freedom, and against grain nodes, on a log-log scale (1 = linear). Needs gmsh, numpy, matplotlib.

--check checks what was parsed against values known without the run, and exits 1 naming every failure:
  - the pass table adds up: the passes sum to the total, and the shares to 100%, within the rounding of the
    printed digits (3 decimals of a second, 1 of a per cent, per row); each share is its seconds over the
    total;
  - the run's rate (M node-steps/s while stepping) is nodes x steps / (total - set-up), to the rounding;
  - the system is the one asked for: the grain count, one wall, and the node count = the container mesh's
    nodes + the nodes of each grain's zone mesh over the first N rows of the particle list (from the .msh
    files and the CSV, not from the run); more grains give more bonds;
  - the CSV has one row per case and thread count;
  - the stepping time grows with the grain nodes, for the same thread count, where it can be timed: only
    between cases whose grain nodes differ by at least 2 times and whose stepping takes 0.5 s or more (a
    few milliseconds, as in the 50-step ctest, is noise); otherwise it says it did not check.
"""
import argparse
import csv
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DECK_DATA = os.path.join(HERE, "data", "compressive_n500")
PAPER_DOF = {25: 13029, 51: 24405, 96: 42900, 200: 84744, 403: 164859}
PASSES = ["set-up", "integration", "neighbours", "bonds", "contact", "other", "output", "rest"]

DECK = """# timing-study case written by timing_study.py: the first {n} grains of compressive_n500
dimension: 2
materials:
  M1: {{density: 1200 kg/m^3, bulk_modulus: 0.0216 GPa, shear_modulus: 0.01296 GPa, fracture_energy: 50 J/m^2,
       horizon: 0.6 mm}}
shapes:
  circle: {{type: mesh_file, file: mesh_particle_1.msh, reference_radius: 1 mm}}
  hexagon: {{type: mesh_file, file: mesh_particle_2.msh, reference_radius: 1 mm}}
  container: {{type: mesh_file, file: {data}/mesh_rigid_wall_0.msh}}
particle_file:
  file: particle_locations.csv
  zones:
    - {{shape: circle, material: M1}}
    - {{shape: hexagon, material: M1}}
walls:
  - {{name: container, shape: container, material: M1}}
contact:
  contact_radius_factor: 0.95
  restitution: 0.95
  damping_factor: 100
  friction: 0
  damping: grain_centres
gravity: [0, -10 m/s^2, 0]
run:
  time_step: 0.1 us
  steps: {steps}
output:
  directory: out
  thermo_every: 1000
  trajectory_every: {steps}
  checkpoint_every: {steps}
  progress_seconds: 3600
"""


def mesh_grains(work, scale):
    """Mesh the deck's two grain shapes again with every mesh length scaled (gmsh -clscale)."""
    for k in (1, 2):
        geo = os.path.join(DECK_DATA, f"mesh_particle_{k}_0.geo")
        out = os.path.join(work, f"mesh_particle_{k}.msh")
        subprocess.run(["gmsh", geo, "-2", "-clscale", str(scale), "-format", "msh22", "-o", out, "-v", "0"],
                       check=True, stdout=subprocess.DEVNULL)


def write_case(work, n, steps):
    case = os.path.join(work, f"n{n}")
    os.makedirs(case, exist_ok=True)
    with open(os.path.join(DECK_DATA, "particle_locations_0.csv")) as f:
        lines = f.read().splitlines()
    if n > len(lines) - 1:
        sys.exit(f"timing_study: --grains {n} is more than the deck's {len(lines) - 1} grains")
    with open(os.path.join(case, "particle_locations.csv"), "w") as f:
        f.write("\n".join(lines[: n + 1]) + "\n")
    for k in (1, 2):
        shutil.copy(os.path.join(work, f"mesh_particle_{k}.msh"), case)
    deck = os.path.join(case, "deck.yaml")
    with open(deck, "w") as f:
        f.write(DECK.format(n=n, steps=steps, data=DECK_DATA))
    return case, deck


def parse_run(text):
    """Node counts and the pass table of a debris_peridem run's output."""
    m = re.search(r"^(\d+) nodes in (\d+) grains and (\d+) walls; (\d+) bonds", text, re.M)
    if not m:
        raise RuntimeError("no node count in the run's output")
    row = {"nodes": int(m.group(1)), "grains": int(m.group(2)), "walls": int(m.group(3)), "bond_count": int(m.group(4)),
           "shares": {}}
    for name in PASSES + ["total"]:
        p = re.search(rf"^{re.escape(name)}\s+([0-9.]+)\s+([0-9.]+)%", text, re.M)
        if not p:
            raise RuntimeError(f"no '{name}' row in the pass table")
        row[name] = float(p.group(1))
        row["shares"][name] = float(p.group(2))
    r = re.search(r"^total\s.*?([0-9.eE+-]+) M node-steps/s while stepping", text, re.M)
    if not r:
        raise RuntimeError("no rate in the pass table's total row")
    row["printed_rate"] = float(r.group(1)) * 1e6
    return row


def mesh_nodes(path):
    """The node count of a Gmsh MSH 2.2 file ($Nodes)."""
    with open(path) as f:
        lines = f.read().splitlines()
    return int(lines[lines.index("$Nodes") + 1])


def expected_grain_nodes(work, n):
    """Nodes of the first n grains of the particle list: each row's zone i uses mesh_particle_{i+1}.msh."""
    per_zone = {k - 1: mesh_nodes(os.path.join(work, f"mesh_particle_{k}.msh")) for k in (1, 2)}
    with open(os.path.join(DECK_DATA, "particle_locations_0.csv")) as f:
        rows = f.read().splitlines()[1: n + 1]
    return sum(per_zone[int(r.split(",")[0])] for r in rows)


def check(rows, a, work, csv_path):
    """The --check checks (see the module's text); returns the failures, printing what it checked."""
    failures = []

    def expect(ok, what):
        print(f"check: {'ok    ' if ok else 'FAILED'} {what}")
        if not ok:
            failures.append(what)

    for r in rows:
        case = f"{r['grains']} grains, {r['threads']} thread(s)"
        passes = sum(r[name] for name in PASSES)
        # Each printed time is within 0.0005 s of the true one (3 decimals), each share within 0.05%.
        expect(abs(passes - r["total"]) <= 0.0005 * (len(PASSES) + 1),
               f"{case}: passes sum to {passes:.3f} s, total {r['total']:.3f} s")
        shares = sum(r["shares"][name] for name in PASSES)
        expect(abs(shares - 100.0) <= 0.05 * len(PASSES) + 1e-9 and r["shares"]["total"] == 100.0,
               f"{case}: shares sum to {shares:.1f}%")
        if r["total"] > 0:
            for name in PASSES:
                # share = 100 s / T from the unrounded s and T; the printed s, T are 0.0005 s off at most
                slack = 0.05 + 100 * 0.0005 * (1 / r["total"] + r[name] / r["total"] ** 2) + 1e-9
                expect(abs(r["shares"][name] - 100 * r[name] / r["total"]) <= slack,
                       f"{case}: {name} {r['shares'][name]:.1f}% of the total = {r[name]:.3f} / {r['total']:.3f} s")
        if r["stepping"] > 0.002:
            rate = r["nodes"] * a.steps / r["stepping"]
            # the printed rate has 3 digits; stepping = total - set-up is 0.001 s off at most
            rel = 0.005 + 0.001 / (r["stepping"] - 0.001)
            expect(abs(r["printed_rate"] - rate) <= rel * rate,
                   f"{case}: printed rate {r['printed_rate'] / 1e6:.3g} M node-steps/s, nodes x steps / stepping "
                   f"= {rate / 1e6:.3g}")
        expect(r["walls"] == 1, f"{case}: {r['walls']} wall (the container)")
        want = expected_grain_nodes(work, r["grains"]) + r["wall_nodes"]
        expect(r["nodes"] == want, f"{case}: {r['nodes']} nodes, meshes and particle list give {want}")
    asked = [int(x) for x in a.grains.split(",")]
    threads = [int(x) for x in a.threads.split(",")]
    expect(sorted({r["grains"] for r in rows}) == sorted(set(asked)), f"grain counts {sorted({r['grains'] for r in rows})}"
           f" as asked ({a.grains})")
    with open(csv_path) as f:
        written = list(csv.DictReader(f))
    expect(len(written) == len(asked) * len(threads), f"{len(written)} CSV rows for {len(asked)} cases x "
           f"{len(threads)} thread counts")
    for t in threads:
        rs = sorted((r for r in rows if r["threads"] == t), key=lambda r: r["grain_nodes"])
        for lo, hi in zip(rs, rs[1:]):
            if hi["grain_nodes"] > lo["grain_nodes"]:
                expect(hi["bond_count"] > lo["bond_count"], f"{t} thread(s): {hi['bond_count']} bonds with "
                       f"{hi['grains']} grains, {lo['bond_count']} with {lo['grains']}")
            if hi["grain_nodes"] >= 2 * lo["grain_nodes"] and lo["stepping"] >= 0.5:
                expect(hi["stepping"] > lo["stepping"], f"{t} thread(s): stepping {hi['stepping']:.3f} s with "
                       f"{hi['grains']} grains, {lo['stepping']:.3f} s with {lo['grains']}")
            else:
                print(f"check: not checked: the stepping time against grains between {lo['grains']} and "
                      f"{hi['grains']} grains on {t} thread(s) (needs 2x the grain nodes and 0.5 s of stepping: "
                      f"{lo['grain_nodes']} -> {hi['grain_nodes']} nodes, {lo['stepping']:.3f} s)")
    return failures


def wall_nodes():
    count = 0
    for name in ("mesh_rigid_wall_0.msh",):
        with open(os.path.join(DECK_DATA, name)) as f:
            lines = f.read().splitlines()
        count += int(lines[lines.index("$Nodes") + 1])
    return count


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--grains", default="25,51,96,200,403")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--steps", type=int, default=10000)
    ap.add_argument("--mesh-scale", type=float, default=0.72)
    ap.add_argument("--csv", default=None)
    ap.add_argument("--plot", default=None)
    ap.add_argument("--check", action="store_true",
                    help="check the parsed tables against values known without the run; exit 1 on a failure")
    a = ap.parse_args()
    binary = os.path.abspath(a.bin)
    os.makedirs(a.work, exist_ok=True)
    mesh_grains(a.work, a.mesh_scale)
    walls = wall_nodes()
    rows = []
    for n in [int(x) for x in a.grains.split(",")]:
        case, deck = write_case(a.work, n, a.steps)
        for t in [int(x) for x in a.threads.split(",")]:
            out = os.path.join(case, f"out_t{t}")
            shutil.rmtree(out, ignore_errors=True)
            env = dict(os.environ, OMP_WAIT_POLICY=os.environ.get("OMP_WAIT_POLICY", "passive"))
            t0 = time.time()
            p = subprocess.run([binary, "-i", deck, "-o", out, "--threads", str(t)], capture_output=True,
                               text=True, env=env)
            wall = time.time() - t0
            if p.returncode != 0:
                sys.exit(f"timing_study: {n} grains on {t} threads exited {p.returncode}:\n{p.stderr[-2000:]}")
            row = parse_run(p.stdout)
            row.update(threads=t, wall_nodes=walls, grain_nodes=row["nodes"] - walls, dof=2 * row["nodes"],
                       paper_dof=PAPER_DOF.get(n, ""), wall_seconds=round(wall, 2))
            row["stepping"] = row["total"] - row["set-up"]
            row["node_steps_per_s"] = row["nodes"] * a.steps / row["stepping"]
            rows.append(row)
            print(f"{n:4d} grains {row['nodes']:6d} nodes ({2 * row['nodes']} dof; paper {PAPER_DOF.get(n, '-')})"
                  f" {t} thread(s): stepping {row['stepping']:.2f} s, set-up {row['set-up']:.2f} s,"
                  f" {row['node_steps_per_s'] / 1e6:.2f} M node-steps/s", flush=True)
    cols = ["grains", "threads", "nodes", "wall_nodes", "grain_nodes", "dof", "paper_dof"] + PASSES + \
        ["total", "stepping", "node_steps_per_s", "wall_seconds"]
    path = a.csv or os.path.join(a.work, "timing.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {path}")
    if a.check:
        failures = check(rows, a, a.work, path)
        if failures:
            sys.exit(f"timing_study: {len(failures)} check(s) failed:\n  " + "\n  ".join(failures))
        print("timing_study: every check passed")

    import numpy as np
    for t in sorted({r["threads"] for r in rows}):
        rs = [r for r in rows if r["threads"] == t]
        if len(rs) >= 2:
            # Against all degrees of freedom (the paper's axis), and against the grain nodes only: the wall
            # nodes have no bonds and cost little, and they are a large share of the smallest cases.
            for axis in ("dof", "grain_nodes"):
                slope = np.polyfit(np.log([r[axis] for r in rs]), np.log([r["stepping"] for r in rs]), 1)[0]
                print(f"{t} thread(s): stepping time ~ {axis}^{slope:.3f} (log-log least squares, {len(rs)} cases)")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    threads = sorted({r["threads"] for r in rows})
    fig, axes = plt.subplots(1, len(threads), figsize=(5 * len(threads), 4), squeeze=False, sharey=True)
    shown = ["bonds", "contact", "neighbours", "integration", "other", "output", "rest"]
    for ax, t in zip(axes[0], threads):
        rs = [r for r in rows if r["threads"] == t]
        x = np.arange(len(rs))
        bottom = np.zeros(len(rs))
        for name in shown:
            v = np.array([r[name] for r in rs])
            ax.bar(x, v, bottom=bottom, label=name)
            bottom += v
        ax.set_xticks(x, [f"{r['grains']}\n{r['dof'] // 1000}k dof" for r in rs])
        ax.set_title(f"{t} thread{'s' if t > 1 else ''}, {a.steps} steps")
        ax.set_xlabel("grains / degrees of freedom")
    axes[0][0].set_ylabel("time (s), set-up not included")
    axes[0][-1].legend(fontsize=8)
    fig.tight_layout()
    plot = a.plot or os.path.join(a.work, "timing.png")
    fig.savefig(plot, dpi=90)
    print(f"wrote {plot}")


if __name__ == "__main__":
    main()
