#!/bin/sh
# The Makefile's batch with GNU parallel (Debian package `parallel`): N shards, JOBS at a time,
# merged and compared with one whole run. From this directory: ./run_parallel.sh [N] [JOBS]
set -eu
N=${1:-3}
JOBS=${2:-2}
IMUCONV=${IMUCONV:-../../build/bin/imuconv}
PIPELINE=${PIPELINE:-euroc_v1_01_windows.json}
OUT=${OUT:-../../build/batch_example_parallel}
mkdir -p "$OUT"
# One job per shard; --halt now,fail=1 stops the batch at the first failing shard.
seq 0 $((N - 1)) | parallel --halt now,fail=1 -j "$JOBS" \
  "$IMUCONV" -q run "$PIPELINE" --shard {}/"$N" -j 1 -o "$OUT"/shard_{}_of_"$N".json
shards=$(seq 0 $((N - 1)) | sed "s|.*|$OUT/shard_&_of_$N.json|")
# shellcheck disable=SC2086 # one argument per shard file
"$IMUCONV" -q merge -o "$OUT/merged_$N.json" $shards
"$IMUCONV" -q run "$PIPELINE" -j 1 -o "$OUT/whole.json"
cmp "$OUT/merged_$N.json" "$OUT/whole.json"
echo "$N shards merged: the same bytes as the whole run ($(stat -c %s "$OUT/whole.json") bytes)"
