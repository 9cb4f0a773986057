#!/usr/bin/env python3
"""Performance-regression check against another commit, built and run side by side on this machine.

perf_check.py judges a machine by a baseline recorded on its kind of CPU. On a kind the baseline file does
not have, the only comparison that holds is A/B on the machine itself: this script builds debris_bench of
a base commit (by default the one in bench/perf_base_commit) in a scratch directory, then runs the two
executables in alternating rounds (new, base; base, new; ...), each run the perf_check subset in items per
CPU-second of the benchmark thread. Within a round the two runs are seconds apart, so a change of the
machine's speed (other tenants, the AMD EPYC guest's slow memory mode lasting minutes) hits both; the check
takes, per benchmark, the median over rounds of the paired ratio new / base and fails (exit 1) when it is
below 1 - tolerance (perf_check.TOLERANCE, 0.15, by default: a benchmark that takes 25% longer, ratio 0.80,
fails; the few per cent of noise between paired runs do not). A benchmark below the limit is measured again
(--confirm more rounds, all rounds then decide).

Cost: building the base's debris_bench (only that target; 1.3 minutes on a quiet 2-core machine, 7 at load 6)
and 2 x --rounds runs of the subset (about 10 s each on a quiet machine, 14 s at load 6: the whole check took
9.8 minutes at load 6). Exit status: 0 passed, 1 regression, 2 could not build, run or parse.

    python3 bench/perf_ab.py --bench build/bin/debris_bench [--base COMMIT | --base-bench PATH]

bench/perf_base_commit names the commit to compare with: the last landed commit whose speed was accepted.
Advance it when work starts from a new landed commit (git rev-parse --short HEAD), and with a note when a
slowdown is accepted on purpose. Python 3 standard library only.
"""
import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.dont_write_bytecode = True  # leave no bench/__pycache__ in the source tree
sys.path.insert(0, HERE)
import perf_check  # noqa: E402  (run_benchmarks, SUBSET, REFERENCE, fail, git)

BASE_COMMIT_FILE = os.path.join(HERE, "perf_base_commit")


def base_commit(requested):
    """The commit to compare with: --base, else the first word of bench/perf_base_commit."""
    name = requested
    if not name:
        try:
            with open(BASE_COMMIT_FILE) as f:
                name = next((l.split()[0] for l in f if l.strip() and not l.startswith("#")), "")
        except OSError:
            perf_check.fail(2, "cannot read %s (it names the commit to compare with)" % BASE_COMMIT_FILE)
    full = perf_check.git("rev-parse", "--verify", "--quiet", name + "^{commit}")
    if not full:
        perf_check.fail(2, "commit '%s' is not in this clone (a shallow clone? clone with history, or pass "
                           "--base-bench): the A/B check needs it" % name)
    return full


def build_base(commit, work, jobs):
    """debris_bench of `commit`, built from `git archive` of it in `work`; returns its path."""
    src, build = os.path.join(work, "src"), os.path.join(work, "build")
    os.makedirs(src)
    archive = subprocess.Popen(["git", "-C", REPO, "archive", "--format=tar", commit], stdout=subprocess.PIPE)
    untar = subprocess.run(["tar", "-x", "-C", src], stdin=archive.stdout)
    archive.stdout.close()
    if archive.wait() != 0 or untar.returncode != 0:
        perf_check.fail(2, "could not extract commit %s" % commit[:12])
    for cmd in (["cmake", "-S", src, "-B", build, "-DDEBRIS_BUILD_TESTS=OFF", "-DDEBRIS_BUILD_BENCH=ON"],
                ["cmake", "--build", build, "-j%d" % jobs, "--target", "debris_bench"]):
        print("running: " + " ".join(cmd), flush=True)
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if proc.returncode != 0:
            sys.stderr.write(proc.stdout[-4000:])
            perf_check.fail(2, "building debris_bench of %s failed" % commit[:12])
    return os.path.join(build, "bin", "debris_bench")


def cpu_rates(bench, args):
    _, _, rates, _ = perf_check.run_benchmarks(bench, args.repetitions, args.min_time, args.timeout)
    return rates


def rounds(new, base, args, count, first_round):
    """Paired ratios new / base per benchmark, one per round; the order alternates between rounds."""
    paired = {n: [] for n in perf_check.SUBSET}
    for r in range(first_round, first_round + count):
        order = [("new", new), ("base", base)] if r % 2 == 0 else [("base", base), ("new", new)]
        got = {label: cpu_rates(path, args) for label, path in order}
        line = []
        for n in perf_check.SUBSET:
            paired[n].append(got["new"][n] / got["base"][n])
            line.append("%s %.3f" % (n.split("/")[0], paired[n][-1]))
        print("round %d (%s first): new / base = %s" % (r + 1, order[0][0], ", ".join(line)), flush=True)
    return paired


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bench", default=perf_check.DEFAULT_BENCH, help="the new debris_bench (default: %(default)s)")
    ap.add_argument("--base", default="", help="commit to compare with (default: bench/perf_base_commit)")
    ap.add_argument("--base-bench", default="", help="an already built base debris_bench (no build)")
    ap.add_argument("--work", default="", help="where to build the base (default: a temporary directory)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 2, help="build jobs (default: %(default)s)")
    ap.add_argument("--rounds", type=int, default=5, help="paired rounds (default: %(default)s)")
    ap.add_argument("--confirm", type=int, default=4,
                    help="rounds added when a benchmark is below its limit (default: %(default)s)")
    ap.add_argument("--tolerance", type=float, default=perf_check.TOLERANCE,
                    help="fail when the median new / base ratio < 1 - tolerance (default: %(default)s)")
    ap.add_argument("--repetitions", type=int, default=3, help="repetitions per run (default: %(default)s)")
    ap.add_argument("--min-time", type=float, default=0.3, help="seconds per repetition (default: %(default)s)")
    ap.add_argument("--timeout", type=int, default=300, help="seconds per run before giving up (default: %(default)s)")
    args = ap.parse_args()
    if not (0 < args.tolerance < 1) or args.rounds < 1 or args.confirm < 0 or args.repetitions < 1:
        perf_check.fail(2, "need 0 < --tolerance < 1, --rounds >= 1, --confirm >= 0, --repetitions >= 1")

    work = None
    try:
        if args.base_bench:
            base, label = args.base_bench, args.base_bench
        else:
            commit = base_commit(args.base)
            work = args.work or tempfile.mkdtemp(prefix="debris_perf_ab_")
            if args.work and os.path.exists(os.path.join(args.work, "src")):
                shutil.rmtree(args.work)
            label = "commit %s" % commit[:12]
            base = build_base(commit, work, args.jobs)
        print("A/B: new %s against base %s, %s (%s), items per CPU-second" % (
            args.bench, label, perf_check.cpu_model(), perf_check.isa_level()), flush=True)
        paired = rounds(args.bench, base, args, args.rounds, 0)
        limit = 1 - args.tolerance
        below = [n for n in perf_check.SUBSET if statistics.median(paired[n]) < limit]
        if below and args.confirm:
            print("below %.2f: %s; %d more rounds to confirm" % (limit, ", ".join(below), args.confirm))
            more = rounds(args.bench, base, args, args.confirm, args.rounds)
            for n in perf_check.SUBSET:
                paired[n] += more[n]
            below = [n for n in perf_check.SUBSET if statistics.median(paired[n]) < limit]
        print("%-46s %8s %8s %8s %11s  %s" % ("benchmark", "median", "min", "max", "fail below", "status"))
        for n in perf_check.SUBSET:
            p = paired[n]
            print("%-46s %8.3f %8.3f %8.3f %11.2f  %s" % (n, statistics.median(p), min(p), max(p), limit,
                                                            "REGRESSION" if n in below else "ok"))
        if below:
            print("\nperf_ab: FAILED: %s slower than %s by more than %.0f%% (median of %d paired rounds)" % (
                ", ".join(below), label, 100 * args.tolerance, len(paired[below[0]])))
            return 1
        print("\nperf_ab: passed against %s (tolerance %.0f%%)" % (label, 100 * args.tolerance))
        return 0
    finally:
        if work and not args.work:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
