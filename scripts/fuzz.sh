#!/usr/bin/env bash
# Builds the libFuzzer targets (kitti_bin_fuzz, pcd_fuzz, pose_fuzz, euroc_fuzz, segments_fuzz,
# kalibr_fuzz, png_gray_fuzz)
# with clang in a separate build folder and runs each for SECONDS (default 60) from a seed corpus
# the fuzzers write themselves (valid .bin, calib/times text, ascii/binary/compressed PCD, PLY,
# KITTI/TUM poses, EuRoC IMU/ground-truth CSV and sensor.yaml, segment files).
# Exits non-zero when a target crashes, hangs (> 10 s on one input), leaks or hits UB; the
# reproducer is left in $BUILD/fuzz-artifacts/.
#
#   scripts/fuzz.sh [SECONDS]        env: BUILD (default build/fuzz), CXX (default clang++-14),
#                                         JOBS (default 2)
set -euo pipefail

SECONDS_PER_TARGET="${1:-60}"
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${BUILD:-$ROOT/build/fuzz}"
CXX_BIN="${CXX:-clang++-14}"
JOBS="${JOBS:-2}"
TARGETS=(kitti_bin_fuzz pcd_fuzz pose_fuzz euroc_fuzz segments_fuzz kalibr_fuzz png_gray_fuzz)

if ! command -v "$CXX_BIN" > /dev/null; then
  echo "fuzz.sh: $CXX_BIN not found (install clang-14 and libclang-rt-14-dev)" >&2
  exit 2
fi

cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER="$CXX_BIN" \
  -DPLUCKER_BUILD_FUZZERS=ON -DPLUCKER_BUILD_TESTS=OFF -DPLUCKER_BUILD_APPS=OFF \
  -DPLUCKER_BUILD_BENCHMARKS=OFF -DCMAKE_PROJECT_INCLUDE="$ROOT/cmake/Fuzzers.cmake" > /dev/null
cmake --build "$BUILD" -j"$JOBS" --target "${TARGETS[@]}"

status=0
mkdir -p "$BUILD/fuzz-artifacts"
for target in "${TARGETS[@]}"; do
  corpus="$BUILD/fuzz-corpus/$target"
  mkdir -p "$corpus"
  # The fuzzer writes its seeds from LLVMFuzzerInitialize when asked to.
  PLUCKER_FUZZ_WRITE_SEEDS="$corpus" "$BUILD/$target" -runs=0 "$corpus" > /dev/null 2>&1 || true
  echo "fuzz.sh: $target for ${SECONDS_PER_TARGET}s ($(ls "$corpus" | wc -l) corpus files)"
  if ! ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      "$BUILD/$target" -max_total_time="$SECONDS_PER_TARGET" -timeout=10 -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$BUILD/fuzz-artifacts/$target-" \
      "$corpus" 2> "$BUILD/fuzz-artifacts/$target.log"; then
    echo "fuzz.sh: $target FAILED; log: $BUILD/fuzz-artifacts/$target.log" >&2
    tail -n 40 "$BUILD/fuzz-artifacts/$target.log" >&2
    status=1
  else
    grep -E "stat::number_of_executed_units|Done" "$BUILD/fuzz-artifacts/$target.log" | head -2 || true
  fi
done
exit $status
