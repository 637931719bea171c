#!/usr/bin/env bash
# The README's Python set-up on a fresh clone (issue 28: "the README states the one command that
# makes `import plucker` work for a new user, and a test runs exactly that on a fresh clone").
#   tests/fresh_clone_python.sh [COMMIT]      (make fresh-clone-python; slow: a full Release build)
# Clones this repository at COMMIT (default HEAD, committed work only) into a scratch folder,
# runs the first line of the README's "From Python" sh block there exactly as written (in bash,
# PYTHONPATH cleared), then in the same shell `/usr/bin/python3 -c "import plucker; ..."` runs
# examples/python/lidar_kitti.py on the shared KITTI extract and checks its poses against the
# clone's `plucker lidar --frame lidar` (byte-identical). PLUCKER_SHARED_DATA_DIR: the data
# (default ../shared/data of this checkout); without it the example runs on no data and the
# test fails. KEEP=1 keeps the clone. Prints the wall time of each step.
set -euo pipefail
SRC="$(cd "$(dirname "$0")/.." && pwd)"
COMMIT="$(git -C "$SRC" rev-parse "${1:-HEAD}")"
DATA="${PLUCKER_SHARED_DATA_DIR:-$SRC/../shared/data}"
SEQ="$(cd "$DATA" && pwd)/kitti-odometry-00/sequences/00"
[ -d "$SEQ/velodyne" ] || { echo "FAIL: the shared KITTI extract is not at $SEQ"; exit 1; }
WORK="$(mktemp -d /tmp/plucker-fresh-clone.XXXXXX)"
[ "${KEEP:-0}" = 1 ] || trap 'rm -rf "$WORK"' EXIT
CLONE="$WORK/plucker"
t0=$(date +%s)
git clone --quiet --no-checkout "$SRC" "$CLONE"
git -C "$CLONE" checkout --quiet --detach "$COMMIT"
# The set-up command: the first line of the sh block after the README's "## From Python".
SETUP="$(awk '/^## From Python/{p=1} p&&/^```sh/{getline; print; exit}' "$CLONE/README.md")"
[ -n "$SETUP" ] || { echo "FAIL: no sh block under '## From Python' in README.md"; exit 1; }
echo "fresh clone of $COMMIT in $CLONE"
echo "README set-up command: $SETUP"
cd "$CLONE"
unset PYTHONPATH
OUT="$WORK/example.txt"
CHECK="import plucker, runpy, sys
assert plucker.__file__.startswith('$CLONE/'), plucker.__file__
sys.argv = ['lidar_kitti.py', '$SEQ', '--out', '$OUT']
runpy.run_path('examples/python/lidar_kitti.py', run_name='__main__')"
t1=$(date +%s)
bash -c "set -e; $SETUP
echo \"set-up: \$(( \$(date +%s) - $t1 )) s\"
/usr/bin/python3 -c \"\$1\"" bash "$CHECK"
t2=$(date +%s)
build/release/apps/plucker/plucker lidar --data "$SEQ" --out "$WORK/cli.txt" --frame lidar --quiet
cmp "$OUT" "$WORK/cli.txt"
echo "PASS: fresh clone, README set-up, import plucker and the LiDAR example ($(wc -l < "$OUT") poses,"\
     "byte-identical to plucker lidar); clone $((t1 - t0)) s, set-up + example $((t2 - t1)) s"
