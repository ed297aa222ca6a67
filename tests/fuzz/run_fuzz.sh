#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, -DLOCKSTEP_FUZZ=ON) and fuzzes the scene
# loader and the snapshot loader for SECONDS seconds in all (docs/FUZZING.md):
# two thirds of the time to scene_fuzz, the rest to snapshot_fuzz:
#   tests/fuzz/run_fuzz.sh SECONDS [BUILD_DIR]
# BUILD_DIR defaults to build-fuzz (in the repository root); the CMake source
# directory is the repository root unless LOCKSTEP_FUZZ_SOURCE names another
# top level that adds tests/fuzz. Needs clang++ and
# libFuzzer (Debian: clang-14 and libclang-rt-14-dev), CMake, and the
# libraries of a normal build (nlohmann-json3-dev, libboost-dev, libgtest-dev,
# librapidcheck-dev: the whole project is configured). Seeds: tests/fuzz/corpus,
# tests/data/bad_scenes, tests/data/hard, tests/data/scenes; the run's corpus
# grows in BUILD_DIR/fuzz-corpus (the repository's corpus is not touched) and
# anything found is written to BUILD_DIR/fuzz-artifacts. Exits 0 when the run
# ends with no finding, non-zero otherwise (crash, sanitizer report, timeout,
# out-of-memory). The snapshot fuzzer's seeds are tests/fuzz/snapshot_corpus;
# its corpus grows in BUILD_DIR/snapshot-fuzz-corpus.
set -euo pipefail

seconds=${1:?usage: run_fuzz.sh SECONDS [BUILD_DIR]}
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${2:-$root/build-fuzz}
jobs=${LOCKSTEP_FUZZ_BUILD_JOBS:-2}
cxx=${CXX_FOR_FUZZ:-clang++}

source_dir=${LOCKSTEP_FUZZ_SOURCE:-$root}

mkdir -p "$build"
cmake -S "$source_dir" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER="$cxx" \
  -DLOCKSTEP_FUZZ=ON -DLOCKSTEP_BUILD_BENCH=OFF -DLOCKSTEP_CUDA=OFF >"$build/fuzz-configure.log" 2>&1 ||
  { cat "$build/fuzz-configure.log"; exit 1; }
cmake --build "$build" -j "$jobs" --target scene_fuzz snapshot_fuzz
fuzzer=$(find "$build" -name scene_fuzz -type f -perm -u+x | head -n 1)
[ -n "$fuzzer" ] || { echo "run_fuzz.sh: scene_fuzz was not built (is tests/fuzz added by tests/CMakeLists.txt?)" >&2; exit 1; }
snapshot_fuzzer=$(find "$build" -name snapshot_fuzz -type f -perm -u+x | head -n 1)
[ -n "$snapshot_fuzzer" ] || { echo "run_fuzz.sh: snapshot_fuzz was not built" >&2; exit 1; }
scene_seconds=$(( (2 * seconds + 2) / 3 ))
snapshot_seconds=$(( seconds - scene_seconds ))
[ "$snapshot_seconds" -ge 1 ] || snapshot_seconds=1

corpus=$build/fuzz-corpus
artifacts=$build/fuzz-artifacts
mkdir -p "$corpus" "$artifacts"
seeds=()
for d in tests/fuzz/corpus tests/data/bad_scenes tests/data/hard tests/data/scenes; do
  [ -d "$root/$d" ] && seeds+=("$root/$d")
done

# Readable stack traces in reports (Debian: llvm-symbolizer-14 from llvm-14).
symbolizer=$(command -v llvm-symbolizer || command -v llvm-symbolizer-14 || true)
[ -n "$symbolizer" ] && export ASAN_SYMBOLIZER_PATH="$symbolizer"

echo "run_fuzz.sh: $fuzzer for ${scene_seconds}s; corpus $corpus; seeds ${seeds[*]}"
# -timeout: one input taking over 10 s is a hang; -rss_limit_mb: over 2 GB is a
# finding; -max_len: scenes of up to 8 KiB.
# libFuzzer exits non-zero on a finding; the status is kept (not left to
# set -e) so that the summary below is printed either way.
started=$build/fuzz-started
touch "$started"
set +e
"$fuzzer" "$corpus" "${seeds[@]}" -dict="$root/tests/fuzz/scene.dict" -max_total_time="$scene_seconds" \
  -timeout=10 -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1 -artifact_prefix="$artifacts/" \
  2>&1 | tee "$build/fuzz.log"
status=${PIPESTATUS[0]}
snapshot_corpus=$build/snapshot-fuzz-corpus
mkdir -p "$snapshot_corpus"
echo "run_fuzz.sh: $snapshot_fuzzer for ${snapshot_seconds}s; corpus $snapshot_corpus; seeds $root/tests/fuzz/snapshot_corpus"
"$snapshot_fuzzer" "$snapshot_corpus" "$root/tests/fuzz/snapshot_corpus" -max_total_time="$snapshot_seconds" \
  -timeout=10 -rss_limit_mb=2048 -max_len=8192 -print_final_stats=1 -artifact_prefix="$artifacts/" \
  2>&1 | tee "$build/snapshot-fuzz.log"
snapshot_status=${PIPESTATUS[0]}
[ "$status" -eq 0 ] && status=$snapshot_status
set -e
findings=$(find "$artifacts" -type f -newer "$started" | wc -l)
echo "run_fuzz.sh: exit $status; corpus now $(find "$corpus" -type f | wc -l) files; new findings in $artifacts: $findings"
# A file this run wrote to the artifacts folder is a finding even if the fuzzer exited 0.
[ "$status" -eq 0 ] && [ "$findings" -gt 0 ] && status=1
exit "$status"
