#!/bin/sh
# The Makefile's `montecarlo` target with GNU parallel (Debian package `parallel`): one montecarlo
# run as N shards, JOBS at a time, merged and compared with the whole run.
# From this directory: ./montecarlo_parallel.sh [N] [JOBS]
set -eu
N=${1:-3}
JOBS=${2:-2}
IMUCONV=${IMUCONV:-../../build/bin/imuconv}
CASE=${CASE:-../../tests/data/reference/cases/smooth-0.json}
OUT=${OUT:-../../build/batch_example_parallel}
RUN="--method rk4 --trials 3000 --seed 7"
mkdir -p "$OUT"
# One job per shard; --halt now,fail=1 stops the batch at the first failing shard.
# shellcheck disable=SC2086 # $RUN is several options
seq 0 $((N - 1)) | parallel --halt now,fail=1 -j "$JOBS" \
  "$IMUCONV" -q montecarlo --case "$CASE" $RUN --threads 1 --shard {}/"$N" -o "$OUT"/mc_shard_{}_of_"$N".mcs
shards=$(seq 0 $((N - 1)) | sed "s|.*|$OUT/mc_shard_&_of_$N.mcs|")
# Exit 1 is the verdict "inconsistent", a result: only 2 (unusable input, a refused shard) stops.
# shellcheck disable=SC2086 # one argument per shard file
"$IMUCONV" montecarlo --merge $shards --json > "$OUT/mc_merged_$N.json" || [ $? -eq 1 ]
# shellcheck disable=SC2086
"$IMUCONV" montecarlo --case "$CASE" $RUN --threads 1 --json > "$OUT/mc_whole.json" || [ $? -eq 1 ]
cmp "$OUT/mc_merged_$N.json" "$OUT/mc_whole.json"
echo "$N montecarlo shards merged: the same bytes as the whole run ($(stat -c %s "$OUT/mc_whole.json") bytes)"
