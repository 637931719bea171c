#!/usr/bin/env bash
# VIO robustness table (issue 26 part 2b): unseen seeds x scenes x rates x starts (+ the
# aggressive and fast motions), one run at a time. Usage:
#   scripts/vio_robustness.sh PLUCKER OUT_DIR [SEEDS] [FRAMES_SECONDS] [CASES]
#   scripts/vio_robustness.sh --summary RUNS.tsv [RUNS.tsv ...]
# SEEDS: e.g. "$(seq 200 219)"; FRAMES_SECONDS: the simulated seconds of each run (frames =
# seconds x rate); CASES: "scene:rate:start:motion ..." (default the table of the issue plus the
# aggressive and fast scenes). Seeds are the outer loop (a run stopped early leaves every case
# with the same seeds). Writes OUT_DIR/runs.tsv (one row per run) and prints the table (median
# and worst ATE after position+yaw alignment, the runs over 0.5 m, the IMU-only share, the
# slowest run's process CPU against the simulated time: `x real time`).
# VIO_ARGS (environment): extra `plucker vio` flags for every run, e.g. "--config my.yaml".
# VIO_KEEP_JSON=1 (environment): keep every run's `--json` as
# OUT_DIR/json/SCENE-RATE-START-MOTION-SEED-LINES.json.gz (the failure detector's study).
# --summary: the table of several runs.tsv files (e.g. two OUT_DIRs run side by side on
# disjoint seeds).
set -u
if [ "${1:-}" = --summary ]; then
  shift
  SUMMARY_FILES=("$@")
else
P="$1"
OUT="$2"
SEEDS="${3:-$(seq 200 219)}"
SECONDS_PER_RUN="${4:-30}"
CASES="${5:-room:10:moving:normal room:10:static:normal room:20:moving:normal room:20:static:normal
corridor:10:moving:normal corridor:10:static:normal corridor:20:moving:normal
corridor:20:static:normal room:30:moving:aggressive corridor:30:moving:aggressive
room:30:moving:fast corridor:30:moving:fast}"
mkdir -p "$OUT"
RUNS="$OUT/runs.tsv"
printf 'scene\trate\tstart\tmotion\tseed\tframes\tate_m\timu_only_frames\texit\tlines\tcpu_s\twall_s\tmax_kf_imu_chi2\n' \
  > "$RUNS"
for seed in $SEEDS; do
  for c in $CASES; do
    IFS=: read -r scene rate start motion <<< "$c"
    frames=$(awk -v s="$SECONDS_PER_RUN" -v r="$rate" 'BEGIN { printf "%d", s * r }')
    stand=0
    [ "$start" = static ] && stand=1.25
    d="$OUT/sim"
    rm -rf "$d"
    "$P" sim camera --out "$d" --scene "$scene" --rate "$rate" --frames "$frames" --seed "$seed" \
      --standing-start "$stand" --motion "$motion" > /dev/null || { echo "sim failed: $c $seed"; continue; }
    grep -v '^#' "$d/body_states.txt" | cut -d' ' -f1-8 > "$OUT/gt.tum"
    for lines in yes no; do
      [ "$lines" = no ] && [ "$motion" = normal ] && continue  # points vs lines: fast motions
      flag=""
      [ "$lines" = no ] && flag="--no-lines"
      rm -f "$OUT/est.tum" "$OUT/est.json"  # a failed run must not leave the previous one's
      # Process CPU (user + system) and wall time of the run: under `nice 19` on a loaded machine
      # the wall time says how much CPU the run was given, not what it needs.
      /usr/bin/time -o "$OUT/time.txt" -f '%U %S %e' "$P" vio --features "$d" --out "$OUT/est.tum" \
        --json "$OUT/est.json" --quiet $flag ${VIO_ARGS:-} 2> "$OUT/last.err"
      rc=$?
      read -r t_user t_sys t_wall < <(tail -1 "$OUT/time.txt")
      cpu=$(awk -v u="$t_user" -v s="$t_sys" 'BEGIN { printf "%.2f", u + s }')
      ate=$("$P" eval ate --gt "$OUT/gt.tum" --est "$OUT/est.tum" --align posyaw --json 2> /dev/null |
        python3 -c 'import json,sys; print("%.4f" % json.load(sys.stdin)["translation_m"]["rmse"])' \
        2> /dev/null || echo nan)
      imu=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["summary"]["imu_only_frames"])' \
        "$OUT/est.json" 2> /dev/null || echo nan)
      # The largest whitened IMU-factor chi2 of the run's keyframes (after their solve).
      chi2=$(python3 -c 'import json,sys; print("%.1f" % max([f.get("imu_chi2", 0) for f in json.load(open(sys.argv[1]))["frames"] if f.get("keyframe")] + [0]))' \
        "$OUT/est.json" 2> /dev/null || echo nan)
      if [ -n "${VIO_KEEP_JSON:-}" ] && [ -f "$OUT/est.json" ]; then
        mkdir -p "$OUT/json"
        gzip -c "$OUT/est.json" > "$OUT/json/$scene-$rate-$start-$motion-$seed-$lines.json.gz"
      fi
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$scene" "$rate" "$start" \
        "$motion" "$seed" "$frames" "$ate" "$imu" "$rc" "$lines" "$cpu" "$t_wall" "$chi2" >> "$RUNS"
    done
  done
done
SUMMARY_FILES=("$RUNS")
fi
python3 - "${SUMMARY_FILES[@]}" <<'PY'
import csv, math, statistics, sys
rows = [r for f in sys.argv[1:] for r in csv.DictReader(open(f), delimiter="\t")]
groups = {}
for r in rows:
    groups.setdefault((r["scene"], r["rate"], r["start"], r["motion"], r["lines"]), []).append(r)
print("| scene | Hz | start | motion | lines | runs | median ATE [m] | worst ATE [m] | runs > 0.5 m | IMU-only frames (worst run) | non-zero exits | x real time (slowest run) |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
total_over = 0
for k, g in groups.items():
    # A run that failed (exit 1: no output) counts as over 0.5 m, its ATE as infinite.
    ate = [float(r["ate_m"]) if r["ate_m"] != "nan" and r["exit"] != "1" else math.inf for r in g]
    over = sum(a > 0.5 for a in ate)
    total_over += over
    imu = max(int(r["imu_only_frames"]) if r["imu_only_frames"] != "nan" else -1 for r in g)
    bad = sum(r["exit"] != "0" for r in g)
    # The simulated seconds over the process CPU (runs.tsv files of before have no CPU column).
    speed = [int(r["frames"]) / float(r["rate"]) / float(r["cpu_s"]) for r in g
             if r.get("cpu_s") not in (None, "", "nan") and float(r["cpu_s"]) > 0]
    print("| %s | %s | %s | %s | %s | %d | %.3f | %.3f | %d | %d | %d | %s |" % (
        k[0], k[1], k[2], k[3], k[4], len(g), statistics.median(ate), max(ate), over, imu, bad,
        "%.1f" % min(speed) if speed else "-"))
print("runs over 0.5 m: %d of %d" % (total_over, len(rows)))
PY
