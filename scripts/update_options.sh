#!/usr/bin/env bash
# Rewrites the generated files of the options tables (apps/plucker/options_table.h) after you
# edit one: config/{lidar,vo,vio}_default.yaml and the options tables of docs/lidar-odometry.md,
# docs/vo.md and docs/vio.md (between their "options table" markers):
#   scripts/update_options.sh [PATH/TO/plucker]   (default build/rel/apps/plucker/plucker)
# The test app_options_table_test fails while any of them is stale.
set -euo pipefail
cd "$(dirname "$0")/.."
PLUCKER="${1:-build/rel/apps/plucker/plucker}"
table="$(mktemp)"
trap 'rm -f "$table"' EXIT
update() {  # update COMMAND DOC
  local command=$1 doc=$2
  "$PLUCKER" config "$command" > "config/${command}_default.yaml.new"
  mv "config/${command}_default.yaml.new" "config/${command}_default.yaml"
  "$PLUCKER" config "$command" --markdown > "$table"
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
  echo "updated config/${command}_default.yaml and $doc"
}
update lidar docs/lidar-odometry.md
update vo docs/vo.md
update vio docs/vio.md
