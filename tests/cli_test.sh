#!/usr/bin/env bash
# End-to-end tests of the `plucker` program: the main commands on small simulated data, and the
# bad-input paths (each must fail, or skip a frame, with a message naming the file, never crash).
#   tests/cli_test.sh PATH/TO/plucker
set -uo pipefail
PLUCKER="$1"
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
pass=0
fail=0

# expect NAME EXPECTED_EXIT(0|nonzero) PATTERN -- command...   (PATTERN searched in stdout+stderr)
expect() {
  local name="$1" want="$2" pattern="$3"
  shift 4
  local out rc
  out="$("$@" 2>&1)"
  rc=$?
  local ok=1
  if [ "$want" = 0 ] && [ $rc -ne 0 ]; then ok=0; fi
  if [ "$want" = nonzero ] && { [ $rc -eq 0 ] || [ $rc -ge 128 ]; }; then ok=0; fi
  if [ -n "$pattern" ] && ! grep -qE -- "$pattern" <<< "$out"; then ok=0; fi
  if [ $ok = 1 ]; then
    pass=$((pass + 1))
    echo "ok   $name"
  else
    fail=$((fail + 1))
    echo "FAIL $name (exit $rc, wanted $want, pattern '$pattern')"
    echo "$out" | tail -20 | sed 's/^/     /'
  fi
}

expect help 0 "check-jacobians" -- "$PLUCKER" --help
expect check-jacobians 0 "functions checked, 0 failed" -- \
  "$PLUCKER" check-jacobians --samples 20 --seed 1
expect check-jacobians-json 0 '"failed": 0' -- "$PLUCKER" check-jacobians --samples 5 --json
expect check-jacobians-bad-filter nonzero "no check matches" -- \
  "$PLUCKER" check-jacobians --samples 5 --filter zzz_nothing

# LiDAR: simulate, run, evaluate.
expect sim-lidar 0 "" -- "$PLUCKER" sim lidar --out "$T/sim" --frames 12 --sensor vlp16 --seed 3
expect lidar 0 "" -- "$PLUCKER" lidar --data "$T/sim" --out "$T/est.txt" --json "$T/stats.json" \
  --quiet
expect lidar-output-rows 0 "^12$" -- bash -c "wc -l < '$T/est.txt'"
expect eval-rpe 0 "" -- "$PLUCKER" eval rpe --gt "$T/sim/poses.txt" --est "$T/est.txt"
expect lidar-threads 0 "" -- "$PLUCKER" lidar --data "$T/sim" --out "$T/est2.txt" --threads 2 --quiet
expect lidar-threads-same-poses 0 "" -- cmp "$T/est.txt" "$T/est2.txt"
expect bench-lidar 0 "speed-up 2 vs 1 threads" -- \
  "$PLUCKER" bench lidar --data "$T/sim" --frames 4 --repeats 1 --threads 1 2
expect bench-lidar-missing-folder nonzero "$T/nothing" -- "$PLUCKER" bench lidar --data "$T/nothing"
expect bench-lidar-needs-data nonzero "--data is required" -- "$PLUCKER" bench lidar
expect bench-lidar-long-folder 0 " 0-4 .* 5-9 .* 10-11 .*growth of the median total" -- \
  bash -c "'$PLUCKER' bench lidar --long --data '$T/sim' --block 5 | tr '\n' ' '"
expect bench-lidar-long-simulated 0 "simulated urban drive.* 0-3 .* 4-7 " -- \
  bash -c "'$PLUCKER' bench lidar --long --sim-frames 8 --sensor vlp16 --block 4 | tr '\n' ' '"
expect eval-ate-plot 0 "" -- "$PLUCKER" eval ate --gt "$T/sim/poses.txt" --est "$T/est.txt" \
  --align se3 --plot "$T/ate.svg"
expect eval-plot-written 0 "<svg" -- head -c 400 "$T/ate.svg"
expect sim-lidar-refuses-user-folder nonzero "" -- \
  bash -c "mkdir -p '$T/user' && echo keep > '$T/user/notes.txt' && '$PLUCKER' sim lidar --out '$T/user' --frames 2"
expect sim-lidar-kept-user-file 0 "keep" -- cat "$T/user/notes.txt"

# Bad LiDAR input: a truncated frame and a missing frame are skipped and reported.
cp -r "$T/sim" "$T/bad"
truncate -s -3 "$T/bad/velodyne/000005.bin"
rm "$T/bad/velodyne/000008.bin"
expect lidar-bad-frames 0 "000005.bin" -- "$PLUCKER" lidar --data "$T/bad" --out "$T/bad_est.txt" \
  --json "$T/bad_stats.json"
expect lidar-bad-frames-rows 0 "^12$" -- bash -c "wc -l < '$T/bad_est.txt'"
expect lidar-bad-frames-json-missing 0 "000008" -- cat "$T/bad_stats.json"
expect lidar-bad-frames-json-truncated 0 "000005.bin" -- cat "$T/bad_stats.json"
# --quiet silences progress, not warnings: the truncated frame is still reported.
expect lidar-quiet-still-reports-skipped 0 "skipped frame 5: .*000005\.bin" -- \
  "$PLUCKER" lidar --data "$T/bad" --out "$T/bad_quiet.txt" --quiet
expect lidar-missing-folder nonzero "$T/nothing" -- \
  "$PLUCKER" lidar --data "$T/nothing" --out "$T/x.txt"
expect lidar-refuses-to-overwrite-input nonzero "" -- \
  "$PLUCKER" lidar --data "$T/sim" --out "$T/sim/poses.txt" --quiet
expect lidar-input-kept 0 "" -- cmp "$T/sim/poses.txt" "$T/sim/poses.txt"

# Bad trajectory files: the error names the file and the line.
printf '1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 zz 0 1 0 0 0 0 1 0\n' > "$T/bad_poses.txt"
expect eval-bad-number nonzero "bad_poses.txt:2" -- \
  "$PLUCKER" eval ate --gt "$T/bad_poses.txt" --est "$T/est.txt" --align se3
expect eval-missing-file nonzero "no_such.txt" -- \
  "$PLUCKER" eval rpe --gt "$T/no_such.txt" --est "$T/est.txt"

# IMU noise model against a EuRoC-layout folder: a tiny synthetic log at rest, then bad input.
E="$T/euroc/mav0"
mkdir -p "$E/imu0" "$E/state_groundtruth_estimate0"
printf 'rate_hz: 200\ngyroscope_noise_density: 1.7e-4\ngyroscope_random_walk: 2e-5\naccelerometer_noise_density: 2e-3\naccelerometer_random_walk: 3e-3\n' > "$E/imu0/sensor.yaml"
awk 'BEGIN { for (k = 0; k <= 400; ++k) printf "%.0f,0,0,0,0,0,9.81\n", 1000000000 + k * 5000000 }' > "$E/imu0/data.csv"
awk 'BEGIN { for (k = 0; k <= 40; ++k) printf "%.0f,0,0,0,1,0,0,0,0,0,0,0,0,0,0,0,0\n", 1000000000 + k * 50000000 }' \
  > "$E/state_groundtruth_estimate0/data.csv"
expect eval-imu 0 "1.00 +21 " -- "$PLUCKER" eval imu --euroc "$T/euroc"
expect eval-imu-json 0 '"windows"' -- "$PLUCKER" eval imu --euroc "$T/euroc" --json --windows 0.5
sed -i '3s/,9.81$/,x/' "$E/imu0/data.csv"
expect eval-imu-bad-number nonzero "imu0/data.csv:3: bad number" -- \
  "$PLUCKER" eval imu --euroc "$T/euroc"
expect eval-imu-not-euroc nonzero "not a EuRoC folder" -- "$PLUCKER" eval imu --euroc "$T/nothing"

# Camera simulation and the demo (camera part only, small).
expect sim-camera 0 "" -- "$PLUCKER" sim camera --out "$T/cam" --scene room --frames 10
expect demo-camera 0 "after" -- "$PLUCKER" demo --no-lidar --frames 8 --out "$T/demo"
expect demo-files 0 "" -- test -s "$T/demo/camera/poses_ba.txt"

# Strecha ground truth as KITTI poses T_w_c (the real files when the shared data is there).
STRECHA="$(dirname "$0")/../../shared/data/strecha-fountain-p11/cameras"
if [ -d "$STRECHA" ]; then
  expect convert-strecha 0 "wrote 11 poses" -- \
    "$PLUCKER" convert strecha --cameras "$STRECHA" --out "$T/strecha_gt.txt"
  expect convert-strecha-rows 0 "^11$" -- bash -c "wc -l < '$T/strecha_gt.txt'"
  expect convert-strecha-centre 0 "^-7.28137 -7.57667 0.204446$" -- \
    awk 'NR == 1 { print $4, $8, $12 }' "$T/strecha_gt.txt"
  expect convert-strecha-eval 0 "" -- \
    "$PLUCKER" eval ate --gt "$T/strecha_gt.txt" --est "$T/strecha_gt.txt" --align sim3
else
  echo "skip convert-strecha: no shared data at $STRECHA"
fi
mkdir -p "$T/badcam" "$T/nocam"
printf '1 0 0\n0 1 x\n' > "$T/badcam/0000.jpg.camera"
expect convert-strecha-bad-file nonzero "0000.jpg.camera: .*not a number: 'x'" -- \
  "$PLUCKER" convert strecha --cameras "$T/badcam" --out "$T/x_gt.txt"
expect convert-strecha-empty-folder nonzero "nocam: no \*\.camera files" -- \
  "$PLUCKER" convert strecha --cameras "$T/nocam" --out "$T/x_gt.txt"

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
