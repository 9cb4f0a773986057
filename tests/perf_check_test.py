#!/usr/bin/env python3
"""Test of bench/perf_check.py against a fake debris_bench: per-CPU-kind baselines, --update, the checks.

The fake benchmark is a small Python script that ignores its arguments and prints Google-Benchmark-style
JSON (median and cv aggregates of perf_check.SUBSET and perf_check.REFERENCE) with rates read from
rates.json beside it, so each test chooses the speeds perf_check sees. No real benchmark runs.

Usage: python3 tests/perf_check_test.py [path/to/bench/perf_check.py] [unittest options]
Python 3 standard library only.
"""
import json
import os
import shutil
import stat
import subprocess
import sys
import tempfile
import unittest

if len(sys.argv) > 1 and sys.argv[1].endswith(".py"):
    SCRIPT = os.path.abspath(sys.argv.pop(1))
else:
    SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench", "perf_check.py")

sys.dont_write_bytecode = True  # leave no bench/__pycache__ in the source tree
sys.path.insert(0, os.path.dirname(SCRIPT))
import perf_check  # noqa: E402  (cpu_model, isa_level, SUBSET, REFERENCE)

SUBSET = list(perf_check.SUBSET)
REFERENCE = perf_check.REFERENCE
HERE_KIND = (perf_check.cpu_model(), perf_check.isa_level())
REPOSITORY_BASELINE = perf_check.DEFAULT_BASELINE  # bench/perf_baseline.json beside the script
FOREIGN_KIND = ("Foreign Test CPU 9000 (not this machine)", "x86-64-v2")
STEP = next(n for n in SUBSET if n.startswith("BM_Step/"))

FAKE_BENCH = r'''#!/usr/bin/env python3
# Fake debris_bench for tests/perf_check_test.py: ignores its arguments, prints Google Benchmark JSON.
import json, os, sys
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "rates.json")) as f:
    spec = json.load(f)
if spec.get("exit_status", 0):
    sys.stderr.write("fake debris_bench: failing on purpose\n")
    sys.exit(spec["exit_status"])
benchmarks = []
for name, r in spec["rates"].items():
    items = r["items_per_iteration"]
    real_ns = items / r["real"] * 1e9
    cpu_ns = items / r["cpu"] * 1e9
    common = {"run_name": name, "run_type": "aggregate", "repetitions": 5, "threads": 1, "time_unit": "ns"}
    benchmarks.append(dict(common, name=name + "_median", aggregate_name="median", iterations=5,
                           real_time=real_ns, cpu_time=cpu_ns, items_per_second=r["real"]))
    benchmarks.append(dict(common, name=name + "_cv", aggregate_name="cv", aggregate_unit="percentage",
                           iterations=5, real_time=0.01, cpu_time=0.01, items_per_second=0.02))
print(json.dumps({"context": {"num_cpus": 2, "library_build_type": "release"}, "benchmarks": benchmarks},
                 indent=2))
'''

# Base rates, items per real second; CPU rates are a bit higher (the thread waited a little).
BASE_RATES = {
    SUBSET[0]: 6.0e6,
    SUBSET[1]: 4.0e6,
    REFERENCE: 4.5e8,
}
if len(SUBSET) > 2:
    for i, n in enumerate(SUBSET[2:]):
        BASE_RATES[n] = 2.0e6 + 1.0e5 * i
CPU_FACTOR = {n: 1.0 + 0.01 * (i + 1) for i, n in enumerate(sorted(BASE_RATES))}


def rates_spec(scale=None, exit_status=0):
    """scale: {name: factor} applied to both the real and the CPU rate of that benchmark."""
    scale = scale or {}
    out = {}
    for n, r in BASE_RATES.items():
        s = scale.get(n, 1.0)
        out[n] = {"real": r * s, "cpu": r * CPU_FACTOR[n] * s,
                  "items_per_iteration": 1.0e6 if n == REFERENCE else 32000.0}
    return {"rates": out, "exit_status": exit_status}


def expected_ratios(spec):
    rates = spec["rates"]
    real = {n: rates[n]["real"] / rates[REFERENCE]["real"] for n in SUBSET}
    cpu = {n: rates[n]["cpu"] / rates[REFERENCE]["cpu"] for n in SUBSET}
    return real, cpu


def make_entry(kind, spec):
    real, cpu = expected_ratios(spec)
    return {"reference": REFERENCE, "ratios": real, "cpu_time_ratios": cpu,
            "recorded": {"cpu": kind[0], "isa": kind[1], "host": "test"}}


class PerfCheckTest(unittest.TestCase):
    def setUp(self):
        self._tmp = tempfile.TemporaryDirectory(prefix="perf_check_test_")
        self.dir = self._tmp.name
        self.bench = os.path.join(self.dir, "fake_debris_bench")
        with open(self.bench, "w") as f:
            f.write(FAKE_BENCH)
        os.chmod(self.bench, os.stat(self.bench).st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
        self.baseline = os.path.join(self.dir, "baseline.json")
        self.set_rates(rates_spec())

    def tearDown(self):
        self._tmp.cleanup()

    def set_rates(self, spec):
        with open(os.path.join(self.dir, "rates.json"), "w") as f:
            json.dump(spec, f)

    def write_baseline(self, document):
        with open(self.baseline, "w") as f:
            json.dump(document, f)

    def read_baseline(self):
        with open(self.baseline) as f:
            return json.load(f)

    def run_check(self, *extra):
        cmd = [sys.executable, SCRIPT, "--bench", self.bench, "--baseline", self.baseline,
               "--repetitions", "1", "--min-time", "0.01", "--timeout", "30"] + list(extra)
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
        return proc.returncode, proc.stdout

    def assertRatiosEqual(self, got, want, what):
        self.assertEqual(sorted(got), sorted(want), what)
        for n in want:
            self.assertAlmostEqual(got[n] / want[n], 1.0, places=9, msg="%s %s" % (what, n))

    def assertEntryMatches(self, entry, spec):
        real, cpu = expected_ratios(spec)
        self.assertEqual(entry.get("reference"), REFERENCE)
        self.assertRatiosEqual(entry["ratios"], real, "ratios")
        self.assertRatiosEqual(entry["cpu_time_ratios"], cpu, "cpu_time_ratios")

    # 1. --update with no baseline file, or one without entries: one entry, this CPU kind, ratios = rates / ref.
    def test_update_creates_entry_for_this_kind(self):
        for initial in (None, {"baselines": []}):
            with self.subTest(initial=initial):
                if initial is None:
                    if os.path.exists(self.baseline):
                        os.remove(self.baseline)
                else:
                    self.write_baseline(initial)
                status, out = self.run_check("--update")
                self.assertEqual(status, 0, out)
                doc = self.read_baseline()
                self.assertEqual(len(doc["baselines"]), 1, doc)
                entry = doc["baselines"][0]
                self.assertEqual(perf_check.kind_of(entry), HERE_KIND)
                self.assertEqual((entry["recorded"]["cpu"], entry["recorded"]["isa"]), HERE_KIND)
                self.assertEntryMatches(entry, rates_spec())

    # 2. --update keeps a foreign CPU kind's entry and adds this kind's; a second --update replaces this kind's.
    def test_update_keeps_other_kinds_and_replaces_own(self):
        foreign = make_entry(FOREIGN_KIND, rates_spec({STEP: 3.0}))
        self.write_baseline({"baselines": [foreign]})
        for spec in (rates_spec(), rates_spec({SUBSET[0]: 1.5, STEP: 0.5})):
            with self.subTest(spec=spec):
                self.set_rates(spec)
                status, out = self.run_check("--update")
                self.assertEqual(status, 0, out)
                doc = self.read_baseline()
                self.assertEqual(len(doc["baselines"]), 2, doc)
                self.assertIn(foreign, doc["baselines"])
                own = [e for e in doc["baselines"] if perf_check.kind_of(e) == HERE_KIND]
                self.assertEqual(len(own), 1, doc)
                self.assertEntryMatches(own[0], spec)

    # 3. Same rates as the baseline: passed.
    def test_check_same_rates_passes(self):
        self.write_baseline({"baselines": [make_entry(HERE_KIND, rates_spec())]})
        for clock in ("cpu", "real"):
            with self.subTest(clock=clock):
                status, out = self.run_check("--clock", clock)
                self.assertEqual(status, 0, out)
                self.assertIn("passed", out)
                self.assertNotIn("REGRESSION", out)

    # 3b. The entry of this CPU kind judges, not a foreign one that would fail (listed first).
    def test_check_uses_this_kinds_entry(self):
        foreign = make_entry(FOREIGN_KIND, rates_spec({STEP: 10.0}))
        self.write_baseline({"baselines": [foreign, make_entry(HERE_KIND, rates_spec())]})
        status, out = self.run_check()
        self.assertEqual(status, 0, out)
        self.assertIn("passed", out)

    # 4. The step 40% slower (real and CPU): regression, exit 1, with either clock deciding.
    def test_check_40_percent_slower_fails(self):
        self.write_baseline({"baselines": [make_entry(HERE_KIND, rates_spec())]})
        self.set_rates(rates_spec({STEP: 0.6}))
        for clock in ("cpu", "real"):
            with self.subTest(clock=clock):
                status, out = self.run_check("--clock", clock)
                self.assertEqual(status, 1, out)
                self.assertIn("REGRESSION", out)
                # Seen in the first run and in both confirming runs (--confirm 2 by default).
                step_lines = [l for l in out.splitlines() if l.startswith(STEP)]
                self.assertEqual(len(step_lines), 3, out)
                for line in step_lines:
                    self.assertIn("REGRESSION", line)
                self.assertIn("in all 3 runs", out)
                for n in SUBSET:
                    if n != STEP:
                        self.assertNotIn("REGRESSION", next(l for l in out.splitlines() if l.startswith(n)))

    # 4b. A baseline entry's own tolerance replaces the default: 40% slower passes under 0.45, and
    # --confirm 0 judges on one run.
    def test_entry_tolerance_and_no_confirmation(self):
        entry = make_entry(HERE_KIND, rates_spec())
        entry["tolerance"] = 0.45
        self.write_baseline({"baselines": [entry]})
        self.set_rates(rates_spec({STEP: 0.6}))
        status, out = self.run_check()
        self.assertEqual(status, 0, out)
        self.assertIn("tolerance 45%", out)
        status, out = self.run_check("--tolerance", "0.25", "--confirm", "0")
        self.assertEqual(status, 1, out)
        self.assertEqual(len([l for l in out.splitlines() if l.startswith(STEP)]), 1, out)

    # 5. The step 10% slower: within the default tolerance (0.15), passed.
    def test_check_10_percent_slower_passes(self):
        self.write_baseline({"baselines": [make_entry(HERE_KIND, rates_spec())]})
        self.set_rates(rates_spec({STEP: 0.90}))
        status, out = self.run_check()
        self.assertEqual(status, 0, out)
        self.assertIn("passed", out)
        self.assertNotIn("REGRESSION", out)

    # 6. Only a foreign CPU kind in the file: never skipped; judged A/B against a base build (perf_ab.py),
    #    whatever the foreign entry says.
    def make_base_bench(self, spec):
        base_dir = os.path.join(self.dir, "base")
        os.makedirs(base_dir, exist_ok=True)
        path = os.path.join(base_dir, "fake_debris_bench")
        shutil.copy(self.bench, path)
        with open(os.path.join(base_dir, "rates.json"), "w") as f:
            json.dump(spec, f)
        return path

    def test_check_foreign_kind_only_is_judged_against_the_base(self):
        self.write_baseline({"baselines": [make_entry(FOREIGN_KIND, rates_spec({STEP: 10.0}))]})
        base = self.make_base_bench(rates_spec({STEP: 1.05}))  # 5% faster than this build: noise, passes
        status, out = self.run_check("--ab-base-bench", base)
        self.assertEqual(status, 0, out)
        self.assertNotIn("skipped", out)
        self.assertIn(FOREIGN_KIND[0], out)
        self.assertIn("perf_ab: passed", out)
        self.assertIn("round 5", out)
        self.assertNotIn("REGRESSION", out)

    def test_ab_30_percent_slower_than_the_base_fails(self):
        self.write_baseline({"baselines": [make_entry(FOREIGN_KIND, rates_spec())]})
        base = self.make_base_bench(rates_spec({STEP: 1.0 / 0.7}))  # this build's step 30% slower
        status, out = self.run_check("--ab-base-bench", base)
        self.assertEqual(status, 1, out)
        self.assertIn("REGRESSION", out)
        self.assertIn("perf_ab: FAILED", out)
        self.assertIn("round 9", out)  # measured again before failing
        self.assertIn(STEP, out.split("perf_ab: FAILED")[1])
        # The cohesive pass, unchanged, is not blamed.
        self.assertNotIn(SUBSET[0] if SUBSET[0] != STEP else SUBSET[1], out.split("perf_ab: FAILED")[1])

    def test_ab_base_commit_missing_from_the_clone_exits_2(self):
        self.write_baseline({"baselines": [make_entry(FOREIGN_KIND, rates_spec())]})
        status, out = self.run_check("--ab-base", "0123456789abcdef0123456789abcdef01234567")
        self.assertEqual(status, 2, out)
        self.assertIn("not in this clone", out)

    # 6b. An entry that says "judge": "ab" is judged against the base, whatever its ratios say; --update keeps
    #     the word (and the reason beside it).
    def test_entry_judged_ab_is_judged_against_the_base(self):
        entry = make_entry(HERE_KIND, rates_spec({STEP: 10.0}))  # would fail if its ratios judged
        entry.update({"judge": "ab", "_judge": "modes of the test CPU"})
        self.write_baseline({"baselines": [entry]})
        base = self.make_base_bench(rates_spec())
        status, out = self.run_check("--ab-base-bench", base)
        self.assertEqual(status, 0, out)
        self.assertIn("modes of the test CPU", out)
        self.assertIn("perf_ab: passed", out)
        self.set_rates(rates_spec({STEP: 0.8}))
        status, out = self.run_check("--ab-base-bench", base)
        self.assertEqual(status, 1, out)
        self.assertIn("perf_ab: FAILED", out)
        status, out = self.run_check("--update")
        self.assertEqual(status, 0, out)
        own = self.read_baseline()["baselines"][0]
        self.assertEqual((own.get("judge"), own.get("_judge")), ("ab", "modes of the test CPU"))

    # 6c. An entry recorded before a benchmark joined SUBSET has no ratio for it: judged against the base
    #     (never a pass that skips the new benchmark, nor an exit 2 until someone refreshes that kind).
    def test_entry_without_a_subset_benchmark_is_judged_against_the_base(self):
        entry = make_entry(HERE_KIND, rates_spec())
        for key in ("ratios", "cpu_time_ratios"):
            del entry[key][SUBSET[-1]]
        self.write_baseline({"baselines": [entry]})
        base = self.make_base_bench(rates_spec())
        self.set_rates(rates_spec({SUBSET[-1]: 0.8}))
        status, out = self.run_check("--ab-base-bench", base)
        self.assertEqual(status, 1, out)
        self.assertIn("has no ratio for " + SUBSET[-1], out)
        self.assertIn(SUBSET[-1], out.split("perf_ab: FAILED")[1])

    # 6d. PeriDEM is checked too: its whole step and its bond passes (the sweeps), on 1 thread.
    def test_subset_has_the_peridem_step_and_bond_passes(self):
        for name in ("BM_PdStep/threads:1/real_time", "BM_PdBondPasses/threads:1/real_time"):
            self.assertIn(name, SUBSET)

    # 6e. On every CPU kind of the repository's baseline file, and on a kind it does not have, each benchmark
    #     of SUBSET taking 25% longer (ratio 0.80) fails the check, and unchanged speeds pass. Each kind is
    #     played by this machine: its entry's policy (tolerance, judge, which ratios it holds) is kept, its
    #     ratios are the fake benchmark's.
    def test_25_percent_slower_fails_on_every_cpu_kind(self):
        with open(REPOSITORY_BASELINE) as f:
            kinds = perf_check.baseline_entries(json.load(f))
        self.assertGreaterEqual(len(kinds), 2, "the repository's baseline file has baselines for an AMD and an Intel CPU")
        real, cpu = expected_ratios(rates_spec())
        base = self.make_base_bench(rates_spec())
        for kind in kinds + [None]:
            name = "a kind without an entry" if kind is None else "%s (%s)" % perf_check.kind_of(kind)
            document = {"baselines": []}
            if kind is not None:
                entry = {k: v for k, v in kind.items() if k not in ("ratios", "cpu_time_ratios", "recorded")}
                entry["recorded"] = {"cpu": HERE_KIND[0], "isa": HERE_KIND[1], "host": "test"}
                for key, ratios in (("ratios", real), ("cpu_time_ratios", cpu)):
                    if key in kind:
                        entry[key] = {n: ratios[n] for n in kind[key] if n in ratios}
                document["baselines"].append(entry)
            self.write_baseline(document)
            with self.subTest(kind=name, speed="unchanged"):
                self.set_rates(rates_spec())
                status, out = self.run_check("--ab-base-bench", base)
                self.assertEqual(status, 0, out)
                self.assertNotIn("REGRESSION", out)
            with self.subTest(kind=name, speed="every benchmark 25% slower"):
                self.set_rates(rates_spec({n: 0.8 for n in SUBSET}))
                status, out = self.run_check("--ab-base-bench", base)
                self.assertEqual(status, 1, out)
                verdict = out.rsplit("perf_check: FAILED", 1)[-1].rsplit("perf_ab: FAILED", 1)[-1]
                for n in SUBSET:
                    self.assertIn(n, verdict, out)

    # 7. Old format (one entry at the top level, this CPU kind) is still read; and still judges.
    def test_old_format_is_read(self):
        old = make_entry(HERE_KIND, rates_spec())
        old["_comment"] = "first format: one baseline at the top level"
        self.write_baseline(old)
        status, out = self.run_check()
        self.assertEqual(status, 0, out)
        self.assertIn("passed", out)
        self.assertNotIn("skipped", out)
        self.set_rates(rates_spec({STEP: 0.6}))
        status, out = self.run_check()
        self.assertEqual(status, 1, out)
        self.assertIn("REGRESSION", out)

    # 7b. --update on an old-format file of this kind rewrites it in the new format with one entry.
    def test_update_converts_old_format(self):
        self.write_baseline(make_entry(HERE_KIND, rates_spec({STEP: 2.0})))
        status, out = self.run_check("--update")
        self.assertEqual(status, 0, out)
        doc = self.read_baseline()
        self.assertEqual(len(doc["baselines"]), 1, doc)
        self.assertEntryMatches(doc["baselines"][0], rates_spec())

    # 8. The benchmark executable fails: exit 2, for the check and for --update (file left alone).
    def test_bench_failure_exits_2(self):
        document = {"baselines": [make_entry(HERE_KIND, rates_spec())]}
        self.write_baseline(document)
        self.set_rates(rates_spec(exit_status=3))
        for extra in ((), ("--update",)):
            with self.subTest(extra=extra):
                status, out = self.run_check(*extra)
                self.assertEqual(status, 2, out)
                self.assertIn("status 3", out)
                self.assertEqual(self.read_baseline(), document)

    # 8a. A malformed or unreadable baseline file: exit 2 (not 1, the status of a regression), for the check
    # and for --update, which never overwrites a file it cannot read.
    def test_malformed_baseline_exits_2(self):
        self.set_rates(rates_spec())
        for text in ('{"baselines": [1]}', '{"baselines": {"a": 1}}', '[]', '', '{"baselines": [{"recorded": 3}]}'):
            for extra in ((), ("--update",)):
                with self.subTest(text=text, extra=extra):
                    with open(self.baseline, "w") as f:
                        f.write(text)
                    status, out = self.run_check(*extra)
                    self.assertEqual(status, 2, out)
                    self.assertIn("cannot parse the baseline", out)
                    with open(self.baseline) as f:
                        self.assertEqual(f.read(), text)

    # 8b. A bench path that does not exist: exit 2.
    def test_missing_bench_exits_2(self):
        self.write_baseline({"baselines": [make_entry(HERE_KIND, rates_spec())]})
        self.bench = os.path.join(self.dir, "no_such_bench")
        status, out = self.run_check()
        self.assertEqual(status, 2, out)


if __name__ == "__main__":
    unittest.main(verbosity=2)
