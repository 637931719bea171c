#!/usr/bin/env bash
# check.sh VIO_EUROC PLUCKER OUT_DIR DATASET...: runs examples/vio_euroc and `plucker vio --euroc`
# on each EuRoC folder and compares their TUM files byte for byte (a folder that is absent is
# skipped with a message).
set -euo pipefail
vio_euroc=$1 plucker=$2 out=$3
shift 3
mkdir -p "$out"
for data in "$@"; do
  name=$(basename "$data")
  if [ ! -d "$data/mav0" ]; then
    echo "vio_euroc: skip $name: no EuRoC folder at $data"
    continue
  fi
  start=$(date +%s)
  "$vio_euroc" "$data" "$out/$name.example.tum"
  "$plucker" vio --euroc "$data" --out "$out/$name.cli.tum" --quiet
  cmp "$out/$name.example.tum" "$out/$name.cli.tum"
  echo "vio_euroc: $name: the example's poses are the CLI's ($(($(date +%s) - start)) s)"
done
