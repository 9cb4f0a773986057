#!/usr/bin/env python3
"""Speed under load: each executable on its default settings, alone and beside one competing busy process.

Run on demand (not in ctest: it times things), on a machine that is otherwise quiet:

    python3 bench/load_check.py --build build

For debris_dem on its default input and debris_peridem on the 502-grain compression deck (its first
--peridem-steps steps), it measures the wall time of the command (best of --repeat runs) with nothing beside
it, then beside one busy loop pinned to CPU 0, then, as the reference for "the best choice", beside the same
loop on each fixed thread count. It prints one table and fails (exit 1) when the default settings run more
than --limit times slower beside the busy loop than alone (the aim: at most 2x).
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def wall(cmd, env=None):
    t0 = time.perf_counter()
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, text=True)
    t = time.perf_counter() - t0
    if r.returncode != 0:
        sys.exit(f"load_check: {' '.join(cmd)} failed with exit {r.returncode}:\n{r.stdout[-2000:]}")
    return t, r.stdout


def best(cmd, repeat, env=None):
    runs = [wall(cmd, env) for _ in range(repeat)]
    return min(runs, key=lambda r: r[0])


class BusyLoop:
    """One process that never sleeps, pinned to CPU 0 when taskset exists (the competing load)."""

    def __enter__(self):
        code = "while True: pass"
        cmd = [sys.executable, "-c", code]
        if shutil.which("taskset"):
            cmd = ["taskset", "-c", "0"] + cmd
        self.p = subprocess.Popen(cmd)
        time.sleep(0.5)  # let it start spinning
        return self

    def __exit__(self, *exc):
        self.p.kill()
        self.p.wait()


def default_env():
    """Default settings: none of the variables a user would set to steer OpenMP."""
    env = dict(os.environ)
    for k in ("OMP_NUM_THREADS", "OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "OMP_PROC_BIND", "OMP_PLACES"):
        env.pop(k, None)
    return env


def tuned_line(out):
    for line in out.splitlines():
        if line.startswith("threads tuned while stepping"):
            return line
    return ""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build", help="build directory (bin/debris_dem, bin/debris_peridem)")
    ap.add_argument("--repeat", type=int, default=2, help="runs per setting; the best counts")
    ap.add_argument("--peridem-steps", type=int, default=300, help="steps of the 502-grain deck")
    ap.add_argument("--limit", type=float, default=2.0, help="largest allowed loaded/alone ratio")
    ap.add_argument("--only", choices=["dem", "peridem"], help="one executable only")
    args = ap.parse_args()

    bindir = Path(args.build).resolve() / "bin"
    tmp = Path(tempfile.mkdtemp(prefix="debris_load_"))
    cases = []
    if args.only in (None, "dem"):
        cases.append(("debris_dem default.yaml (1,600 particles, 4,000 steps)",
                      [str(bindir / "debris_dem"), "-i", str(ROOT / "scenarios/dem/hcp_wall_load.yaml"),
                       "-o", str(tmp / "dem")]))
    if args.only in (None, "peridem"):
        # The deck reads its meshes relative to itself: a copy beside a link to its data.
        deck = (ROOT / "scenarios/peridem/compression_n500.yaml").read_text()
        deck = deck.replace("run:\n", f"run:\n  steps: {args.peridem_steps}\n", 1)
        (tmp / "data").symlink_to(ROOT / "scenarios/peridem/data")
        (tmp / "deck.yaml").write_text(deck)
        cases.append((f"debris_peridem compression_n500.yaml (502 grains, {args.peridem_steps} steps)",
                      [str(bindir / "debris_peridem"), "-i", str(tmp / "deck.yaml"), "-o", str(tmp / "pd")]))

    env = default_env()
    cpus = os.cpu_count() or 1
    failed = False
    print(f"machine: {cpus} CPUs; load average before: {os.getloadavg()[0]:.2f}")
    for name, cmd in cases:
        alone, _ = best(cmd, args.repeat, env)
        with BusyLoop():
            loaded, out = best(cmd, args.repeat, env)
            fixed = {n: best(cmd + ["--threads", str(n)], args.repeat, env)[0] for n in range(1, cpus + 1)}
        best_fixed = min(fixed.values())
        ratio = loaded / alone
        ok = ratio <= args.limit
        failed |= not ok
        print(f"\n{name}")
        print(f"  alone, default settings        {alone:8.2f} s")
        print(f"  beside a busy loop, default    {loaded:8.2f} s   x{ratio:.2f} of alone "
              f"({'ok' if ok else 'FAIL'}: limit x{args.limit})")
        for n, t in fixed.items():
            print(f"  beside a busy loop, {n} thread{'s' if n > 1 else ' '}     {t:8.2f} s")
        print(f"  default against the best fixed count beside the loop: x{loaded / best_fixed:.2f}")
        line = tuned_line(out)
        if line:
            print(f"  ({line})")
    shutil.rmtree(tmp, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
