#!/usr/bin/env bash
# The fisheye simulation against its pinhole twin (docs/results/fisheye.md): VIO ATE (position +
# yaw alignment) and VO ATE (Sim(3)) on the same scene, trajectory and seed, with the default
# pinhole camera, the Kannala-Brandt fisheye with points in the full image (raw pixels) and with
# points in the segments' undistorted view; points + lines and points only.
# Usage: scripts/fisheye_table.sh PLUCKER OUT_DIR [vio|vo|both] [SCENES] [FRAMES] [SEEDS] [CAMERAS]
# SEEDS: one or more, e.g. "1 2 3 4 5" (a row per seed); CAMERAS: a subset of
# "pinhole kb-full kb-view". (VO on 600 frames takes minutes a run on the shared machine; VIO
# seconds, the fisheye view corridor about a minute of CPU.) VIO_FLAGS / VO_FLAGS (environment):
# more flags for every run, e.g. VIO_FLAGS="--config my.yaml".
set -euo pipefail
P=$1
OUT=$2
WHAT=${3:-both}
SCENES=${4:-"room corridor"}
FRAMES=${5:-600}
SEEDS=${6:-1}
CAMERAS=${7:-"pinhole kb-full kb-view"}
read -r -a vio_flags <<<"${VIO_FLAGS:-}"
read -r -a vo_flags <<<"${VO_FLAGS:-}"
mkdir -p "$OUT"
ate() { "$P" eval ate --gt "$1" --est "$2" --align "$3" | awk '/ATE translation/ {print $5}'; }
echo "| scene | seed | camera | points | lines | VIO ATE [m] | VO ATE [m] |"
echo "|---|---|---|---|---|---|---|"
for scene in $SCENES; do
  for SEED in $SEEDS; do
  for cam in $CAMERAS; do
    d="$OUT/${scene}_${SEED}_${cam}"
    case $cam in
      pinhole) flags=() ;;
      kb-full) flags=(--camera-model kb --points full) ;;
      kb-view) flags=(--camera-model kb --points view) ;;
    esac
    rm -rf "$d"
    "$P" sim camera --scene "$scene" --frames "$FRAMES" --seed "$SEED" --out "$d" "${flags[@]}" >/dev/null
    grep -v '^#' "$d/body_states.txt" | cut -d' ' -f1-8 >"$d.gt.tum"
    for lines in yes no; do
      extra=()
      [ "$lines" = no ] && extra=(--no-lines)
      vio=- vo=-
      [ "$WHAT" != vo ] && vio=$("$P" vio --features "$d" --out "$d.vio.$lines.tum" --quiet "${extra[@]}" "${vio_flags[@]}" >/dev/null 2>&1 &&
        ate "$d.gt.tum" "$d.vio.$lines.tum" posyaw || echo failed)
      [ "$WHAT" != vio ] && vo=$("$P" vo --features "$d" --out "$d.vo.$lines.txt" --quiet "${extra[@]}" "${vo_flags[@]}" >/dev/null 2>&1 &&
        ate "$d/trajectory.txt" "$d.vo.$lines.txt" sim3 || echo failed)
      pts=$([ "$cam" = kb-view ] && echo view || ([ "$cam" = kb-full ] && echo full || echo image))
      echo "| $scene | $SEED | ${cam%%-*} | $pts | $lines | $vio | $vo |"
    done
  done
  done
done
