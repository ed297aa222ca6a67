#!/usr/bin/env bash
# Runs the GPU engine's device tests and measurements on the device machine
# (docs/GPU.md "Performance"). The binaries are built on a machine with nvcc
# (cmake -DCMAKE_BUILD_TYPE=Release -DLOCKSTEP_BUILD_BENCH=ON; targets
# gpu_device_tests gpu_tests gpu_bench lockstep) and copied to $BIN. Writes
# its results under $OUT.
#   gpu/bench/run_device.sh [BIN] [SIZES]
# QUICK=1: only the awake and asleep piles of SIZES (default 10^6) with the
# stage breakdown, for each of the comma-separated binary folders in BIN
# (each holding a gpu_bench): versions compared in one call.
# CPU_SIZES (default 10000,100000): the CPU engines' sizes in the full run
# ("" for none). SOLVERS (default "coloured jacobi"): the pair solvers the
# full run measures (gpu_bench --solver), the CPU engines with the first.
# MODEL (default oriented_box): the pile's pair model (gpu_bench --model).
# ACCURACY=1: also `lockstep accuracy` with the gpu and gpu-jacobi columns
# through CUDA (docs/accuracy/h100). NCU=0: no Nsight Compute pass; NCU=detail: also the
# speed-of-light, occupancy, memory, scheduler, instruction, warp-state and
# source-counter sections of the first NCU_COUNT (4) of the gather, contact,
# solver and correction kernels (the last folder's gpu_bench).
set -u
BIN=${1:-build-gpu-carry}
OUT=${OUT:-/tmp/lockstep-gpu-out}
mkdir -p "$OUT"
ncu_pass() {  # $1: folder with gpu_bench
  command -v ncu > /dev/null || return 0
  [ "${NCU:-1}" = 0 ] && return 0
  echo "== ncu: DRAM bytes per kernel, one frame of the 10^6-cube pile ($1)"
  timeout 300 ncu --profile-from-start off --metrics dram__bytes_read.sum,dram__bytes_write.sum,gpu__time_duration.sum \
    --csv "$1/gpu_bench" --model "${MODEL:-oriented_box}" --profile 1000000 > "$OUT/ncu.csv" 2> "$OUT/ncu.err"
  echo "ncu rc=$?"; tail -3 "$OUT/ncu.err"
  if [ "${NCU:-1}" = detail ]; then
    timeout 400 ncu --profile-from-start off --kernel-name-base demangled \
      -k 'regex:GatherK|ContactsK|SolveK|CorrectIntegrateK' --launch-count "${NCU_COUNT:-4}" \
      --section SpeedOfLight --section Occupancy --section MemoryWorkloadAnalysis --section WarpStateStats \
      --section SchedulerStats --section InstructionStats --section LaunchStats --section SourceCounters \
      "$1/gpu_bench" --model "${MODEL:-oriented_box}" --profile 1000000 > "$OUT/ncu_detail.txt" 2>&1
    echo "ncu detail rc=$?"
  fi
}

if [ "${QUICK:-0}" = 1 ]; then
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm,clocks.max.sm,clocks.mem --format=csv
  SIZES=${2:-1000000}
  last=""
  for dir in ${BIN//,/ }; do
    echo "== $dir"
    "$dir/gpu_bench" --model "${MODEL:-oriented_box}" --sizes "$SIZES" --cpu-sizes "" --sleep-size 0 2>&1 | tee "$OUT/quick_$(basename "$dir").txt"
    last=$dir
  done
  ncu_pass "$last"
  exit 0
fi
SIZES=${2:-10000,100000,1000000,10000000}
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
cpu=${CPU_SIZES-10000,100000}
for solver in ${SOLVERS:-coloured jacobi}; do
  echo "== benchmark, $solver pair solver"
  "$BIN/gpu_bench" --model "${MODEL:-oriented_box}" --solver "$solver" --sizes "$SIZES" --cpu-sizes "$cpu" --json "$OUT/bench_$solver.json" 2>&1 \
    | tee "$OUT/bench_$solver.txt"
  cpu=""
done
ncu_pass "$BIN"
if [ "${ACCURACY:-0}" = 1 ]; then
  echo "== accuracy versus time"
  "$BIN/lockstep" accuracy --engines fixed,float,double,mp,gpu,gpu-jacobi --out "$OUT/accuracy" --quiet \
    --machine "$(nvidia-smi --query-gpu=name --format=csv,noheader) (gpu columns through CUDA), host CPU of the device machine for the CPU engines" \
    --date "$(date -u +%F)" > "$OUT/accuracy.log" 2>&1
  echo "accuracy rc=$?"
fi
