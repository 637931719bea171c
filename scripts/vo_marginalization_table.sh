#!/usr/bin/env bash
# Marginalization with the line observations of the marginalized keyframe kept against dropped
# (and points only), `plucker vo` on simulated rooms and corridors over several seeds (issue 9):
# the same simulation, the same front end (features folder, two-view start) and the same options
# for the three variants, ATE rmse after Sim(3) alignment, paired per seed. Prints one row per
# scene and seed and a summary per scene over the seeds where all three variants ran: the mean of
# each, the mean and median of the paired difference (dropped - kept: positive = kept better)
# and how many seeds kept beat dropped.
#
#   scripts/vo_marginalization_table.sh [options]
#     --seeds N        seeds 1..N (default 10)
#     --frames N       frames per sequence (default 100)
#     --scenes LIST    default "room corridor"
#     --plucker PATH   default build/release/apps/plucker/plucker
#     --work DIR       simulations and poses (default a temporary folder, removed)
#     -- ARGS          further arguments for every `plucker vo` run (e.g. --config FILE)
# Point strides: room 10 (about 10 point tracks per frame against 29 segments), corridor 40
# (about 14 against 73): the scarce-points setting of docs/results/vo.md.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
plucker="$repo/build/release/apps/plucker/plucker"
seeds=10
frames=100
scenes="room corridor"
work=""
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) seeds="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    --plucker) plucker="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "vo_marginalization_table.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
[ -x "$plucker" ] || { echo "vo_marginalization_table.sh: no plucker at '$plucker'" >&2; exit 2; }
if [ -z "$work" ]; then
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"

# ATE rmse of one run, or "fail".
ate() {
  local seq="$1" est="$2"
  shift 2
  if "$plucker" vo --features "$seq" --out "$est" --quiet "$@" >/dev/null 2>&1; then
    "$plucker" eval ate --gt "$seq/trajectory.txt" --est "$est" --align sim3 --json |
      python3 -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["translation_m"]["rmse"])'
  else
    echo fail
  fi
}

printf '%-9s %4s %8s %8s %8s %9s\n' scene seed kept dropped points dropped-kept
for scene in $scenes; do
  stride=10
  [ "$scene" = corridor ] && stride=40
  rows="$work/$scene.rows"
  : >"$rows"
  for seed in $(seq 1 "$seeds"); do
    seq_dir="$work/${scene}_$seed"
    "$plucker" sim camera --scene "$scene" --frames "$frames" --seed "$seed" --out "$seq_dir" \
      >/dev/null 2>&1
    common=(--point-stride "$stride" "${extra[@]}")
    k=$(ate "$seq_dir" "$work/kept.txt" "${common[@]}")
    d=$(ate "$seq_dir" "$work/dropped.txt" "${common[@]}" --drop-marginalized-lines)
    p=$(ate "$seq_dir" "$work/points.txt" "${common[@]}" --no-lines)
    diff=-
    [ "$k" != fail ] && [ "$d" != fail ] && diff=$(awk -v k="$k" -v d="$d" 'BEGIN{printf "%+.4f", d-k}')
    printf '%-9s %4d %8s %8s %8s %9s\n' "$scene" "$seed" "$k" "$d" "$p" "$diff"
    echo "$k $d $p" >>"$rows"
  done
  python3 - "$scene" "$rows" <<'PY'
import statistics, sys
scene, rows = sys.argv[1], sys.argv[2]
runs = [l.split() for l in open(rows)]
ok = [[float(v) for v in r] for r in runs if "fail" not in r]
if not ok:
    print(f"{scene}: no seed where all three ran")
    sys.exit(0)
n = len(ok)
diff = [d - k for k, d, _ in ok]
wins = sum(k < d for k, d, _ in ok)
print(f"{scene}, {n} seeds where all ran: mean ATE kept {sum(r[0] for r in ok) / n:.4f}, "
      f"dropped {sum(r[1] for r in ok) / n:.4f}, points {sum(r[2] for r in ok) / n:.4f}; "
      f"dropped-kept mean {sum(diff) / n:+.4f} median {statistics.median(diff):+.4f}; "
      f"kept better on {wins} of {n}")
PY
done
