#!/usr/bin/env bash
# The device check for a machine with an NVIDIA GPU (issue 12), in one go and well under 8 minutes, because
# device time is scarce (15 minutes per task, start-up included):
#
#   1. builds the nvptx configuration (GCC 12 OpenMP offload), unless $BUILD already holds it (build it on
#      the host beforehand and carry it: `cmake -S . -B build-nvptx -DDEBRIS_OFFLOAD=nvptx
#      -DDEBRIS_PARAVIEW_TEST=OFF && cmake --build build-nvptx -j2`);
#   2. proves the kernels run on the GPU (GCC falls back to the host silently even under MANDATORY, so the
#      first line of a debris_dem run, which asks a target region where it ran, must say "GPU");
#   3. runs the offload test subset with OMP_TARGET_OFFLOAD=MANDATORY: the DEM and PeriDEM models, which
#      are device-resident, the same selection as .ci/run's hostdevice stage;
#   4. runs the device benchmarks (the whole DEM step, the full-list contact pass, the neighbour build and
#      the rebuild at N = 4,000, 32,000 and 256,000) and writes one table, gpu_check_out/table.md, with the
#      GPU, the driver and each benchmark's rate.
#
# Usage: bash bench/gpu_check.sh   (BUILD=build-nvptx OUT=gpu_check_out by default). Exit 2: no GPU or no
# build; 1: kernels fell back to the host or a test failed. Each step is time-limited so the whole stays
# under 8 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build-nvptx}
OUT=${OUT:-gpu_check_out}
mkdir -p "$OUT"
say() { echo "gpu_check ($((SECONDS / 60)) min $((SECONDS % 60)) s): $*"; }

if ! gpu=$(nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader 2>/dev/null); then
  say "no NVIDIA GPU here (nvidia-smi failed): nothing to check"
  exit 2
fi
say "GPU: $gpu"

if [ ! -x "$BUILD/bin/debris_dem" ] || [ ! -x "$BUILD/bin/debris_bench" ]; then
  say "building the nvptx configuration in $BUILD"
  timeout 300 bash -c "cmake -S . -B '$BUILD' -DDEBRIS_OFFLOAD=nvptx -DDEBRIS_PARAVIEW_TEST=OFF >/dev/null &&
                       cmake --build '$BUILD' -j\$(nproc) >/dev/null" || { say "the build failed or took over 5 min"; exit 2; }
fi

export OMP_TARGET_OFFLOAD=MANDATORY
say "where the kernels run"
timeout 60 "$BUILD/bin/debris_dem" -i scenarios/dem/default.yaml -o "$OUT/dem_default" --threads 1 >"$OUT/dem_default.log" 2>&1 ||
  { say "debris_dem failed on the GPU:"; tail -20 "$OUT/dem_default.log"; exit 1; }
head -1 "$OUT/dem_default.log"
grep -q "kernels run on GPU" "$OUT/dem_default.log" || { say "kernels fell back to the host"; exit 1; }

say "offload tests (MANDATORY)"
# The selection of .ci/run's hostdevice stage: the long runs are left out (PeriDEM runs: device-resident).
test_status=0
timeout 180 ctest --test-dir "$BUILD" -j4 --output-on-failure \
  -E 'EnergyIsConserved|StabilityAtTheCriticalTimeStep|DefaultInputRuns|^Patch|Amorphous|RestitutionCli|StagedRun|WearJunction|CarveCli|PerfCheck|paraview' \
  >"$OUT/ctest.log" 2>&1 || test_status=1
grep -E "tests passed|tests failed" "$OUT/ctest.log" || true

say "device benchmarks"
timeout 150 "$BUILD/bin/debris_bench" \
  --benchmark_filter='BM_(Step|CohesivePassFullList|NeighborBuild|Rebuild)/N:[0-9]+/threads:1/' \
  --benchmark_min_time=0.3 --benchmark_format=json --benchmark_out="$OUT/bench.json" >/dev/null 2>"$OUT/bench.log" ||
  say "the benchmarks failed or ran over 150 s (what finished is in $OUT/bench.json)"

python3 - "$OUT/bench.json" "$gpu" "$test_status" >"$OUT/table.md" <<'EOF'
import json, sys
path, gpu, tests = sys.argv[1], sys.argv[2], sys.argv[3]
try:
    runs = json.load(open(path)).get("benchmarks", [])
except (OSError, ValueError):
    runs = []
print(f"GPU: {gpu}; offload tests: {'passed' if tests == '0' else 'FAILED (see ctest.log)'}\n")
print("| benchmark | N | items/s | real time per iteration |")
print("|---|---|---|---|")
for r in runs:
    if r.get("run_type") == "aggregate":
        continue
    parts = r["name"].split("/")
    n = next((p[2:] for p in parts if p.startswith("N:")), "")
    rate = r.get("items_per_second", 0.0)
    print(f"| {parts[0]} | {n} | {rate / 1e6:.2f} M | {r['real_time']:.3g} {r['time_unit']} |")
EOF
cat "$OUT/table.md"
say "done; files in $OUT/"
exit $test_status
