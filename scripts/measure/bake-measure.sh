#!/usr/bin/env bash
# Maps per minute of scripts/bake.py (Dask.distributed, local cluster on 127.0.0.1) with 1
# and 2 worker processes on the shared maps, alternating the worker counts RUNS times
# (the machine is noisy), each run compiling everything (--no-cache), -threads 1 per map.
# With BINS="OLD_BIN NEW_BIN" (bsp2vdg executables) every run bakes with each build in turn,
# the order flipping each run, and the medians of each build and worker count come last
# with the ratio new/old (above 1: the new build bakes more maps per minute).
#
#   scripts/bake-measure.sh [MAPS...]      default: ../shared/testmaps free GoldSrc and Quake maps
#   RUNS=3 OPTS="-sd 24" scripts/bake-measure.sh
#   BINS="/old/bsp2vdg target/release/bsp2vdg" scripts/bake-measure.sh
set -euo pipefail
cd "$(dirname "$(readlink -f "$0")")/../.."
SHARED=${SHARED:-../shared}
RUNS=${RUNS:-2}
if [ $# -gt 0 ]; then maps=("$@"); else
    shopt -s nullglob
    maps=("$SHARED"/testmaps/goldsrc/*.bsp "$SHARED"/testmaps/quake1/*.bsp)
fi
[ ${#maps[@]} -gt 0 ] || { echo "skipped: no maps (is $SHARED/testmaps there?)"; exit 0; }
if [ -z "${BINS:-}" ]; then
    cargo build --release -q -p bsp2vdg
    BINS=target/release/bsp2vdg
fi
read -r -a bins <<< "$BINS"
OUT=target/bake-measure
results=$(mktemp)
trap 'rm -f "$results"' EXIT
for r in $(seq "$RUNS"); do
    order=("${bins[@]}")
    if [ $((r % 2)) -eq 0 ] && [ ${#bins[@]} -eq 2 ]; then order=("${bins[1]}" "${bins[0]}"); fi
    for w in 1 2; do
        for b in "${order[@]}"; do
            line=$(python3 scripts/bake.py --bsp2vdg "$b" --workers "$w" --no-cache --out "$OUT/out" \
                --cache "$OUT/cache" "${maps[@]}" -- ${OPTS:-} | tail -1) || true
            echo "run $r workers $w bin $b: $line"
            printf '%s\t%s\t%s\n' "$b" "$w" "$line" >> "$results"
        done
    done
done
python3 - "$results" "${bins[@]}" <<'PY'
import re, statistics, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])]
bins = sys.argv[2:]
def rate(line):
    m = re.search(r"([0-9.]+) maps/min", line)
    return float(m.group(1)) if m else None
med = {}
for b in bins:
    for w in ("1", "2"):
        xs = [rate(l) for bb, ww, l in rows if bb == b and ww == w]
        xs = [x for x in xs if x is not None]
        med[(b, w)] = statistics.median(xs) if xs else None
        print(f"median {b} workers {w}: {med[(b, w)]} maps/min over {len(xs)} runs")
if len(bins) == 2:
    for w in ("1", "2"):
        o, n = med[(bins[0], w)], med[(bins[1], w)]
        if o and n:
            print(f"ratio new/old workers {w}: {n / o:.2f}")
PY
