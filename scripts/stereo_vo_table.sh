#!/usr/bin/env bash
# Stereo VO on the simulator (docs/results/vo.md, "Stereo"): `plucker vo --stereo` (metric, ATE
# after SE(3): no scale correction) against monocular VO (ATE after Sim(3)) and VIO (ATE after
# position + yaw) on the same scene, trajectory and seed; points + lines and points only.
# Usage: scripts/stereo_vo_table.sh PLUCKER OUT_DIR [SCENES] [FRAMES] [SEEDS] [BASELINE_M] [all|stereo]
# (600-frame VO runs take minutes each on the shared machine; `stereo` skips mono VO and VIO.)
set -euo pipefail
P=$1
OUT=$2
SCENES=${3:-"room corridor"}
FRAMES=${4:-600}
SEEDS=${5:-1}
BASELINE=${6:-0.11}
WHAT=${7:-all}
mkdir -p "$OUT"
ate() { "$P" eval ate --gt "$1" --est "$2" --align "$3" | awk '/ATE translation/ {print $5}'; }
echo "| scene | seed | lines | stereo VO ATE SE(3) [m] | stereo VO ATE Sim(3) [m] | mono VO ATE Sim(3) [m] | VIO ATE [m] |"
echo "|---|---|---|---|---|---|---|"
for scene in $SCENES; do
  for seed in $SEEDS; do
    d="$OUT/${scene}_${seed}"
    rm -rf "$d"
    "$P" sim camera --scene "$scene" --frames "$FRAMES" --seed "$seed" --stereo "$BASELINE" \
      --out "$d" >/dev/null
    grep -v '^#' "$d/body_states.txt" | cut -d' ' -f1-8 >"$d.gt.tum"
    for lines in yes no; do
      extra=()
      [ "$lines" = no ] && extra=(--no-lines)
      st=- st3=- vo=- vio=-
      if "$P" vo --features "$d" --stereo --out "$d.stereo.$lines.txt" --quiet "${extra[@]}" \
        >/dev/null 2>&1; then
        st=$(ate "$d/trajectory.txt" "$d.stereo.$lines.txt" se3)
        st3=$(ate "$d/trajectory.txt" "$d.stereo.$lines.txt" sim3)
      else
        st=failed
      fi
      if [ "$WHAT" = all ]; then
        vo=$("$P" vo --features "$d" --out "$d.vo.$lines.txt" --quiet "${extra[@]}" >/dev/null 2>&1 &&
          ate "$d/trajectory.txt" "$d.vo.$lines.txt" sim3 || echo failed)
        vio=$("$P" vio --features "$d" --out "$d.vio.$lines.tum" --quiet "${extra[@]}" >/dev/null 2>&1 &&
          ate "$d.gt.tum" "$d.vio.$lines.tum" posyaw || echo failed)
      fi
      echo "| $scene | $seed | $lines | $st | $st3 | $vo | $vio |"
    done
  done
done
