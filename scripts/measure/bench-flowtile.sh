#!/usr/bin/env bash
# Random scan-line tiling benchmark for flowtile-bake.
#
# Runs `flowtile-bake tile --grid WxH --set 5,5,1 --seed S --json` for many
# seeds and reports the median of its internal "seconds" (tiling only: problem
# setup + feasibility + random fill, no process start-up, no baking), then
# the library benchmark (benches/tiling.rs) over more sets and borders. The
# new build's processor time of the same runs ("cpu_seconds") is printed too.
#
# Usage: scripts/bench-flowtile.sh [runs32] [runs256]
# With OLD=path/to/an/older/flowtile-bake the two binaries run alternately,
# seed by seed, and each line gives both medians and their ratio (the machine
# is shared: only runs interleaved in time compare fairly).
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
RUNS32=${1:-101}
RUNS256=${2:-11}
OLD=${OLD:-}
nice cargo build --release -q -p flowtile-bake
BIN=target/release/flowtile-bake

median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
# One JSON field of a run's report (empty when the build lacks it).
field() { sed -nE "s/.*\"$1\":([0-9.eE+-]+).*/\1/p" <<<"$2"; }

for spec in "32x32 $RUNS32" "256x256 $RUNS256"; do
  set -- $spec
  for set in 5,5,1 3,3,5; do
    for border in free zero periodic; do
      args=(tile --grid "$1" --set "$set" --border "$border")
      new=() cpu=() old=()
      for s in $(seq 1 "$2"); do
        if [ -n "$OLD" ]; then
          old+=("$(field seconds "$(nice "$OLD" "${args[@]}" --seed "$s" --json)")")
        fi
        report=$(nice "$BIN" "${args[@]}" --seed "$s" --json)
        new+=("$(field seconds "$report")")
        cpu+=("$(field cpu_seconds "$report")")
      done
      n=$(printf '%s\n' "${new[@]}" | median)
      # Processor time of the new build (POSIX): the wall time less the
      # waits for a core, which dominate on a loaded machine.
      c=$(printf '%s\n' "${cpu[@]}" | median)
      ms() { awk -v s="${1:-nan}" 'BEGIN {printf "%.3f", s*1000}'; }
      if [ -n "$OLD" ]; then
        o=$(printf '%s\n' "${old[@]}" | median)
        printf '%-8s set %-6s border %-9s median %9s ms (cpu %9s ms)  old %9s ms  old/new %5.2f  (%s runs each)\n' \
          "$1" "$set" "$border" "$(ms "$n")" "$(ms "$c")" "$(ms "$o")" \
          "$(awk -v a="$o" -v b="$n" 'BEGIN {print a/b}')" "$2"
      else
        printf '%-8s set %-6s border %-9s median %9s ms (cpu %9s ms)  (%s runs)\n' \
          "$1" "$set" "$border" "$(ms "$n")" "$(ms "$c")" "$2"
      fi
    done
  done
done

echo "--- library benchmark (includes Tiling::new) ---"
nice cargo bench -q -p flowtile-bake --bench tiling
