#!/usr/bin/env bash
# Rewrites config/lidar_default.yaml and the options table of docs/lidar-odometry.md from the one
# options table (apps/plucker/lidar_options_table.cc), after you edit it:
#   scripts/update_lidar_options.sh [PATH/TO/plucker]   (default build/release/apps/plucker/plucker)
# The test app_lidar_options_table_test fails while either file is stale.
set -euo pipefail
cd "$(dirname "$0")/.."
PLUCKER="${1:-build/release/apps/plucker/plucker}"
"$PLUCKER" config lidar > config/lidar_default.yaml.new
mv config/lidar_default.yaml.new config/lidar_default.yaml
table="$(mktemp)"
trap 'rm -f "$table"' EXIT
"$PLUCKER" config lidar --markdown > "$table"
doc=docs/lidar-odometry.md
grep -q '^<!-- options table begin' "$doc" && grep -q '^<!-- options table end -->' "$doc" || {
  echo "$doc: the options table markers are missing" >&2
  exit 1
}
awk -v table="$table" '
  /^<!-- options table begin/ { print; while ((getline line < table) > 0) print line; skip = 1; next }
  /^<!-- options table end -->/ { skip = 0 }
  !skip { print }
' "$doc" > "$doc.new"
mv "$doc.new" "$doc"
echo "updated config/lidar_default.yaml and $doc"
