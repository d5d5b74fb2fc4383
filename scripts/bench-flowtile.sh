#!/usr/bin/env bash
# Random scan-line tiling benchmark for flowtile-bake.
#
# Runs `flowtile-bake tile --grid WxH --set 5,5,1 --seed S --json` for many
# seeds and reports the median of its internal "seconds" (tiling only: problem
# setup + feasibility + random fill, no process start-up, no baking), then
# the library benchmark (benches/tiling.rs) over more sets and borders.
#
# Usage: scripts/bench-flowtile.sh [runs32] [runs256]
set -euo pipefail
cd "$(dirname "$0")/.."
RUNS32=${1:-101}
RUNS256=${2:-11}
nice cargo build --release -q -p flowtile-bake
BIN=target/release/flowtile-bake

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

for spec in "32x32 $RUNS32" "256x256 $RUNS256"; do
  set -- $spec
  for set in 5,5,1 3,3,5; do
    for border in free zero periodic; do
      secs=$(for s in $(seq 1 "$2"); do
        nice "$BIN" tile --grid "$1" --set "$set" --border "$border" --seed "$s" --json |
          sed -E 's/.*"seconds":([0-9.eE+-]+).*/\1/'
      done | median)
      printf '%-8s set %-6s border %-9s median %10.3f ms  (%s runs)\n' \
        "$1" "$set" "$border" "$(awk -v s="$secs" 'BEGIN {print s*1000}')" "$2"
    done
  done
done

echo "--- library benchmark (includes Tiling::new) ---"
nice cargo bench -q -p flowtile-bake --bench tiling
