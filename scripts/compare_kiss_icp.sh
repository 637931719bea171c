#!/usr/bin/env bash
# Speed of `plucker lidar` as a ratio to KISS-ICP (../shared/tools/kiss-icp-baseline), measured
# in one run: both programs process the same KITTI-layout folder on the same core (taskset), one
# thread each, interleaved (the order alternates from run to run) so that both see the same
# machine load. The figure is whole-process wall time divided by the number of frames (reading,
# start-up and writing the poses included); the process CPU time (user + sys) is printed beside
# it, the steadier figure on a loaded machine. Prints every run and the medians.
#
#   scripts/compare_kiss_icp.sh [options] DATA_DIR
#     DATA_DIR            folder with velodyne/NNNNNN.bin (e.g. ../shared/data/kitti-odometry-00/
#                         sequences/00, or a `plucker sim lidar` output)
#     --runs N            interleaved runs of each program (default 5)
#     --cpu C             core to pin both to (default 0)
#     --plucker PATH      default build/release/apps/plucker/plucker
#     --kiss PATH         kiss_driver built out of tree as its README says (default
#                         ../kiss-build/kiss_driver, then $KISS_DRIVER)
#     --kitti-correction  pass KISS-ICP's KITTI vertical-angle correction (off by default: the
#                         registration pipeline alone, which favours KISS-ICP's time)
#     --keep DIR          keep the pose files of the last run in DIR
#     --baseline PATH     also time this second plucker (e.g. the previous commit's) in every
#                         run, so that both ratios come from the same runs (rows "base")
set -euo pipefail

runs=5
cpu=0
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
plucker="$repo/build/release/apps/plucker/plucker"
kiss="${KISS_DRIVER:-$repo/../kiss-build/kiss_driver}"
kiss_extra=()
keep=""
baseline=""
data=""
while [ $# -gt 0 ]; do
  case "$1" in
    --runs) runs="$2"; shift 2 ;;
    --cpu) cpu="$2"; shift 2 ;;
    --plucker) plucker="$2"; shift 2 ;;
    --kiss) kiss="$2"; shift 2 ;;
    --kitti-correction) kiss_extra+=(--kitti-correction); shift ;;
    --keep) keep="$2"; shift 2 ;;
    --baseline) baseline="$2"; shift 2 ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    -*) echo "compare_kiss_icp: unknown option $1" >&2; exit 2 ;;
    *) data="$1"; shift ;;
  esac
done
if [ -z "$data" ]; then echo "compare_kiss_icp: DATA_DIR missing (see --help)" >&2; exit 2; fi
for exe in "$plucker" "$kiss" ${baseline:+"$baseline"}; do
  if [ ! -x "$exe" ]; then echo "compare_kiss_icp: $exe: not an executable" >&2; exit 2; fi
done
scans="$data/velodyne"
[ -d "$scans" ] || scans="$data"
frames=$(find "$scans" -maxdepth 1 -name '*.bin' | wc -l)
if [ "$frames" -eq 0 ]; then echo "compare_kiss_icp: $data: no velodyne/*.bin" >&2; exit 2; fi
if ! [[ "$runs" =~ ^[1-9][0-9]*$ ]]; then echo "compare_kiss_icp: --runs must be >= 1" >&2; exit 2; fi

tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# "wall_us cpu_us" of one command (whole process; cpu = user + sys).
measure() {
  /usr/bin/time -f "%e %U %S" -o "$tmp/time.txt" "$@" >"$tmp/out.log" 2>&1 ||
    { cat "$tmp/out.log" >&2; echo "compare_kiss_icp: failed: $*" >&2; exit 1; }
  awk '{ printf "%d %d\n", $1 * 1e6, ($2 + $3) * 1e6 }' "$tmp/time.txt"
}
run_plucker() { measure taskset -c "$cpu" "$plucker" lidar --data "$data" --out "$tmp/plucker.txt" --quiet; }
run_base() { measure taskset -c "$cpu" "$baseline" lidar --data "$data" --out "$tmp/base.txt" --quiet; }
run_kiss() { measure taskset -c "$cpu" "$kiss" "$data" -o "$tmp/kiss.txt" --threads 1 --quiet "${kiss_extra[@]}"; }
per_frame() { awk -v us="$1" -v n="$frames" 'BEGIN { printf "%.2f", us / 1000 / n }'; }

echo "data: $data ($frames frames); core $cpu; $runs interleaved runs each"
echo "load before: $(uptime | sed 's/.*load average/load average/')"
printf "%-6s %10s %10s %8s   %10s %10s %8s\n" run "plucker" "kiss-icp" "ratio" "plucker" \
  "kiss-icp" "ratio"
printf "%-6s %30s   %30s\n" "" "wall ms per frame" "CPU ms per frame"
pw=(); kw=(); rw=(); pc=(); kc=(); rc=(); bw=(); bc=(); rbw=(); rbc=()
for ((r = 1; r <= runs; r++)); do
  if [ -n "$baseline" ] && (( r % 2 )); then b=$(run_base); fi
  if (( r % 2 )); then p=$(run_plucker); k=$(run_kiss); else k=$(run_kiss); p=$(run_plucker); fi
  if [ -n "$baseline" ] && ! (( r % 2 )); then b=$(run_base); fi
  read -r p_wall p_cpu <<<"$p"
  read -r k_wall k_cpu <<<"$k"
  pw+=("$(per_frame "$p_wall")"); kw+=("$(per_frame "$k_wall")")
  pc+=("$(per_frame "$p_cpu")"); kc+=("$(per_frame "$k_cpu")")
  rw+=("$(awk -v a="$k_wall" -v b="$p_wall" 'BEGIN { printf "%.2f", a / b }')")
  rc+=("$(awk -v a="$k_cpu" -v b="$p_cpu" 'BEGIN { printf "%.2f", a / b }')")
  printf "%-6d %10s %10s %7sx   %10s %10s %7sx\n" "$r" "${pw[-1]}" "${kw[-1]}" "${rw[-1]}" \
    "${pc[-1]}" "${kc[-1]}" "${rc[-1]}"
  if [ -n "$baseline" ]; then
    read -r b_wall b_cpu <<<"$b"
    bw+=("$(per_frame "$b_wall")"); bc+=("$(per_frame "$b_cpu")")
    rbw+=("$(awk -v a="$k_wall" -v b="$b_wall" 'BEGIN { printf "%.2f", a / b }')")
    rbc+=("$(awk -v a="$k_cpu" -v b="$b_cpu" 'BEGIN { printf "%.2f", a / b }')")
    printf "%-6s %10s %10s %7sx   %10s %10s %7sx\n" "base" "${bw[-1]}" "${kw[-1]}" "${rbw[-1]}" \
      "${bc[-1]}" "${kc[-1]}" "${rbc[-1]}"
  fi
done
median() { printf "%s\n" "$@" | sort -g | awk '{ v[NR] = $1 } END { if (NR % 2) print v[(NR + 1) / 2]; else printf "%.2f\n", (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
printf "%-6s %10s %10s %7sx   %10s %10s %7sx\n" median "$(median "${pw[@]}")" \
  "$(median "${kw[@]}")" "$(median "${rw[@]}")" "$(median "${pc[@]}")" "$(median "${kc[@]}")" \
  "$(median "${rc[@]}")"
if [ -n "$baseline" ]; then
  printf "%-6s %10s %10s %7sx   %10s %10s %7sx\n" "median" "$(median "${bw[@]}")" \
    "$(median "${kw[@]}")" "$(median "${rbw[@]}")" "$(median "${bc[@]}")" "$(median "${kc[@]}")" \
    "$(median "${rbc[@]}")"
  echo "(the second median row: the baseline $baseline)"
fi
echo "ratio = KISS-ICP time / plucker time (> 1: plucker is faster)"
echo "load after: $(uptime | sed 's/.*load average/load average/')"
if [ -n "$keep" ]; then mkdir -p "$keep" && cp "$tmp/plucker.txt" "$tmp/kiss.txt" "$keep/"; fi
