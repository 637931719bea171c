#!/usr/bin/env bash
# Runs the Python tests on the build tree's package (ctest entry python_pytest).
#   python/tests/run_pytest.sh BUILD_PYTHON_DIR TESTS_DIR
# Environment: PLUCKER_PYTHON (the interpreter the module is built for; default python3),
# PLUCKER_SHARED_DATA_DIR (real-data tests skip without it), PLUCKER_CLI (the
# plucker program, for the comparisons with the command line), PLUCKER_ASAN_RUNTIME (libasan.so:libstdc++.so
# of a sanitized build: preloaded into python3, leak checks off as Python keeps its objects).
# Exit 77 (skipped) without pytest or numpy; pytest's 5 (no test collected) is a failure.
set -uo pipefail
PKG="$1"; TESTS="$2"
PY="${PLUCKER_PYTHON:-python3}"
if ! "$PY" -c "import pytest, numpy" 2>/dev/null; then
  echo "SKIP: python3-pytest or python3-numpy is not installed (scripts/install_deps.sh)"; exit 77
fi
export PYTHONPATH="$PKG${PYTHONPATH:+:$PYTHONPATH}"
if [ -n "${PLUCKER_ASAN_RUNTIME:-}" ]; then
  # Last wins: the leak check is off even when the caller's ASAN_OPTIONS turn it on.
  export LD_PRELOAD="$PLUCKER_ASAN_RUNTIME" ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
fi
cd "$TESTS" || exit 1
"$PY" -m pytest -q -p no:cacheprovider -rs "$TESTS"
rc=$?
if [ $rc -eq 5 ]; then echo "FAIL: pytest collected no test"; exit 1; fi
exit $rc
