#!/usr/bin/env bash
# The installed package is the library alone: installs the build tree into a scratch prefix and
# fails if test or benchmark scaffolding got in (the verify and testing layers, random geometry,
# factor benchmarks, synthetic problems, *_test_utils.h, the fuzzing helpers, test sources) or an
# installed header including one of them (or io/sensor including sim), or
# if the library itself is missing (so the check cannot pass on an empty install).
#   tests/install_tree_test.sh BUILD_DIR
set -uo pipefail
BUILD="$1"
P="$(mktemp -d)"
trap 'rm -rf "$P"' EXIT
if ! cmake --install "$BUILD" --prefix "$P" > "$P.log" 2>&1; then
  cat "$P.log"; rm -f "$P.log"; echo "FAIL cmake --install"; exit 1
fi
rm -f "$P.log"
fail=0
bad="$(find "$P" \( -path '*/plucker/verify*' -o -path '*/plucker/testing*' \
  -o -name '*plucker_verify*' -o -name '*plucker_testing*' -o -name 'random_geometry.h' \
  -o -name 'factor_bench.h' -o -name 'synthetic_problem.h' -o -name '*_test_utils.h' \
  -o -name 'fuzz_util.h' -o -name '*_fuzz.cc' \
  -o -name '*_test.cc' -o -name 'checks.h' -o -name 'jacobian_check.h' \
  -o -name 'cost_function_check.h' \) -print)"
if [ -n "$bad" ]; then
  echo "FAIL scaffolding installed:"; echo "$bad" | sed 's/^/     /'; fail=1
fi
if grep -rnE '#include "plucker/(verify|testing)/' "$P/include"; then
  echo "FAIL an installed header includes a scaffolding header"; fail=1
fi
if grep -rn '#include "plucker/sim/' "$P/include/plucker/io" "$P/include/plucker/sensor"; then
  echo "FAIL an installed io or sensor header includes a sim header (io and sensor are below sim)"
  fail=1
fi
if grep -rlE 'plucker::(verify|testing)|plucker_(verify|testing)' "$P"/lib*/cmake/plucker; then
  echo "FAIL the exported targets name a scaffolding target"; fail=1
fi
for f in include/plucker/geometry/se3.h include/plucker/factors/pose_manifold.h \
         include/plucker/sensor/lidar_scan.h include/plucker/lidar/odometry.h \
         include/plucker/ba/bundle_adjustment.h; do
  [ -f "$P/$f" ] || { echo "FAIL missing $f"; fail=1; }
done
# The Python package, when the build has it: importable from the prefix as the README says.
if ls "$BUILD"/python/plucker/_plucker*.so > /dev/null 2>&1; then
  site="$P/lib/python3/dist-packages"
  preload=()
  [ -n "${PLUCKER_ASAN_RUNTIME:-}" ] && preload=(env LD_PRELOAD="$PLUCKER_ASAN_RUNTIME" ASAN_OPTIONS=detect_leaks=0)
  if ! out=$(cd / && "${preload[@]}" env PYTHONPATH="$site" "${PLUCKER_PYTHON:-python3}" -c \
      "import plucker; assert plucker.__file__.startswith('$site'), plucker.__file__; print(plucker.so3_exp([0, 0, 0.5]).shape)" 2>&1); then
    echo "FAIL PYTHONPATH=$site python3 -c 'import plucker':"; echo "$out" | sed 's/^/     /'; fail=1
  else
    echo "ok   PYTHONPATH=<prefix>/lib/python3/dist-packages python3 -c 'import plucker'"
  fi
  [ -f "$site/plucker/_plucker.pyi" ] || { echo "FAIL the type stubs are not installed"; fail=1; }
  if find "$P" -name '_plucker_verify*' | grep -q .; then
    echo "FAIL the test-only _plucker_verify module is installed"; fail=1
  fi
fi
headers=$(find "$P/include/plucker" -name '*.h' | wc -l)
layers=$(find "$P/include/plucker" -mindepth 1 -maxdepth 1 -type d | sort | xargs -n1 basename | tr '\n' ' ')
echo "installed: $headers headers in layers: $layers"
[ "$headers" -ge 40 ] || { echo "FAIL only $headers headers installed"; fail=1; }
[ $fail = 0 ] && echo "ok   install tree holds the library and no scaffolding"
exit $fail
