#!/usr/bin/env bash
# Type-checks the package's stubs and a typed use of them with mypy --strict (ctest python_mypy).
#   python/tests/run_mypy.sh PYTHON_SOURCE_DIR
# Exit 77 (skipped) when mypy is not installed.
set -uo pipefail
SRC="$1"
if ! command -v mypy > /dev/null; then echo "SKIP: mypy is not installed"; exit 77; fi
cd "$SRC" || exit 1
exec mypy --strict --no-incremental --cache-dir=/dev/null plucker tests/typed_use.py
