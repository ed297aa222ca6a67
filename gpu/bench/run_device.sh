#!/usr/bin/env bash
# Runs the GPU engine's device tests and measurements on the device machine
# (docs/GPU.md "Performance"). The binaries are built on a machine with nvcc
# (cmake -DCMAKE_BUILD_TYPE=Release; targets gpu_device_tests gpu_tests
# gpu_bench lockstep) and copied to $BIN. Writes its results under $OUT.
#   gpu/bench/run_device.sh [BIN] [SIZES]
set -u
BIN=${1:-build-gpu-carry}
SIZES=${2:-10000,100000,1000000,10000000}
OUT=${OUT:-/tmp/lockstep-gpu-out}
mkdir -p "$OUT"
{
  date -u
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm,clocks.mem --format=csv
  "$BIN/lockstep" run drop --engine gpu --out - --quiet > /dev/null && echo "lockstep run --engine gpu: ok"
  "$BIN/lockstep" run drop --engine gpu --out /dev/null --no-progress 2>&1 | tail -2
} > "$OUT/info.txt" 2>&1
cat "$OUT/info.txt"
echo "== tests (label gpu, then the host build's)"
"$BIN/gpu_device_tests" > "$OUT/device_tests.txt" 2>&1; echo "device tests rc=$?"
grep -E "^\[  (PASSED|FAILED|  OK|SKIPPED)|Failure|Which is|actual" "$OUT/device_tests.txt" | head -40
"$BIN/gpu_tests" > "$OUT/host_tests.txt" 2>&1; echo "host-build tests rc=$?"; tail -1 "$OUT/host_tests.txt"
echo "== benchmark"
"$BIN/gpu_bench" --sizes "$SIZES" --cpu-sizes 10000,100000 --json "$OUT/bench.json" 2>&1 | tee "$OUT/bench.txt"
if command -v ncu > /dev/null && [ "${NCU:-1}" = 1 ]; then
  echo "== ncu: DRAM bytes per kernel, one frame of the 10^6-cube pile"
  timeout 300 ncu --profile-from-start off --metrics dram__bytes_read.sum,dram__bytes_write.sum,gpu__time_duration.sum \
    --csv "$BIN/gpu_bench" --profile 1000000 > "$OUT/ncu.csv" 2> "$OUT/ncu.err"
  echo "ncu rc=$?"; tail -3 "$OUT/ncu.err"
fi
