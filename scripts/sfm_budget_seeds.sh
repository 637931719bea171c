#!/usr/bin/env bash
# Paired seed loop of `plucker sfm` at a point budget: for each seed, points + lines and points
# only on the same random subset of point tracks (--max-points N --point-seed S), each evaluated
# by `plucker eval sfm` against the Strecha ground truth (--gt) and against every reference
# reconstruction given (--ref: e.g. the poses.txt of a run with every point, or COLMAP's from
# scripts/compare_colmap.sh), Sim(3)-aligned. Prints per seed and metric the two errors, then per
# metric the means, medians, mean difference (lines - points only), the seeds where lines win, a
# two-sided sign test and the paired t statistic.
#   scripts/sfm_budget_seeds.sh PLUCKER DATA_DIR OUT_DIR BUDGET "SEEDS" [REF_POSES...]
# Environment: SFM_ARGS: more `plucker sfm` arguments for both runs (e.g. --refine-segments);
# RESUME=1 keeps the runs already in OUT_DIR (a run is done when its poses.txt exists);
# POINTS_ONLY_FROM=DIR links the points-only runs of DIR (an earlier OUT_DIR) instead of repeating
# them: they do not depend on the line options (--refine-segments, --line-sigma).
set -euo pipefail
P="${1:?plucker binary}"
D="${2:?data folder (strecha-fountain-p11)}"
O="${3:?output folder}"
BUDGET="${4:?point budget}"
SEEDS="${5:?seeds}"
shift 5
REFS=("$@")
mkdir -p "$O"
for s in $SEEDS; do
  for v in points_lines points_only; do
    n="seed${s}_$v"
    if [ "${RESUME:-0}" = 1 ] && [ -f "$O/$n/poses.txt" ]; then continue; fi
    if [ "$v" = points_only ] && [ -n "${POINTS_ONLY_FROM:-}" ]; then
      rm -rf "${O:?}/$n"
      ln -s "$(realpath "$POINTS_ONLY_FROM/$n")" "$O/$n"
      continue
    fi
    rm -rf "${O:?}/$n"
    extra=()
    [ "$v" = points_only ] && extra=(--no-lines)
    load=$(cut -d' ' -f1 /proc/loadavg)
    # shellcheck disable=SC2086
    /usr/bin/time -f "%e %U %S" -o "$O/$n.time" "$P" sfm --images "$D/images" \
      --intrinsics "$D/images/K.txt" --out "$O/$n" --quiet --max-points "$BUDGET" \
      --point-seed "$s" "${extra[@]}" ${SFM_ARGS:-}
    echo "$n $(cat "$O/$n.time") $load" >> "$O/times.txt"
  done
done
for s in $SEEDS; do
  for v in points_lines points_only; do
    n="seed${s}_$v"
    "$P" eval sfm --gt "$D/cameras" --est "$O/$n/poses.txt" --json > "$O/$n.gt.json"
    for i in "${!REFS[@]}"; do
      "$P" eval sfm --ref "${REFS[$i]}" --est "$O/$n/poses.txt" --json > "$O/$n.ref$i.json"
    done
  done
done
python3 - "$O" "${#REFS[@]}" "$SEEDS" "${REFS[@]}" <<'PY'
import json, math, statistics, sys
o, nrefs, seeds, refs = sys.argv[1], int(sys.argv[2]), sys.argv[3].split(), sys.argv[4:]
metrics = [("gt", "ground truth")] + [(f"ref{i}", f"reference {r}") for i, r in enumerate(refs)]

def get(seed, variant, m, key):
    return json.load(open(f"{o}/seed{seed}_{variant}.{m}.json"))[key]

def sign_p(wins, n):  # two-sided binomial sign test, p = 0.5
    k = min(wins, n - wins)
    return min(1.0, 2 * sum(math.comb(n, i) for i in range(k + 1)) / 2 ** n)

for m, title in metrics:
    for key, unit, scale in [("median_centre_mm", "mm", 1.0), ("median_rotation_deg", "deg", 1.0)]:
        lines = [get(s, "points_lines", m, key) * scale for s in seeds]
        points = [get(s, "points_only", m, key) * scale for s in seeds]
        d = [a - b for a, b in zip(lines, points)]
        n = len(d)
        wins = sum(x < 0 for x in d)
        t = (statistics.mean(d) / (statistics.stdev(d) / math.sqrt(n))
             if n > 1 and statistics.stdev(d) > 0 else float("nan"))
        print(f"{title}, {key} [{unit}], {n} seeds:")
        print("  per seed (lines / points only): " +
              "  ".join(f"{s}: {a:.4g}/{b:.4g}" for s, a, b in zip(seeds, lines, points)))
        print(f"  mean lines {statistics.mean(lines):.4g}, points only {statistics.mean(points):.4g};"
              f" median {statistics.median(lines):.4g} / {statistics.median(points):.4g};"
              f" mean difference {statistics.mean(d):+.4g}; lines better on {wins} of {n}"
              f" (sign test p = {sign_p(wins, n):.2g}); paired t = {t:+.2f} ({n - 1} dof)")
PY
