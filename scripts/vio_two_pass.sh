#!/usr/bin/env bash
# Two passes of `plucker vio` over the same input (offline): the second pass's dynamic start is
# solved with the biases the first pass ended with, held (init.accel_bias, init.gyro_bias, the
# start's bundle adjustment and a tight window prior on the accelerometer bias), and the
# extrinsic estimated online (set TWO_PASS_EXTRINSIC=0 to leave it out). Why: on the MH_05 take-off
# the accelerometer bias trades against the gravity direction and the scale until the body has
# turned, which the end of a run has seen (docs/results/vio.md, "the take-off's biases").
#   scripts/vio_two_pass.sh PLUCKER OUT_DIR VIO_INPUT_ARGS...
# e.g. scripts/vio_two_pass.sh build/rel/apps/plucker/plucker out --euroc ../shared/data/euroc-mh05-clip
# Writes OUT_DIR/pass1.{tum,json}, OUT_DIR/pass2.yaml and OUT_DIR/pass2.{tum,json} (the result).
# VIO_INPUT_ARGS must not hold --config, --out or --json. Needs python3.
set -euo pipefail
[ $# -ge 3 ] || { sed -n '2,12p' "$0" >&2; exit 2; }
P=$1 OUT=$2
shift 2
mkdir -p "$OUT"
"$P" vio "$@" --out "$OUT/pass1.tum" --json "$OUT/pass1.json" --quiet
python3 - "$OUT/pass1.json" > "$OUT/pass2.yaml" <<'PY'
import json, sys
frames = [f for f in json.load(open(sys.argv[1]))["frames"] if f.get("state")]
if not frames:
    sys.exit(sys.argv[1] + ": the first pass has no state (it did not start)")
s = frames[-1]["state"]
vec = lambda v: "[" + ", ".join("%.9g" % x for x in v) + "]"
print("init:\n  ba_iterations: 20\n  ba_accel_bias_prior_sigma: 0.01")
print("  accel_bias: " + vec(s["accel_bias"]) + "\n  gyro_bias: " + vec(s["gyro_bias"]))
print("inertial:\n  accel_bias_prior_sigma: 0.01")
PY
extra=()
[ "${TWO_PASS_EXTRINSIC:-1}" = 1 ] && extra+=(--estimate-extrinsic)
"$P" vio "$@" --config "$OUT/pass2.yaml" ${extra[@]+"${extra[@]}"} --out "$OUT/pass2.tum" \
  --json "$OUT/pass2.json" --quiet
