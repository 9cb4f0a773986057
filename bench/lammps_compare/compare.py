#!/usr/bin/env python3
"""debris_dem against the author's LAMMPS pair style on the same particles (the aim: at least 2x as fast).

The system is BM_Step's benchmark packing at N = 32,000 (bench/bench_dem.cpp): LAMMPS writes it as a data
file (make_fcc.lmp) and both codes read that file, so they start from the same positions, diameters,
densities and velocities. Both run the same time step (0.1 dt_c of eq 6, as debris computes it) for the same
number of steps, in interleaved rounds: LAMMPS on one thread (the style has no OpenMP variant), debris once per
round at each count of --debris-threads (default 1); the best round of each counts (a VM's neighbours only
ever slow a round down). The time compared is the loop less its output in both codes: LAMMPS's "Loop time"
less its Output row, debris's total less its set-up and output rows.

LAMMPS needs the author's pair style gran/cohesive/history compiled in (S. Pham-Ba's public source; it is
not part of debris). The measurement in the README was made with LAMMPS 7 Jan 2022 (Debian's source package,
`apt-get source lammps`), built serial with cmake -D PKG_GRANULAR=yes -D BUILD_MPI=no
-D CMAKE_BUILD_TYPE=Release (-O3, as debris), with the style's two files added to src/GRANULAR (in that
LAMMPS the style's forward_comm(this) is spelled forward_comm_pair(this); where an Open MPI runtime without
its headers is installed, add -D CMAKE_DISABLE_FIND_PACKAGE_MPI=ON).

  python3 bench/lammps_compare/compare.py --lmp /path/to/lmp_serial --debris build/bin/debris_dem \
      [--rounds 3] [--steps 2000] [--debris-threads 1,2]

Run it on a quiet machine; it prints one line per run and a summary table (markdown).
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
N = 32000


def run(cmd, cwd, env=None):
    r = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}")
    return r.stdout + r.stderr


def lammps_rate(out, steps):
    loop = re.search(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps", out)
    output = re.search(r"^Output\s*\|\s*[0-9.eE+-]+\s*\|\s*[0-9.eE+-]+\s*\|\s*([0-9.eE+-]+)", out, re.M)
    if not loop or not output:
        sys.exit("could not read LAMMPS's loop time:\n" + out[-3000:])
    assert int(loop.group(2)) == steps
    seconds = float(loop.group(1)) - float(output.group(1))
    return N * steps / seconds / 1e6, seconds


def debris_rate(out, steps):
    rows = dict(re.findall(r"^(set-up|output|total)\s+([0-9.]+)", out, re.M))
    if len(rows) != 3:
        sys.exit("could not read debris's pass table:\n" + out[-3000:])
    seconds = float(rows["total"]) - float(rows["set-up"]) - float(rows["output"])
    return N * steps / seconds / 1e6, seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lmp", required=True, help="LAMMPS executable with gran/cohesive/history")
    ap.add_argument("--debris", required=True, help="debris_dem executable")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--debris-threads", default="1",
                    help="comma-separated thread counts for debris_dem, each run every round (default: 1)")
    ap.add_argument("--dt", type=float, default=13.6792,
                    help="time step; debris prints dt = 13.6792 = 0.1 dt_c for this system")
    a = ap.parse_args()
    lmp, debris = os.path.abspath(a.lmp), os.path.abspath(a.debris)
    counts = [int(t) for t in a.debris_threads.split(",")]
    if not counts or min(counts) < 1:
        sys.exit(f"--debris-threads: expected counts of 1 or more, got {a.debris_threads!r}")

    work = tempfile.mkdtemp(prefix="debris_lammps_compare_")
    for f in ("make_fcc.lmp", "run_fcc.lmp"):
        shutil.copy(os.path.join(HERE, f), work)
    run([lmp, "-in", "make_fcc.lmp", "-log", "none"], work)
    with open(os.path.join(HERE, "debris_fcc.yaml")) as f:
        deck = f.read()
    deck = deck.replace("  steps: 1000\n  time_step_fraction: 0.1\n",
                        f"  steps: {a.steps}\n  time_step: {a.dt!r}\n")
    deck = deck.replace("  thermo_every: 1000\n", f"  thermo_every: {a.steps}\n  checkpoint_every: 0\n")
    assert f"time_step: {a.dt!r}" in deck
    with open(os.path.join(work, "debris_fcc.yaml"), "w") as f:
        f.write(deck)

    # The wait policy is the caller's (GCC's default spins at barriers): OMP_WAIT_POLICY=passive would cost
    # debris's multi-thread runs a sleep and wake at each of a step's barriers.
    env = dict(os.environ, OMP_NUM_THREADS="1")
    best = {"lammps": (0, 0), **{t: (0, 0) for t in counts}}
    for k in range(a.rounds):
        out = run([lmp, "-in", "run_fcc.lmp", "-log", "none", "-var", "dt", repr(a.dt),
                   "-var", "steps", str(a.steps)], work, env)
        r = lammps_rate(out, a.steps)
        print(f"round {k + 1}: LAMMPS {r[0]:.3f} M particle-steps/s ({r[1]:.2f} s)", flush=True)
        best["lammps"] = max(best["lammps"], r)
        for t in counts:
            out = run([debris, "-i", "debris_fcc.yaml", "--threads", str(t)], work,
                      dict(env, OMP_NUM_THREADS=str(t)))
            r = debris_rate(out, a.steps)
            print(f"round {k + 1}: debris, {t} thread(s), {r[0]:.3f} M particle-steps/s ({r[1]:.2f} s)", flush=True)
            best[t] = max(best[t], r)
    shutil.rmtree(work)

    lam = best["lammps"][0]
    print(f"\n| N | steps | LAMMPS (author's style), 1 thread | debris_dem, threads | debris_dem | ratio |")
    print(f"|---|---|---|---|---|---|")
    for t in counts:
        deb = best[t][0]
        print(f"| {N:,} | {a.steps} | {lam:.2f} M | {t} | {deb:.2f} M | {deb / lam:.2f}x |")


if __name__ == "__main__":
    main()
