#!/usr/bin/env bash
# Side-by-side accuracy and time of `plucker sfm` (points + lines and points only, with every point
# and with the point budget cut to --max-points) and, when installed, COLMAP (intrinsics fixed:
# PINHOLE from K.txt, SIFT on the CPU, exhaustive matching, mapper) on Strecha fountain-P11, each
# evaluated by `plucker eval sfm` (Sim(3) alignment to the .camera ground truth). COLMAP is for the
# comparison only, not a dependency (apt-get install colmap).
#   scripts/compare_colmap.sh [PLUCKER] [DATA_DIR] [OUT_DIR] [MAX_POINTS] [SEEDS]
# The runs are interleaved so that plucker and COLMAP share the machine's load: plucker points +
# lines, COLMAP, plucker points only, plucker points + lines again, then the budget runs. SEEDS
# (default "0 1 2 3 4 5"): one budget pair (lines, no lines) per seed, on the same point subset
# (seed 0: the longest tracks; > 0: a random subset, --point-seed). Every row gives the wall
# time, the CPU time (user + sys) and the 1-minute load average when the run started.
# Environment: COLMAP=0 skips COLMAP, FULL=0 skips the runs with every point (budget runs only).
set -euo pipefail
P="${1:-build/release/apps/plucker/plucker}"
D="${2:-../shared/data/strecha-fountain-p11}"
O="${3:-out/compare_sfm}"
BUDGET="${4:-770}"
SEEDS="${5-0 1 2 3 4 5}"  # an empty argument: no budget runs
mkdir -p "$O"
row() {  # name wall cpu load eval-json
  python3 - "$@" <<'PY'
import json, sys
name, wall, cpu, load, path = sys.argv[1:]
e = json.load(open(path))
print(f"| {name} | {e['registered']}/{e['cameras']} | {e['median_centre_mm']:.2f} | "
      f"{e['max_centre_mm']:.2f} | {e['median_rotation_deg']:.4f} | "
      f"{e['median_rotation_centres_deg']:.4f} | {float(wall):.0f} | {float(cpu):.0f} | {load} |")
PY
}
timed() {  # name command...: appends "name wall cpu load" to times.txt
  local name="$1"; shift
  local load; load=$(cut -d' ' -f1 /proc/loadavg)
  /usr/bin/time -f "%e %U %S" -o "$O/$name.time" "$@"
  read -r wall user sys < "$O/$name.time"
  echo "$name $wall $(echo "$user + $sys" | bc) $load" >> "$O/times.txt"
}
run_plucker() {  # name args...
  local name="$1"; shift
  rm -rf "${O:?}/$name"
  timed "$name" "$P" sfm --images "$D/images" --intrinsics "$D/images/K.txt" --out "$O/$name" \
    --quiet "$@"
  "$P" eval sfm --gt "$D/cameras" --est "$O/$name/poses.txt" --json > "$O/$name.eval.json"
}
run_colmap() {
  C="$O/colmap"
  rm -rf "$C" && mkdir -p "$C/sparse" "$C/txt"
  K=$(awk 'NR==1{fx=$1; cx=$3} NR==2{fy=$2; cy=$3} END{printf "%s,%s,%s,%s", fx, fy, cx, cy}' \
    "$D/images/K.txt")
  cat > "$C/run.sh" <<SH
set -e
colmap feature_extractor --database_path "$C/db.db" --image_path "$D/images" \\
  --ImageReader.camera_model PINHOLE --ImageReader.single_camera 1 \\
  --ImageReader.camera_params "$K" --SiftExtraction.use_gpu 0
colmap exhaustive_matcher --database_path "$C/db.db" --SiftMatching.use_gpu 0
colmap mapper --database_path "$C/db.db" --image_path "$D/images" --output_path "$C/sparse" \\
  --Mapper.ba_refine_focal_length 0 --Mapper.ba_refine_principal_point 0 \\
  --Mapper.ba_refine_extra_params 0
SH
  timed colmap bash -c "bash '$C/run.sh' > '$C/log.txt' 2>&1"
  colmap model_converter --input_path "$C/sparse/0" --output_path "$C/txt" --output_type TXT \
    >> "$C/log.txt" 2>&1
  # images.txt: IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME (world to camera) -> T_w_c rows in
  # name order, twelve nan for an image COLMAP did not register.
  python3 - "$C/txt/images.txt" "$D/images" > "$C/poses.txt" <<'PY'
import os, sys
import math
lines = [l for l in open(sys.argv[1]) if l.strip() and not l.startswith('#')]
poses = {}
for l in lines[0::2]:
    f = l.split()
    qw, qx, qy, qz, tx, ty, tz = map(float, f[1:8])
    R = [[1-2*(qy*qy+qz*qz), 2*(qx*qy-qz*qw), 2*(qx*qz+qy*qw)],
         [2*(qx*qy+qz*qw), 1-2*(qx*qx+qz*qz), 2*(qy*qz-qx*qw)],
         [2*(qx*qz-qy*qw), 2*(qy*qz+qx*qw), 1-2*(qx*qx+qy*qy)]]
    t = [tx, ty, tz]
    c = [-sum(R[r][k]*t[r] for r in range(3)) for k in range(3)]  # C = -R^T t
    poses[f[9]] = [[R[k][r] for k in range(3)] + [c[r]] for r in range(3)]  # [R^T | C]
names = sorted(n for n in os.listdir(sys.argv[2]) if n.lower().endswith(('.jpg', '.png')))
for n in names:
    if n in poses:
        print(' '.join(repr(v) for row in poses[n] for v in row))
    else:
        print(' '.join(['nan'] * 12))
PY
  "$P" eval sfm --gt "$D/cameras" --est "$C/poses.txt" --json > "$O/colmap.eval.json"
}

mkdir -p "$O"
: > "$O/times.txt"
if [ "${FULL:-1}" != 0 ]; then
  run_plucker points_lines
  if [ "${COLMAP:-1}" = 0 ]; then
    :
  elif command -v colmap > /dev/null; then
    run_colmap
  else
    echo "colmap not installed: not run (the issue quotes 2.4 mm / 0.028 deg in 150 s)" >&2
  fi
  run_plucker points_only --no-lines
  run_plucker points_lines_again
fi
for s in $SEEDS; do
  run_plucker "budget_seed${s}_points_lines" --max-points "$BUDGET" --point-seed "$s"
  run_plucker "budget_seed${s}_points_only" --max-points "$BUDGET" --point-seed "$s" --no-lines
done

echo "| run | registered | median centre [mm] | max centre [mm] | median rotation [deg] | median rotation, centres' alignment [deg] | wall [s] | CPU [s] | load |"
echo "|---|---|---|---|---|---|---|---|---|"
while read -r name wall cpu load; do
  row "$name" "$wall" "$cpu" "$load" "$O/$name.eval.json"
done < "$O/times.txt"
# Budget runs: mean and per-seed difference (lines - points only) of the median centre error.
python3 - "$O" $SEEDS <<'PY'
import json, sys
o, seeds = sys.argv[1], sys.argv[2:]
if not seeds:
    sys.exit(0)
get = lambda n: json.load(open(f"{o}/{n}.eval.json"))["median_centre_mm"]
lines = [get(f"budget_seed{s}_points_lines") for s in seeds]
points = [get(f"budget_seed{s}_points_only") for s in seeds]
diff = [a - b for a, b in zip(lines, points)]
print(f"budget, {len(seeds)} subsets: median centre error, mean over the subsets: lines "
      f"{sum(lines) / len(lines):.2f} mm, points only {sum(points) / len(points):.2f} mm; "
      f"lines better in {sum(d < 0 for d in diff)} of {len(diff)} (differences "
      + " ".join(f"{d:+.2f}" for d in diff) + ")")
PY
