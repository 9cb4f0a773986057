#!/usr/bin/env python3
"""Performance-regression check of the DEM and PeriDEM engines, as same-run ratios to a reference loop.

It runs debris_bench on a short subset (SUBSET below, all on 1 thread: the DEM contact pass and whole step at
N = 32,000, and PeriDEM's bond passes and whole step on the 502-grain compressive deck, 62,994 nodes) together
with BM_ReferenceLoop, all in one process with repetitions interleaved in random order
(--benchmark_enable_random_interleaving), and computes for each subset benchmark

    ratio = median items/s of the benchmark / median items/s of BM_ReferenceLoop

Absolute speeds vary with the machine and its load (shared 2-core machines); a ratio measured back to back
cancels most of that (shared/notes/measuring-speed.md). The check fails, exit status 1, when a ratio fell
below baseline * (1 - tolerance), tolerance 0.15 by default: a benchmark that takes 25% longer (ratio 0.80
of its baseline) fails on every CPU, whichever way it is judged (perf_ab.py uses the same limit). A baseline
entry may set its own "tolerance", with the measured spread that justifies it in "_tolerance" (--update
keeps both). It never fails on a speed-up; it says when one is large enough to deserve a new baseline.

Which clock. All benchmarks of the subset run on 1 thread, so their items per CPU-second of the benchmark
thread (items per iteration / median CPU time) measure the same work as items per real second, minus the
time the thread waited for a core. Measured on a 2-core AMD EPYC machine with a load average of 3-4
(2026-11-23, 22 checks against 4 baselines): the real-time ratio moved between -38% and +24% from its
baseline (one false failure), the CPU-time ratio between -12% and +17%. So the CPU-time ratio decides by
default (--clock cpu) and the real-time one is printed beside it; --clock real makes the real-time ratio
decide (right on a quiet machine). Both are stored in the baseline. "cv" is the coefficient of variation
of the benchmark's real-time items/s over the repetitions: a large one says the machine was busy.

The baseline file (bench/perf_baseline.json) holds one baseline per kind of CPU (model name and x86-64
level: the ratio of a pair kernel to a triad and a sqrt chain depends on the microarchitecture and on the
compiler). Where a baseline does not carry, the build is judged by bench/perf_ab.py instead: the base commit
(bench/perf_base_commit) built and run side by side with this build, in paired rounds, so the check never
passes by skipping. That is a machine of a kind the file does not have, a kind whose entry lacks a
benchmark of SUBSET (recorded before it was added), and a kind whose entry says "judge": "ab" (with the
measurements that say why in "_judge"; --update keeps both). Refreshing is
done on purpose, never automatically: after an intended change of speed (a faster kernel: tighten; an
accepted slowdown: say why), after changing BM_ReferenceLoop, the benchmark system or SUBSET, or to add a
kind of CPU CI now runs on. --update replaces this kind's entry and keeps the others. Run, from the
repository root, on the machine kind in question and with the machine otherwise as quiet as it can be:

    python3 bench/perf_check.py --bench build/bin/debris_bench --update

then run the check two or three times to see the spread, and commit perf_baseline.json with a note.

A regression must be seen again: a benchmark below its limit is measured again (--confirm more runs, 2 by
default) and fails the check only when every run puts it below the limit. On the 2-core AMD EPYC CI machine
kind no baseline carries: the memory-bound passes switch between a fast and a slow mode that lasts minutes
(other tenants of the host share its caches and memory; the reference loop, bound by a sqrt chain, hardly
moves): measured 2026-12-01 on a quiet guest, BM_Step's CPU-time ratio was 0.0134 in one check and
0.0084-0.0099 in fifteen runs over the next five minutes (-26% to -37%); BM_CohesivePass 0.0127 against
0.0085-0.0098. A reference with a 12 MiB gather did not track the modes either. A tolerance wide enough for
both modes (0.45) let a 40% slowdown pass, so that kind is judged A/B ("judge": "ab"): the two builds' runs
are seconds apart, in the same mode.

Exit status: 0 passed (or baseline written), 1 regression, 2 could not run, parse or find a baseline.
Python 3 standard library only.
"""
import argparse
import datetime
import json
import os
import platform
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
DEFAULT_BENCH = os.path.join(REPO, "build", "bin", "debris_bench")
DEFAULT_BASELINE = os.path.join(HERE, "perf_baseline.json")

TIME_UNITS = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}

REFERENCE = "BM_ReferenceLoop/real_time"
SUBSET = [
    "BM_CohesivePass/N:32000/threads:1/real_time",
    "BM_Step/N:32000/threads:1/real_time",
    "BM_PdBondPasses/threads:1/real_time",
    "BM_PdStep/threads:1/real_time",
]
# Fail below baseline * (1 - TOLERANCE): a benchmark 25% slower (its time x 1.25, its ratio x 0.80) fails with
# room to spare, and unchanged code passes (measured A/B on an AMD EPYC guest at load 5-7: medians of the paired
# ratios 0.95-1.11 for identical builds, 0.76-0.79 for a PeriDEM step or bond step made to take 25% longer).
TOLERANCE = 0.15


def run_benchmarks(bench, repetitions, min_time, timeout):
    names = SUBSET + [REFERENCE]
    pattern = "^(" + "|".join(re.escape(n) for n in names) + ")$"
    cmd = [
        bench,
        "--benchmark_filter=" + pattern,
        "--benchmark_repetitions=%d" % repetitions,
        "--benchmark_report_aggregates_only=true",
        "--benchmark_enable_random_interleaving=true",
        "--benchmark_min_time=%g" % min_time,
        "--benchmark_format=json",
    ]
    print("running: " + " ".join(cmd), flush=True)
    try:
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=timeout)
    except (FileNotFoundError, PermissionError):
        fail(2, "cannot run '%s' (build the debris_bench target, or pass --bench PATH)" % bench)
    except subprocess.TimeoutExpired:
        fail(2, "debris_bench ran longer than %d s" % timeout)
    if proc.returncode != 0:
        sys.stderr.write(proc.stderr)
        fail(2, "debris_bench exited with status %d" % proc.returncode)
    try:
        report = json.loads(proc.stdout)
    except json.JSONDecodeError as e:
        sys.stderr.write(proc.stdout[-2000:])
        fail(2, "could not parse the JSON output of debris_bench: %s" % e)
    medians, cvs, cpu_rates = {}, {}, {}
    for b in report.get("benchmarks", []):
        if b.get("run_type") != "aggregate":
            continue
        if b.get("error_occurred"):
            fail(2, "%s: %s" % (b.get("run_name"), b.get("error_message")))
        if b.get("aggregate_name") == "median":
            medians[b["run_name"]] = float(b["items_per_second"])
            # Items per CPU-second of the benchmark thread, for information (1-thread benchmarks only: it
            # leaves out the time the thread was not running). Items per iteration = items/s * real time,
            # exact for the median of an odd number of repetitions.
            scale = TIME_UNITS.get(b.get("time_unit"), float("nan"))
            items = medians[b["run_name"]] * float(b["real_time"]) * scale
            cpu_rates[b["run_name"]] = items / (float(b["cpu_time"]) * scale)
        elif b.get("aggregate_name") == "cv":
            cvs[b["run_name"]] = float(b.get("items_per_second", float("nan")))
    missing = [n for n in names if n not in medians]
    if missing:
        fail(2, "debris_bench reported no median items/s for: %s (were the benchmarks renamed? update SUBSET)"
             % ", ".join(missing))
    return medians, cvs, cpu_rates, report.get("context", {})


def fail(status, message):
    sys.stderr.write("perf_check: %s\n" % message)
    sys.exit(status)


def git(*args):
    try:
        return subprocess.run(["git", "-C", REPO] + list(args), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                              text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.TimeoutExpired):
        return ""


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def isa_level():
    """x86-64 micro-architecture level from the CPU flags: which clone of the vectorised kernels runs."""
    try:
        with open("/proc/cpuinfo") as f:
            flags = next((l.split(":", 1)[1].split() for l in f if l.startswith("flags")), [])
    except OSError:
        return "unknown"
    if all(x in flags for x in ("avx512f", "avx512bw", "avx512cd", "avx512dq", "avx512vl")):
        return "x86-64-v4"
    if all(x in flags for x in ("avx2", "fma", "bmi2")):
        return "x86-64-v3"
    return "x86-64"


def baseline_entries(document):
    """The per-CPU-kind baselines of a baseline file; a file of the first format (one baseline at the top
    level) reads as a list of one."""
    if not isinstance(document, dict):
        raise ValueError("the top level is not an object")
    entries = document["baselines"] if "baselines" in document else ([document] if "ratios" in document else [])
    if not isinstance(entries, list):
        raise ValueError("'baselines' is not a list")
    for k, e in enumerate(entries):
        if not isinstance(e, dict) or not isinstance(e.get("recorded", {}), dict):
            raise ValueError("baseline %d is not an object with a 'recorded' object" % k)
    return entries


def kind_of(entry):
    rec = entry.get("recorded", {})
    return (rec.get("cpu"), rec.get("isa"))


def measure(args):
    """One run of the subset: ratios to the reference loop, real and CPU time."""
    medians, cvs, cpu_rates, context = run_benchmarks(args.bench, args.repetitions, args.min_time, args.timeout)
    ref = medians[REFERENCE]
    ratios = {n: medians[n] / ref for n in SUBSET}
    cpu_ratios = {n: cpu_rates[n] / cpu_rates[REFERENCE] for n in SUBSET}
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    commit = git("log", "-1", "--format=%h")
    dirty = bool(git("status", "--short", "--untracked-files=no"))
    print("%s, commit %s%s, load average %.2f %.2f %.2f, %s" % (
        datetime.datetime.now().astimezone().isoformat(timespec="seconds"), commit or "?",
        " (modified)" if dirty else "", load[0], load[1], load[2], cpu_model()))
    print("reference %s: median %.4g items/s (cv %.1f%%)" % (REFERENCE, ref, 100 * cvs.get(REFERENCE, float("nan"))))
    return medians, cvs, cpu_rates, ratios, cpu_ratios, context, commit, dirty, load


def judge(args, base_ratios, ratios, cpu_ratios, cvs):
    """Prints the table of one run; returns the benchmarks below their limit."""
    other_name = "cpu ratio" if args.clock == "real" else "real ratio"
    print("ratios decided on: items per %s second (--clock %s)" % ("real" if args.clock == "real" else "CPU",
                                                                    args.clock))
    print("%-46s %11s %11s %8s %11s %6s %11s  %s" % ("benchmark", "baseline", "measured", "change", "fail below",
                                                     "cv", other_name, "status"))
    measured = ratios if args.clock == "real" else cpu_ratios
    other = cpu_ratios if args.clock == "real" else ratios
    regressions, missing = [], []
    for n in SUBSET:
        cv = 100 * cvs.get(n, float("nan"))
        if n not in base_ratios:
            missing.append(n)
            print("%-46s %11s %11.5g %8s %11s %5.1f%% %11.5g  not in baseline" % (n, "-", measured[n], "-", "-", cv,
                                                                                 other[n]))
            continue
        b = float(base_ratios[n])
        limit = b * (1 - args.tolerance)
        change = measured[n] / b - 1
        if measured[n] < limit:
            status = "REGRESSION"
            regressions.append(n)
        elif change > args.tolerance:
            status = "faster (consider --update)"
        else:
            status = "ok"
        print("%-46s %11.5g %11.5g %+7.1f%% %11.5g %5.1f%% %11.5g  %s" % (n, b, measured[n], 100 * change, limit, cv,
                                                                         other[n], status))
    if missing:
        fail(2, "no baseline ratio for %s: refresh the baseline with --update" % ", ".join(missing))
    return regressions


def judge_ab(args, reason):
    """The build judged against the base commit, side by side (bench/perf_ab.py); its exit status."""
    print("perf_check: %s. So this build is judged against the base commit, side by side (bench/perf_ab.py)."
          % reason, flush=True)
    cmd = [sys.executable, os.path.join(HERE, "perf_ab.py"), "--bench", args.bench]
    cmd += ["--base-bench", args.ab_base_bench] if args.ab_base_bench else []
    cmd += ["--base", args.ab_base] if args.ab_base else []
    cmd += ["--tolerance", "%g" % args.tolerance] if args.tolerance is not None else []
    return subprocess.run(cmd, timeout=3600).returncode


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 epilog="See the comment at the top of this file for when and how to refresh "
                                        "the baseline.")
    ap.add_argument("--bench", default=DEFAULT_BENCH, help="debris_bench executable (default: %(default)s)")
    ap.add_argument("--baseline", default=DEFAULT_BASELINE, help="baseline file (default: %(default)s)")
    ap.add_argument("--tolerance", type=float, default=None,
                    help="fail when ratio < baseline * (1 - tolerance) (default: the baseline entry's 'tolerance', "
                         "else %g; perf_ab.py's when judged A/B)" % TOLERANCE)
    ap.add_argument("--repetitions", type=int, default=5, help="repetitions per benchmark (default: %(default)s)")
    ap.add_argument("--min-time", type=float, default=0.5,
                    help="--benchmark_min_time per repetition, seconds (default: %(default)s)")
    ap.add_argument("--timeout", type=int, default=300, help="seconds before giving up (default: %(default)s)")
    ap.add_argument("--clock", choices=["cpu", "real"], default="cpu",
                    help="which ratio decides: items per CPU-second of the benchmark thread (default; steady "
                         "on a loaded machine) or per real second (flaky when other processes compete)")
    ap.add_argument("--confirm", type=int, default=2,
                    help="measure again up to this many times while a benchmark is below its limit; it fails only "
                         "if below in every run (default: %(default)s)")
    ap.add_argument("--update", action="store_true",
                    help="write the measured ratios to the baseline file instead of checking")
    ap.add_argument("--ab-base", default="",
                    help="where no baseline fits this CPU: the commit perf_ab.py compares with (default: "
                         "bench/perf_base_commit)")
    ap.add_argument("--ab-base-bench", default="",
                    help="where no baseline fits this CPU: an already built base debris_bench for perf_ab.py")
    args = ap.parse_args()
    if args.tolerance is not None and not (0 < args.tolerance < 1):
        fail(2, "--tolerance must be in (0, 1), got %g" % args.tolerance)
    if args.repetitions < 1:
        fail(2, "--repetitions must be >= 1")
    if args.confirm < 0:
        fail(2, "--confirm must be >= 0")

    here = (cpu_model(), isa_level())
    entries = []
    try:
        with open(args.baseline) as f:
            entries = baseline_entries(json.load(f))
    except OSError:
        if not args.update:
            fail(2, "cannot read the baseline %s; create it with --update" % args.baseline)
    except (ValueError, KeyError, TypeError) as e:
        fail(2, "cannot parse the baseline %s (%s); fix or remove it (--update then writes a new one; it never "
                "overwrites a file it cannot read, which may hold other CPU kinds' baselines)" % (args.baseline, e))
    if not args.update:
        # A kernel's speed relative to the reference loop depends on the CPU (and on which vector clone it
        # runs), so each baseline only judges machines of the kind it was recorded on.
        baseline = next((e for e in entries if kind_of(e) == here), None)
        if baseline is None:
            kinds = "; ".join("%s (%s)" % kind_of(e) for e in entries) or "none"
            return judge_ab(args, "no baseline for this kind of CPU, %s (%s); the file has: %s. Ratios are not "
                                  "comparable across CPU kinds. Record a baseline on this kind with --update"
                                  % (here[0], here[1], kinds))
        if baseline.get("judge") == "ab":
            return judge_ab(args, "baselines do not carry on this kind of CPU, %s (%s): %s"
                                  % (here[0], here[1], baseline.get("_judge", "its entry says \"judge\": \"ab\"")))
        lacking = [n for n in SUBSET if n not in baseline.get("cpu_time_ratios", {})
                   or n not in baseline.get("ratios", {})]
        if lacking:
            return judge_ab(args, "the baseline of this kind of CPU, %s (%s), has no ratio for %s (recorded before "
                                  "they were added); refresh it on this kind with --update"
                                  % (here[0], here[1], ", ".join(lacking)))
        if baseline.get("reference", REFERENCE) != REFERENCE:
            fail(2, "the baseline was measured against %s, not %s: refresh it with --update"
                 % (baseline.get("reference"), REFERENCE))
        if args.tolerance is None:
            args.tolerance = float(baseline.get("tolerance", TOLERANCE))
            if not (0 < args.tolerance < 1):
                fail(2, "the baseline's tolerance must be in (0, 1), got %g" % args.tolerance)
        try:
            base_ratios = baseline["ratios" if args.clock == "real" else "cpu_time_ratios"]
        except KeyError as e:
            fail(2, "the baseline for this CPU kind has no %s; refresh it with --update" % e)

    if args.update:
        medians, cvs, cpu_rates, ratios, cpu_ratios, context, commit, dirty, load = measure(args)
        previous = next((e for e in entries if kind_of(e) == here), {})
        entry = {k: previous[k] for k in ("tolerance", "_tolerance", "judge", "_judge") if k in previous}
        entry.update({
            "reference": REFERENCE,
            "ratios": ratios,
            "cpu_time_ratios": cpu_ratios,
            "recorded": {
                "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds"),
                "commit": commit,
                "modified_tree": dirty,
                "host": platform.node(),
                "cpu": cpu_model(),
                "isa": isa_level(),
                "num_cpus": context.get("num_cpus"),
                "load_average": [round(x, 2) for x in load],
                "repetitions": args.repetitions,
                "min_time_s": args.min_time,
                "median_items_per_second": {n: medians[n] for n in SUBSET + [REFERENCE]},
                "cv_items_per_second": {n: cvs.get(n) for n in SUBSET + [REFERENCE]},
            },
        })
        # This CPU kind's entry is replaced; the other kinds' entries are kept.
        kept = [e for e in entries if kind_of(e) != here]
        document = {
            "_comment": "One baseline per CPU kind (cpu model and x86-64 level). ratios: (median items/s) / "
                        "(median items/s of the reference), real time; cpu_time_ratios: the same in items per "
                        "CPU-second (what decides by default). Each measured in one run by bench/perf_check.py "
                        "--update. Refresh on purpose only; see the top of perf_check.py.",
            "baselines": kept + [entry],
        }
        # Written beside it and renamed over it: an interrupted update leaves the old file, with the other
        # kinds' baselines, whole.
        partial = args.baseline + ".partial"
        with open(partial, "w") as f:
            json.dump(document, f, indent=2, sort_keys=False)
            f.write("\n")
        os.replace(partial, args.baseline)
        print("%-46s %12s %8s %12s" % ("benchmark", "ratio", "cv", "cpu ratio"))
        for n in SUBSET:
            print("%-46s %12.5g %7.1f%% %12.5g" % (n, ratios[n], 100 * cvs.get(n, float("nan")), cpu_ratios[n]))
        print("\nwrote %s. Now run the check two or three times (without --update) to see the spread of the "
              "ratios, and commit the file with a note saying why the baseline changed." % args.baseline)
        return 0

    suspects = []
    for attempt in range(1 + args.confirm):
        if attempt:
            print("\nmeasured again (%d of %d) to confirm: %s" % (attempt, args.confirm, ", ".join(suspects)))
        medians, cvs, cpu_rates, ratios, cpu_ratios, context, commit, dirty, load = measure(args)
        below = judge(args, base_ratios, ratios, cpu_ratios, cvs)
        # A benchmark stays a suspect only while every run so far found it below its limit.
        suspects = below if attempt == 0 else [n for n in suspects if n in below]
        if not suspects:
            print("\nperf_check: passed (tolerance %.0f%%%s)" % (
                100 * args.tolerance, ", after %d confirming run(s)" % attempt if attempt else ""))
            return 0
    print("\nperf_check: FAILED: %d benchmark(s) slower than baseline by more than %.0f%% relative to the "
          "reference loop in all %d runs: %s. If the slowdown is intended, refresh the baseline: python3 "
          "bench/perf_check.py --bench %s --update" % (len(suspects), 100 * args.tolerance, 1 + args.confirm,
                                                      ", ".join(suspects), args.bench))
    return 1


if __name__ == "__main__":
    sys.exit(main())
