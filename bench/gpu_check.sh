#!/usr/bin/env bash
# The device check for a machine with an NVIDIA GPU (the OpenMP offload build), in one go and well under
# 8 minutes, because device time is scarce (15 minutes per task, start-up included):
#
#   1. builds the nvptx configuration (GCC 12 OpenMP offload), unless $BUILD already holds it (build it on
#      the host beforehand and carry it: `cmake -S . -B build-nvptx -DDEBRIS_OFFLOAD=nvptx
#      -DDEBRIS_PARAVIEW_TEST=OFF && cmake --build build-nvptx -j2`);
#   2. proves the kernels run on the GPU (GCC falls back to the host silently even under MANDATORY, so the
#      first line of a debris_dem run, which asks a target region where it ran, must say "GPU");
#   3. runs the offload test subset with OMP_TARGET_OFFLOAD=MANDATORY: the DEM and PeriDEM models, which
#      are device-resident, the same selection as .ci/run's hostdevice stage;
#   4. runs the device benchmarks (the whole DEM step, the full-list contact pass, the neighbour build and
#      the rebuild at N = 256,000, 1,048,576, 4,000,000 and 16,384,000: FCC boxes of 4 c^3), then the
#      PeriDEM step on the 502-grain deck tiled 4 x 4 and 8 x 8 times (1.0 M and 4.0 M nodes, PD_TILES), and
#      writes one table, gpu_check_out/table.md, with the GPU, the driver and each benchmark's rate.
#
# Usage: bash bench/gpu_check.sh   (BUILD=build-nvptx OUT=gpu_check_out by default). Exit 2: no GPU or no
# build; 1: kernels fell back to the host or a test failed. Each step is time-limited so the whole stays
# under 8 minutes.
#
# Rehearsal without a GPU: REHEARSAL=1 bash bench/gpu_check.sh runs every step the same way on the
# hostdevice build (BUILD=build-hostdevice by default; build it with -DDEBRIS_OFFLOAD=hostdevice and clang 19,
# benchmarks on), where the host CPU is a device with its own memory, at small sizes (BENCH_SIZES, default
# 4000,32000; PD_TILES 1): so the first GPU run is not the script's first run.
set -euo pipefail
cd "$(dirname "$0")/.."
REHEARSAL=${REHEARSAL:-0}
if [ "$REHEARSAL" = 1 ]; then
  BUILD=${BUILD:-build-hostdevice}
  BENCH_SIZES=${BENCH_SIZES:-4000,32000}
  TEST_SECONDS=${TEST_SECONDS:-900}  # the host CPU runs the device's kernels: the test subset takes minutes
  BENCH_SECONDS=${BENCH_SECONDS:-120}
  BENCH_BUDGET=${BENCH_BUDGET:-600}
  PD_TILES=${PD_TILES:-1}
  PD_SECONDS=${PD_SECONDS:-240}
  PD_BUDGET=${PD_BUDGET:-300}
  device_line="the host CPU as a separate-memory device"
else
  BUILD=${BUILD:-build-nvptx}
  BENCH_SIZES=${BENCH_SIZES:-256000,1048576,4000000,16384000}
  TEST_SECONDS=${TEST_SECONDS:-150}
  BENCH_SECONDS=${BENCH_SECONDS:-45}
  BENCH_BUDGET=${BENCH_BUDGET:-140}
  PD_TILES=${PD_TILES:-4,8}
  PD_SECONDS=${PD_SECONDS:-100}  # set-up (placing, bonds: on the host) + 100 warm-up steps + the timed steps
  PD_BUDGET=${PD_BUDGET:-120}
  device_line="GPU"
fi
OUT=${OUT:-gpu_check_out}
mkdir -p "$OUT"
say() { echo "gpu_check ($((SECONDS / 60)) min $((SECONDS % 60)) s): $*"; }

if [ "$REHEARSAL" = 1 ]; then
  gpu="none: rehearsal on $BUILD ($device_line)"
  [ -x "$BUILD/bin/debris_dem" ] && [ -x "$BUILD/bin/debris_bench" ] ||
    { say "rehearsal: no hostdevice build with benchmarks in $BUILD"; exit 2; }
elif ! gpu=$(nvidia-smi --query-gpu=name,memory.total,driver_version --format=csv,noheader 2>/dev/null); then
  say "no NVIDIA GPU here (nvidia-smi failed): nothing to check (REHEARSAL=1 rehearses on the hostdevice build)"
  exit 2
fi
say "device: $gpu"

if [ ! -x "$BUILD/bin/debris_dem" ] || [ ! -x "$BUILD/bin/debris_bench" ]; then
  say "building the nvptx configuration in $BUILD"
  timeout 300 bash -c "cmake -S . -B '$BUILD' -DDEBRIS_OFFLOAD=nvptx -DDEBRIS_PARAVIEW_TEST=OFF >/dev/null &&
                       cmake --build '$BUILD' -j\$(nproc) >/dev/null" || { say "the build failed or took over 5 min"; exit 2; }
fi

export OMP_TARGET_OFFLOAD=MANDATORY
say "where the kernels run"
timeout 60 "$BUILD/bin/debris_dem" -i scenarios/dem/hcp_wall_load.yaml -o "$OUT/dem_default" --threads 1 >"$OUT/dem_default.log" 2>&1 ||
  { say "debris_dem failed on the device:"; tail -20 "$OUT/dem_default.log"; exit 1; }
head -1 "$OUT/dem_default.log"
grep -q "kernels run on $device_line" "$OUT/dem_default.log" || { say "kernels fell back to the host"; exit 1; }

say "offload tests (MANDATORY)"
# The selection of .ci/run's hostdevice stage: tests/offload_excluded_tests.txt (both models run: they are
# device-resident).
test_status=0
timeout "$TEST_SECONDS" ctest --test-dir "$BUILD" -j4 --output-on-failure \
  -E "$(bash tests/offload_excluded.sh)" \
  >"$OUT/ctest.log" 2>&1 || test_status=1
grep -E "tests passed|tests failed" "$OUT/ctest.log" || true

say "device benchmarks"
# One process per benchmark and size, each time-limited, so a size that does not fit or runs long costs only
# its own row; no new one starts once the benchmarks have had BENCH_BUDGET seconds in all.
: >"$OUT/bench.log"
bench_start=$SECONDS
for n in ${BENCH_SIZES//,/ }; do
  for b in Step CohesivePassFullList NeighborBuild Rebuild; do
    if [ $((SECONDS - bench_start)) -ge "$BENCH_BUDGET" ]; then
      say "benchmark budget ($BENCH_BUDGET s) spent: BM_$b at N = $n and after not run"
      break 2
    fi
    DEBRIS_BENCH_SIZES=$n timeout "$BENCH_SECONDS" "$BUILD/bin/debris_bench" \
      --benchmark_filter="BM_$b/N:$n/threads:1/" --benchmark_min_time=0.3 --benchmark_format=json \
      --benchmark_out="$OUT/bench_${b}_$n.json" >/dev/null 2>>"$OUT/bench.log" ||
      say "BM_$b at N = $n failed or ran over $BENCH_SECONDS s"
  done
done

# The PeriDEM step on the tiled deck (bench_peridem.cpp, BM_PdStepTiled): one process per tiling.
pd_start=$SECONDS
for k in ${PD_TILES//,/ }; do
  if [ $((SECONDS - pd_start)) -ge "$PD_BUDGET" ]; then
    say "PeriDEM budget ($PD_BUDGET s) spent: BM_PdStepTiled at $k x $k tiles and after not run"
    break
  fi
  DEBRIS_PD_TILES=$k timeout "$PD_SECONDS" "$BUILD/bin/debris_bench" \
    --benchmark_filter="BM_PdStepTiled/tiles_per_side:$k/threads:1/" --benchmark_min_time=0.3 --benchmark_format=json \
    --benchmark_out="$OUT/bench_PdStepTiled_$k.json" >/dev/null 2>>"$OUT/bench.log" ||
    say "BM_PdStepTiled at $k x $k tiles failed or ran over $PD_SECONDS s"
done

python3 - "$OUT" "$gpu" "$test_status" >"$OUT/table.md" <<'EOF'
import glob, json, os, sys
out, gpu, tests = sys.argv[1], sys.argv[2], sys.argv[3]
runs = []
for path in sorted(glob.glob(os.path.join(out, "bench_*.json")), key=os.path.getmtime):
    try:
        runs += json.load(open(path)).get("benchmarks", [])
    except (OSError, ValueError):
        pass  # killed by its time limit: no row
print(f"GPU: {gpu}; offload tests: {'passed' if tests == '0' else 'FAILED (see ctest.log)'}\n")
print("| benchmark | N (particles or nodes) | items/s | real time per iteration | bytes per particle or node on the device | transfers per step |")
print("|---|---|---|---|---|---|")
for r in runs:
    if r.get("run_type") == "aggregate":
        continue
    parts = r["name"].split("/")
    n = next((p[2:] for p in parts if p.startswith("N:")), "") or f"{r.get('nodes', 0):.0f}"
    rate = r.get("items_per_second", 0.0)
    moved = r.get("transfer_bytes_per_step")
    moved_text = "" if moved is None else f"{moved:.3g} B ({100 * r.get('transfer_share', 0):.2g}% of the time)"
    print(f"| {parts[0]} | {n} | {rate / 1e6:.2f} M | {r['real_time']:.3g} {r['time_unit']} | "
          f"{r.get('bytes_per_particle', r.get('bytes_per_node', 0)):.0f} | {moved_text} |")
EOF
cat "$OUT/table.md"
say "done; files in $OUT/"
exit $test_status
