#!/usr/bin/env bash
# The camera-IMU time offset table of docs/results/vio.md: the MH_05 clip with its IMU stamps
# shifted by S ms (S = 0, +-5, +-10; IMU late: td = +S ms), `plucker vio --estimate-time-offset`
# on each, ATE after SE(3) against the unshifted ground truth and the estimate.
#   scripts/vio_time_offset_table.sh PLUCKER [CLIP_DIR] [WORK_DIR]
# The shifted copies (imu0 rewritten, cam0 and the ground truth linked) go to WORK_DIR
# (default: a new temporary folder); nothing in CLIP_DIR is written.
set -euo pipefail
P=${1:?usage: $0 PLUCKER [CLIP_DIR] [WORK_DIR]}
CLIP=${2:-../shared/data/euroc-mh05-clip}
WORK=${3:-$(mktemp -d)}
[ -f "$CLIP/mav0/imu0/data.csv" ] || { echo "$0: $CLIP/mav0/imu0/data.csv not found" >&2; exit 2; }
CLIP=$(cd "$CLIP" && pwd)
mkdir -p "$WORK"
"$P" convert euroc-gt --euroc "$CLIP" --out "$WORK/gt.tum" > /dev/null
for S in 0 5 -5 10 -10; do
  C="$WORK/clip_$S"
  mkdir -p "$C/mav0/imu0"
  for d in cam0 state_groundtruth_estimate0 body.yaml; do
    [ -e "$CLIP/mav0/$d" ] && ln -sfn "$CLIP/mav0/$d" "$C/mav0/$d"
  done
  cp "$CLIP/mav0/imu0/sensor.yaml" "$C/mav0/imu0/"
  # Integers in Python: awk's doubles lose the nanoseconds.
  python3 - "$CLIP/mav0/imu0/data.csv" "$C/mav0/imu0/data.csv" "$S" <<'PY'
import sys
src, dst, shift = sys.argv[1], sys.argv[2], int(sys.argv[3]) * 1000000
with open(src) as f, open(dst, "w") as out:
    for line in f:
        if line.startswith("#") or not line.strip():
            out.write(line)
            continue
        t, rest = line.split(",", 1)
        out.write(f"{int(t) + shift},{rest}")
PY
  "$P" vio --euroc "$C" --out "$C/vio.tum" --json "$C/vio.json" --quiet --estimate-time-offset
  ate=$("$P" eval ate --gt "$WORK/gt.tum" --est "$C/vio.tum" --align se3 | grep -o "rmse [0-9.]*" | head -1)
  td=$(grep -o '"camera_imu_time_offset_s": *[-0-9.e]*' "$C/vio.json" | grep -o '[-0-9.e]*$')
  printf "shift %+3d ms  ATE %s m  td %s s\n" "$S" "${ate#rmse }" "$td"
done
